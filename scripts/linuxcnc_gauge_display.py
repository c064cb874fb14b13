#!/usr/bin/python3
"""The "display" of a headless system-D LinuxCNC session started by scripts/linuxcnc-sim-gauge.

LinuxCNC starts it (the INI's [DISPLAY]DISPLAY) once HAL is up and stops the session when it
exits. It brings the machine out of estop, turns it on, homes it, runs the program and follows
every part through the HAL pins of lathectl_gauge_plant and lathectl_gauge (polled every 5 ms:
each part lasts seconds and its end state stays until the next part's load): the steps the gauge
operated with their times, the size threshold's crossing, the backstop, alarms, the trip-to-stop
latency, and the finished size (the plant's finished-error-um when the next part is loaded, its
error-um for the last). A feed hold (a sensor alarm) aborts the program after a second, as an
operator would. Writes parts.csv and summary.json into $LATHECTL_SIM_OUT.
"""

import csv
import json
import math
import os
import sys
import time

import hal
import linuxcnc

from linuxcnc_session import Session, reason_names, realtime_threads

G = "lathectl-gauge."
P = "lathectl-gauge-plant."


def stats(errors_um, tol_um):
    n = len(errors_um)
    if n == 0:
        return float("nan"), float("nan"), float("nan"), float("nan")
    mean = sum(errors_um) / n
    sigma = math.sqrt(sum((e - mean) ** 2 for e in errors_um) / (n - 1)) if n > 1 else float("nan")
    if not (sigma > 0):
        return mean, sigma, float("nan"), float("nan")
    cp = 2.0 * tol_um / (6.0 * sigma)
    cpk = min(tol_um - mean, mean + tol_um) / (3.0 * sigma)
    return mean, sigma, cp, cpk


def main():
    program = os.environ["LATHECTL_SIM_PROGRAM"]
    out_dir = os.environ["LATHECTL_SIM_OUT"]
    timeout_s = float(os.environ.get("LATHECTL_SIM_TIMEOUT_S", "600"))
    break_um = os.environ.get("LATHECTL_SIM_BREAK_WIRE_UM", "")
    break_um = float(break_um) if break_um else None
    ses = Session("linuxcnc_gauge_display")
    stat, cmd, errors = ses.stat, ses.cmd, ses.errors
    me = hal.component("lathectl-gauge-display")
    me.ready()
    realtime_threads()
    ses.wait_task()
    ses.start(program)
    thresholds = [hal.get_value(G + "threshold-%d" % i) for i in range(8)]
    thresholds = [t for t in thresholds if t != 0.0]
    progress = None
    if os.environ.get("LATHECTL_SIM_PROGRESS"):
        try:
            progress = open(os.environ["LATHECTL_SIM_PROGRESS"], "w")
        except OSError:
            progress = None

    parts = []
    cur = None  # the part being machined

    def finish(part, error_um):
        part["error_um"] = error_um
        parts.append(part)
        if progress is not None:
            progress.write("linuxcnc-sim: part %d: %+.2f um%s\n" % (
                part["part"], error_um, " (backstop)" if part["backstop"] else ""))
            progress.flush()

    t0 = time.monotonic()
    ses.run()
    idle = 0
    hold_since = None
    aborted = timed_out = broken = False
    while True:
        stat.poll()
        ses.drain()
        now = time.monotonic()
        n = int(hal.get_value(P + "part"))
        if cur is None or n != cur["part"]:
            if cur is not None and cur["part"] > 0 and n > cur["part"]:
                finish(cur, hal.get_value(P + "finished-error-um"))
            cur = {"part": n, "steps": [], "backstop": False, "size": False, "alarm": False,
                   "reason": 0, "trip_to_stop_s": None, "stop_latency_s": None,
                   "unreachable": False, "last_step": 0, "wall_start": now}
        if n > 0:
            step = int(hal.get_value(G + "step"))
            if step > cur["last_step"]:
                cur["steps"].append({"step": step, "time_s": round(hal.get_value(G + "part-time"), 4),
                                     "size_um": round(hal.get_value(P + "size-um"), 3)})
                cur["last_step"] = step
            cur["backstop"] |= bool(hal.get_value(G + "backstop"))
            cur["size"] |= bool(hal.get_value(G + "size"))
            cur["unreachable"] |= bool(hal.get_value(G + "unreachable"))
            cur["bridged"] = cur.get("bridged", False) or bool(hal.get_value(G + "bridged"))
            if hal.get_value(G + "alarm") and not cur["alarm"]:
                cur["alarm"] = True
                cur["reason"] = int(hal.get_value(G + "reason"))
            if hal.get_value(G + "probe"):
                cur["trip_to_stop_s"] = hal.get_value(G + "trip-to-stop")
                cur["stop_latency_s"] = hal.get_value(G + "stop-latency")
                if "wall_to_stop_s" not in cur:
                    # The base thread's clock (its periods counted) against the wall's since the
                    # part was loaded: below 1 when the thread lost periods.
                    cur["wall_to_stop_s"] = round(now - cur["wall_start"], 4)
                    cur["clock_to_stop_s"] = round(hal.get_value(G + "part-time"), 4)
        if (break_um is not None and not broken and n > 0 and
                hal.get_value(P + "size-um") <= break_um):
            hal.set_p(P + "break-wire", "1")  # in-process: the size read next is the break's
            cur["wire_broken_at_um"] = hal.get_value(P + "size-um")
            broken = True
        idle = idle + 1 if ses.program_done() else 0
        if idle >= 40:
            break
        if hal.get_value(G + "feed-hold"):
            hold_since = hold_since or now
            if now - hold_since > 1.0:
                cur["held_size_um"] = hal.get_value(P + "size-um")
                cmd.abort()
                cmd.wait_complete()
                aborted = True
                break
        if now - t0 > timeout_s:
            ses.abort(timeout_s)
            timed_out = True
            break
        time.sleep(0.005)
    wall_s = time.monotonic() - t0
    ses.drain()
    if cur is not None and cur["part"] > 0:
        finish(cur, hal.get_value(P + "error-um"))
    update_ns_max = {"gauge": int(hal.get_value(G + "update-ns-max")),
                     "plant": int(hal.get_value(P + "update-ns-max"))}
    period_error = bool(hal.get_value(G + "period-error")) or bool(
        hal.get_value(P + "period-error"))
    cmd.state(linuxcnc.STATE_OFF)

    import tomllib
    sc = tomllib.load(open(os.environ.get("LATHECTL_SIM_SCENARIO"), "rb"))
    proc = sc.get("process", {})
    tol = proc.get("tolerance_um", 10.0)
    target = proc.get("target_um", 50.0)
    backstop = proc.get("backstop_um", target - tol)
    names = reason_names()
    errs = [p["error_um"] for p in parts]
    mean, sigma, cp, cpk = stats(errs, tol)
    with open(os.path.join(out_dir, "parts.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["part", "error_um", "backstop", "steps", "trip_to_stop_s", "stop_latency_s",
                    "reason"])
        for p in parts:
            w.writerow([p["part"], "%.4f" % p["error_um"], int(p["backstop"]),
                        " ".join("%d@%.3f" % (s["step"], s["time_s"]) for s in p["steps"]),
                        p["trip_to_stop_s"], p["stop_latency_s"], names.get(p["reason"], "")])
    alarms = [{"part": p["part"], "reason_code": p["reason"],
               "reason": names.get(p["reason"], "unknown")} for p in parts if p["alarm"]]
    latencies = [p["trip_to_stop_s"] for p in parts if p["trip_to_stop_s"] is not None and
                 not p["backstop"]]
    # The cycle as `lathectl run`'s summary gives it: each step's threshold, the size it was
    # planned at and where its command operated (here the mean over the parts that reached it).
    seq = sc.get("sequence", {})
    planned = [target + seq.get("fine_um", 60.0), target + seq.get("spark_um", 25.0), target]
    cycle = []
    for i, (name, th) in enumerate(zip(["fine", "spark-out", "size"], thresholds)):
        if i < 2:
            at = [p["steps"][i]["size_um"] for p in parts if len(p["steps"]) > i]
        else:
            at = [target + p["error_um"] for p in parts]
        cycle.append({"step": name, "threshold_V": th, "planned_um": planned[i],
                      "size_um": sum(at) / len(at) if at else float("nan")})
    ir = sc.get("interruption")
    interruption = None
    if ir:
        interruption = {"kind": ir.get("kind", "keyway"), "count": ir.get("count", 1),
                        "depth_um": ir.get("depth_um"), "spindle_rpm": ir.get("spindle_rpm", 600.0),
                        "gate": ir.get("gate", True), "guard_ms": ir.get("guard_ms", 20.0)}
    summary = {
        "program": os.environ.get("LATHECTL_SIM_SOURCE", program),
        "scenario": os.environ.get("LATHECTL_SIM_SCENARIO", ""),
        "finished": not aborted and not errors,
        "aborted_on_feed_hold": aborted,
        "timed_out": timed_out,
        "errors": errors,
        "messages": ses.messages,
        "wall_time_s": round(wall_s, 3),
        "metrics": {
            "parts": len(parts),
            "size_mean_error_um": mean,
            "size_sigma_um": sigma,
            "cp": cp,
            "cpk": cpk,
            "tolerance_um": tol,
            "backstop_um": backstop,
            "backstop_trips": sum(1 for p in parts if p["backstop"]),
            "threshold_V": thresholds[-1] if thresholds else float("nan"),
            "step_thresholds_V": thresholds,
            "part_errors_um": errs,
            "trip_to_stop_s_max": max(latencies) if latencies else None,
            "alarms": alarms,
        },
        "cycle": cycle,
        "interruption": interruption,
        "parts_detail": parts,
        "update_ns_max": update_ns_max,
        "period_error": period_error,
    }
    tmp = os.path.join(out_dir, "summary.json.tmp")
    with open(tmp, "w") as fj:
        json.dump(summary, fj, indent=2, default=lambda v: None)
        fj.write("\n")
    os.replace(tmp, os.path.join(out_dir, "summary.json"))
    if progress is not None:
        progress.write("linuxcnc-sim: %d parts, mean %+.3f um, sigma %.3f um, %d at the backstop "
                       "(%.1f s)\n" % (len(parts), mean, sigma,
                                       summary["metrics"]["backstop_trips"], wall_s))
        progress.close()
    sys.exit(0 if not errors else 1)


if __name__ == "__main__":
    main()
