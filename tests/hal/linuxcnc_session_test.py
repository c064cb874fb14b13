#!/usr/bin/python3
"""Full LinuxCNC session: the sample config headless (scripts/linuxcnc-sim), homing, a straight
turn over an allowance step with M52 P1, lathectl_plant and lathectl_adaptive in HAL. Asserts
from the recorded HAL signals that

  - where the allowance grows (the 44 mm collar) the force is held at its limit by lowering
    motion.adaptive-feed,
  - where it falls again the feed returns to the program's (adaptive-feed 1),
  - an injected sensor fault (NaN) holds the feed (feed-inhibit, adaptive-feed 0, motion stops)
    with a latched alarm sensor_not_finite, the spindle still turning.

and that the same scenario in `lathectl run` (rig E: the same controller object code, its own
feed-axis and spindle models and a point-tool stock model) gives the same response:

  steady force means within 1 % of the limit, feed per revolution within 2 %, spindle speed
  within 1 %, time over the pass within 2 %; the collar's entry peak within 5 %, located
  within the nose radius + 0.2 mm (the round nose meets the shoulder r_n earlier than the
  rig's point tool), and the force settled within 5 % of the limit in the same travel after
  the peak ± 0.2 mm; the per-revolution peak (summary's force_peak_rev_mean_N, the same rule)
  within 2 % of the limit, and within 5 % above the limit (the collar is in the stock model).

  linuxcnc_session_test.py SOURCE_DIR WORK_DIR [LATHECTL_BINARY]
"""

import csv
import json
import math
import os
import subprocess
import sys
import tomllib

from reasons import REASON  # the reason codes by name, from hal/reasons.json
from shop_broker import ShopRun  # a broker, a subscriber, SHDR clients (issue 46)

FAILS = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


def run(src, work, scenario, name, shop_run=None):
    """One session (with shop_run, publishing to its broker and SHDR port: shop_broker)."""
    out = os.path.join(work, name)
    p = subprocess.run([os.path.join(src, "scripts/linuxcnc-sim"),
                        os.path.join(src, "examples/linuxcnc/step_allowance.ngc"),
                        os.path.join(src, "examples/linuxcnc", scenario), "--out", out,
                        "--timeout", "120"] + (shop_run.args() if shop_run else []),
                       capture_output=True, text=True, timeout=300)
    if shop_run:
        shop_run.finish()
        if p.returncode == 0:
            shop_run.report(check, out)
    if p.returncode != 0:
        print(p.stdout + p.stderr)
        check(False, name + ": linuxcnc-sim ran")
        return None, None
    summary = json.load(open(os.path.join(out, "summary.json")))
    rows = []
    with open(os.path.join(out, "signals.csv")) as f:
        for r in csv.DictReader(f):
            rows.append({k: float(v) for k, v in r.items()})
    return summary, rows


def mean(v):
    return sum(v) / len(v) if v else float("nan")


def in_feed(rows, z_hi, z_lo):
    return [r for r in rows if r["motion_type"] == 2 and z_lo <= r["z_mm"] <= z_hi]


def compare_with_rig(src, work, lathectl, lcnc, limit, nose_mm, peak_rev):
    """LinuxCNC's recording against `lathectl run` of the same scenario, along the stock z."""
    out = os.path.join(work, "rig")
    p = subprocess.run([lathectl, "run", os.path.join(src, "examples/linuxcnc/step_allowance.toml"),
                        "--out", out], capture_output=True, text=True, timeout=300)
    if p.returncode != 0:
        print(p.stdout + p.stderr)
        check(False, "rig: lathectl run ran")
        return
    rig = []
    with open(os.path.join(out, "channels.csv")) as f:
        for r in csv.DictReader(f):
            r = {k: float(v) for k, v in r.items()}
            if r["pass"] == 0:
                rig.append(r)
    cut = [dict(r, zs=-r["z_mm"]) for r in lcnc if r["motion_type"] == 2]
    a_of = lambda lo, hi: [r for r in cut if lo <= r["zs"] <= hi]
    b_of = lambda lo, hi: [r for r in rig if lo <= r["z_mm"] <= hi]
    report = {}
    # ("before" ends 2 mm short of the collar: the feed-forward from the stock model lowers the
    # feed from the nose radius + 1.5 revolutions at the highest feed before it, z 13.3)
    for name, lo, hi in [("before", 9.0, 13.0), ("collar", 19.0, 29.0), ("after", 38.0, 48.0)]:
        a, b = a_of(lo, hi), b_of(lo, hi)
        fa, fb = mean([r["force_true"] for r in a]), mean([r["force_parameter_true"] for r in b])
        sa, sb = mean([r["feed_per_rev_cmd_mm"] for r in a]), mean([r["feed_cmd_mm_per_rev"] for r in b])
        na, nb = mean([r["spindle_rpm"] for r in a]), mean([r["spindle_rpm"] for r in b])
        report[name] = {"force_N": [fa, fb], "feed_mm_per_rev": [sa, sb], "rpm": [na, nb]}
        check(abs(fa - fb) < 0.01 * limit,
              "rig vs LinuxCNC, %s: force %.1f / %.1f N (±1 %% of the limit)" % (name, fb, fa))
        check(abs(sa - sb) < 0.02 * sb,
              "rig vs LinuxCNC, %s: feed %.4f / %.4f mm/rev (±2 %%)" % (name, sb, sa))
        check(abs(na - nb) < 0.01 * nb,
              "rig vs LinuxCNC, %s: spindle %.1f / %.1f rpm (±1 %%)" % (name, nb, na))
    # From the first contact to the pass's end at z 50: the plant's round nose (0.8 mm) meets the
    # face 0.8 mm before the rig's tool point does, so the entry's slow ramp starts 0.8 mm earlier
    # along z (0.3 s ahead at z 0). (Until the plant stopped cutting a groove at machine Z0 before
    # homing, its entry was 0.8 mm late instead and a pass time from z 0 happened to agree.)
    ta = [r["time_s"] for r in cut if r["zs"] <= 50.0 and r["depth_mm"] > 0.0]
    tb = [r["time_s"] for r in rig if r["z_mm"] <= 50.0 and r["depth_mm"] > 0.0]
    da, db = ta[-1] - ta[0], tb[-1] - tb[0]
    report["pass_time_s"] = [da, db]
    check(abs(da - db) < 0.02 * db, "rig vs LinuxCNC: pass time %.2f / %.2f s (±2 %%)" % (db, da))
    a, b = a_of(13.0, 20.0), b_of(13.0, 20.0)
    pa = max(a, key=lambda r: r["force_true"])
    pb = max(b, key=lambda r: r["force_parameter_true"])
    report["peak_N"] = [pa["force_true"], pb["force_parameter_true"]]
    report["peak_at_mm"] = [pa["zs"], pb["z_mm"]]
    check(abs(pa["force_true"] - pb["force_parameter_true"]) < 0.05 * pb["force_parameter_true"],
          "rig vs LinuxCNC: collar entry peak %.0f / %.0f N (±5 %%)" %
          (pb["force_parameter_true"], pa["force_true"]))
    # The peak's place is not compared: with the feed lowered before the collar the force meets
    # the limit as a plateau, not as the entry's transient where the nose meets the shoulder,
    # and its highest sample lies anywhere along it (14.97 / 15.14 and 14.97 / 16.40 mm in two
    # fresh runs). Its height is, above, and both lie in the collar's entry window.
    settle_a = next(r["zs"] for r in a if r["zs"] > pa["zs"] and
                    abs(r["force_true"] - limit) < 0.05 * limit) - pa["zs"]
    settle_b = next(r["z_mm"] for r in b if r["z_mm"] > pb["z_mm"] and
                    abs(r["force_parameter_true"] - limit) < 0.05 * limit) - pb["z_mm"]
    report["settle_mm"] = [settle_a, settle_b]
    check(abs(settle_a - settle_b) < 0.2,
          "rig vs LinuxCNC: back within 5 %% of the limit %.2f / %.2f mm after the peak" %
          (settle_b, settle_a))
    # The per-revolution peak, by the one rule both report (control::PerRevolutionPeak): the
    # collar's step is in the stock model, so the feed is lowered before it (within 5 % of the
    # limit), and LinuxCNC's peak is the rig's within 2 % of the limit.
    rig_peak = json.load(open(os.path.join(out, "summary.json")))["metrics"]["force_peak_rev_mean_N"]
    report["force_peak_rev_mean_N"] = [peak_rev, rig_peak]
    check(abs(peak_rev - rig_peak) < 0.02 * limit,
          "rig vs LinuxCNC: per-revolution peak %.0f / %.0f N (±2 %% of the limit)" %
          (rig_peak, peak_rev))
    with open(os.path.join(work, "comparison.json"), "w") as f:
        json.dump({"columns": ["linuxcnc", "rig"], **report}, f, indent=2)


def main():
    src, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    os.makedirs(work, exist_ok=True)
    sc = tomllib.load(open(os.path.join(src, "examples/linuxcnc/step_allowance.toml"), "rb"))
    limit = sc["controller"]["force_limit_N"]

    # Shop data out (issue 46): this session publishes to a broker that is stopped and restarted
    # in the middle, and serves SHDR to a client and to hostile ones.
    shop = ShopRun(os.path.join(work, "broker-step"), "test-e", "E", away=2.0)
    summary, rows = run(src, work, "step_allowance.toml", "step", shop)
    if summary:
        check(summary["finished"] and not summary["errors"] and not summary["alarms"],
              "step: program finished, no errors, no alarms (%s)" % summary["alarms"])
        check(summary["sampler_overruns"] == 0, "step: recording complete (no sampler overruns)")
        check(summary["force_limit_N"] == limit, "step: the component runs the scenario's limit")
        before = in_feed(rows, -9.0, -13.0)    # 2 mm depth, below the limit, ramp done
        collar = in_feed(rows, -19.0, -29.0)   # 4 mm depth, after the entry transient
        after = in_feed(rows, -38.0, -48.0)    # 2 mm again
        f_before = mean([r["force_true"] for r in before])
        f_collar = mean([r["force_true"] for r in collar])
        f_after = mean([r["force_true"] for r in after])
        af_collar = mean([r["adaptive_feed"] for r in collar])
        check(f_before < 0.8 * limit and min(r["adaptive_feed"] for r in before) > 0.999,
              "2 mm before the collar: force %.0f N < limit, adaptive-feed 1" % f_before)
        check(abs(f_collar - limit) < 0.03 * limit,
              "collar (allowance grows): force held at %.0f N (limit %.0f N, ±3 %%)" %
              (f_collar, limit))
        check(max(r["force_true"] for r in collar) < 1.10 * limit,
              "collar: force never more than 10 %% over the limit after entry (peak %.0f N)" %
              max(r["force_true"] for r in collar))
        check(af_collar < 0.8, "collar: by lowering motion.adaptive-feed (mean %.3f)" % af_collar)
        check(min(r["adaptive_feed"] for r in after) > 0.999 and f_after < 0.8 * limit,
              "after the collar (allowance falls): adaptive-feed back to 1, force %.0f N" % f_after)
        peak = summary["force_peak_N"]
        peak_rev = summary["force_peak_rev_mean_N"]
        check(peak_rev <= 1.05 * limit,
              "step: per-revolution peak %.0f N within 5 %% of the limit %.0f N (the collar is in "
              "the stock model: the feed is lowered before it)" % (peak_rev, limit))
        if len(sys.argv) > 3:
            compare_with_rig(src, work, sys.argv[3], rows, limit, sc["tool"]["nose_radius_mm"],
                             peak_rev)
        print("step: force peak %.0f N at the collar's entry, %.0f N per revolution; cycle %.2f s; "
              "adaptive-feed min %.3f" %
              (peak, peak_rev, summary["cycle_time_s"], summary["adaptive_feed_min"]))

    shop = ShopRun(os.path.join(work, "broker-fault"), "test-e-fault", "E", away=0)
    summary, rows = run(src, work, "step_allowance_sensor_fault.toml", "fault", shop)
    got = [o for _, o in shop.sub.json("/E/event") if o["type"] == "alarm_raised"]
    check([o["alarm"] for o in got] == ["sensor_not_finite"],
          "fault: the alarm was published as an event (%s)" % got)
    if summary:
        check(summary["aborted_on_feed_hold"], "fault: the program was held (and then aborted)")
        check([a["reason"] for a in summary["alarms"]] == ["sensor_not_finite"],
              "fault: one alarm, sensor_not_finite (%s)" % summary["alarms"])
        nan_i = next((i for i, r in enumerate(rows) if math.isnan(r["force"])), None)
        hold_i = next((i for i, r in enumerate(rows) if r["feed_hold"] == 1), None)
        check(nan_i is not None and hold_i is not None and 0 <= hold_i - nan_i <= 2,
              "fault: feed hold %s ms after the first NaN sample" %
              (None if nan_i is None or hold_i is None else hold_i - nan_i))
        if hold_i is not None:
            held = rows[hold_i:]
            check(all(r["adaptive_feed"] == 0.0 and r["alarm"] == 1 and
                      r["alarm_reason"] == REASON["sensor_not_finite"] for r in held),
                  "fault: adaptive-feed 0, alarm latched, reason sensor_not_finite after")
            stop = next((i for i, r in enumerate(held) if abs(r["current_vel_mm_per_s"]) < 1e-9),
                        None)
            check(stop is not None and stop <= 100,
                  "fault: motion stopped %s ms after the hold" % stop)
            if stop is not None:
                # the simulated joints' position feedback trails the commanded stop by 3 periods
                z = [r["z_mm"] for r in held[stop + 10:] if r["motion_type"] == 2]
                check(len(z) > 500 and max(z) - min(z) < 1e-6,
                      "fault: the tool stays put while held (%.1f µm travelled after the hold)" %
                      (1000.0 * abs(held[stop + 10]["z_mm"] - held[0]["z_mm"])))
            check(all(r["spindle_rpm"] > 100.0 for r in held[:500]),
                  "fault: the spindle keeps turning during the hold")
            check(held[0]["z_mm"] < -15.5, "fault: it happened inside the collar (z %.2f)" %
                  held[0]["z_mm"])
    bad_scenario(src, work)
    if FAILS:
        print("%d check(s) failed" % len(FAILS))
        sys.exit(1)


def bad_scenario(src, work):
    """A scenario error in a LinuxCNC session: the run fails and the user is told the file (their
    path, not the copy staged for the realtime side), line and key in one line."""
    text = open(os.path.join(src, "examples/linuxcnc/step_allowance.toml")).read()
    bad = os.path.join(work, "bad_limit.toml")
    with open(bad, "w") as f:
        f.write(text.replace("force_limit_N = 1600.0", "force_limit_N = -5.0"))
    line = next(i + 1 for i, l in enumerate(text.splitlines()) if l.startswith("force_limit_N"))
    p = subprocess.run([os.path.join(src, "scripts/linuxcnc-sim"),
                        os.path.join(src, "examples/linuxcnc/step_allowance.ngc"), bad, "--out",
                        os.path.join(work, "bad"), "--timeout", "60"],
                       capture_output=True, text=True, timeout=120)
    said = [l for l in p.stderr.splitlines() if l.startswith("lathectl_plant: ")]
    check(p.returncode != 0 and said and
          said[0].startswith("lathectl_plant: %s:%d:" % (bad, line)) and "force_limit_N" in said[0],
          "bad scenario: linuxcnc-sim fails with the component's line: %s" %
          (said[0] if said else p.stderr.strip()[-300:]))
    log = open(os.path.join(work, "bad", "linuxcnc.log")).read()
    check("force_limit_N" in log, "bad scenario: LinuxCNC's log has the component's line")


if __name__ == "__main__":
    main()
