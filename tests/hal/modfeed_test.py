#!/usr/bin/python3
"""halrun-level tests of system B's HAL components (lathectl_modfeed, lathectl_chatter), with the
streamer → component → sampler pattern of halrun_test.py.

  modfeed_test.py stream SOURCE_DIR WORK_DIR       the module against a stimulus: idle-power
                                                    compensation, dead zone, engagement, the
                                                    seed's quanta, the programmed variant
  modfeed_test.py loop SOURCE_DIR WORK_DIR         the chatter plant and the module in a closed HAL
                                                    loop (the path integrated from the adaptive
                                                    feed), compared with `lathectl run`
  modfeed_test.py plan SOURCE_DIR WORK_DIR         the re-plan on its own thread
                                                    (lathectl-modfeed.plan) against the re-plan
                                                    inside the servo function: the same plans,
                                                    handed over within one plan period + one servo
                                                    period; the servo function's time both ways
  modfeed_test.py bad_input SOURCE_DIR WORK_DIR    bad scenarios and module parameters
"""

import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import halrun_test as H  # noqa: E402  (check, halrun, stream_session, FAILS)
from reasons import REASON  # noqa: E402  (the reason codes by name, from hal/reasons.json)

SCENARIO = "examples/linuxcnc/b_chatter_single.toml"
# The re-plan's own thread, as a machine's HAL adds it (lathectl_modfeed(9)): slower than the
# servo thread and created after it, so at a lower priority.
PLAN_PERIOD_NS = 10000000
PLAN_THREAD = " name2=modfeed-plan period2=%d" % PLAN_PERIOD_NS
ADD_PLAN = "addf lathectl-modfeed.plan modfeed-plan"
IDLE_W = 300 + 0.3 * 820 + 1e-4 * 820 ** 2  # the scenario's spindle idle law at 820 rpm


# The module's inputs a stimulus drives (cut_rows' columns, in this order).
STIM = ["lathectl-modfeed.a0-um", "lathectl-modfeed.omega-d-Hz", "lathectl-modfeed.spindle-power",
        "lathectl-modfeed.spindle-rpm", "lathectl-modfeed.x-pos", "lathectl-modfeed.requested-vel",
        "lathectl-modfeed.current-vel", "lathectl-modfeed.motion-type",
        "lathectl-modfeed.idle-block"]
STIM_CFG = "fffffffsb"


# The closed loops' common wiring: the spindle angle integrated from 820 rpm, the module's x and
# speed, the plant enabled, and the plant's detectors and power into the module.
SPINDLE_AND_DETECTORS = """net revs-rate integ.1.in
sets revs-rate %.6f
net revs integ.1.out => lathectl-chatter.spindle-revs
net rpm lathectl-chatter.spindle-rpm lathectl-modfeed.spindle-rpm
sets rpm 820
net xpos lathectl-modfeed.x-pos
sets xpos 20
setp lathectl-chatter.enable 1
net out1 lathectl-modfeed.a0-um
net out2 lathectl-modfeed.omega-d-Hz
net pw lathectl-chatter.spindle-power => lathectl-modfeed.spindle-power
""" % (820 / 60.0)


def cut_rows(n, idle_rows, a0_of):
    """n rows (1 ms each) for STIM: an idle block for idle_rows, then a feed block at the mean
    feed 0.30 mm/rev × 820 rpm (the program's F at the ceiling 2) drawing 1000 W of cutting
    power at 85 % efficiency; a0_of(k) the vibration amplitude [µm] at row k (227 Hz while
    > 0)."""
    mean = 0.30 * 820
    F = 2.0 * mean / 60.0
    rows = []
    for k in range(n):
        idle = k < idle_rows
        a0 = a0_of(k)
        rows.append([a0, 227.0 if a0 > 0 else 0.0, IDLE_W + (0.0 if idle else 1000.0 / 0.85),
                     820.0, 20.0, F, 0.0 if idle else mean / 60.0, 0 if idle else 2,
                     1 if idle else 0])
    return rows


def near_multiple(v, q, tol=1e-6):
    return abs(v / q - round(v / q)) < tol


def test_stream(src, work):
    sc = H.rt_path(src, os.path.join(src, SCENARIO))
    mean = 0.30 * 820  # mm/min: the feed to keep
    # Idle block for 0.5 s, chatter of 20 µm from 2 s.
    rows = cut_rows(6000, 500, lambda k: 20.0 if k >= 2000 else 0.0)
    stim = STIM
    outs = ["lathectl-modfeed.adaptive-feed", "lathectl-modfeed.feed", "lathectl-modfeed.cut-power",
            "lathectl-modfeed.engaged", "lathectl-modfeed.reason", "lathectl-modfeed.s-min",
            "lathectl-modfeed.ds", "lathectl-modfeed.dl", "lathectl-modfeed.n-s"]
    got = H.stream_session(work, "modfeed", ["lathectl_modfeed scenario=" + sc], STIM_CFG, rows,
                           stim, "fffbsfffs", outs)
    if not got:
        return
    before = [r for i, r in enumerate(got) if 1000 <= i < 2000]
    H.check(all(abs(r[0] - 0.5) < 1e-9 and r[3] == 0 for r in before),
            "below the dead zone (a0 = 0): not engaged, adaptive-feed = 1/ceiling = 0.5")
    nc = sum(r[2] for r in before) / len(before)
    H.check(abs(nc - 1000 / 0.85) < 10.0,
            "idle power stored at the idle block, N_c = N_m − N_idle = %.1f W (expected %.1f)"
            % (nc, 1000 / 0.85))
    after = [r for i, r in enumerate(got) if i >= 2300]
    H.check(all(r[3] == 1 for r in after), "engaged once a0 and ω_d come above the dead zone")
    H.check(all(int(r[4]) in (REASON["modulation_engaged"], REASON["modulation_limited"])
                for r in after),
            "reason code modulation_engaged or modulation_limited")
    last = after[-1]
    s_min, ds, dl, n_s = last[5], last[6], last[7], int(last[8])
    H.check(ds > 0 and near_multiple(ds, 0.1), "ΔS = %.1f mm/min, a multiple of 0.1" % ds)
    H.check(dl > 0 and near_multiple(dl, 0.001), "Δl = %.3f mm, a multiple of the 1 µm resolution" % dl)
    levels = {round(s_min + k * ds, 6) for k in range(n_s + 1)}
    feeds = {round(r[1], 6) for r in after}
    H.check(feeds <= levels and len(feeds) == n_s + 1,
            "the feed walks the staircase S_min + k·ΔS, k = 0…%d: %s" % (n_s, sorted(feeds)))
    # (the sampler prints six significant digits)
    H.check(all(abs(r[0] - r[1] / (2.0 * mean)) < 1e-5 and 0 < r[0] <= 1.0 for r in after),
            "adaptive-feed = S/F in (0, 1]")

    # The programmed variant: the NC block's parameters, whatever the vibration.
    prog = {"source": 1, "prog-s-min": 150.0, "prog-ds": 25.0, "prog-dl": 0.2, "prog-n-s": 4}
    extra = "\n".join("setp lathectl-modfeed.%s %s" % (k, v) for k, v in prog.items())
    got = H.stream_session(work, "modfeed-prog", ["lathectl_modfeed scenario=" + sc], STIM_CFG,
                           rows, stim, "fffbsfffs", outs, extra)
    if got:
        cut = [r for i, r in enumerate(got) if i >= 600]
        feeds = sorted({round(r[1], 6) for r in cut})
        H.check(feeds == [150.0, 175.0, 200.0, 225.0, 250.0],
                "programmed (150, 25, 0.2, 4): levels %s" % feeds)
        H.check(all(int(r[4]) == REASON["modulation_programmed"] for r in cut),
            "reason code modulation_programmed")


def test_loop(src, work):
    """Closed loop in HAL: path speed = F·adaptive-feed (mult2), the path integrated (integ), the
    machine z = −path + z0 (scale), the spindle angle integrated from its speed; the chatter plant
    reads z and the angle, the module reads the plant's detectors and power."""
    sc_path = os.path.join(src, SCENARIO)
    rt_sc = H.rt_path(src, sc_path)
    n = 10000
    F = 2.0 * 0.30 * 820 / 60.0
    rows = [[0.0 if k < 500 else F, 0 if k < 500 else 2, 1 if k < 500 else 0] for k in range(n)]
    pre = """
loadrt mult2
loadrt integ count=2
loadrt scale
addf mult2.0 t
addf integ.0 t
addf integ.1 t
addf scale.0 t
"""
    # Signals out0…out11 are the sampled pins below (stream_session names them); the loop joins
    # them.
    hal = """
setp scale.0.gain -1
setp scale.0.offset -279
net stim0 mult2.0.in0
net out3 mult2.0.in1
net speed mult2.0.out => integ.0.in lathectl-modfeed.current-vel
net out6 scale.0.in
net zpos scale.0.out => lathectl-chatter.z-pos
""" + SPINDLE_AND_DETECTORS
    outs = ["lathectl-chatter.vibration-um", "lathectl-chatter.a0-um", "lathectl-chatter.omega-d-Hz",
            "lathectl-modfeed.adaptive-feed", "lathectl-modfeed.engaged", "lathectl-modfeed.reason",
            "integ.0.out", "lathectl-modfeed.s-min", "lathectl-modfeed.ds", "lathectl-modfeed.dl",
            "lathectl-modfeed.n-s", "lathectl-chatter.in-contact", "lathectl-chatter.update-ns",
            "lathectl-modfeed.update-ns"]
    # The streamer's pins are wired by stream_session's stim_pins; `extra` adds mult2 to pin 0's
    # signal.
    # The module as a machine runs it: the re-plan on its own slower thread.
    got = H.stream_session(work, "loop",
                           ["lathectl_chatter scenario=%s z_origin_mm=0" % rt_sc,
                            "lathectl_modfeed scenario=%s" % rt_sc],
                           "fsb", rows, ["lathectl-modfeed.requested-vel", "lathectl-modfeed.motion-type",
                                         "lathectl-modfeed.idle-block"],
                           "ffffbsffffsbss", outs, hal, pre + ADD_PLAN + "\n", threads=PLAN_THREAD)
    if not got:
        return
    # The same scenario in the simulator.
    out = os.path.join(work, "rig")
    subprocess.run([os.environ.get("LATHECTL", "lathectl"), "run", sc_path, "--out", out],
                   check=False, capture_output=True)
    rig = json.load(open(os.path.join(out, "summary.json")))["metrics"] if os.path.exists(
        os.path.join(out, "summary.json")) else None
    contact = [i for i, r in enumerate(got) if r[11] == 1]
    H.check(len(contact) > 0, "the tool reaches the part")
    a0max = max(r[1] for r in got)
    H.check(a0max > 5.0, "the part chatters in the HAL loop: a0 up to %.0f µm" % a0max)
    engaged = [i for i, r in enumerate(got) if r[4] == 1]
    H.check(len(engaged) > 0, "the module engages")
    if not engaged or not contact:
        return
    t_eng = (engaged[0] - contact[0]) * 1e-3
    wd = [r[2] for r in got[engaged[0]:] if r[2] > 0]
    fd = sum(wd) / len(wd) if wd else 0.0
    H.check(all(int(r[5]) in (REASON["modulation_engaged"], REASON["modulation_limited"])
                for r in got[engaged[0]:]),
            "reason codes modulation_engaged/modulation_limited while engaged")
    # Time-mean path speed after engagement, over whole staircase cycles: the program's mean.
    i0 = engaged[0] + 100
    dt = (n - 1 - i0) * 1e-3
    mean_speed = (got[-1][6] - got[i0][6]) / dt * 60.0
    H.check(abs(mean_speed / (0.30 * 820) - 1.0) < 0.1,
            "mean feed while modulating %.1f mm/min = %.3f × the program's mean" %
            (mean_speed, mean_speed / (0.30 * 820)))
    def stats(col):
        v = sorted(r[col] for r in got)
        return {"median_ns": v[len(v) // 2], "p99_9_ns": v[int(0.999 * (len(v) - 1))],
                "max_ns": v[-1]}

    summary = {"update_chatter": stats(12), "update_modfeed": stats(13),
               "engaged_after_contact_s": t_eng, "chatter_Hz": fd, "a0_max_um": a0max,
               "S_min": got[-1][7], "dS": got[-1][8], "dl": got[-1][9], "n_s": got[-1][10],
               "mean_feed_mm_per_min": mean_speed}
    if rig:
        m = rig["modulation"]
        summary["rig"] = {"engaged_at_s": m["engaged_at_s"], "chatter_Hz": rig["chatter_frequency_Hz"],
                          "S_min": m["S_min_mm_per_min"], "dS": m["dS_mm_per_min"], "dl": m["dl_mm"]}
        # The rig's clock starts with its idle block; the tool then travels approach_mm (1 mm) at
        # the programmed feed before it touches the part.
        rig_after_contact = m["engaged_at_s"] - 0.5 - 1.0 / (0.30 * 820 / 60.0)
        summary["rig"]["engaged_after_contact_s"] = rig_after_contact
        # Within one gate of frequency detector 20 (0.1 s; the gates count from each host's
        # start, not from the contact) and the estimate above (the 30 Hz feed drive's 5 ms lag):
        # with the 1 µm initial disturbance at the contact a0 reaches the dead zone near a gate's
        # end here (measured: HAL 0.808 s, lathectl run 0.905 s; the rig alone with its approach
        # 30 µm shorter 0.807 s; before, with no seed, 1.108 s against 1.105 s).
        H.check(abs(t_eng - rig_after_contact) < 0.11,
                "engaged %.3f s after contact in LinuxCNC's HAL, %.3f s in lathectl run" %
                (t_eng, rig_after_contact))
        H.check((got[-1][7], got[-1][8], round(got[-1][9], 6)) ==
                (m["S_min_mm_per_min"], m["dS_mm_per_min"], round(m["dl_mm"], 6)),
                "the same plan in HAL and in lathectl run: S_min %.1f, ΔS %.1f, Δl %.3f" %
                (got[-1][7], got[-1][8], got[-1][9]))
        H.check(abs(fd - rig["chatter_frequency_Hz"]) < 10.0,
                "chatter frequency HAL %.0f Hz, rig %.0f Hz (detector resolution 5 Hz)" %
                (fd, rig["chatter_frequency_Hz"]))
    with open(os.path.join(work, "loop.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(json.dumps(summary, indent=2))


def test_plan(src, work):
    """The same stimulus twice, the re-plan inside the servo function (no plan function added:
    the configuration of before) and on the modfeed-plan thread: a cut from 0.2 s, chatter of
    6 µm from 0.4 s (the plan at engagement) and of 12 µm from 1.2 s (a re-plan: a0 above the
    planned, more than replan_period_s = 0.5 s after the first plan). Both amplitudes ask for
    less force variation than the ceiling allows (20 µm would not: the plan would stay at the
    limit), so the second plan differs from the first."""
    sc = H.rt_path(src, os.path.join(src, SCENARIO))
    rows = cut_rows(1500, 200, lambda k: 0.0 if k < 400 else 6.0 if k < 1200 else 12.0)
    outs = ["lathectl-modfeed.engaged", "lathectl-modfeed.s-min", "lathectl-modfeed.ds",
            "lathectl-modfeed.dl", "lathectl-modfeed.n-s", "lathectl-modfeed.plans-inline",
            "lathectl-modfeed.plans-taken", "lathectl-modfeed.plans-made",
            "lathectl-modfeed.time", "lathectl-modfeed.update-ns"]
    # HAL's own measure of each function (hal_export_funct): the .time pin every call, the
    # .tmax parameter its largest.
    post = "show param lathectl-modfeed.tmax\nshow param lathectl-modfeed.plan.tmax"
    runs = {}
    for name, threads, extra in (("inline", "", ""), ("thread", PLAN_THREAD, ADD_PLAN)):
        got = H.stream_session(work, "plan-" + name, ["lathectl_modfeed scenario=" + sc],
                               STIM_CFG, rows, STIM, "bfffssssss", outs, extra,
                               threads=threads, post=post)
        if not got:
            return
        tmax = {}
        for l in H.LAST_LOG.splitlines():
            f = l.split()
            if len(f) == 5 and f[4].endswith(".tmax"):
                tmax[f[4]] = int(f[3])
        plan_of = lambda r: (r[1], r[2], round(r[3], 6), int(r[4]))
        # The rows where the running plan changes (the first: engagement).
        changes = [i for i in range(1, len(got)) if got[i][0] == 1 and
                   (got[i - 1][0] == 0 or plan_of(got[i]) != plan_of(got[i - 1]))]
        runs[name] = {"rows": got, "changes": changes, "plans": [plan_of(got[i]) for i in changes],
                      "tmax": tmax}
    inl, thr = runs["inline"], runs["thread"]
    last_in, last_th = inl["rows"][-1], thr["rows"][-1]
    H.check(len(inl["changes"]) == 2 and int(last_in[5]) == 2 and int(last_in[6]) == 0,
            "without the plan function the servo function plans itself: plans-inline %d, "
            "plans-taken %d, plans at rows %s" % (last_in[5], last_in[6], inl["changes"]))
    H.check(all(int(r[5]) == 0 for r in thr["rows"]) and int(last_th[6]) == 2 and
            int(last_th[7]) == 2,
            "with lathectl-modfeed.plan on its own thread the servo function never plans: "
            "plans-inline 0, plans-made %d, plans-taken %d" % (last_th[7], last_th[6]))
    H.check(inl["plans"] == thr["plans"] and len(thr["plans"]) == 2,
            "the same plans both ways (S_min, ΔS, Δl, n_s): %s" % thr["plans"])
    # The request goes out in the servo period that asks (the plan inside the servo function
    # appears in that row); the plan thread runs within PLAN_PERIOD_NS, the servo function takes
    # its answer in its next period.
    bound = PLAN_PERIOD_NS // 1000000 + 1
    lags = [b - a for a, b in zip(inl["changes"], thr["changes"])]
    H.check(len(lags) == 2 and all(1 <= d <= bound for d in lags),
            "the plan handed over %s servo periods after the request (≤ %d: one plan period + "
            "one servo period)" % (lags, bound))
    # The servo function's time: HAL's .time pin (CPU clocks, rtapi_get_clocks) sampled every
    # period and its .tmax, and the module's own update-ns; in the periods that made a plan
    # (inline) or took one (thread), and over the run. Reported, not asserted: on a kernel
    # without PREEMPT_RT and a shared CPU, the largest values are the machine's (preemption).
    def times(run, key):
        t = sorted(int(r[8]) for r in run["rows"])
        return {"servo_tmax_clocks": run["tmax"].get("lathectl-modfeed.tmax"),
                "servo_time_p50_clocks": t[len(t) // 2],
                "servo_time_p99_clocks": t[int(0.99 * (len(t) - 1))],
                key + "_clocks": [int(run["rows"][i][8]) for i in run["changes"]],
                key.replace("servo_time", "update_ns"): [int(run["rows"][i][9])
                                                         for i in run["changes"]]}
    summary = {"inline": times(inl, "servo_time_in_planning_periods"),
               "thread": times(thr, "servo_time_in_handover_periods"),
               "plan_function_tmax_clocks": thr["tmax"].get("lathectl-modfeed.plan.tmax"),
               "handover_lag_periods": lags, "plans": thr["plans"]}
    with open(os.path.join(work, "plan.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print(json.dumps(summary, indent=2))


def test_bad_input(src, work):
    sc = H.rt_path(src, os.path.join(src, SCENARIO))
    e = H.rt_path(src, os.path.join(src, "examples/linuxcnc/step_allowance.toml"))
    cases = [
        ("lathectl_modfeed scenario=" + e, ["system-B"]),
        ("lathectl_modfeed scenario=%s ceiling=0.5" % sc, ["ceiling"]),
        ("lathectl_modfeed scenario=%s output=offset" % sc, ["output=offset", "eoffset"]),
        ("lathectl_modfeed scenario=%s output=eoffset ceiling=2" % sc, ["ceiling", "eoffset"]),
        ("lathectl_modfeed", ["scenario=PATH", "required"]),
        ("lathectl_chatter scenario=%s period_ns=12" % sc, ["period_ns"]),
    ]
    for load, words in cases:
        rc, log = H.halrun("loadrt threads name1=t period1=1000000\nloadrt %s\n" % load, work, "bad")
        H.check(rc != 0 and all(w in log for w in words),
                "load fails with a clear message: loadrt %s → %s" %
                (load.replace(src, "SRC"),
                 next((l for l in log.splitlines() if l.startswith("lathectl_")), "(none)")))


def main():
    if len(sys.argv) < 4:
        print(__doc__)
        sys.exit(2)
    what, src, work = sys.argv[1], os.path.abspath(sys.argv[2]), os.path.abspath(sys.argv[3])
    os.makedirs(work, exist_ok=True)
    os.chmod(work, 0o777)
    {"stream": test_stream, "loop": test_loop, "plan": test_plan,
     "bad_input": test_bad_input}[what](src, work)
    if H.FAILS:
        print("%d check(s) failed" % len(H.FAILS))
        sys.exit(1)


if __name__ == "__main__":
    main()
