#!/usr/bin/python3
"""lathectl_publish — shop data out (never in the servo thread): the lathectl components' pins of
whichever systems are loaded (E lathectl_adaptive, A lathectl_slide, B lathectl_modfeed, D
lathectl_gauge) and LinuxCNC's own state, to

  - MQTT (paho): lathectl/<machine>/state (retained online/offline, the last will offline),
    lathectl/<machine>/<system>/live (QoS 0, --rate Hz), lathectl/<machine>/<system>/event
    (QoS 1, a seq per machine and system). Events are kept in OUT/publish-spool.sqlite until the
    broker acknowledges them (at most --spool-max, the oldest dropped and counted), so a broker
    away loses none;
  - MTConnect SHDR on TCP --shdr PORT (lathectl_shdr), with --devices-xml its Devices.xml.

  loadusr -W lathectl_publish.py [--mqtt HOST:PORT] [--shdr PORT] [--out DIR] [--rate HZ]
          [--machine NAME] [--unit N|W] [--username U --password P | --password-file F]
          [--cafile CA.pem] [--spool-max N]
  lathectl_publish.py --keys [--systems EABD] | --devices-xml [--systems EABD]

The keys are made from hal/pins.json (lathectl_shopdata). The publisher subscribes to nothing and
has no out pins: nothing received from the network writes a HAL pin. Its in pins are netted to the
components' out pins when it starts (to the out pin's signal, or a new one).
"""

import argparse
import configparser
import json
import math
import os
import queue
import signal
import socket
import sqlite3
import sys
import time
import tomllib

import lathectl_shopdata as shop

HERE = os.path.dirname(os.path.abspath(__file__))
# scripts/linuxcnc-sim puts lines in front of the user's program: lines are the user's (as
# lathectl_oplog's).
LINE_OFFSET = int(os.environ.get("LATHECTL_SIM_LINE_OFFSET", "0"))


def ini_value(section, key):
    path = os.environ.get("INI_FILE_NAME", "")
    if not path or not os.path.exists(path):
        return None
    cp = configparser.ConfigParser(strict=False, interpolation=None, inline_comment_prefixes=("#",))
    cp.optionxform = str
    try:
        cp.read(path)
        return cp.get(section, key, fallback=None)
    except configparser.Error:
        return None


def reason_table():
    try:
        with open(os.path.join(HERE, "reasons.json")) as f:
            rows = json.load(f)["reasons"]
    except (OSError, ValueError, KeyError):
        return {}
    return {r["code"]: r for r in rows}


def strict(obj):
    """The object with every NaN or infinity as None: strict JSON, which a browser's JSON.parse
    reads (a NaN sensor, a limit not set)."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: strict(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [strict(v) for v in obj]
    return obj


def dumps(obj):
    return json.dumps(strict(obj), allow_nan=False)


class Spool:
    """The events not yet acknowledged by the broker, on disk (SQLite), oldest dropped past max;
    each system's last seq, so numbers survive a restart of the publisher too."""

    def __init__(self, path, limit):
        self.db = sqlite3.connect(path)
        self.limit = limit
        self.db.execute("CREATE TABLE IF NOT EXISTS events (id INTEGER PRIMARY KEY, topic TEXT, "
                        "payload TEXT)")
        self.db.execute("CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value INTEGER)")
        self.db.commit()

    def meta(self, key):
        r = self.db.execute("SELECT value FROM meta WHERE key = ?", (key,)).fetchone()
        return r[0] if r else 0

    def set_meta(self, key, value):
        self.db.execute("INSERT OR REPLACE INTO meta VALUES (?, ?)", (key, value))

    def add(self, system, topic, event):
        seq = self.meta("seq_" + system) + 1
        self.set_meta("seq_" + system, seq)
        event = dict(seq=seq, **event)
        cur = self.db.execute("INSERT INTO events (topic, payload) VALUES (?, ?)",
                              (topic, dumps(event)))
        over = self.db.execute("SELECT COUNT(*) FROM events").fetchone()[0] - self.limit
        if over > 0:
            self.db.execute("DELETE FROM events WHERE id IN (SELECT id FROM events ORDER BY id "
                            "LIMIT ?)", (over,))
            self.set_meta("dropped", self.meta("dropped") + over)
        self.db.commit()
        return cur.lastrowid

    def rows(self):
        return self.db.execute("SELECT id, topic, payload FROM events ORDER BY id").fetchall()

    def done(self, rowid):
        self.db.execute("DELETE FROM events WHERE id = ?", (rowid,))
        self.db.commit()


class Mqtt:
    """The broker link: paho's network thread; its callbacks only queue, the main thread acts."""

    def __init__(self, a, machine, spool):
        import paho.mqtt.client as mqtt
        self.mqtt = mqtt
        self.base = "lathectl/%s" % machine
        self.spool = spool
        self.q = queue.Queue()
        self.connected = False
        self.handed = {}   # spool row id -> mid (paho resends these itself after a reconnect)
        self.mids = {}     # mid -> spool row id
        self.sent = 0
        host, _, port = a.mqtt.rpartition(":")
        self.c = mqtt.Client(client_id="lathectl-publish-" + machine, clean_session=True)
        self.c.max_inflight_messages_set(100)
        if a.username:
            self.c.username_pw_set(a.username, a.password)
        if a.cafile:
            self.c.tls_set(ca_certs=a.cafile)
        self.c.will_set(self.base + "/state", "offline", qos=1, retain=True)
        self.c.on_connect = lambda c, u, f, rc: self.q.put(("connect", rc))
        self.c.on_disconnect = lambda c, u, rc: self.q.put(("disconnect", rc))
        self.c.on_publish = lambda c, u, mid: self.q.put(("puback", mid))
        self.c.reconnect_delay_set(0.2, 2)
        self.c.connect_async(host or "127.0.0.1", int(port), keepalive=5)
        self.c.loop_start()

    def service(self):
        while True:
            try:
                what, x = self.q.get_nowait()
            except queue.Empty:
                return
            if what == "connect" and x == 0:
                self.connected = True
                self.c.publish(self.base + "/state", "online", qos=1, retain=True)
                self.flush()
            elif what == "connect":
                print("lathectl_publish: broker refused: %s" % self.mqtt.connack_string(x),
                      file=sys.stderr, flush=True)
            elif what == "disconnect":
                self.connected = False
            elif what == "puback" and x in self.mids:
                rowid = self.mids.pop(x)
                self.handed.pop(rowid, None)
                self.spool.done(rowid)
                self.sent += 1

    def flush(self):
        """Hand paho every spooled event it does not hold yet (in order)."""
        if not self.connected:
            return
        for rowid, topic, payload in self.spool.rows():
            if rowid in self.handed or not self.connected:
                continue
            info = self.c.publish(topic, payload, qos=1)
            if info.rc == self.mqtt.MQTT_ERR_SUCCESS:
                self.handed[rowid] = info.mid
                self.mids[info.mid] = rowid

    def event(self, system, event):
        self.spool.add(system, "%s/%s/event" % (self.base, system), event)
        self.flush()

    def live(self, system, obj):
        if self.connected:
            self.c.publish("%s/%s/live" % (self.base, system), dumps(obj), qos=0)

    def close(self):
        end = time.time() + 3.0  # the events handed over: their acknowledgements
        while self.connected and self.handed and time.time() < end:
            time.sleep(0.02)
            self.service()
        if self.connected:
            self.c.publish(self.base + "/state", "offline", qos=1, retain=True).wait_for_publish(2)
        self.c.disconnect()
        self.c.loop_stop()


class Lcnc:
    """LinuxCNC's own state when a session runs (its stat()), else None for each."""

    def __init__(self):
        try:
            import linuxcnc
            self.s = linuxcnc.stat()
            self.s.poll()
        except Exception:
            self.s = None

    def state(self):
        if self.s is not None:
            try:
                self.s.poll()
                line = int(self.s.motion_line)
                return {"program_line": max(0, line - LINE_OFFSET) if line else 0,
                        "tool": int(self.s.tool_in_spindle),
                        "spindle_rpm": float(self.s.spindle[0]["speed"]),
                        "feed_override": float(self.s.feedrate)}
            except Exception:
                pass
        return {"program_line": None, "tool": None, "spindle_rpm": None, "feed_override": None}


class System:
    """One loaded system: its pins on the publisher (netted to the component's), its live object
    and the events its pins make."""

    def __init__(self, letter, comps, comp, unit, reasons, tolerance_um):
        import hal
        self.hal, self.letter, self.c, self.reasons = hal, letter, comp, reasons
        s = shop.SYSTEMS[letter]
        self.prefix = comps[s["component"]]["prefix"]
        self.keys = shop.live_keys(comps, letter, unit)
        self.pins = {}  # HAL name of the source -> our pin's name
        wanted = [k[2] for k in self.keys if k[1] == "pin"]
        for name in [s["reason"], s["alarm"], s["alarm_reason"]] + s["events"]:
            if name:
                wanted.append(self.prefix + "." + name)
        self.part = None
        if "part" in s and hal.component_exists(s["part"]["component"]):
            pp = comps[s["part"]["component"]]["prefix"]
            wanted += [pp + "." + n for n in s["part"]["pins"]]
            self.part = pp
        kinds = {"float": hal.HAL_FLOAT, "s32": hal.HAL_S32, "bit": hal.HAL_BIT, "u32": hal.HAL_U32}
        types = {c["prefix"] + "." + p["name"]: p["type"] for c in comps.values() for p in c["pins"]}
        for src in dict.fromkeys(wanted):
            mine = letter.lower() + "." + src.split(".", 1)[1]
            if self.part and src.startswith(self.part + "."):
                mine = letter.lower() + ".part-" + src.split(".", 1)[1]
            comp.newpin(mine, kinds[types[src]], hal.HAL_IN)
            self.pins[src] = mine
        self.params = {k[2]: None for k in self.keys if k[1] == "param"}
        self.alarms = []
        self.last = {}
        self.gauged = False
        self.tolerance_um = tolerance_um

    def connect(self, drivers, name):
        """Net each of our in pins to its source's signal (a new one when it has none)."""
        for src, mine in self.pins.items():
            sig = drivers.get(src)
            if sig is None:  # (HAL names are at most 47 characters)
                sig = "pub-" + src.replace("lathectl-", "", 1).replace(".", "-")
                self.hal.new_sig(sig, {"float": self.hal.HAL_FLOAT, "bit": self.hal.HAL_BIT,
                                       "s32": self.hal.HAL_S32, "u32": self.hal.HAL_U32}[
                    self.kind(src)])
                self.hal.connect(src, sig)
                drivers[src] = sig
            self.hal.connect(name + "." + mine, sig)
            # (the hal module prints a failed connect and goes on: check it took)
            got = {s["NAME"]: s["DRIVER"] for s in self.hal.get_info_signals()}
            if got.get(sig) != src:
                raise SystemExit("lathectl_publish: could not net %s to %s" % (src, sig))
        for p in self.params:
            try:
                self.params[p] = self.hal.get_value(p)
            except RuntimeError:  # a module older than its pin table: the key is null
                print("lathectl_publish: no parameter %s" % p, file=sys.stderr, flush=True)
        self.last = {src: self.c[mine] for src, mine in self.pins.items()}

    def kind(self, src):
        for p in self.hal.get_info_pins():
            if p["NAME"] == src:
                return {self.hal.HAL_FLOAT: "float", self.hal.HAL_BIT: "bit",
                        self.hal.HAL_S32: "s32", self.hal.HAL_U32: "u32"}[p["TYPE"]]
        raise KeyError(src)

    def get(self, short):
        return self.c[self.pins[self.prefix + "." + short]]

    def reason_name(self, code):
        return self.reasons.get(code, {}).get("name", str(code)) if code else ""

    def active_alarms(self):
        s = shop.SYSTEMS[self.letter]
        if not s["alarm"] or not self.get(s["alarm"]):
            return []
        return [self.reason_name(self.get(s["alarm_reason"])) or "alarm"]

    def live(self, now, machine, lcnc):
        obj = {"ts": round(now, 3), "machine": machine, "system": self.letter}
        obj.update(lcnc)
        obj["reason"] = self.reason_name(self.get(shop.SYSTEMS[self.letter]["reason"]))
        obj["alarms"] = self.active_alarms()
        for key, how, name, kind, _ in self.keys:
            v = (self.c[self.pins[name]] if how == "pin" or (how == "part" and self.gauged) else
                 None if how == "part" else self.params[name] if how == "param"
                 else self.hal.get_value(name))
            obj[key] = (None if v is None else bool(v) if kind == "bool" else int(v)
                        if kind == "int" else float(v))
        obj = strict(obj)  # a NaN (a lost sensor) is null, in MQTT and SHDR alike
        return obj

    def events(self, now, by_code, by_bit):
        """The events since the last call: [event dict without seq]."""
        out = []
        alarms = self.active_alarms()
        for name in alarms:
            if name not in self.alarms:
                out.append({"ts": now, "type": "alarm_raised", "alarm": name,
                            "message": self.reasons.get(self.code_of(name), {}).get("meaning", "")})
        for name in self.alarms:
            if name not in alarms:
                out.append({"ts": now, "type": "alarm_cleared", "alarm": name, "message": ""})
        self.alarms = alarms
        if self.letter == "E":
            out += self.e_events(now, by_code, by_bit)
        if self.part:
            n = self.c[self.pins[self.part + ".part"]]
            if n != self.last.get("part", n) and self.last.get("part", 0) > 0:
                err = self.c[self.pins[self.part + ".finished-error-um"]]
                out.append({"ts": now, "type": "gauged_part", "part": self.last["part"],
                            "size_error_um": round(err, 4), "lower_um": -self.tolerance_um,
                            "upper_um": self.tolerance_um})
                self.gauged = True  # size_error_um: the last gauged part's from now on
            self.last["part"] = n
        return out

    def final_events(self, now):
        """At the end: the part on the machine (its size now, as the gauge display takes it)."""
        if not self.part or self.last.get("part", 0) <= 0:
            return []
        err = self.c[self.pins[self.part + ".error-um"]]
        return [{"ts": now, "type": "gauged_part", "part": self.last["part"],
                 "size_error_um": round(err, 4), "lower_um": -self.tolerance_um,
                 "upper_um": self.tolerance_um}]

    def code_of(self, name):
        return next((c for c, r in self.reasons.items() if r["name"] == name), None)

    def e_events(self, now, by_code, by_bit):
        import lathectl_oplog
        out = []
        seq = self.get("op-seq")
        if seq != self.last.get("op"):
            if "op" in self.last:
                row = lathectl_oplog.operation_row(self.get, seq, 0.0, LINE_OFFSET, by_code,
                                                   by_bit)
                row.pop("time_s")
                row["op_seq"] = row.pop("seq")
                out.append(dict({"ts": now, "type": "operation"}, **row))
            self.last["op"] = seq
        tseq = self.get("teach-seq")
        if tseq != self.last.get("teach"):
            if "teach" in self.last:
                out.append({"ts": now, "type": "teach_in", "tool": self.get("teach-tool"),
                            "operation": self.get("teach-operation"),
                            "reference": round(self.get("teach-reference"), 3)})
            self.last["teach"] = tseq
        return out


def shdr_values(objs, systems):
    """The SHDR items' text from the live objects (lathectl_shopdata.shdr_items' keys)."""
    values, conds = {"avail": "AVAILABLE"}, {}
    for s in systems:
        obj = objs[s.letter]
        for key in ("program_line", "tool", "spindle_rpm", "feed_override"):
            v = obj[key]
            if key == "feed_override" and v is not None:
                v = round(100.0 * v, 1)  # MTConnect's override is in percent
            values[key] = "UNAVAILABLE" if v is None else v
        for key, _, _, kind, _ in s.keys:
            v = obj[key]
            values["%s_%s" % (s.letter, key)] = "UNAVAILABLE" if v is None else (
                "true" if v else "false") if kind == "bool" else ("%.6g" % v if kind == "float"
                                                                  else v)
        code = obj["reason"]
        values["%s_reason" % s.letter] = (code, s.reasons.get(s.code_of(code), {}).get(
            "meaning", "")) if code else ("", "")
        conds["%s_alarm" % s.letter] = [
            ("FAULT", a, s.reasons.get(s.code_of(a), {}).get("meaning", "")) for a in obj["alarms"]]
    return values, conds


def args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mqtt", default="", help="the broker, HOST:PORT")
    ap.add_argument("--shdr", type=int, default=0, help="MTConnect SHDR port (7878), 0 none")
    ap.add_argument("--out", default="", help="where the event spool is ([LATHECTL]LOG_DIR)")
    ap.add_argument("--rate", type=float, default=10.0, help="live messages a second per system")
    ap.add_argument("--machine", default="", help="[LATHECTL]MACHINE, default the host name")
    ap.add_argument("--unit", default="", choices=["", "N", "W"], help="E's load unit")
    ap.add_argument("--username", default="")
    ap.add_argument("--password-file", default="", help="a file holding the broker password "
                    "(else $LATHECTL_MQTT_PASSWORD)")
    ap.add_argument("--cafile", default="", help="TLS: the broker's CA certificate (PEM)")
    ap.add_argument("--spool-max", type=int, default=10000, help="events kept while away")
    ap.add_argument("--name", default="lathectl-publish")
    ap.add_argument("--systems", default="", help="with --keys/--devices-xml: which (EABD)")
    ap.add_argument("--keys", action="store_true", help="print each system's live keys (JSON)")
    ap.add_argument("--devices-xml", action="store_true", help="print MTConnect Devices.xml")
    a = ap.parse_args()
    if not 0.1 <= a.rate <= 100:
        ap.error("--rate %g: expected 0.1 .. 100 Hz" % a.rate)
    if a.mqtt and not a.mqtt.rpartition(":")[2].isdigit():
        ap.error("--mqtt %s: expected HOST:PORT" % a.mqtt)
    a.password = None
    if a.password_file:
        with open(a.password_file) as f:
            a.password = f.read().strip()
    elif os.environ.get("LATHECTL_MQTT_PASSWORD"):
        a.password = os.environ["LATHECTL_MQTT_PASSWORD"]
    a.machine = a.machine or ini_value("LATHECTL", "MACHINE") or socket.gethostname()
    a.unit = a.unit or ini_value("LATHECTL", "UNIT") or "N"
    a.out = a.out or ini_value("LATHECTL", "LOG_DIR") or os.getcwd()
    return a


def tolerance_um():
    path = os.environ.get("LATHECTL_SIM_SCENARIO") or ini_value("LATHECTL", "SCENARIO") or ""
    try:
        with open(path, "rb") as f:
            return float(tomllib.load(f).get("process", {}).get("tolerance_um", 10.0))
    except (OSError, ValueError):
        return 10.0


def main():
    a = args()
    comps = shop.components(os.path.join(HERE, "pins.json"))
    if a.keys or a.devices_xml:
        letters = a.systems or "EABD"
        if a.keys:
            print(json.dumps({s: shop.all_keys(comps, s, a.unit) for s in letters}, indent=1))
        else:
            sys.stdout.write(shop.devices_xml(comps, letters, a.machine, a.unit))
        return
    import hal
    import lathectl_oplog
    c = hal.component(a.name)
    reasons = reason_table()
    by_code = {k: r["name"] for k, r in reasons.items()}
    by_bit = {r["bit"]: r["name"] for r in reasons.values()}
    systems = [System(s, comps, c, a.unit, reasons, tolerance_um()) for s in shop.SYSTEMS
               if hal.component_exists(shop.SYSTEMS[s]["component"])]
    c.ready()
    drivers = {sig["DRIVER"]: sig["NAME"] for sig in hal.get_info_signals() if sig["DRIVER"]}
    for s in systems:
        s.connect(drivers, a.name)
    print("lathectl_publish: machine %s, systems %s%s%s" % (
        a.machine, "".join(s.letter for s in systems) or "none",
        ", MQTT " + a.mqtt if a.mqtt else "", ", SHDR port %d" % a.shdr if a.shdr else ""),
        file=sys.stderr, flush=True)
    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    os.makedirs(a.out, exist_ok=True)
    spool = Spool(os.path.join(a.out, "publish-spool.sqlite"), a.spool_max)
    mq = Mqtt(a, a.machine, spool) if a.mqtt else None
    shdr = None
    if a.shdr:
        import lathectl_shdr
        shdr = lathectl_shdr.ShdrServer(a.shdr)
        shdr.start()
    lcnc = Lcnc()
    stats = {"live": 0, "events": 0, "first_seq": {s.letter: spool.meta("seq_" + s.letter) + 1
                                                   for s in systems}}
    period, next_live = 1.0 / a.rate, time.time()
    while not stop:
        now = time.time()
        for s in systems:
            for ev in s.events(now, by_code, by_bit):
                stats["events"] += 1
                if mq:
                    mq.event(s.letter, ev)
        if mq:
            mq.service()
        if now >= next_live:
            state = lcnc.state()
            objs = {s.letter: s.live(now, a.machine, state) for s in systems}
            if mq:
                for s in systems:
                    mq.live(s.letter, objs[s.letter])
            if shdr and systems:
                shdr.update(now, *shdr_values(objs, systems))
            stats["live"] += 1
            next_live = max(next_live + period, now - period)
        time.sleep(0.005)
    for s in systems:  # what only the end tells: the last gauged part's size
        for ev in s.final_events(time.time()):
            stats["events"] += 1
            if mq:
                mq.event(s.letter, ev)
    if mq:
        mq.service()
        mq.close()
        stats.update(events_acked=mq.sent, spooled=len(spool.rows()), dropped=spool.meta("dropped"))
    if shdr:
        shdr.stop()
        stats["shdr"] = shdr.stats
    stats["last_seq"] = {s.letter: spool.meta("seq_" + s.letter) for s in systems}
    lathectl_oplog.atomic_write(os.path.join(a.out, "publish.json"), json.dumps(stats) + "\n")


if __name__ == "__main__":
    main()
