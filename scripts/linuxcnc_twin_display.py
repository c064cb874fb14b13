#!/usr/bin/python3
"""The "display" of a headless system-B LinuxCNC session started by scripts/linuxcnc-sim-twin.

LinuxCNC starts it (the INI's [DISPLAY]DISPLAY) once HAL is up and stops the session when it
exits. It brings the machine out of estop, turns it on, homes it, runs the program, records the
HAL channels of lathectl-twin.hal with halsampler (one row per servo period), turns the operator's
feed override to VALUE when the program reaches LINE (LATHECTL_SIM_OVERRIDE "LINE=VALUE,..."),
and at the end writes into $LATHECTL_SIM_OUT: signals.csv (the recording) and summary.json (what
the recording measures, under the keys of `lathectl run`'s summary for a system-B scenario where
the quantity is the same, and the session's own: phases, override, the offset's latency).
"""

import json
import math
import os
import subprocess
import sys
import time

import hal
import linuxcnc

from linuxcnc_session import Session, realtime_threads, reason_names

# Recorded channels: sampler.0.pin.N in lathectl-twin.hal's order.
CHANNELS = ["z_mm", "w_mm", "w_eoffset_mm", "w_planned_vel_mm_per_s", "vibration_peak_um", "a0_um",
            "omega_d_Hz", "feed_mm_per_min", "feed_ratio", "eoffset_request_mm", "engaged",
            "reason_code", "S_min_mm_per_min", "dS_mm_per_min", "dl_mm", "n_s", "motion_type",
            "in_contact_right", "in_contact_left", "cut_power_W", "module_on"]
PERIOD_S = 1e-3  # the servo period (lathectl-twin.ini)
M = "lathectl-modfeed."


def col(rows, name):
    i = CHANNELS.index(name)
    return [r[i] for r in rows]


def growth_rate(t, a, lo, hi):
    """Least-squares slope of ln a over t where lo ≤ a ≤ hi [1/s]: the chatter's exponential
    growth rate while the loop is linear (a property of the set-up, not of when it started)."""
    pts = [(ti, math.log(ai)) for ti, ai in zip(t, a) if lo <= ai <= hi]
    if len(pts) < 50:
        return None
    n = len(pts)
    mt = sum(p[0] for p in pts) / n
    ml = sum(p[1] for p in pts) / n
    sxx = sum((p[0] - mt) ** 2 for p in pts)
    return sum((p[0] - mt) * (p[1] - ml) for p in pts) / sxx if sxx > 0 else None


def envelope(peak, every=20):
    """The vibration's envelope: the largest per-period peak over `every` periods (20 ms: more than
    four cycles of the chatter), one value per period."""
    out = []
    for i in range(len(peak)):
        out.append(max(peak[max(0, i - every + 1):i + 1]))
    return out


def measure(rows):
    """The session's metrics from the recording. The phases: contact (either tool in the part),
    the module on (digital-out-01) and engaged, the module off in the cut. Sources of the
    definitions: src/systems/b_chatter/metrics.hpp (the rig's: peak |y_highpass| for the
    amplitude, the turrets' mean feed over the cut); the windows here are aligned on the events
    the session shows (engagement, the module switched off), since a shorter cut than the rig's
    has no steady last 30 %."""
    n = len(rows)
    t = [k * PERIOD_S for k in range(n)]
    contact = [r[CHANNELS.index("in_contact_right")] or r[CHANNELS.index("in_contact_left")]
               for r in rows]
    on = col(rows, "module_on")
    eng = col(rows, "engaged")
    z, w = col(rows, "z_mm"), col(rows, "w_mm")
    peak = col(rows, "vibration_peak_um")
    env = envelope(peak)
    cut = [k for k in range(n) if contact[k]]
    if not cut:
        return {"error": "the tools never reached the part"}
    k0, k1 = cut[0], cut[-1]
    engaged = [k for k in range(k0, k1 + 1) if eng[k]]
    off = [k for k in range(k0, k1 + 1) if not on[k]]
    ke = engaged[0] if engaged else None
    koff = off[0] if off else None
    res = {"contact_at_s": t[k0], "cut_end_s": t[k1]}
    # The module on: the feeds over whole staircase cycles are the mean feeds (the program's
    # for the left turret whatever the right one does).
    def feed(pos, a, b):
        return abs(pos[b] - pos[a]) / (t[b] - t[a]) * 60.0 if b > a else None
    prog = None
    for k in range(k0, k1):
        if rows[k][CHANNELS.index("motion_type")] in (2, 3):
            prog = abs(rows[k][CHANNELS.index("w_planned_vel_mm_per_s")]) * 60.0
            break
    end_on = (koff if koff is not None else k1) - 1
    # The operator's override: the feed periods of the cut where W's planned speed is off the
    # program's by more than 3 % (LinuxCNC's override scales the planned speed of every axis).
    wpv = col(rows, "w_planned_vel_mm_per_s")
    mt = col(rows, "motion_type")
    ov = [k for k in range(k0 + 100, k1) if mt[k] in (2, 3) and prog and
          abs(abs(wpv[k]) * 60.0 / prog - 1.0) > 0.03]
    a_end = end_on
    runs = []
    for k in ov:  # contiguous stretches (the longest is the override's; the others are ramps)
        if runs and k - runs[-1][1] <= 50:
            runs[-1][1] = k
        else:
            runs.append([k, k])
    runs = [r for r in runs if r[1] - r[0] >= 300]  # the override's: 0.3 s at least
    if runs:
        a, b = max(runs, key=lambda r: r[1] - r[0])
        mid = range(a + 100, b - 100)
        res["override"] = {
            "from_s": t[a], "to_s": t[b],
            "factor": sum(abs(wpv[k]) for k in mid) * 60.0 / prog / len(mid),
            "left_mm_per_min": feed(z, mid[0], mid[-1]),
            "right_planned_mm_per_min": sum(abs(wpv[k]) for k in mid) * 60.0 / len(mid)}
        a_end = min(end_on, a - 1)
    res["mean_feed_mm_per_min"] = {
        "programmed": prog, "left": feed(z, k0 + 100, a_end), "right": feed(w, k0 + 100, a_end),
        "window_s": [t[k0 + 100], t[a_end]]}
    modulation = {"engaged": ke is not None}
    if ke is not None:
        last = rows[end_on]
        modulation.update({
            "engaged_at_s": t[ke], "engaged_after_contact_s": t[ke] - t[k0],
            "S_min_mm_per_min": last[CHANNELS.index("S_min_mm_per_min")],
            "dS_mm_per_min": last[CHANNELS.index("dS_mm_per_min")],
            "dl_mm": last[CHANNELS.index("dl_mm")], "n_s": int(last[CHANNELS.index("n_s")]),
            "reason": reason_names().get(int(last[CHANNELS.index("reason_code")]), "unknown"),
            "a0_at_engaging_um": rows[ke][CHANNELS.index("a0_um")]})
        levels = col(rows[ke:end_on], "feed_mm_per_min")
        modulation["S_max_mm_per_min"] = max(levels) if levels else None
    res["modulation"] = modulation
    # Amplitudes: with the module, 2 to 3 s after it engaged (peak |y_highpass|); without it,
    # the envelope's growth rate before the module engaged and after it was switched off, and
    # the amplitude the chatter reached when the cut ended.
    vib = {}
    if ke is not None and ke + 3000 <= end_on:
        vib["with"] = max(peak[ke + 2000:ke + 3000])
        vib["with_window_s"] = [t[ke + 2000], t[ke + 3000]]
    if koff is not None:
        vib["without"] = max(peak[max(koff, k1 - 200):k1 + 1])
        vib["without_at_s"] = t[k1]
    res["vibration_amplitude_um"] = vib
    res["growth_rate_per_s"] = {
        "before_engaging": growth_rate(t[k0:ke or k1], env[k0:ke or k1], 0.3, 4.0),
        "module_off": growth_rate(t[koff:k1] if koff else [], env[koff:k1] if koff else [],
                                  1.0, 300.0)}
    # Detector 20 (5 Hz resolution) while ADC 19 reads the chatter: the median.
    f = sorted(r[CHANNELS.index("omega_d_Hz")] for r in rows[k0:k1 + 1]
               if r[CHANNELS.index("a0_um")] > 0 and r[CHANNELS.index("omega_d_Hz")] > 0)
    res["chatter_frequency_Hz"] = f[len(f) // 2] if f else None
    res["cutting_power_W"] = {"measured": sum(col(rows[k0 + 500:end_on], "cut_power_W")) /
                              max(1, end_on - k0 - 500)}
    # The left turret, untouched: the program moves Z and W alike, so Z stands where W's plan
    # is — W's position less the offset motion applied — in every servo period of the cut
    # (measured: the joints' feedback carries axis.w.eoffset as the pin read three periods
    # earlier).
    eo = col(rows, "w_eoffset_mm")
    gap = [abs(z[k] - (w[k] - eo[k - 3])) for k in range(max(k0, 3), k1 + 1)]
    res["left_turret_max_gap_to_plan_mm"] = max(gap) if gap else None
    # The offset: W's speed against its planned speed × S/S_p; the latency of a feed step (the
    # module's new S/S_p → W's speed within 10 % of the new level, from the step's row).
    ratio = col(rows, "feed_ratio")
    lat = []
    for k in range(max(k0, 1), end_on - 50):
        dr = ratio[k] - ratio[k - 1]
        if abs(dr) < 0.05 or not eng[k]:
            continue
        target = abs(wpv[k]) * ratio[k]
        step = abs(wpv[k]) * abs(dr)
        for j in range(k, k + 50):
            v = abs(w[j + 1] - w[j]) / PERIOD_S
            if abs(v - target) <= 0.1 * step:
                lat.append((j + 1 - k) * PERIOD_S * 1e3)
                break
        else:
            lat.append(None)
    got = sorted(x for x in lat if x is not None)
    # The programmed variant (reason modulation_programmed, 53) in feed blocks: the levels the
    # module ran, the share of the settled periods (15 ms after a step) where the flagged axis
    # ran at the level, and the other axis's speed. In b_twin_feed.ngc the left turret (Z) is
    # flagged: Z runs the staircase, W the program's feed.
    code = col(rows, "reason_code")
    feedc = col(rows, "feed_mm_per_min")
    pr = [k for k in range(1, n - 1) if int(code[k]) == 53 and mt[k] in (2, 3)]
    if len(pr) > 100:
        mid = pr[50:-50]
        vz = {k: abs(z[k + 1] - z[k]) / PERIOD_S * 60.0 for k in mid}
        vw = {k: abs(w[k + 1] - w[k]) / PERIOD_S * 60.0 for k in mid}
        settled = [k for k in mid if all(feedc[j] == feedc[k] for j in range(k - 15, k + 1))]
        on_level = [k for k in settled if abs(vz[k] - feedc[k]) <= 1.0]
        last = rows[pr[-1]]
        res["programmed"] = {
            "from_s": t[pr[0]], "to_s": t[pr[-1]],
            "plan": [last[CHANNELS.index("S_min_mm_per_min")],
                     last[CHANNELS.index("dS_mm_per_min")], last[CHANNELS.index("dl_mm")],
                     int(last[CHANNELS.index("n_s")])],
            "levels_mm_per_min": sorted({round(feedc[k], 3) for k in pr}),
            "left_on_level_share": len(on_level) / len(settled) if settled else None,
            "left_mean_mm_per_min": feed(z, mid[0], mid[-1]),
            "right_speed_mm_per_min": [min(vw.values()), max(vw.values())]}
    res["eoffset"] = {
        "feed_steps": len(lat), "steps_settled": len(got),
        "latency_ms": {"median": got[len(got) // 2] if got else None,
                       "max": got[-1] if got else None},
        "max_abs_mm": max(abs(x) for x in eo), "at_cut_end_mm": eo[k1],
        "at_end_mm": eo[-1], "left_at_end_mm": z[-1] - w[-1]}
    return res


def main():
    program = os.environ["LATHECTL_SIM_PROGRAM"]
    out_dir = os.environ["LATHECTL_SIM_OUT"]
    timeout_s = float(os.environ.get("LATHECTL_SIM_TIMEOUT_S", "120"))
    overrides = {}
    for item in filter(None, os.environ.get("LATHECTL_SIM_OVERRIDE", "").split(",")):
        line, value = item.split("=")
        overrides[int(line)] = float(value)
    raw_path = os.path.join(out_dir, "signals.raw")
    ses = Session("linuxcnc_twin_display")
    stat, cmd = ses.stat, ses.cmd
    me = hal.component("lathectl-twin-display")
    me.newpin("record", hal.HAL_BIT, hal.HAL_OUT)
    me.ready()
    subprocess.run(["halcmd", "net", "lathectl-twin-record", "lathectl-twin-display.record",
                    "sampler.0.enable"], check=True)
    realtime_threads()
    ses.wait_task()
    ses.start(program)
    override_log, current = [], None
    with open(raw_path, "w") as raw:
        sampler = subprocess.Popen(["halsampler", "-t"], stdout=raw)
        me["record"] = 1
        t0 = time.monotonic()
        ses.run()
        idle, timed_out, snapshot = 0, False, None
        while True:
            stat.poll()
            ses.drain()
            line = stat.motion_line
            if line in overrides and (current is None or current["line"] != line):
                cmd.feedrate(overrides[line])
                current = {"line": line, "value": overrides[line],
                           "from_s": round(time.monotonic() - t0, 3)}
                override_log.append(current)
            elif current is not None and line != current["line"] and current["value"] != 1.0:
                cmd.feedrate(1.0)
                current["to_s"] = round(time.monotonic() - t0, 3)
                current = {"line": line, "value": 1.0,
                           "from_s": round(time.monotonic() - t0, 3)}
            if snapshot is None and abs(hal.get_value("axis.w.eoffset")) > 0.05:
                # whether motion's axis command carries the offset (lathectl-twin.hal subtracts it)
                snapshot = {k: hal.get_value(k) for k in (
                    "axis.w.pos-cmd", "axis.w.eoffset", "joint.3.pos-cmd", "joint.3.pos-fb")}
            idle = idle + 1 if ses.program_done() else 0
            if idle >= 40:
                break
            if time.monotonic() - t0 > timeout_s:
                ses.abort(timeout_s)
                timed_out = True
                break
            time.sleep(0.005)
        wall_s = time.monotonic() - t0
        time.sleep(0.1)
        me["record"] = 0
        time.sleep(0.3)  # let halsampler drain the FIFO
        sampler.terminate()
        sampler.wait()
    overruns = int(hal.get_value("sampler.0.overruns"))
    session = {"program_wall_s": round(wall_s, 3), "timed_out": timed_out,
               "sampler_overruns": overruns,
               "update_ns_max": {"modfeed": int(hal.get_value(M + "update-ns-max")),
                                 "chatter": int(hal.get_value("lathectl-chatter.update-ns-max"))},
               "plans": {"inline": int(hal.get_value(M + "plans-inline")),
                         "taken": int(hal.get_value(M + "plans-taken")),
                         "made": int(hal.get_value(M + "plans-made"))},
               "eoffset_snapshot": snapshot,
               "errors": ses.errors, "messages": ses.messages}
    ses.drain()
    cmd.state(linuxcnc.STATE_OFF)

    rows = []
    with open(raw_path) as f:
        for line in f:
            v = line.split()
            if len(v) == len(CHANNELS) + 1:
                rows.append([float(x) for x in v[1:]])
    os.remove(raw_path)
    with open(os.path.join(out_dir, "signals.csv"), "w") as f:
        f.write("time_s," + ",".join(CHANNELS) + "\n")
        for k, r in enumerate(rows):
            f.write("%.3f," % (k * PERIOD_S) + ",".join("%.10g" % x for x in r) + "\n")
    session["override_commands"] = override_log
    summary = {"source": "linuxcnc", "session": session}
    summary.update(measure(rows) if rows else {"error": "nothing recorded"})
    with open(os.path.join(out_dir, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    sys.exit(0 if not ses.errors and not timed_out else 1)


if __name__ == "__main__":
    main()
