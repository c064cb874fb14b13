#!/usr/bin/python3
"""lathectl_oplog — the userspace side of lathectl_adaptive (never in the servo thread):

  - the operation log: one row per program line with feed moves (lathectl_adaptive's op-* pins,
    read when op-seq changes) → OUT/operations.csv (appended and flushed row by row) and
    OUT/operations.json (rewritten atomically), for `lathectl report OUT/operations.json`;
  - teach-in: a new reference (teach-seq) is stored in the taught file atomically (a temporary
    file in the same directory, fsync, rename over it), which lathectl_adaptive reads at load;
  - operator messages: a bad per-operation setting (bad-code), an overload warning, a taught
    reference, through LinuxCNC's operator channels (error_msg / text_msg, as AXIS shows them)
    when a LinuxCNC session runs, and always into the log.

  loadusr -Wn lathectl-oplog lathectl_oplog.py --out DIR [--taught PATH] [--unit N|W]
          [--program FILE] [--line-offset K]

The pins are lathectl_adaptive's outputs of the same names (lathectl.hal nets them). Polls at
200 Hz: an operation shorter than 5 ms between two others may be missed; the log says how many
(op-seq counts every one).
"""

import argparse
import csv
import json
import math
import os
import re
import signal
import sys
import tempfile
import time

import hal

FIELDS = ["seq", "time_s", "tool", "operation", "line", "mode", "limit", "load_mean",
          "load_peak", "load_peak_pct", "feed_min", "feed_mean", "time_in_cut_s", "time_s_line",
          "reasons", "alarm"]
MODES = {1: "off", 2: "adaptive", 3: "teach"}
BAD = {1: "limit is not a number", 2: "limit is negative", 3: "limit above the machine's rating",
       4: "feed bounds invalid (need 0 <= min < max <= rating)", 5: "mode/operation not a valid code",
       6: "percentage of the taught reference out of range", 7: "no taught reference for this tool"
       " and operation (teach it first: M68 E3 Q3)"}
BAD_WORD = {1: ("E0",), 2: ("E0",), 3: ("E0",), 4: ("E1", "E2"), 5: ("E3", "E4"), 6: ("E0",),
            7: ("E3",)}


def reason_table(path):
    """{code: name} and {bit: name} from reasons.json (`lathectl reasons --json`, generated from
    the one reason table in the core and installed beside this script)."""
    try:
        with open(path) as f:
            rows = json.load(f)["reasons"]
    except (OSError, ValueError, KeyError) as e:
        print("lathectl_oplog: %s: %s: reasons are logged as numbers" % (path, e), file=sys.stderr)
        return {}, {}
    return ({r["code"]: r["name"] for r in rows}, {r["bit"]: r["name"] for r in rows})


# The pins read: lathectl_adaptive's outputs of these names (its records, its setting errors and
# the overload warning), with their types from pins.json (`lathectl_hal_pin_docs --json`, made
# from the component's pin table and installed beside this script): one declaration of each pin.
READ = re.compile(r"^(op-.*|teach-.*|bad-(code|line|value)|overload-warn)$")


def read_pins(path):
    """[(name, HAL type)] of lathectl_adaptive's out pins this program reads, from the pin list."""
    kinds = {"s32": hal.HAL_S32, "float": hal.HAL_FLOAT, "bit": hal.HAL_BIT, "u32": hal.HAL_U32}
    with open(path) as f:
        comps = {c["name"]: c for c in json.load(f)["components"]}
    return [(p["name"], kinds[p["type"]]) for p in comps["lathectl_adaptive"]["pins"]
            if p["dir"] == "out" and READ.match(p["name"])]


def reasons_of(mask, by_bit):
    """The names of the reasons set in op-reasons (bit = the reason's position in the table)."""
    mask &= 0xFFFFFFFF  # an s32 pin: bit 31 reads negative
    return [by_bit.get(b, "bit%d" % b) for b in range(32) if mask >> b & 1]


def operation_row(get, seq, time_s, line_offset, by_code, by_bit):
    """The operation log's row of the last finished operation, from the op-* pins (get(name) reads
    one): operations.csv's columns, FIELDS (lathectl_publish sends the same as its event)."""
    limit = get("op-limit")
    alarm = get("op-alarm")
    return {"seq": seq, "time_s": round(time_s, 3), "tool": get("op-tool"),
            "operation": get("op-operation"), "line": get("op-line") - line_offset,
            "mode": MODES.get(get("op-mode"), str(get("op-mode"))), "limit": round(limit, 3),
            "load_mean": round(get("op-load-mean"), 3), "load_peak": round(get("op-load-peak"), 3),
            "load_peak_pct": round(100.0 * get("op-load-peak") / limit, 2) if limit else 0.0,
            "feed_min": round(get("op-feed-min"), 4), "feed_mean": round(get("op-feed-mean"), 4),
            "time_in_cut_s": round(get("op-time-in-cut"), 3), "time_s_line": round(get("op-time"), 3),
            "reasons": " ".join(reasons_of(get("op-reasons"), by_bit)),
            "alarm": by_code.get(alarm, str(alarm)) if alarm else ""}


def atomic_write(path, text):
    d = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=d, prefix="." + os.path.basename(path) + ".")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def read_taught(path):
    """The taught file as {(tool, op): (reference, unit)} (the format lathectl_adaptive reads)."""
    out = {}
    if not path or not os.path.exists(path):
        return out
    import tomllib
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    for t in doc.get("taught", []):
        out[(int(t["tool"]), int(t.get("operation", 0)))] = (float(t["reference"]), t["unit"])
    return out


def taught_text(taught):
    lines = ["# lathectl teach-in references (written by lathectl_oplog; read by",
             "# lathectl_adaptive taught=THIS_FILE at load). One table per tool and operation."]
    for (tool, op), (ref, unit) in sorted(taught.items()):
        lines += ["", "[[taught]]", "tool = %d" % tool, "operation = %d" % op,
                  "reference = %.3f" % ref, 'unit = "%s"' % unit]
    return "\n".join(lines) + "\n"


class Messenger:
    """LinuxCNC's operator channels when a session runs; stderr otherwise."""

    def __init__(self):
        self.cmd = None
        try:
            import linuxcnc
            self.cmd = linuxcnc.command()
        except Exception:
            self.cmd = None

    def _send(self, channel, text):
        print("lathectl_oplog: " + text, file=sys.stderr, flush=True)
        if self.cmd is not None:
            try:
                getattr(self.cmd, channel)(text)
            except Exception:
                pass

    def error(self, text):
        self._send("error_msg", text)

    def text(self, text):
        self._send("text_msg", text)


def source_line(program, line, words, value):
    """Where the program set the bad value: the M67/M68 line with one of `words` (E0, ...) and
    Q equal to `value`. M68 waits for motion, so it follows the line motion was on; M67 takes
    effect with the next move, so it precedes it: the nearest match after, else before."""
    if not program or not os.path.exists(program):
        return ""
    text = open(program, errors="replace").read().splitlines()
    hits = []
    for i, l in enumerate(text):
        code = re.sub(r"\([^)]*\)|;.*", "", l).upper().replace(" ", "")
        m = re.search(r"M6[78](E\d+)Q([-+.\dA-Z\[\]#<>_]+)", code)
        if not m or m.group(1) not in words:
            continue
        try:
            q = float(m.group(2))
        except ValueError:
            q = None  # an expression: any value
        if q is None or (math.isnan(value) or abs(q - value) <= 1e-6 * max(1.0, abs(value))):
            hits.append(i + 1)
    after = [h for h in hits if h >= line]
    before = [h for h in hits if h < line]
    pick = after[0] if after else before[-1] if before else None
    return "line %d: %s" % (pick, text[pick - 1].strip()) if pick else ""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True)
    ap.add_argument("--taught", default="")
    ap.add_argument("--unit", default="N", choices=["N", "W"])
    ap.add_argument("--program", default=os.environ.get("LATHECTL_SIM_SOURCE", ""))
    ap.add_argument("--line-offset", type=int,
                    default=int(os.environ.get("LATHECTL_SIM_LINE_OFFSET", "0")))
    ap.add_argument("--name", default="lathectl-oplog")
    a = ap.parse_args()
    # scripts/linuxcnc-sim: the realtime side reads a staged copy; the user's file is written.
    a.taught = os.environ.get("LATHECTL_SIM_TAUGHT_WRITE") or a.taught
    os.makedirs(a.out, exist_ok=True)
    here = os.path.dirname(os.path.abspath(__file__))
    by_code, by_bit = reason_table(os.path.join(here, "reasons.json"))

    c = hal.component(a.name)
    for name, kind in read_pins(os.path.join(here, "pins.json")):
        c.newpin(name, kind, hal.HAL_IN)
    c.newpin("rows", hal.HAL_S32, hal.HAL_OUT)
    c.newpin("missed", hal.HAL_S32, hal.HAL_OUT)
    c.ready()

    stop = []
    signal.signal(signal.SIGTERM, lambda *_: stop.append(1))
    signal.signal(signal.SIGINT, lambda *_: stop.append(1))
    msg = Messenger()
    taught = read_taught(a.taught)
    csv_path = os.path.join(a.out, "operations.csv")
    json_path = os.path.join(a.out, "operations.json")
    rows, messages, missed = [], [], 0
    fcsv = open(csv_path, "w", newline="")
    w = csv.writer(fcsv)
    w.writerow(FIELDS)
    fcsv.flush()
    t0 = time.monotonic()
    last = {"op": c["op-seq"], "teach": c["teach-seq"], "bad": 0, "warn": False}
    dirty = False
    last_json = 0.0

    def note(kind, text):
        messages.append({"time_s": round(time.monotonic() - t0, 3), "kind": kind, "text": text})

    def write_json():
        doc = {"unit": a.unit, "program": a.program, "rows": rows, "messages": messages,
               "missed_rows": missed, "taught": [
                   {"tool": k[0], "operation": k[1], "reference": v[0], "unit": v[1]}
                   for k, v in sorted(taught.items())]}
        atomic_write(json_path, json.dumps(doc, indent=1) + "\n")

    write_json()
    while not stop:
        seq = c["op-seq"]
        if seq != last["op"]:
            missed += max(0, (seq - last["op"]) - 1)
            last["op"] = seq
            row = operation_row(lambda n: c[n], seq, time.monotonic() - t0, a.line_offset,
                                by_code, by_bit)
            rows.append(row)
            w.writerow([row[k] for k in FIELDS])
            fcsv.flush()
            c["rows"] = len(rows)
            c["missed"] = missed
            dirty = True
        tseq = c["teach-seq"]
        if tseq != last["teach"]:
            last["teach"] = tseq
            key = (c["teach-tool"], c["teach-operation"])
            ref = c["teach-reference"]
            taught[key] = (ref, a.unit)
            if a.taught:
                atomic_write(a.taught, taught_text(taught))
            text = "lathectl: taught tool %d operation %d: reference %.1f %s" % (key + (ref, a.unit))
            msg.text(text)
            note("teach", text)
            dirty = True
        code = c["bad-code"]
        if code != last["bad"]:
            last["bad"] = code
            if code:
                line = c["bad-line"] - a.line_offset
                v = c["bad-value"]
                where = source_line(a.program, line, BAD_WORD.get(code, ("E0",)), v)
                text = "lathectl: %s (%s) near program %s: feed held, not used" % (
                    BAD.get(code, "bad setting %d" % code), "NaN" if math.isnan(v) else "%g" % v,
                    where or "line %d" % line)
                msg.error(text)
                note("bad_setting", text)
                dirty = True
        warn = bool(c["overload-warn"])
        if warn and not last["warn"]:
            text = "lathectl: overload warning, tool %d" % c["op-tool"]
            msg.text(text)
            note("overload_warning", text)
            dirty = True
        last["warn"] = warn
        now = time.monotonic()
        if dirty and now - last_json > 0.5:
            write_json()
            dirty, last_json = False, now
        time.sleep(0.005)
    fcsv.close()
    write_json()


if __name__ == "__main__":
    main()
