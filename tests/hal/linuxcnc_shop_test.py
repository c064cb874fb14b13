#!/usr/bin/python3
"""A shop's program on LinuxCNC's simulated lathe (scripts/linuxcnc-sim): two tools, four
operations of examples/linuxcnc/two_tool.ngc (a limit from the program with M68, one from the
per-tool table switched with M67 at a block boundary, a teach-in cut, a cut at the table's
percentage of the taught load), then a bad value. Run twice: on the scenario's force sensor (N)
and with sensor=power (the spindle drive's power minus the learned idle power, W). Asserts:

  - every operation runs at its own limit: the program's, the table's, 90 % of the taught load;
    its per-revolution load (the plant's true force or cutting power) stays within 5 % of that
    limit in steady cutting (5 mm after the entry to 1 mm before the end of the cut; op 2 and
    op 4, 2 mm before: they end at the shoulders op 1 and op 3 left at Z-20 and Z-40, and the
    feed-forward from the stock model lowers the feed from about 1.2 mm before them, as it
    should: in one fresh-clone run op 2's last revolution in the 1 mm window read 941 N against
    the 1000 N limit; op 4's, in the first fresh-clone run after issue 47's merges, read 831 N
    against 900 N at Z-38.8, the 66 before it 891-916 N);
  - the limit pin switches in the servo period the program's value reaches motion (M68: the
    analog output; M67: the first period of the next move);
  - teach-in: the taught reference within 2 % of the true mean load over the steady cut, stored
    in the taught file (written atomically by lathectl_oplog) with the tool and operation;
  - power: after the automatic tare (the program's idle sweep, then the rapids), the learned idle
    law differs from the plant's warm-up-drifting one (with the spindle's friction: what the drive
    draws in air) by < 2 % of the drive's rated power over the speed range swept, and the cutting
    power estimated in the cut by < 2 % too, against the cutting power as the drive's power meter
    shows it (lagged by the scenario's meter, as in lathectl run); control on power
    holds its limits as closely as control on force (the worst steady deviation of the load each
    holds within 1 point; on power the true cutting power adds the estimate's error);
  - a bad value (above the rating) holds the feed at once, names the program line in the operator
    message, and is never used as a limit;
  - lathectl_oplog wrote one row per cutting line, CSV and JSON.

  linuxcnc_shop_test.py SOURCE_DIR WORK_DIR
Writes WORK_DIR/shop.json: the per-operation table, teach-in accuracy, idle-tare error curve and
the limit-switch latencies.
"""

import csv
import json
import math
import os
import subprocess
import sys
import tomllib

FAILS = []
RATED_W = 15000.0  # two_tool.toml [spindle] max_power_kW


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


def program(src, work, unit):
    """two_tool.ngc with the unit's op-1 limit (on force without the idle sweep), and a bad value
    (above the rating) after op 4."""
    text = open(os.path.join(src, "examples/linuxcnc/two_tool.ngc")).read()
    if unit == "W":
        text = text.replace("M68 E0 Q1400", "M68 E0 Q3200")
    else:  # the idle sweep is the power tare's: on force, 7 s of the session saved
        sweep = text[text.index("(the idle power tare"):text.index("(op 1, T1")]
        text = text.replace(sweep, "")
    bad = 9000 if unit == "N" else 20000
    text = text.replace("M5\nM2", "M68 E3 Q2\nM68 E0 Q%d (a value above the rating)\nG1 X24 F0.25\n"
                        "M5\nM2" % bad)
    path = os.path.join(work, "two_tool_%s.ngc" % unit)
    with open(path, "w") as f:
        f.write(text)
    lines = text.splitlines()
    find = lambda pat, after=0: next(i + 1 for i, l in enumerate(lines) if i + 1 > after and pat in l)
    op1 = find("G1 Z-20")
    op2 = find("G1 Z-20", op1)
    op3 = find("G1 Z-40")
    op4 = find("G1 Z-40", op3)
    return path, {"op1": op1, "op2": op2, "op3": op3, "op4": op4,
                  "m67": find("M67 E0"), "bad_m68": find("M68 E0 Q%d" % bad), "bad": bad}


def tools_file(work, unit):
    path = os.path.join(work, "tools-%s.toml" % unit)
    t1, rating = (1000.0, 5000.0) if unit == "N" else (2000.0, 15000.0)
    with open(path, "w") as f:
        f.write("[machine]\nlimit_max = %g\n\n[[tool]]\nnumber = 1\nlimit = %g\n\n"
                "[[tool]]\nnumber = 2\nreference_pct = 90.0\n" % (rating, t1))
    return path


def run(src, work, unit, shop_run=None):
    prog, lines = program(src, work, unit)
    out = os.path.join(work, unit)
    taught = os.path.join(work, "taught-%s.toml" % unit)
    if os.path.exists(taught):
        os.remove(taught)
    cmd = [os.path.join(src, "scripts/linuxcnc-sim"), prog,
           os.path.join(src, "examples/linuxcnc/two_tool.toml"), "--out", out, "--tools",
           tools_file(work, unit), "--taught", taught, "--timeout", "150", "--quiet"]
    if unit == "W":
        cmd += ["--sensor", "power"]
    if shop_run:
        cmd += shop_run.args()
    first = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if unit == "N":  # a second session beside a running one is refused, the first lives on
        import time
        time.sleep(8.0)
        second = subprocess.run(cmd[:3] + ["--out", os.path.join(work, "second"), "--quiet"],
                                capture_output=True, text=True, timeout=60)
        check(second.returncode == 3 and "running" in second.stderr and first.poll() is None,
              "a second linuxcnc-sim is refused (exit %d: %s), the first runs on" %
              (second.returncode, second.stderr.strip()))
    out_s, err_s = first.communicate(timeout=300)
    if shop_run:
        shop_run.finish()
        if os.path.exists(os.path.join(out, "publish.json")):
            shop_run.report(check, out)
            ev = shop_run.sub.json("/E/event")
            ops = [o for _, o in ev if o["type"] == "operation"]
            logged = json.load(open(os.path.join(out, "operations.json")))["rows"]
            check([(o["op_seq"], o["line"], o["load_peak"]) for o in ops] ==
                  [(r["seq"], r["line"], r["load_peak"]) for r in logged]
                  and any(o["type"] == "teach_in" for _, o in ev),
                  unit + ": every logged operation published as an event (%d), and the teach-in"
                  % len(ops))
    summary_path = os.path.join(out, "summary.json")
    if not os.path.exists(summary_path):
        print(out_s + err_s)
        check(False, unit + ": linuxcnc-sim ran")
        return None
    rows = []
    with open(os.path.join(out, "signals.csv")) as f:
        for r in csv.DictReader(f):
            rows.append({k: float(v) for k, v in r.items()})
    return {"summary": json.load(open(summary_path)), "rows": rows, "lines": lines,
            "ops": json.load(open(os.path.join(out, "operations.json"))),
            "csv": open(os.path.join(out, "operations.csv")).read(), "taught": taught}


def per_rev(rows, key):
    """Per-revolution means of rows (1 ms each) at the recorded spindle speed."""
    out, acc, n, phase = [], 0.0, 0, 0.0
    for r in rows:
        acc += r[key]
        n += 1
        phase += r["spindle_rpm"] / 60.0 * 1e-3
        if phase >= 1.0:
            out.append(acc / n)
            acc, n, phase = 0.0, 0, phase - 1.0
    return out


def cuts(rows):
    """The contiguous runs of feed-move rows in contact: one a cut."""
    out, run = [], []
    for r in rows:
        if r["in_contact"] == 1 and r["motion_type"] == 2:
            run.append(r)
        elif run:
            out.append(run)
            run = []
    if run:
        out.append(run)
    return out


def steady(rows, line, z_hi, z_lo):
    return [r for r in rows if int(r["program_line"]) == line and r["in_contact"] == 1 and
            z_lo <= r["z_mm"] <= z_hi]


def analyse(res, unit, report):
    s, rows, L = res["summary"], res["rows"], res["lines"]
    off = 1  # linuxcnc-sim's "M52 P1" in front of the program
    key = "force_true" if unit == "N" else "cut_power_W"
    check(s["aborted_on_feed_hold"] and not s["timed_out"],
          "%s: the program ran to the bad value and was held there" % unit)
    ops = {r["line"]: r for r in res["ops"]["rows"]}
    taught = tomllib.load(open(res["taught"], "rb")) if os.path.exists(res["taught"]) else {}
    t_ref = next((t["reference"] for t in taught.get("taught", [])
                  if t["tool"] == 2 and t["operation"] == 1 and t["unit"] == unit), None)
    check(t_ref is not None, "%s: the taught file holds tool 2 operation 1 (%s)" % (unit, t_ref))
    t_ref = t_ref or float("nan")
    t1 = 1000.0 if unit == "N" else 2000.0
    expect = {"op1": (1400.0 if unit == "N" else 3200.0, "program (M68 E0)"),
              "op2": (t1, "tool table (M67 E0 Q0)"),
              "op4": (0.9 * t_ref, "90 % of the taught load (table)")}
    table = []
    worst = worst_ctl = 0.0
    for op, (z_hi, z_lo) in (("op1", (-5.0, -19.0)), ("op2", (-5.0, -18.0)),
                             ("op3", (-25.0, -39.0)), ("op4", (-25.0, -38.0))):
        line = L[op] + off
        st = steady(rows, line, z_hi, z_lo)
        revs = per_rev(st, key)
        lim_pin = [r["limit"] for r in st]
        row = ops.get(L[op], {})
        entry = {"operation": op, "line": L[op], "tool": int(st[0]["tool"]) if st else None,
                 "limit": lim_pin[0] if lim_pin else None,
                 "steady_load_mean": sum(revs) / len(revs) if revs else None,
                 "steady_per_rev_max": max(revs) if revs else None,
                 "steady_per_rev_min": min(revs) if revs else None,
                 "log_load_mean": row.get("load_mean"), "log_load_peak": row.get("load_peak"),
                 "log_feed_min": row.get("feed_min"), "log_feed_mean": row.get("feed_mean"),
                 "log_time_in_cut_s": row.get("time_in_cut_s"), "mode": row.get("mode")}
        table.append(entry)
        check(len(revs) >= 20, "%s %s: %d steady revolutions recorded" % (unit, op, len(revs)))
        if not revs:
            continue
        if op == "op3":  # teach: the program's feed, the reference is the mean
            true_mean = sum(r[key] for r in st) / len(st)
            err = (t_ref - true_mean) / true_mean
            entry["taught_reference"] = t_ref
            entry["true_mean"] = true_mean
            report["teach_error_%s" % unit] = err
            check(all(r["adaptive_feed"] == 1.0 for r in st),
                  "%s teach: the cut runs at the programmed feed (adaptive-feed 1)" % unit)
            check(abs(err) < 0.02, "%s teach: taught %.1f vs true mean %.1f %s (%.2f %%, ±2 %%)" %
                  (unit, t_ref, true_mean, unit, 100 * err))
            continue
        want, how = expect[op]
        check(all(abs(v - want) < 1e-6 * max(1.0, want) for v in lim_pin),
              "%s %s: limit %.1f %s from the %s" % (unit, op, want, unit, how))
        dev = max(abs(v - want) / want for v in revs)
        worst = max(worst, dev)
        entry["steady_dev_max_pct"] = 100 * dev
        # What the controller holds: its own load (on power, the estimated cutting power; the
        # estimate's error against the plant's is checked on its own in tare()).
        dev_ctl = max(abs(v - want) / want for v in per_rev(st, "load"))
        worst_ctl = max(worst_ctl, dev_ctl)
        check(dev < 0.05, "%s %s (tool %d): per-revolution load %.0f..%.0f %s, within %.1f %% of "
              "%.0f (±5 %%)" % (unit, op, entry["tool"], min(revs), max(revs), unit, 100 * dev,
                                want))
        # (the taught file keeps 3 decimals of the reference the component holds in full)
        check(row and abs(row["limit"] - want) < 0.01 and row["time_in_cut_s"] > 1.0,
              "%s %s: the operation log's row (limit %s, %s s in cut)" %
              (unit, op, row.get("limit"), row.get("time_in_cut_s")))
    report["operations_%s" % unit] = table
    report["worst_steady_dev_%s" % unit] = worst
    report["worst_steady_dev_control_%s" % unit] = worst_ctl

    # The limit switch at block boundaries, in servo periods.
    lat = {}
    i_cmd = next((i for i in range(1, len(rows)) if rows[i]["limit_cmd"] == expect["op1"][0] and
                  rows[i - 1]["limit_cmd"] != rows[i]["limit_cmd"]), None)
    i_lim = next((i for i in range(1, len(rows)) if rows[i]["limit"] == expect["op1"][0] and
                  rows[i - 1]["limit"] != rows[i]["limit"]), None)
    lat["m68_periods"] = None if i_cmd is None or i_lim is None else i_lim - i_cmd
    # M67 (synchronized): motion puts the value out when it activates the next move (while
    # blending, motion.program-line already shows that move): the component switches in the same
    # period, and before the operation's first feed move.
    i_cmd2 = next((i for i in range(1, len(rows)) if rows[i]["limit_cmd"] == 0.0 and
                   rows[i - 1]["limit_cmd"] == expect["op1"][0]), None)
    i_lim2 = next((i for i in range(1, len(rows)) if rows[i]["limit"] == t1 and
                   rows[i - 1]["limit"] == expect["op1"][0]), None)  # op 1's → the table's
    feed2 = L["op2"] + off
    i_feed = next((i for i in range(len(rows)) if int(rows[i]["program_line"]) == feed2), None)
    m67_move = L["m67"] + 1 + off  # the move after M67
    i_blk = next((i for i in range(1, len(rows)) if int(rows[i]["program_line"]) == m67_move and
                  int(rows[i - 1]["program_line"]) != m67_move), None)
    lat["m67_periods"] = None if i_cmd2 is None or i_lim2 is None else i_lim2 - i_cmd2
    lat["m67_after_move_line_shown_periods"] = (None if i_blk is None or i_lim2 is None
                                                else i_lim2 - i_blk)
    lat["m67_before_feed_move_periods"] = (None if i_feed is None or i_lim2 is None
                                           else i_feed - i_lim2)
    report["latency_%s" % unit] = lat
    check(lat["m68_periods"] == 0, "%s: M68's limit in effect %s servo periods after motion's "
          "analog output changed (same period)" % (unit, lat["m68_periods"]))
    check(lat["m67_periods"] == 0 and (lat["m67_before_feed_move_periods"] or 0) > 0,
          "%s: M67's limit in effect %s periods after motion's output changed, %s periods before "
          "the operation's feed move" % (unit, lat["m67_periods"],
                                         lat["m67_before_feed_move_periods"]))

    # The bad value: held in the period it appears, never used, the message names the line.
    i_bad = next((i for i, r in enumerate(rows) if r["bad_setting"] == 1), None)
    check(i_bad is not None and rows[i_bad]["feed_hold"] == 1 and
          rows[i_bad]["adaptive_feed"] == 0.0 and rows[i_bad]["limit_cmd"] == L["bad"],
          "%s bad value: feed hold in the period motion put out %s" % (unit, L["bad"]))
    check(all(r["limit"] != L["bad"] for r in rows), "%s bad value: never used as the limit" % unit)
    msgs = [m["text"] for m in res["ops"]["messages"] if m["kind"] == "bad_setting"]
    check(len(msgs) == 1 and ("line %d" % L["bad_m68"]) in msgs[0] and "rating" in msgs[0],
          "%s bad value: operator message %r" % (unit, msgs[0] if msgs else None))
    report["bad_value_message_%s" % unit] = msgs[0] if msgs else None
    if os.environ.get("LATHECTL"):
        html = os.path.join(os.path.dirname(res["taught"]), unit, "report.html")
        page = open(html).read() if os.path.exists(html) else ""
        check("Operations" in page and "Load against the limit" in page and
              ("line %d" % L["bad_m68"]) in page,
              "%s: lathectl report wrote report.html (table, plots, the bad value's message)" %
              unit)
    check(res["csv"].count("\n") == len(res["ops"]["rows"]) + 1 and
          res["ops"]["missed_rows"] == 0 and all(r["line"] > 0 for r in res["ops"]["rows"]),
          "%s: operations.csv and .json, one row per cutting line (%d rows, none missed)" %
          (unit, len(res["ops"]["rows"])))


def tare(res, src, report):
    """The idle law learned against the plant's, over the swept speeds; the in-cut estimate."""
    sc = tomllib.load(open(os.path.join(src, "examples/linuxcnc/two_tool.toml"), "rb"))
    sp = sc["spindle"]
    # What the drive draws in air (what the tare learns): the idle law and the spindle's viscous
    # friction b·ω²/η (drives::air_power_W; [spindle] viscous_N_m_s, its documented default 0.01).
    b = sp.get("viscous_N_m_s", 0.01)
    law = lambda n: (sp["idle_p0_W"] + sp["idle_p1_W_per_rpm"] * n + sp["idle_p2_W_per_rpm2"] * n * n)
    friction = lambda n: b * (n * 2 * 3.141592653589793 / 60) ** 2 / sp["efficiency"]
    t = res["summary"]["idle_tare"]
    fit = lambda n: t["p0_W"] + t["p1_W_per_rpm"] * n + t["p2_W_per_rpm2"] * n * n
    eta = sp["efficiency"]
    curve = []
    for n in range(150, 2901, 250):
        err = eta * (fit(n) - law(n) * t["plant_drift_factor"] - friction(n))
        curve.append({"rpm": n, "error_W": round(err, 1),
                      "error_pct_rated": round(100 * err / RATED_W, 3)})
    report["idle_tare_curve"] = curve
    worst = max(abs(c["error_W"]) for c in curve)
    check(worst < 0.02 * RATED_W, "power: learned idle law within %.0f W (%.2f %% of %.0f kW "
          "rated) of the plant's over 150..2900 rpm at the end of the run (< 2 %%)" %
          (worst, 100 * worst / RATED_W, RATED_W / 1000))
    # The load pin is η·(P_drive − P_idle) − J·ω·dω/dt; the truth is the plant's cutting power as
    # the drive's power meter shows it: lagged by the meter's time constant (the scenario's
    # [sensor] power_meter_time_constant_ms, default 20 ms, as in lathectl run), a lag no
    # estimator can undo (unlagged, the estimate entering a cut reads up to 0.5 kW low for a
    # revolution). The drive's power carries noise per sample: compare per-revolution means.
    tau = sc.get("sensor", {}).get("power_meter_time_constant_ms", 20.0) * 1e-3
    k, lagged = 1.0 - math.exp(-1e-3 / tau), 0.0  # the rows are servo periods of 1 ms
    for r in res["rows"]:
        lagged += k * (r["cut_power_W"] - lagged)
        r["cut_power_metered_W"] = lagged
    errs = []
    for run in cuts(res["rows"]):
        a, c = per_rev(run, "load"), per_rev(run, "cut_power_metered_W")
        errs += [abs(x - y) for x, y in zip(a, c)]
    e = max(errs) if errs else float("nan")
    report["cut_power_error_max_W"] = e
    check(e < 0.02 * RATED_W, "power: cutting power estimated within %.0f W per revolution in "
          "every cut (%.2f %% of rated, < 2 %%) of the metered cutting power" %
          (e, 100 * e / RATED_W))


def timeout_run(src, work):
    """--timeout: the program is aborted, what was recorded is kept, nothing raw left behind."""
    out = os.path.join(work, "timeout")
    p = subprocess.run([os.path.join(src, "scripts/linuxcnc-sim"),
                        os.path.join(src, "examples/linuxcnc/two_tool.ngc"),
                        os.path.join(src, "examples/linuxcnc/two_tool.toml"), "--out", out,
                        "--timeout", "7"], capture_output=True, text=True, timeout=120)
    s = json.load(open(os.path.join(out, "summary.json"))) if os.path.exists(
        os.path.join(out, "summary.json")) else {}
    check(p.returncode == 4 and s.get("timed_out") and s.get("samples", 0) > 3000 and
          os.path.exists(os.path.join(out, "signals.csv")) and
          not [f for f in os.listdir(out) if f.endswith(".raw")],
          "--timeout 7: exit %d, summary.json timed_out with %s samples, signals.csv kept, no raw "
          "file left" % (p.returncode, s.get("samples")))
    check("linuxcnc-sim:" in p.stderr and " s  line " in p.stderr,
          "progress lines on stderr while it runs: %r" %
          next((l for l in p.stderr.splitlines() if " s  line " in l), None))


def main():
    src, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    os.makedirs(work, exist_ok=True)
    os.chmod(work, 0o755)
    report = {}
    timeout_run(src, work)
    force = run(src, work, "N")
    if force:
        analyse(force, "N", report)
    # Shop data out (issue 46): the session on power publishes (its keys in W); the broker is
    # stopped after the first event until two more wait in the publisher's spool (at most 20 s).
    from shop_broker import ShopRun
    power = run(src, work, "W", ShopRun(os.path.join(work, "broker-W"), "test-shop", "E",
                                         away=20.0, hostile_clients=False, unit="W",
                                         spool_dir=os.path.join(work, "W")))
    if power:
        analyse(power, "W", report)
        tare(power, src, report)
    if force and power:
        # Control on power against control on force, each on the load it holds (force: the
        # dynamometer; power: the drive's power less the learned idle power). The true cutting
        # power differs from the estimate by the idle law's error, up to about 50 W here: 2 % of
        # op 4's 2239 W, which made the worst true deviations differ by 0.76-1.04 points from run
        # to run (2.53 % against 1.49 % on force in one fresh clone).
        wn, wc = report["worst_steady_dev_N"], report["worst_steady_dev_control_W"]
        check(wc <= wn + 0.01, "power holds its limits as closely as force: worst steady "
              "deviation %.2f %% on power (%.2f %% of the true cutting power, the idle law's error "
              "included), %.2f %% on force" % (100 * wc, 100 * report["worst_steady_dev_W"],
                                               100 * wn))
    with open(os.path.join(work, "shop.json"), "w") as f:
        json.dump(report, f, indent=2)
    if FAILS:
        print("%d check(s) failed" % len(FAILS))
        sys.exit(1)


if __name__ == "__main__":
    main()
