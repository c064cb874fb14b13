#!/usr/bin/python3
"""halrun-level tests of lathectl_adaptive's shop settings (seconds each; the LinuxCNC session is
linuxcnc_shop_test.py): a streamer plays what motion and iocontrol would put out, a sampler
records the component in the same 1 ms period.

  shop_halrun_test.py settings SRC WORK  per-operation settings: the program's value in the period
                                         it appears, the tool table's defaults by tool number,
                                         every bad value held with its code, never used
  shop_halrun_test.py teach SRC WORK     teach-in against a known load (entry ramp, per-revolution
                                         ripple, noise, exit): the reference within 2 % of the
                                         steady mean; lathectl_oplog stores it; a restart (the
                                         component loaded again) controls at a % of it
  shop_halrun_test.py breakage SRC WORK  the plant cuts a straight turn; a broken tool (the plant's
                                         break_at_s) stops the feed in the servo period its force
                                         collapses, while a programmed fast exit from the material
                                         does not, with the stock model (z_origin_mm); the
                                         controller's own collapse detector trips on that exit;
                                         the tool's table row changed in a feed move: alarm tool_data_changed
  shop_halrun_test.py files SRC WORK     unreadable or wrong tools/taught files: the load fails
                                         with one line naming file, line and key
"""

import math
import os
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import halrun_test as h  # noqa: E402  (the halrun/streamer/sampler helpers and staging)
from reasons import REASON  # noqa: E402  (the reason codes by name, from hal/reasons.json)

check = h.check

TOOLS = """[machine]
limit_max = 5000.0
feed_max_mm_per_rev = 0.8

[[tool]]
number = 1
limit = 1000.0
feed_min_mm_per_rev = 0.05
feed_max_mm_per_rev = 0.6

[[tool]]
number = 2
limit = 900.0
reference_pct = 90.0
warn_pct = 120.0
hold_pct = 160.0
"""

STIM_PINS = ["force", "spindle-rpm", "spindle-rpm-programmed", "requested-vel", "current-vel",
             "x-pos", "motion-type", "limit-cmd", "feed-min-cmd", "feed-max-cmd", "mode-cmd",
             "operation-cmd", "tool-number", "program-line"]
STIM_CFG = "ffffffsfffffss"
OUT_PINS = ["adaptive-feed", "feed-hold", "limit", "bad-code", "bad-setting", "feed-min",
            "feed-max", "teaching", "teach-reference", "teach-seq", "bad-line", "adaptive-on"]
OUT_CFG = "fbfsbffbfssb"


def tools_file(src, work, text=TOOLS, name="tools.toml"):
    path = os.path.join(work, name)
    with open(path, "w") as f:
        f.write(text)
    return path


def session(src, work, name, rows, params, pre="", extra=""):
    stim = ["lathectl-adaptive." + p for p in STIM_PINS]
    out = ["lathectl-adaptive." + p for p in OUT_PINS]
    load = "lathectl_adaptive scenario=%s %s" % (h.rt_scenario(src), params)
    got = h.stream_session(work, name, [load], STIM_CFG, rows, stim, OUT_CFG, out,
                           "setp lathectl-adaptive.enable 1\n"
                           "setp lathectl-adaptive.feed-per-rev-mode 1\n" + extra, pre)
    return [dict(zip(OUT_PINS, r)) for r in got]


def test_settings(src, work):
    sc = tomllib.load(open(h.scenario_path(src), "rb"))
    c = sc["controller"]
    tools = h.rt_path(src, tools_file(src, work))
    rpm, s_prog, x = 1200.0, 0.3, 18.0
    nan = float("nan")
    # (from [s), limit-cmd, feed-min-cmd, feed-max-cmd, mode-cmd, tool, expected bad code)
    bad = [(nan, 0, 0, 0, 5, 1), (-5, 0, 0, 0, 5, 2), (6000, 0, 0, 0, 5, 3),
           (0, 0.5, 0.3, 0, 5, 4), (0, 0, 0.9, 0, 5, 4), (0, nan, 0, 0, 5, 4), (0, 0, 0, 7, 5, 5),
           (0, 0, 0, 2.5, 5, 5), (0, 0, 0, 4, 1, 7), (250, 0, 0, 4, 1, 6)]
    phases = [(0.0, 0, 0, 0, 0, 1, 0), (0.1, 1200, 0, 0, 0, 1, 0), (0.2, 0, 0, 0, 0, 5, 0)]
    for b in bad:  # each bad value for 0.05 s, then a good one (nothing set, tool 5) for 0.05 s
        t = phases[-1][0] + 0.05
        phases += [(t,) + b, (t + 0.05, 0, 0, 0, 0, 5, 0)]
    phases += [(phases[-1][0] + 0.05, 0, 0.1, 0.4, 0, 2, 0)]
    rows = []
    for k in range(int((phases[-1][0] + 0.1) / h.PERIOD_S)):
        t = k * h.PERIOD_S
        ph = [p for p in phases if p[0] <= t + 1e-9][-1]
        # A tool changes (M6) with motion stopped: motion-type 0 in that period (a tool number
        # that changes inside a feed move is alarm tool_data_changed, test_breakage).
        mtype = 0 if rows and rows[-1][12] != ph[5] else 2
        rows.append([0.0, rpm, rpm, s_prog, s_prog * rpm / 60.0, x, mtype, ph[1], ph[2], ph[3],
                     ph[4], 0, ph[5], 10 + phases.index(ph)])
    got = session(src, work, "settings", rows, "tools=" + tools)
    if not got:
        return
    at = lambda t: int(round(t / h.PERIOD_S))
    check(got[at(0.05)]["limit"] == 1000.0 and got[at(0.05)]["feed-min"] == 0.05 and
          got[at(0.05)]["feed-max"] == 0.6, "tool 1, nothing programmed: the table's 1000 N, "
          "0.05..0.6 mm/rev (%s)" % {k: got[at(0.05)][k] for k in ("limit", "feed-min", "feed-max")})
    check(got[at(0.1) - 1]["limit"] == 1000.0 and got[at(0.1)]["limit"] == 1200.0,
          "M68 E0 Q1200: in effect in the period the value appears (0 periods)")
    check(got[at(0.25)]["limit"] == c["force_limit_N"],
          "tool 5 (not in the table): the scenario's %g N" % c["force_limit_N"])
    names = {1: "NaN limit", 2: "negative limit", 3: "limit above the 5000 N rating",
             4: "feed bounds", 5: "mode", 6: "percentage above 200", 7: "no taught reference"}
    for i, ph in enumerate(phases):
        code = ph[6]
        if not code:
            continue
        k0, k1 = at(ph[0]), at(phases[i + 1][0]) - 1
        seg = got[k0:k1]
        before = got[k0 - 1]
        ok = (all(r["bad-code"] == code and r["bad-setting"] == 1 and r["feed-hold"] == 1 and
                  r["adaptive-feed"] == 0.0 for r in seg) and
              all(r["limit"] == before["limit"] and r["feed-min"] == before["feed-min"] and
                  r["feed-max"] == before["feed-max"] for r in seg) and
              seg[0]["bad-line"] == 10 + i)
        check(ok, "%s (%s): bad-code %d, feed hold from the first period, the last good "
              "settings kept (limit %g), bad-line %d" % (names[code], ph[1:5], seg[0]["bad-code"],
                                                          seg[0]["limit"], seg[0]["bad-line"]))
        nxt = got[at(phases[i + 1][0]) + 1]
        check(nxt["bad-code"] == 0 and nxt["feed-hold"] == 0,
              "%s: a good value clears the hold" % names[code])
    last = got[-1]
    check(last["limit"] == 900.0 and last["feed-min"] == 0.1 and last["feed-max"] == 0.4,
          "tool 2 with E1 0.1 / E2 0.4: limit %g (table), feeds %g..%g (program)" %
          (last["limit"], last["feed-min"], last["feed-max"]))


def teach_rows(limit_cmd, mode, rpm=1200.0, seconds=3.4):
    """Tool 2, operation 1: rapid, entry ramp over 6 revolutions, steady 1000 N with a
    per-revolution ripple (±80 N) and noise, exit ramp, rapid. Returns rows and the true mean of
    the steady cut."""
    rows, steady = [], []
    f_rev = rpm / 60.0
    for k in range(int(seconds / h.PERIOD_S)):
        t = k * h.PERIOD_S
        noise = 12.0 * math.sin(0.7 * k) + 7.0 * math.sin(0.13 * k)
        if t < 0.2 or t >= 3.2:
            mtype, force = 1, noise
        elif t < 0.5:
            mtype, force = 2, 1000.0 * (t - 0.2) / 0.3 + noise
        elif t < 3.0:
            mtype, force = 2, 1000.0 + 80.0 * math.sin(2 * math.pi * f_rev * t) + noise
            steady.append(force)
        else:
            mtype, force = 2, max(0.0, 1000.0 * (3.2 - t) / 0.2) + noise
        rows.append([force, rpm, rpm, 0.25, 0.25 * rpm / 60.0, 18.0, mtype, limit_cmd, 0, 0, mode,
                     1, 2, 7])
    return rows, sum(steady) / len(steady) if steady else float("nan")


def test_teach(src, work):
    tools = h.rt_path(src, tools_file(src, work))
    taught = os.path.join(work, "taught.toml")
    if os.path.exists(taught):
        os.remove(taught)
    oplog = os.path.join(src, "hal", "lathectl_oplog.py")
    logdir = os.path.join(work, "log")
    rows, true_mean = teach_rows(0, 3)
    pins = ["teach-seq", "teach-tool", "teach-operation", "teach-reference", "op-seq", "op-line",
            "op-tool", "op-limit", "op-load-mean", "op-load-peak", "op-feed-min", "op-feed-mean",
            "op-time-in-cut", "op-time", "op-mode", "op-operation", "op-reasons", "op-alarm",
            "bad-code", "bad-line", "bad-value"]
    # Pins the sampler records are on its signals (outN) already: the log joins those.
    nets = "".join("net %s lathectl-adaptive.%s => lathectl-oplog.%s\n" % (p, p, p)
                   for p in pins if p not in OUT_PINS)
    joins = "".join("net out%d => lathectl-oplog.%s\n" % (OUT_PINS.index(p), p)
                    for p in pins if p in OUT_PINS)
    pre = ("loadusr -Wn lathectl-oplog /usr/bin/python3 %s --out %s --taught %s --unit N\n" %
           (oplog, logdir, taught)) + nets
    # The taught file does not exist yet: the component starts with nothing taught.
    got = session(src, work, "teach", rows, "tools=%s taught=%s" % (tools, taught), pre=pre,
                  extra=joins)
    if not got:
        return
    ref = got[-1]["teach-reference"]
    err = (ref - true_mean) / true_mean
    check(got[-1]["teach-seq"] == 1 and abs(err) < 0.02,
          "teach: reference %.2f N against the steady cut's true mean %.2f N (%.3f %%, ±2 %%; "
          "entry ramp and exit left out)" % (ref, true_mean, 100 * err))
    at = lambda t: int(round(t / h.PERIOD_S))
    check(all(r["adaptive-feed"] == 1.0 for r in got[at(0.2):at(3.2)]) and
          got[at(1.0)]["teaching"] == 1 and got[at(3.3)]["teaching"] == 0,
          "teach: the program's feed throughout (adaptive-feed 1), teaching until the cut ends")
    doc = tomllib.load(open(taught, "rb")) if os.path.exists(taught) else {}
    t = doc.get("taught", [])
    check(len(t) == 1 and t[0]["tool"] == 2 and t[0]["operation"] == 1 and t[0]["unit"] == "N" and
          abs(t[0]["reference"] - ref) < 1e-3,
          "lathectl_oplog stored it: %s" % t)
    check(not [f for f in os.listdir(work) if f.startswith(".taught.toml.")],
          "the taught file was written atomically (no temporary left)")
    # Restart: a new session reads the taught file; E3 = 4 with E0 = 80 → 80 % of it.
    rows2, _ = teach_rows(80, 4, seconds=0.3)
    got2 = session(src, work, "restart", rows2, "tools=%s taught=%s" %
                   (tools, h.rt_path(src, taught)))
    if got2:
        check(abs(got2[-1]["limit"] - 0.8 * ref) < 1e-3 * ref and got2[-1]["bad-code"] == 0 and
              got2[-1]["adaptive-on"] == 1,
              "restart: the taught reference survives, limit %.2f N = 80 %% of it" %
              got2[-1]["limit"])
    rows3, _ = teach_rows(0, 4, seconds=0.3)
    got3 = session(src, work, "restart_table_pct", rows3, "tools=%s taught=%s" %
                   (tools, h.rt_path(src, taught)))
    if got3:
        check(abs(got3[-1]["limit"] - 0.9 * ref) < 1e-3 * ref,
              "E0 = 0: the table's reference_pct (90 %%): limit %.2f N" % got3[-1]["limit"])


def breakage_session(src, work, name, plant_params, adaptive_params, exit_at=None,
                     diameter=lambda k: 0.8, rapid=lambda k: False):
    """A straight turn at 2 mm depth (x 18 on the 40 mm bar, z 2 → −12 at 0.3 mm/rev, 1200 rpm);
    exit_at: at that z the tool leaves the material in +x at 300 mm/s (a feed move); diameter(k)
    the tool table's diameter (halui.tool.diameter) and rapid(k) a rapid in period k."""
    rows, rpm = [], 1200.0
    x, z, v = 18.0, 2.0, 0.3 * rpm / 60.0
    for k in range(2000):  # 2 s: the exit at 1.7 s, the broken tip at 1.3 s
        mtype = 1 if rapid(k) else 2
        if exit_at is not None and z <= exit_at:
            x = min(25.0, x + 300.0 * h.PERIOD_S)
        else:
            z -= v * h.PERIOD_S
        rows.append([x, z, rpm, mtype, diameter(k)])
    stim = ["lathectl-plant.x-pos", "lathectl-plant.z-pos", "lathectl-plant.spindle-rpm",
            "lathectl-adaptive.motion-type", "lathectl-adaptive.tool-diameter"]
    out = ["lathectl-plant.force", "lathectl-adaptive.feed-hold", "lathectl-adaptive.alarm",
           "lathectl-adaptive.alarm-reason", "lathectl-adaptive.predicted-depth",
           "lathectl-adaptive.breakage", "lathectl-plant.depth",
           "lathectl-adaptive.tool-data-changed"]
    sc = h.rt_scenario(src)
    pre = ("net stim0 => lathectl-adaptive.x-pos\nnet stim1 => lathectl-adaptive.z-pos\n"
           "net stim2 => lathectl-adaptive.spindle-rpm lathectl-adaptive.spindle-rpm-programmed\n")
    extra = ("net out0 => lathectl-adaptive.force\n"  # the plant's force (sampled as out0)
             "setp lathectl-plant.enable 1\nsetp lathectl-adaptive.homed 1\n"
             "setp lathectl-adaptive.enable 1\nsetp lathectl-adaptive.feed-per-rev-mode 1\n"
             "setp lathectl-adaptive.requested-vel 0.3\n")
    got = h.stream_session(work, name, ["lathectl_plant scenario=%s %s" % (sc, plant_params),
                                        "lathectl_adaptive scenario=%s %s" % (sc, adaptive_params)],
                           "fffsf", rows, stim, "fbbsfbfb", out, extra, pre)
    return [dict(zip(["force", "hold", "alarm", "reason", "predicted", "breakage", "depth",
                      "tool_data"], r))
            for r in got]


def test_breakage(src, work):
    limit = tomllib.load(open(h.scenario_path(src), "rb"))["controller"]["force_limit_N"]
    air = 0.1 * limit
    # A broken tool: the plant's force vanishes after 1 s in cut, the stock is still there.
    got = breakage_session(src, work, "broken", "break_at_s=1.0", "z_origin_mm=0")
    if got:
        i_drop = next((i for i in range(1, len(got)) if got[i - 1]["force"] > 0.5 * limit and
                       got[i]["force"] < air), None)
        i_stop = next((i for i, r in enumerate(got) if r["breakage"] == 1), None)
        check(i_drop is not None and i_stop == i_drop and got[i_stop]["hold"] == 1 and
              got[i_stop]["reason"] == REASON["tool_breakage"] and got[i_stop]["predicted"] > 1.5,
              "broken tool: breakage alarm and feed hold in the servo period the force collapses "
              "(%s periods; predicted depth %.2f mm)" %
              (None if i_drop is None or i_stop is None else i_stop - i_drop,
               got[i_stop]["predicted"] if i_stop is not None else float("nan")))
        check(all(r["hold"] == 1 for r in got[i_stop:]) if i_stop is not None else False,
              "broken tool: the hold latches")
    # A programmed exit at 300 mm/s: the load collapses within the 10 ms window, and so does the
    # engagement the stock model predicts.
    got = breakage_session(src, work, "exit_path", "", "z_origin_mm=0", exit_at=-8.0)
    if got:
        fell = next((i for i in range(10, len(got)) if got[i]["force"] < air and
                     max(r["force"] for r in got[i - 10:i]) > 0.5 * limit), None)
        check(fell is not None and not any(r["breakage"] or r["alarm"] for r in got),  # 10 ms
              "programmed exit with the stock model: no alarm (the predicted depth fell with the "
              "load: %.2f mm then)" % (got[fell]["predicted"] if fell else float("nan")))
    # The tool table rewritten under the running program (LinuxCNC's rs274 as the same user:
    # halui.tool.diameter 0.8 → 1.6 mm with T2 in the spindle, measured beside a session). In a
    # rapid (0.7 s) nothing: the next move's data; in a feed move in the cut (1.4 s) its own
    # alarm tool_data_changed and the hold in that servo period, never a breakage.
    got = breakage_session(src, work, "tool_data", "", "z_origin_mm=0",
                           diameter=lambda k: 0.8 if k < 700 else 1.2 if k < 1400 else 1.6,
                           rapid=lambda k: 690 <= k < 710)
    if got:
        changed = REASON["tool_data_changed"]
        i = next((i for i, r in enumerate(got) if r["tool_data"] == 1 or r["alarm"]), None)
        check(i == 1400 and got[i - 1]["force"] > 100.0 and got[i]["hold"] == 1 and got[i]["alarm"] == 1 and
              got[i]["reason"] == changed and
              all(r["reason"] == changed and r["hold"] == 1 and not r["breakage"]
                  for r in got[i:]),
              "tool data changed in a feed move: alarm tool_data_changed and feed hold in that period, latched, "
              "no breakage; in a rapid no alarm (first alarm in period %s)" % i)
    got = breakage_session(src, work, "exit_old", "", "", exit_at=-8.0)
    if got:
        check(any(r["alarm"] and r["reason"] == REASON["tool_breakage"] for r in got),
              "the same exit with the controller's own collapse detector: a false breakage alarm "
              "(what pawn_bar.toml had to switch off)")


def test_files(src, work):
    sc = h.rt_scenario(src)
    bad_key = tools_file(src, work, TOOLS.replace("limit = 900.0", "limit = -900.0"), "bad1.toml")
    line_key = next(i + 1 for i, l in enumerate(open(bad_key).read().splitlines())
                    if l.startswith("limit = -900"))
    unknown = tools_file(src, work, TOOLS.replace("warn_pct", "warn_percent"), "bad2.toml")
    line_unknown = next(i + 1 for i, l in enumerate(open(unknown).read().splitlines())
                        if l.startswith("warn_percent"))
    twice = tools_file(src, work, TOOLS.replace("number = 2", "number = 1"), "bad3.toml")
    wrong_unit = os.path.join(work, "taught-W.toml")
    with open(wrong_unit, "w") as f:
        f.write('[[taught]]\ntool = 1\noperation = 0\nreference = 2500.0\nunit = "W"\n')
    syntax = tools_file(src, work, "[[tool]\nnumber = 1\n", "bad4.toml")
    cases = [
        ("tools=/nonexistent/tools.toml", ["cannot read tool limits /nonexistent/tools.toml"]),
        ("tools=" + h.rt_path(src, bad_key), ["bad1.toml:%d" % line_key, "limit"]),
        ("tools=" + h.rt_path(src, unknown), ["bad2.toml:%d" % line_unknown, "warn_percent"]),
        ("tools=" + h.rt_path(src, twice), ["bad3.toml", "tool 1 twice"]),
        ("tools=" + h.rt_path(src, syntax), ["bad4.toml:1"]),
        ("taught=" + h.rt_path(src, wrong_unit), ["taught-W.toml", "taught in W"]),
        ("sensor=torque", ["sensor=torque", "force or power"]),
    ]
    for params, words in cases:
        rc, log = h.halrun("loadrt threads name1=t period1=1000000\n"
                           "loadrt lathectl_adaptive scenario=%s %s\n" % (sc, params), work, "bad")
        said = next((l for l in log.splitlines() if l.startswith("lathectl_adaptive")), "(none)")
        check(rc != 0 and all(w in said for w in words),
              "load fails with one line: %s → %s" % (params.replace(work, "WORK"), said))
    rc, log = h.halrun("loadrt threads name1=t period1=1000000\n"
                       "loadrt lathectl_adaptive scenario=%s taught=/nonexistent/taught.toml\n"
                       % sc, work, "absent")
    check(rc == 0, "an absent taught file is no error (nothing taught yet)")


def main():
    what, src, work = sys.argv[1], os.path.abspath(sys.argv[2]), os.path.abspath(sys.argv[3])
    os.makedirs(work, exist_ok=True)
    os.chmod(work, 0o777)  # the realtime uid writes nothing here, the sampler files are ours
    {"settings": test_settings, "teach": test_teach, "files": test_files,
     "breakage": test_breakage}[what](src, work)
    if h.FAILS:
        print("%d check(s) failed" % len(h.FAILS))
        sys.exit(1)


if __name__ == "__main__":
    main()
