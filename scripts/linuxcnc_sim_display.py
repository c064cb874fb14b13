#!/usr/bin/python3
"""The "display" of a headless LinuxCNC session started by scripts/linuxcnc-sim.

LinuxCNC starts it (the INI's [DISPLAY]DISPLAY) once HAL is up and stops the session when it
exits, returning its exit code. It brings the machine out of estop, turns it on, homes it, runs
the program, records the HAL signals with halsampler (the config's sampler.0), and writes
signals.csv and summary.json into $LATHECTL_SIM_OUT. A latched controller alarm holds the feed
(motion.feed-inhibit): the run then aborts the program after a second of hold, as an operator
would, and reports the alarm.

With LATHECTL_SIM_GUI=1 (linuxcnc-sim --gui) it first starts AXIS on the same INI ($DISPLAY:
an X server, Xvfb in the tests) with the operator panel (PyVCP, [HAL]POSTGUI_HALFILE), waits
until the panel is wired, runs the program as above while AXIS shows it, and closes AXIS at the end.
"""

import csv
import json
import math
import os
import subprocess
import sys
import time

import hal
import linuxcnc

from linuxcnc_session import Session, exec_state, reason_names, realtime_threads

# Recorded channels: sampler.0.pin.N in lathectl.hal's order.
CHANNELS = [
    ("x_mm", float), ("z_mm", float), ("spindle_rpm", float), ("current_vel_mm_per_s", float),
    ("requested_vel_mm_per_s", float), ("adaptive_feed", float), ("motion_type", int),
    ("force", float), ("force_true", float), ("depth_mm", float),
    ("feed_per_rev_mm", float), ("feed_per_rev_cmd_mm", float), ("cutting_speed_m_per_min", float),
    ("spindle_rpm_cmd", float), ("feed_hold", int), ("alarm", int),
    ("reason", int), ("alarm_reason", int), ("in_cut", int), ("program_line", int),
    ("update_ns", int), ("load", float), ("limit", float), ("cut_power_W", float),
    ("spindle_power_W", float), ("idle_power_W", float), ("idle_power_true_W", float),
    ("tool", int), ("bad_setting", int), ("teaching", int), ("in_contact", int),
    ("limit_cmd", float), ("operator_override", float), ("feed_override", float),
    ("feed_override_in_motion", float), ("feed_factor", float),
]
CHANNELS_0 = 21  # sampler.0's pins; the rest are sampler.1's


RAW = []  # the raw recording: never left behind
GUI = [True] if os.environ.get("LATHECTL_SIM_GUI") == "1" else []  # then AXIS's process


def close_gui():
    """AXIS goes with the display, however it ends (LinuxCNC waits for it otherwise)."""
    for g in GUI[1:]:
        g.terminate()
        try:
            g.wait(10)
        except subprocess.TimeoutExpired:
            g.kill()
            g.wait()


def remove_raw():
    for r in RAW:
        if os.path.exists(r):
            os.remove(r)


def main():
    program = os.environ["LATHECTL_SIM_PROGRAM"]
    out_dir = os.environ["LATHECTL_SIM_OUT"]
    timeout_s = float(os.environ.get("LATHECTL_SIM_TIMEOUT_S", "600"))
    period_s = 1e-3  # [EMCMOT]SERVO_PERIOD of the sample config
    ses = Session("linuxcnc_sim_display", on_fail=remove_raw)
    stat, cmd, errors = ses.stat, ses.cmd, ses.errors
    me = hal.component("lathectl-sim-display")  # hal.set_p/get_value need a component
    realtime_threads()
    me.newpin("record", hal.HAL_BIT, hal.HAL_OUT)
    me.ready()
    if GUI:
        ini = sys.argv[sys.argv.index("-ini") + 1]
        # AXIS opens a file of its own at start (its splash program): give it ours.
        GUI.append(subprocess.Popen(["axis", "-ini", ini, program], env=dict(
            os.environ, DISPLAY=os.environ.get("LATHECTL_SIM_X_DISPLAY", ""))))
        gui = GUI[1]
        end = time.monotonic() + 60
        while True:  # the panel's last net (lathectl-panel.hal): AXIS has run the postgui file
            shown = subprocess.run(["halcmd", "-s", "show", "pin", "pyvcp.teach-reference"],
                                   capture_output=True, text=True).stdout
            if "<==" in shown:
                break
            if gui.poll() is not None or time.monotonic() > end:
                ses.fail("AXIS with the operator panel did not come up (exit %s)" % gui.poll())
            time.sleep(0.2)
    # Both samplers start in the same servo period (their sample numbers then match).
    subprocess.run(["halcmd", "net", "lathectl-sim-record", "lathectl-sim-display.record",
                    "sampler.0.enable", "sampler.1.enable"], check=True)
    ses.wait_task()
    # Above the program's feed (lathectl-above.hal): halui sends the component's first feed scale
    # as soon as it is wired: let that command through before ours, one client at a time.
    end = time.monotonic() + 10
    while os.environ.get("LATHECTL_SIM_ABOVE") == "1" and abs(hal.get_value("lathectl-adaptive.feed-override-in-motion") -
              hal.get_value("lathectl-adaptive.feed-override")) > 1e-9:
        if time.monotonic() > end:
            ses.fail("halui did not apply the first feed scale")
        time.sleep(0.02)
    ses.start(program)

    csv_raw = os.path.join(out_dir, "signals.raw")
    csv_raw1 = os.path.join(out_dir, "signals1.raw")
    RAW.extend([csv_raw, csv_raw1])
    with open(csv_raw, "w") as raw, open(csv_raw1, "w") as raw1:
        sampler = subprocess.Popen(["halsampler", "-t"], stdout=raw)
        sampler1 = subprocess.Popen(["halsampler", "-t", "-c", "1"], stdout=raw1)
        me["record"] = 1
        t0 = time.monotonic()
        cmd.auto(linuxcnc.AUTO_RUN, 0)
        if GUI:  # AXIS may still be opening the program when we run it: then once more
            for _ in range(5):
                end = time.monotonic() + 3
                while time.monotonic() < end:
                    stat.poll()
                    if stat.interp_state != linuxcnc.INTERP_IDLE:
                        break
                    time.sleep(0.02)
                if stat.interp_state != linuxcnc.INTERP_IDLE:
                    break
                cmd.mode(linuxcnc.MODE_AUTO)
                cmd.wait_complete()
                cmd.program_open(program)
                cmd.wait_complete()
                cmd.auto(linuxcnc.AUTO_RUN, 0)
        ses.wait(lambda s: s.interp_state != linuxcnc.INTERP_IDLE, 30, "program start",
                 say_errors=True)
        hold_since = None
        aborted = timed_out = task_exited = False
        # LinuxCNC's task process: gone in the middle of a program when LinuxCNC's standalone
        # rs274 ran as the same user (2.9 ≤ 2.9.10: it truncates $HOME/.tool.mmap, the session's
        # tool table, and milltask dies of SIGBUS; LinuxCNC pull request 4385). Without it the
        # status stays frozen at its last value, so it is watched directly.
        try:
            task_pids = [int(p) for p in subprocess.run(["pidof", "milltask"], capture_output=True,
                                                        text=True).stdout.split()]
        except (OSError, ValueError):
            task_pids = []
        next_task_check = time.monotonic() + 0.5
        progress = None
        if os.environ.get("LATHECTL_SIM_PROGRESS"):
            try:
                progress = open(os.environ["LATHECTL_SIM_PROGRESS"], "w")
            except OSError:
                progress = None
        next_progress = t0 + 5.0
        idle = 0
        # --override: the operator's knob turned when the program reaches a line.
        line_offset = int(os.environ.get("LATHECTL_SIM_LINE_OFFSET", "0"))
        knob = sorted((int(a), float(b)) for a, b in (
            kv.split("=") for kv in os.environ.get("LATHECTL_SIM_OVERRIDE", "").split(",") if kv))
        while True:
            stat.poll()
            ses.drain()
            # The end: idle for 0.2 s (a tool change can show idle with nothing queued for a poll;
            # seen once on a loaded machine: a run "finished" at T2 M6).
            idle = idle + 1 if (stat.interp_state == linuxcnc.INTERP_IDLE and stat.queue == 0 and
                                stat.exec_state == linuxcnc.EXEC_DONE) else 0
            if idle >= 20:
                break
            while knob and stat.motion_line - line_offset >= knob[0][0]:
                # With the panel (--gui) the knob is its scale (moved through its param pin, as
                # the operator's hand would); headless, the signal itself.
                value = str(knob.pop(0)[1])
                subprocess.run(["halcmd", "setp", "pyvcp.scale.0.param_pin", value] if GUI else
                               ["halcmd", "sets", "operator-override", value], check=True)
            if hal.get_value("lathectl-adaptive.feed-hold"):
                hold_since = hold_since or time.monotonic()
                if time.monotonic() - hold_since > 1.0:
                    cmd.abort()
                    cmd.wait_complete()
                    aborted = True
                    break
            if task_pids and time.monotonic() >= next_task_check:
                next_task_check += 0.5
                if not any(os.path.exists("/proc/%d" % p) for p in task_pids):
                    task_exited = True
                    errors.append("LinuxCNC's task process (milltask) exited during the program "
                                  "(motion line %d); the run is incomplete (was LinuxCNC's "
                                  "rs274 run as this user meanwhile? it truncates "
                                  "$HOME/.tool.mmap)" % (stat.motion_line - line_offset))
                    break
            if time.monotonic() - t0 > timeout_s:
                # Where LinuxCNC waits, before the abort clears it.
                state = "interp %s, exec %s, queue %s, motion line %s, current line %s" % (
                    stat.interp_state, exec_state(stat.exec_state), stat.queue, stat.motion_line,
                    stat.current_line)
                cmd.abort()
                cmd.wait_complete()
                timed_out = True
                errors.append("program still running after %g s (--timeout): aborted (%s)"
                              % (timeout_s, state))
                break
            if progress is not None and time.monotonic() >= next_progress:
                next_progress += 5.0
                progress.write("linuxcnc-sim: %5.0f s  line %d  tool %d  load %.0f / %.0f  "
                               "feed x%.2f%s\n" % (
                                   time.monotonic() - t0,
                                   stat.motion_line - line_offset,
                                   stat.tool_in_spindle,
                                   hal.get_value("lathectl-adaptive.load"),
                                   hal.get_value("lathectl-adaptive.limit"),
                                   hal.get_value("lathectl-adaptive.feed-factor"),
                                   "  HOLD" if hal.get_value("lathectl-adaptive.feed-hold") else ""))
                progress.flush()
            time.sleep(0.01)
        wall_s = time.monotonic() - t0
        time.sleep(0.1)
        me["record"] = 0
        time.sleep(0.3)  # let halsampler drain the FIFO
        for p in (sampler, sampler1):
            p.terminate()
            p.wait()
        overruns = int(hal.get_value("sampler.0.overruns")) + int(
            hal.get_value("sampler.1.overruns"))
        update_ns_max = int(hal.get_value("lathectl-adaptive.update-ns-max"))
        plant_ns_max = int(hal.get_value("lathectl-plant.update-ns-max"))
        force_limit = float(hal.get_value("lathectl-adaptive.force-limit"))
        # The per-revolution peak, as lathectl run reports it (the plant's control::PerRevolutionPeak
        # over feed moves).
        force_rev_peak = float(hal.get_value("lathectl-plant.force-rev-peak"))
        max_override = float(hal.get_value("lathectl-adaptive.max-feed-override"))
        # The idle tare the controller learned (sensor=power) and the plant's true warm-up state.
        idle_tare = {"p0_W": hal.get_value("lathectl-adaptive.idle-p0"),
                     "p1_W_per_rpm": hal.get_value("lathectl-adaptive.idle-p1"),
                     "p2_W_per_rpm2": hal.get_value("lathectl-adaptive.idle-p2"),
                     "plant_drift_factor": hal.get_value("lathectl-plant.idle-drift-factor")}
    ses.drain()
    cmd.state(linuxcnc.STATE_OFF)

    rows = []
    second = {}
    with open(csv_raw1) as raw1:
        for line in raw1:
            f = line.split()
            if len(f) == len(CHANNELS) - CHANNELS_0 + 1:
                second[int(f[0])] = f[1:]
    with open(csv_raw) as raw:
        for line in raw:
            f = line.split()
            if len(f) != CHANNELS_0 + 1 or int(f[0]) not in second:
                continue
            f = f + second[int(f[0])]
            rows.append([int(f[0])] + [conv(v) if conv is int else float(v)
                                       for (name, conv), v in zip(CHANNELS, f[1:])])
    os.remove(csv_raw)
    os.remove(csv_raw1)
    if not rows:
        ses.fail("nothing recorded")
    n0 = rows[0][0]
    tmp = os.path.join(out_dir, "signals.csv.tmp")
    with open(tmp, "w", newline="") as fcsv:
        w = csv.writer(fcsv)
        w.writerow(["time_s"] + [c for c, _ in CHANNELS])
        for r in rows:
            w.writerow(["%.3f" % ((r[0] - n0) * period_s)] + r[1:])
    os.replace(tmp, os.path.join(out_dir, "signals.csv"))

    idx = {c: i + 1 for i, (c, _) in enumerate(CHANNELS)}
    finite = [r[idx["force_true"]] for r in rows if math.isfinite(r[idx["force_true"]])]
    feed_rows = [r for r in rows if r[idx["motion_type"]] in (2, 3)]
    feed_forces = [r[idx["force_true"]] for r in feed_rows if math.isfinite(r[idx["force_true"]])]
    # Rapids through material: the adaptive feed does not act on them (motion-type 1).
    rapid_cut = [r for r in rows if r[idx["motion_type"]] == 1 and r[idx["force_true"]] > 0.0]
    alarms, last = [], 0
    for r in rows:
        a = r[idx["alarm_reason"]]
        if r[idx["alarm"]] and a != last:
            alarms.append({"time_s": round((r[0] - n0) * period_s, 3), "reason_code": a})
        last = a if r[idx["alarm"]] else 0
    for a in alarms:
        a["reason"] = reason_names().get(a["reason_code"], "unknown")
    summary = {
        "program": os.environ.get("LATHECTL_SIM_SOURCE", program),
        "scenario": os.environ.get("LATHECTL_SIM_SCENARIO", ""),
        "finished": not aborted and not errors,
        "aborted_on_feed_hold": aborted,
        "timed_out": timed_out,
        "task_exited": task_exited,
        "errors": errors,
        "cycle_time_s": round(len(rows) * period_s, 3),
        "wall_time_s": round(wall_s, 3),
        "samples": len(rows),
        "sampler_overruns": overruns,
        "force_peak_N": max(finite) if finite else 0.0,
        "force_peak_in_feed_N": max(feed_forces) if feed_forces else 0.0,
        "force_limit_N": force_limit,
        "force_peak_rev_mean_N": force_rev_peak,
        "force_overshoot_pct": 100.0 * (force_rev_peak - force_limit) / force_limit
        if force_limit > 0.0 else 0.0,
        "rapid_in_material_s": round(len(rapid_cut) * period_s, 3),
        "force_peak_in_rapid_N": max((r[idx["force_true"]] for r in rapid_cut), default=0.0),
        "adaptive_feed_min": min(r[idx["adaptive_feed"]] for r in feed_rows) if feed_rows else 1.0,
        # The net override of the program's feed (operator's knob × the controller's factor).
        "feed_factor_max": max((r[idx["feed_factor"]] for r in feed_rows), default=1.0),
        "max_feed_override": max_override,
        "alarms": alarms,
        "update_ns_max_adaptive": update_ns_max,
        "update_ns_max_plant": plant_ns_max,
        "idle_tare": idle_tare,
    }
    tmp = os.path.join(out_dir, "summary.json.tmp")
    with open(tmp, "w") as fj:
        json.dump(summary, fj, indent=2)
        fj.write("\n")
    os.replace(tmp, os.path.join(out_dir, "summary.json"))
    if progress is not None:
        progress.write("linuxcnc-sim: %s after %.1f s of program; %s\n" % (
            "timed out" if timed_out else "held and aborted" if aborted else "finished",
            wall_s, out_dir))
        progress.close()
    sys.exit(0 if not errors else 1)


if __name__ == "__main__":
    try:
        main()
    finally:
        close_gui()
