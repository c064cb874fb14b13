#!/usr/bin/python3
"""System E on generated parts in LinuxCNC: parts nobody wrote by hand (the generator of the rig's
200-part acceptance, tests/sim/e_part_generator.hpp), each written as a scenario and the NC
program of its passes (tests/hal/e_generated_program.cpp: the rig's own sequence of moves), run in
LinuxCNC's simulated lathe (scripts/linuxcnc-sim) with seed 004's controller in HAL. Holds LinuxCNC
to the acceptance's invariants, as the rig is held over 200 parts:

  - the program runs to its end (a sound tool: finished, not held, not timed out);
  - no alarm (the limit is reachable at the minimum feed on these parts, so any alarm is false);
  - the per-revolution force (the parameter the scenario's dynamometer measures, Pz or Py), each
    cut's first revolution left out (control::PerRevolutionPeak, in lathectl_plant as in the
    rig), at most 7.5 % above the limit: the bound the rig's 200-part acceptance holds every
    part to (its goal, 5 %, it holds for 99 % of them; the test prints whether this run met it).
    Measured over five runs (three fresh clones, two local): seed 1039 +1.7 to +5.1 % in
    LinuxCNC (1.7, 2.1, 4.4, 5.1 and one under 5), against +2.9 to +4.1 % in the rig over eight
    noise seeds; seed 1002 -5.3 % against -4.2 %. With G64 alone in the program (no P tolerance) LinuxCNC's planner rounded
    the shoulder's corner over 2 mm of plunge and seed 1039 reached +5.8 % and +8.4 % in two
    runs: a program for adaptive control needs its corners exact (e_generated_program writes
    G64 P0.01);
  - the controller worked: the per-revolution peak at least 90 % of the limit (on a part the
    feed can drive to the limit, a peak far below it is a controller that did not act);
  - LinuxCNC against the rig: per-revolution peaks within 3 % of the limit of each other (the
    eccentric's phase at the entry differs run to run); on a part of one diameter, where one S
    is the rig's programmed speed all along, the time from the first feed move's start to the
    last one's end within 3 % of the rig's cycle (measured 10.17 s against 10.16 s). On a
    stepped blank the program's S is the pass's first section's while the rig's follows the
    surface, so the times are printed, not compared (seed 1039: about 14.0 s against 12.8 s).

LinuxCNC runs in real time, so the set is small: seeds 1039 (steel 40Kh, Py, prior art's
force-by-feed at 253 m/min; a stepped blank, the second pass plunging at a shoulder with its
feed bound, M67 E2) and 1002 (steel 45, Pz, seed 004's speed law at 160 m/min, an eccentric
bar). They are the first seeds from 1000 whose rig cycle is under 15 s with the force at its
limit, one per dynamometer parameter; power in LinuxCNC is the shop test's (it needs the idle
sweep). The test checks each still answers that description, so a changed generator asks for
new seeds rather than testing easy parts. About 35 s of real time.

  linuxcnc_generated_test.py SOURCE_DIR WORK_DIR E_GENERATED_PROGRAM
"""

import csv
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from halrun_test import FAILS, check  # noqa: E402  (the suite's check and its failures)
from sim_session import run_linuxcnc_sim  # noqa: E402

SEEDS = (1039, 1002)



def rig_tool_table(work):
    """The rig's tool: T1 with the scenario's nose (no D) at Q2 and no I/J (the nose alone, as rig
    E cuts). The simulated lathe's T1 is a CNMG (I85 J5), whose 5-degree end edge cuts into the
    shoulders the generated programs plunge beside (seed 1039: overload, tool breakage, +49.5 %
    per revolution): LinuxCNC and the rig compare the same tool."""
    path = os.path.join(work, "rig-tools.tbl")
    with open(path, "w") as f:
        f.write("T1 P1 Q2 ; the rig's tool: the scenario's nose alone (no D, no I/J)\n")
    return path

def main():
    src, work, tool = (os.path.abspath(a) for a in sys.argv[1:4])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    table = []
    for seed in SEEDS:
        p = subprocess.run([tool, str(seed), work], capture_output=True, text=True, timeout=120)
        if p.returncode != 0:
            check(False, "seed %d: e_generated_program ran (%s)" % (seed, p.stderr.strip()))
            continue
        part = json.loads(p.stdout)
        rig, limit = part["rig"], part["limit"]
        name = "seed %d (%s, %s)" % (seed, part["parameter"], part["type"])
        # Still the part the test was written for: short, on a dynamometer, at its limit.
        check(part["parameter"] in ("Pz", "Py") and part["reachable"] and rig["finished"]
              and not rig["alarms"] and rig["cycle_time_s"] < 15.0
              and abs(rig["force_peak_rev_mean"] / limit - 1.0) <= 0.10,
              "%s: the rig finishes in %.1f s (< 15 s) with no alarm, per-rev peak %.0f N at "
              "its limit %.0f N (within 10 %%)"
              % (name, rig["cycle_time_s"], rig["force_peak_rev_mean"], limit))
        out = os.path.join(work, "out-%d" % seed)
        r = run_linuxcnc_sim([os.path.join(src, "scripts/linuxcnc-sim"),
                              os.path.join(work, "generated_%d.ngc" % seed),
                              os.path.join(work, "generated_%d.toml" % seed),
                              "--out", out, "--timeout", "60", "--quiet",
                              "--tool-table", rig_tool_table(work)])
        path = os.path.join(out, "summary.json")
        if not os.path.exists(path):
            print(r.stdout + r.stderr)
            check(False, "%s: linuxcnc-sim ran (exit %d)" % (name, r.returncode))
            continue
        s = json.load(open(path))
        check(s["finished"] and not s.get("timed_out"),
              "%s: LinuxCNC ran the program to its end (exit %d)" % (name, r.returncode))
        check(not s["alarms"], "%s: no alarm in LinuxCNC (%s)" % (name, s["alarms"]))
        peak = s["force_peak_rev_mean_N"]
        over = 100.0 * (peak / limit - 1.0)
        check(over <= 7.5,
              "%s: LinuxCNC's per-rev peak %.0f N, %+.1f %% of the limit %.0f N (at most 7.5 %%, "
              "the rig's acceptance bound; its goal, 5 %%, %s)"
              % (name, peak, over, limit, "met" if over <= 5.0 else "missed"))
        check(peak >= 0.90 * limit,
              "%s: and at least 90 %% of it: the controller drove the feed to the limit" % name)
        check(abs(peak - rig["force_peak_rev_mean"]) <= 0.03 * limit,
              "%s: the rig's per-rev peak %.0f N (%+.1f %%) within 3 %% of the limit of LinuxCNC's"
              % (name, rig["force_peak_rev_mean"],
                 100.0 * (rig["force_peak_rev_mean"] / limit - 1.0)))
        feed = [float(row["time_s"]) for row in csv.DictReader(open(os.path.join(out, "signals.csv")))
                if row["motion_type"] == "2"]
        span = feed[-1] - feed[0] if feed else 0.0
        if part["sections"] == 1:
            check(abs(span / rig["cycle_time_s"] - 1.0) <= 0.03,
                  "%s: one diameter: first feed move to last %.2f s in LinuxCNC, the rig's cycle "
                  "%.2f s (within 3 %%)" % (name, span, rig["cycle_time_s"]))
        else:
            print("     %s: stepped blank: first feed move to last %.2f s in LinuxCNC (the pass's "
                  "first section's S), the rig's cycle %.2f s (S following the surface)"
                  % (name, span, rig["cycle_time_s"]))
        table.append({"seed": seed, "part": part["what"], "limit": limit,
                      "linuxcnc": {"cycle_time_s": s["cycle_time_s"], "feed_span_s": span,
                                   "force_peak_rev_mean_N": peak,
                                   "adaptive_feed_min": s.get("adaptive_feed_min"),
                                   "alarms": s["alarms"]},
                      "rig": rig})
    with open(os.path.join(work, "generated.json"), "w") as f:
        json.dump(table, f, indent=1)


if __name__ == "__main__":
    main()
    if FAILS:
        print("%d check(s) failed" % len(FAILS))
        sys.exit(1)
