"""lathectl_shopdata — what lathectl_publish sends, made from the pin list (hal/pins.json, the
components' pin tables): one place for the MQTT live keys, the SHDR keys and Devices.xml, which the
publisher, `lathectl_publish.py --keys`/`--devices-xml` and docs/shop-data.md's test all use.

A live key is a pin's name (or the stem below) in snake_case with its unit from the pin table as
a suffix ("mm/rev" -> "mm_per_rev", "%" -> "pct", "kg*m^2" -> "kg_m2"); E's load unit "N or W"
is the session's (N with a force sensor, W on spindle power). Which pins a system publishes is
the small mapping SYSTEMS below, by pin name: every system has one "load" and one "limit" (the
controlled value against its limit), its "reason" and its alarms.
"""

import json
import re
import xml.etree.ElementTree as ET

# Per system: its component, the pins published as (stem, pin) — the key is the stem with the
# pin's unit — where the reason code and the alarm are, and the pins events are made from.
# A pin read by get_value (an in pin, a parameter) is marked "param:" / "in:"; "part:" a pin of
# the simulated part's component (D: the last gauged part's size; null without it).
SYSTEMS = {
    "E": {"component": "lathectl_adaptive", "live": [
        ("load", "load"), ("limit", "limit"), ("rev_mean_load", "load-rev"),
        ("usage", "load-percent"), ("feed", "feed-per-rev"),
        ("feed_factor", "feed-factor"), ("cutting_speed", "cutting-speed-cmd"),
        ("spindle_cmd", "spindle-speed-out"), ("cut_power", "cut-power"),
        ("depth_ahead", "depth-ahead"), ("in_cut", "in-cut"), ("feed_hold", "feed-hold"),
        ("adaptive_on", "adaptive-on"), ("teaching", "teaching"), ("update_max", "update-ns-max")],
        "reason": "reason", "alarm": "alarm", "alarm_reason": "alarm-reason",
        "events": ["op-seq", "op-line", "op-tool", "op-operation", "op-mode", "op-reasons",
                   "op-alarm", "op-limit", "op-load-mean", "op-load-peak", "op-feed-min",
                   "op-feed-mean", "op-time-in-cut", "op-time", "teach-seq", "teach-tool",
                   "teach-operation", "teach-reference"]},
    "A": {"component": "lathectl_slide", "live": [
        ("load", "force-estimate"), ("limit", "force-set-out"), ("feed", "feed-cmd"),
        ("frequency", "frequency"), ("pulse_width", "pulse-width"), ("enabled", "enabled"),
        ("roughing", "roughing-out"), ("update_max", "update-ns-max")],
        "reason": "reason", "alarm": "alarm", "alarm_reason": "alarm-reason", "events": []},
    "B": {"component": "lathectl_modfeed", "live": [
        ("load", "in:a0-um"), ("limit", "param:dead-zone"), ("frequency", "in:omega-d-Hz"),
        ("feed", "feed"), ("feed_ratio", "feed-ratio"), ("modulation_frequency", "omega-m-Hz"),
        ("cut_power", "cut-power"), ("engaged", "engaged"), ("update_max", "update-ns-max")],
        "reason": "reason", "alarm": None, "alarm_reason": None, "events": []},
    "D": {"component": "lathectl_gauge", "live": [
        ("load", "signal"), ("limit", "next-threshold"), ("step", "step"),
        ("command", "command"), ("trips", "trips"), ("armed", "armed"), ("size", "size"),
        ("backstop", "backstop"), ("update_max", "update-ns-max"),
        ("size_error", "part:finished-error-um")],
        "reason": "reason", "alarm": "alarm", "alarm_reason": "reason", "events": [],
        # the simulated part (scripts/linuxcnc-sim-gauge): its size when the next one is loaded
        "part": {"component": "lathectl_gauge_plant", "pins": ["part", "finished-error-um", "error-um"]}},
}
# What every live object has besides the system's values (LinuxCNC's own state from its stat()).
COMMON = [("ts", "float", "s", "unix time the pins were read"),
          ("machine", "str", "", "[LATHECTL]MACHINE, default the host name"),
          ("system", "str", "", "A, B, D or E"),
          ("program_line", "int", "", "the program line (stat().motion_line; in linuxcnc-sim the "
                                      "user's program's line)"),
          ("tool", "int", "", "the tool in the spindle (stat().tool_in_spindle)"),
          ("spindle_rpm", "float", "rpm", "spindle speed (stat().spindle[0]['speed'])"),
          ("feed_override", "float", "", "LinuxCNC's feed override ratio, 1.0 = 100 % "
                                         "(stat().feedrate)"),
          ("reason", "str", "", "why the controller limits: the reason's name, \"\" for none"),
          ("alarms", "list", "", "the active alarms' names, [] when none")]
EVENT_TYPES = ["alarm_raised", "alarm_cleared", "operation", "gauged_part", "teach_in"]
KINDS = {"float": "float", "s32": "int", "u32": "int", "bit": "bool"}


def unit_suffix(unit, load_unit="N"):
    """A pin table's unit as a key suffix ("" for none)."""
    if unit == "N or W":
        unit = load_unit
    return unit.replace("/", "_per_").replace("%", "pct").replace("*", "_").replace("^", "")


def key_of(stem, unit, load_unit="N"):
    suffix = unit_suffix(unit, load_unit)
    if not suffix or stem.endswith("_" + suffix):
        return stem
    return stem + "_" + suffix


def components(pins_json):
    with open(pins_json) as f:
        return {c["name"]: c for c in json.load(f)["components"]}


def pin_info(comps, component, ref):
    """(how, pin dict) of a mapping's pin: how is 'pin' (an out pin: the publisher's own in pin
    is netted to it), 'in' (an in pin, read with get_value) or 'param' (a parameter, read once)."""
    how, _, name = ref.rpartition(":")
    how = how or "pin"
    if how == "part":  # the gauged part's (D's simulated part, when its plant is loaded)
        component = next(s["part"]["component"] for s in SYSTEMS.values()
                         if s["component"] == component)
    c = comps[component]
    rows = c["params"] if how == "param" else c["pins"]
    for p in rows:
        if p["name"] == name:
            if how in ("pin", "part") and p["dir"] != "out":
                raise ValueError("%s.%s is not an out pin" % (component, name))
            return how, p
    raise KeyError("%s has no %s %s (hal/pins.json)" % (component, how, name))


def live_keys(comps, system, load_unit="N"):
    """[(key, how, HAL name, kind, unit)] of a system's values in its live object."""
    s = SYSTEMS[system]
    out = []
    for stem, ref in s["live"]:
        how, p = pin_info(comps, s["component"], ref)
        kind = "float" if how == "param" else KINDS[p["type"]]
        unit = p["unit"] if p["unit"] != "N or W" else load_unit
        comp = s["part"]["component"] if how == "part" else s["component"]
        out.append((key_of(stem, p["unit"], load_unit), how,
                    comps[comp]["prefix"] + "." + p["name"], kind, unit))
    return out


def all_keys(comps, system, load_unit="N"):
    """Every key of a system's live object, in order: the common ones, then its values."""
    return [k[0] for k in COMMON] + [k[0] for k in live_keys(comps, system, load_unit)]


# MTConnect (SHDR): a data item per live value, `<system>_<key>`; the reason a Message, the
# alarms a Condition, LinuxCNC's state once per device. Types by unit, else lathectl's own (x:).
# (Values are sent in the pin table's unit: a unit MTConnect has no name for is declared with an
# x: type and no units.)
MTC_UNITS = {"N": ("NEWTON", "x:FORCE"), "W": ("WATT", "WATTAGE"), "rpm": ("REVOLUTION/MINUTE",
             "ROTARY_VELOCITY"), "mm": ("MILLIMETER", "x:LENGTH"), "Hz": ("HERTZ", "x:FREQUENCY"),
             "mm/s": ("MILLIMETER/SECOND", "PATH_FEEDRATE"), "V": ("VOLT", "x:VOLTAGE"),
             "s": ("SECOND", "x:DURATION"), "%": ("PERCENT", "LOAD")}


def shdr_items(comps, systems, load_unit="N"):
    """[(shdr key, category, type, units, native units, live key, system or None)], every data
    item the adapter sends for the loaded systems (the device's own first)."""
    items = [("program_line", "EVENT", "LINE_NUMBER", "", "", "program_line", None),
             ("tool", "EVENT", "TOOL_NUMBER", "", "", "tool", None),
             ("spindle_rpm", "SAMPLE", "ROTARY_VELOCITY", "REVOLUTION/MINUTE", "rpm",
              "spindle_rpm", None),
             ("feed_override", "EVENT", "PATH_FEEDRATE_OVERRIDE", "", "", "feed_override", None)]
    for s in systems:
        for key, _, _, kind, unit in live_keys(comps, s, load_unit):
            if kind == "float":
                units, typ = MTC_UNITS.get(unit, ("", "x:" + re.sub(r"\W", "_", key).upper()))
                items.append(("%s_%s" % (s, key), "SAMPLE", typ, units, unit, key, s))
            else:
                items.append(("%s_%s" % (s, key), "EVENT", "x:" + key.upper(), "", "", key, s))
        items.append(("%s_reason" % s, "EVENT", "MESSAGE", "", "", "reason", s))
        items.append(("%s_alarm" % s, "CONDITION", "SYSTEM", "", "", "alarms", s))
    return items


def devices_xml(comps, systems, machine, load_unit="N"):
    """MTConnect Devices.xml (2.x) of a Lathe with lathectl's data items."""
    ns = "urn:mtconnect.org:MTConnectDevices:2.0"
    ET.register_namespace("", ns)
    root = ET.Element("{%s}MTConnectDevices" % ns)
    root.set("xmlns:x", "urn:lathectl:shop-data")  # the x: types (ElementTree declares only tags')
    ET.SubElement(root, "{%s}Header" % ns, {"creationTime": "1970-01-01T00:00:00Z",
                  "sender": machine, "instanceId": "1", "version": "2.0.0.0",
                  "assetBufferSize": "1", "assetCount": "0", "bufferSize": "131072"})
    devices = ET.SubElement(root, "{%s}Devices" % ns)
    dev = ET.SubElement(devices, "{%s}Device" % ns, {"id": "lathe", "name": machine,
                        "uuid": "lathectl-" + machine})
    ET.SubElement(dev, "{%s}Description" % ns,
                  {"manufacturer": "lathectl"}).text = "Lathe controlled by LinuxCNC and lathectl"
    items = ET.SubElement(dev, "{%s}DataItems" % ns)
    ET.SubElement(items, "{%s}DataItem" % ns, {"id": "avail", "category": "EVENT",
                  "type": "AVAILABILITY"})
    comps_el = ET.SubElement(dev, "{%s}Components" % ns)
    ctrl = ET.SubElement(comps_el, "{%s}Controller" % ns, {"id": "controller"})
    path_items = None
    groups = {}
    for key, cat, typ, units, native, _, s in shdr_items(comps, systems, load_unit):
        if s is None:
            if path_items is None:
                sub = ET.SubElement(ctrl, "{%s}Components" % ns)
                path = ET.SubElement(sub, "{%s}Path" % ns, {"id": "path"})
                path_items = ET.SubElement(path, "{%s}DataItems" % ns)
            parent = path_items
        else:
            if s not in groups:
                sys_el = ET.SubElement(comps_el, "{%s}Controller" % ns,
                                       {"id": "system_" + s, "name": "lathectl_" + s})
                groups[s] = ET.SubElement(sys_el, "{%s}DataItems" % ns)
            parent = groups[s]
        attrs = {"id": key, "name": key, "category": cat, "type": typ}
        if units:
            attrs["units"] = units
        ET.SubElement(parent, "{%s}DataItem" % ns, attrs)
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
