#!/usr/bin/env bash
# End-to-end checks of the lathectl program: exit codes, error messages, outputs, atomic writes.
# Usage: cli_test.sh LATHECTL SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1; src=$2; work=$3
umount "$work/full" 2>/dev/null  # the full-disk case's tmpfs, had a run been killed inside it
rm -rf "$work"; mkdir -p "$work"
fail=0; pass=0
ok() { pass=$((pass+1)); }
bad() { echo "FAIL: $*"; fail=$((fail+1)); }
expect_rc() {  # expected_rc description command...
  local want=$1 what=$2; shift 2
  "$@" >"$work/out.txt" 2>"$work/err.txt"; local rc=$?
  if [ "$rc" -eq "$want" ]; then ok; else bad "$what: exit $rc, expected $want; stderr: $(cat "$work/err.txt")"; fi
}

# --help on every command
for c in "" run check demo lobes report design reference systems "design pulse-regulator" "design adaptive-speed" "design gauge" "design tracer" "design modulation"; do
  expect_rc 0 "--help for '$c'" $bin $c --help
done
# every example validates
for f in "$src"/examples/scenarios/*.toml; do expect_rc 0 "check $f" $bin check "$f"; done

# bad input: exit 2, one line naming file, line and key
sed 's/^mass_kg = 60.0/mass_kg = -3/' "$src/examples/scenarios/a_finishing_aim.toml" > "$work/bad_range.toml"
expect_rc 2 "out-of-range value" $bin check "$work/bad_range.toml"
grep -q "bad_range.toml:[0-9]*:[0-9]*: key 'slide.mass_kg'" "$work/err.txt" || bad "range message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "error message is not one line"
sed 's/^\[slide\]/[slide]\nspeeed = 3/' "$src/examples/scenarios/a_finishing_aim.toml" > "$work/bad_key.toml"
expect_rc 2 "unknown key" $bin run "$work/bad_key.toml" --out "$work/never"
grep -q "unknown key 'slide.speeed'" "$work/err.txt" || bad "unknown-key message: $(cat "$work/err.txt")"
[ ! -e "$work/never" ] || bad "a failed run left an output directory behind"
expect_rc 2 "missing file" $bin run "$work/does_not_exist.toml" --out "$work/never"
printf 'system = "A"\nname = [\n' > "$work/syntax.toml"
expect_rc 2 "syntax error" $bin check "$work/syntax.toml"
grep -q "syntax.toml:[0-9]*:[0-9]*: TOML syntax error" "$work/err.txt" || bad "syntax message: $(cat "$work/err.txt")"
expect_rc 2 "unknown subcommand" $bin frobnicate
expect_rc 2 "design without period" $bin design pulse-regulator --d-mm 8

# --version: the project's version and the commit it was built from
expect_rc 0 "--version" $bin --version
grep -Eq '^lathectl [0-9]+\.[0-9]+\.[0-9]+ \(commit ([0-9a-f]{7,}(-dirty)?|unknown)\)$' "$work/out.txt" ||
  bad "--version: $(cat "$work/out.txt")"
# demo: an unknown example name and a missing examples directory are bad input, one line each
expect_rc 2 "demo unknown example" $bin demo no_such_example --out "$work/never"
grep -q "no example 'no_such_example' in .*(known: .*a_finishing_aim" "$work/err.txt" || bad "demo name message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "demo name message is not one line"
expect_rc 2 "demo missing examples dir" $bin demo --examples "$work/no_such_dir" --out "$work/never"
grep -q "no_such_dir" "$work/err.txt" || bad "demo examples-dir message: $(cat "$work/err.txt")"
[ ! -e "$work/never" ] || bad "a failed demo left an output directory behind"

# a run writes the three outputs, with the summary's required shape
expect_rc 0 "run a_roughing_aim" $bin run "$src/examples/scenarios/a_roughing_aim.toml" --out "$work/rough"
for f in summary.json channels.csv channels_compare.csv report.html; do [ -s "$work/rough/$f" ] || bad "missing $f"; done
python3 - "$work/rough/summary.json" <<'PY' || bad "summary.json shape"
import json, sys
s = json.load(open(sys.argv[1]))
m = s["metrics"]
assert s["system"] == "A" and s["scenario"] == "a_roughing_aim"
for k in ["feed_rate_mean_mm_per_min", "feed_rate_deviation_pct", "force_peak_N", "force_setpoint_N",
          "force_settling_time_s", "feed_drift_pct"]:
    assert k in m, k
assert abs(m["force_final_error_pct"]) <= 5.0
PY
ls "$work/rough" | grep -q '\.tmp\.' && bad "temporary files left behind"

# design calculator, JSON, against formula (1) worked by hand:
# μπd·sqrt(2Δp/ρ) = 0.65·π·0.008·sqrt(2·0.5e6/870) = 0.016336·33.903 = 0.55385 m²/s
# Q = 0.55385 · 40e-6 · 10/50 = 4.4308e-6 m³/s = 265.85 cm³/min
expect_rc 0 "design json" $bin design pulse-regulator --d-mm 8 --h-mm 0.04 --dp-MPa 0.5 --dt-ms 10 --T-ms 50 --json
python3 - "$work/out.txt" <<'PY' || bad "design json values"
import json, sys
j = json.load(open(sys.argv[1]))
assert abs(j["si"]["Q_m3_per_s"] / 4.4308e-6 - 1) < 1e-3, j["si"]["Q_m3_per_s"]
assert abs(j["shop"]["duty_pct"] - 20) < 1e-9
PY

# design adaptive-speed (seed 004 and the handbook tool-life law), JSON against hand-worked values:
# V_opt = V_p·(S_p/S)^yv = 150·(0.3/0.15)^0.35 = 150·2^0.35 = 150·e^(0.35·0.693147)
#       = 150·e^0.242601 = 150·1.274561 = 191.184 m/min
expect_rc 0 "adaptive-speed V_opt" $bin design adaptive-speed --Vp 150 --Sp 0.3 --yv 0.35 --S 0.15 --json
python3 - "$work/out.txt" <<'PY' || bad "adaptive-speed V_opt json: $(cat "$work/out.txt")"
import json, sys
j = json.load(open(sys.argv[1]))
assert abs(j["results"]["V_opt_m_per_min"] - 191.184) < 1e-3, j["results"]
assert j["inputs"]["Vp_m_per_min"] == 150 and j["inputs"]["S_mm_per_rev"] == 0.15, j["inputs"]
assert set(j["results"]) == {"V_opt_m_per_min"}, j["results"]  # only the complete group
PY
# the spindle speed for V_opt on a Ø80 mm part: n = 1000·191.184/(π·80) = 191184/251.3274 = 760.697 rpm
expect_rc 0 "adaptive-speed spindle speed" $bin design adaptive-speed --Vp 150 --Sp 0.3 --yv 0.35 --S 0.15 --D-mm 80 --json
python3 - "$work/out.txt" <<'PY' || bad "adaptive-speed spindle speed json: $(cat "$work/out.txt")"
import json, sys
j = json.load(open(sys.argv[1]))
assert abs(j["results"]["n_opt_rpm"] - 760.697) < 1e-3, j["results"]
assert j["inputs"]["D_mm"] == 80, j["inputs"]
PY
# Handbook (Kosilova & Meshcheryakov, vol. 2, table 17), steel 45, T15K6, s <= 0.7 mm/rev:
# Cv = 350, xv = 0.15, yv = 0.35, m = 0.2; t = 3 mm, s = 0.5 mm/rev, T = 60 min:
# V = 350/(60^0.2·3^0.15·0.5^0.35) = 350/(2.267933·1.179148·0.784584) = 350/2.098157 = 166.813 m/min;
# back: T at V = 166.813 is 60 min (60.0001); s = F/n = 150/1000 = 0.15 mm/rev.
expect_rc 0 "adaptive-speed tool life" $bin design adaptive-speed --Cv 350 --m 0.2 --xv 0.15 --yv 0.35 \
  --t 3 --s 0.5 --T-target 60 --V 166.813 --F 150 --n 1000 --json
python3 - "$work/out.txt" <<'PY' || bad "adaptive-speed tool-life json: $(cat "$work/out.txt")"
import json, sys
r = json.load(open(sys.argv[1]))["results"]
assert abs(r["speed_for_life_m_per_min"] - 166.813) < 1e-3, r
assert abs(r["tool_life_min"] / 60 - 1) < 1e-4, r
assert abs(r["feed_per_rev_mm_per_rev"] - 0.15) < 1e-12, r
assert "V_opt_m_per_min" not in r
PY
# The same from the material file: steel_45's range s <= 0.7 holds Cv = 350, m = 0.2, xv = 0.15,
# yv = 0.35 → 166.813 m/min. V_opt at S = 0.2 uses the range s <= 0.3 (yv = 0.20):
# 150·(0.3/0.2)^0.2 = 150·1.5^0.2 = 150·e^(0.2·0.405465) = 150·1.084472 = 162.671 m/min.
expect_rc 0 "adaptive-speed material" $bin design adaptive-speed --material steel_45 --t 3 --s 0.5 \
  --T-target 60 --Vp 150 --Sp 0.3 --S 0.2 --json
python3 - "$work/out.txt" <<'PY' || bad "adaptive-speed material json: $(cat "$work/out.txt")"
import json, sys
j = json.load(open(sys.argv[1]))
r, c = j["results"], j["coefficients"]
assert abs(r["speed_for_life_m_per_min"] - 166.813) < 1e-3, r
assert abs(r["V_opt_m_per_min"] - 162.671) < 1e-3, r
assert c["tool_life"]["Cv"] == 350 and c["tool_life"]["range_feed_max_mm_per_rev"] == 0.7, c
assert c["V_opt"]["yv"] == 0.2 and j["inputs"]["material"] == "steel_45", j
PY
# Seed 004's setters by the handbook (tests/design/adaptive_speed_test.cpp works it by hand):
# steel 45, t_p = 3 mm, T = 60 min, Pz ≤ 2500 N → S_p = 0.504040 mm/rev, V_p = 166.344 m/min.
expect_rc 0 "planned-mode" $bin design planned-mode --material steel_45 --t 3 --force-limit 2500 --json
python3 - "$work/out.txt" <<'PY' || bad "planned-mode json: $(cat "$work/out.txt")"
import json, sys
j = json.load(open(sys.argv[1]))
r = j["results"]
assert abs(r["Sp_mm_per_rev"] - 0.504040) < 2e-6, r
assert abs(r["Vp_m_per_min"] - 166.344) < 2e-3, r
assert abs(r["Pz_N"] - 2500) < 1e-6, r
assert j["limit"] == "force limit" and "n_rpm" not in r, j
PY
expect_rc 2 "planned-mode without depth" $bin design planned-mode --material steel_45
grep -q "give the planned depth --t" "$work/err.txt" || bad "planned-mode without depth: $(cat "$work/err.txt")"
expect_rc 0 "adaptive-speed table" $bin design adaptive-speed --F 150 --n 1000
grep -q "feed per revolution.* 0.15 mm/rev" "$work/out.txt" || bad "adaptive-speed table: $(cat "$work/out.txt")"
# missing or bad inputs: exit 2, one line
expect_rc 2 "adaptive-speed without inputs" $bin design adaptive-speed
grep -q "nothing to compute.*--Vp --Sp --yv --S.*--T-target.*--F --n" "$work/err.txt" || bad "adaptive-speed groups message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "adaptive-speed error message is not one line"
expect_rc 2 "adaptive-speed incomplete group" $bin design adaptive-speed --Vp 150 --Sp 0.3 --S 0.15 --json
expect_rc 2 "adaptive-speed unknown material" $bin design adaptive-speed --material unobtainium --t 3 --s 0.5 --T-target 60
grep -q "unknown material 'unobtainium'" "$work/err.txt" || bad "unknown-material message: $(cat "$work/err.txt")"
expect_rc 2 "adaptive-speed negative feed rate" $bin design adaptive-speed --F -150 --n 1000

# design modulation (seed 001's module): b_twin_feed_division's shaft (Ø40 × 600 mm, tool at
# mid-cut 285 mm) and the a0, ω_d, N_c its rig planned on. m_d against the closed form of a
# pinned-pinned beam's first mode, (M/2)/sin²(πx/L); the plan against the rig's (the golden
# summary: S_min 50, ΔS 35.9, Δl 0.096 mm, n_s 5, ω_m/2π = S_p/(2·n_s·Δl) = 1.99306 Hz).
expect_rc 0 "design modulation" $bin design modulation --L-mm 600 --x-mm 285 --a0-um 6 \
  --fd-Hz 227.8 --power-kW 0.449 --json
python3 - "$work/out.txt" <<'PY' || bad "design modulation values"
import json, math, sys
j = json.load(open(sys.argv[1]))["si"]
M = math.pi / 4 * 0.04 ** 2 * 0.6 * 7850
md = M / 2 / math.sin(math.pi * 0.285 / 0.6) ** 2
assert abs(j["m_d_kg"] / md - 1) < 1e-6, (j["m_d_kg"], md)
assert abs(j["S_min_m_per_s"] * 6e4 - 50.0) < 1e-9 and abs(j["dS_m_per_s"] * 6e4 - 35.9) < 1e-9
assert abs(j["dl_m"] - 0.096e-3) < 1e-12 and j["n_s"] == 5
assert abs(j["f_m_Hz"] - 114.8 / 60 / 0.96) < 1e-9
wd, wm = 2 * math.pi * 227.8, 2 * math.pi * j["f_m_Hz"]
assert abs(j["A_P_required_N"] - 1.41 * 6e-6 * md * abs(wd * wd - wm * wm)) < 1e-9
assert abs(j["B_m"] - j["A_P_planned_N"] / (md * abs(wd * wd - wm * wm))) < 1e-15
assert j["limited"] == (j["A_P_planned_N"] < j["A_P_required_N"])
PY
expect_rc 2 "design modulation tool outside the centres" $bin design modulation --L-mm 600 --x-mm 700

# design gauge (seed 003, linearised vibro-contact gauging). Defaults: 24 V, 50 Hz, K_g = 50 V/(m/s),
# T_g = 0.2 ms, T_f = 100 ms, t_r = 20 ms, m_x = 250 µm, a = 20 µm/s, x_k = 100 µm, σ = 2 µm, β = 5.
# K = (2/π)·K_g·2ω/sqrt(1 + (2ω·T_g)²), 2ω = 4π·50 = 628.3185 rad/s:
#   (2/π)·50·628.3185 = 20000.00; 2ω·T_g = 0.1256637, squared 0.0157914; sqrt(1.0157914) = 1.0078648
#   K = 20000/1.0078648 = 19843.93 V/m = 19.84393 mV/µm
# S_th (23) = K·(A0 − x_k − a·(T_f + t_r)), checked with the printed A0 and K; a·(T_f + t_r) = 2.4 µm.
# σ_x = 2/sqrt(1 + 5·0.1) = 1.632993 µm; Cp = 2·10/(6·1.632993) = 2.041241; t_k = 150/20 = 7.5 s.
expect_rc 0 "design gauge json" $bin design gauge --tolerance-um 10 --json
python3 - "$work/out.txt" <<'PY' || bad "design gauge json values: $(cat "$work/out.txt")"
import json, sys
j = json.load(open(sys.argv[1]))
si, shop = j["si"], j["shop"]
assert abs(si["K_V_per_m"] / 19843.93 - 1) < 1e-6, si
assert abs(shop["K_mV_per_um"] - 19.84393) < 1e-5, shop
A0, K = shop["A0_um"], shop["K_mV_per_um"]
assert 250 < A0 < 350 and abs(si["A0_m"] * 1e6 - A0) < 1e-9, (A0, si)
assert abs(shop["S_th_V"] - K * 1e-3 * (A0 - 100 - 20 * (0.1 + 0.02))) < 1e-9, shop
assert abs(si["S_th_V"] - shop["S_th_V"]) < 1e-12
assert abs(shop["S_target_V"] - K * 1e-3 * (A0 - 100)) < 1e-9, shop
assert abs(shop["t_k_s"] - 7.5) < 1e-9, shop
assert abs(shop["sigma_x_um"] - 1.632993) < 1e-6, shop
assert abs(shop["sigma_y_mV"] - K * shop["sigma_x_um"]) < 1e-9, shop
assert abs(si["D_y_V2"] - si["sigma_y_V"] ** 2) < 1e-15, si
assert abs(si["D_y_V2"] - 4e-12 * si["K_V_per_m"] ** 2 / 1.5) < 1e-12, si
assert abs(shop["Cp"] - 2.041241) < 1e-6 and si["Cp"] == shop["Cp"], shop
assert j["inputs"]["allowance_um"] == 250 and j["inputs"]["tolerance_um"] == 10, j["inputs"]
PY
# the shop-unit options reach the formulas: T_f = 50 ms, relay 0, a = 10 µm/s → S_th = K·(A0 − x_k − 0.5 µm)
expect_rc 0 "design gauge options" $bin design gauge --filter-ms 50 --relay-ms 0 --removal-um-per-s 10 \
  --target-um 80 --noise-sigma-um 3 --noise-beta 10 --json
python3 - "$work/out.txt" <<'PY' || bad "design gauge options json: $(cat "$work/out.txt")"
import json, sys
shop = json.load(open(sys.argv[1]))["shop"]
A0, K = shop["A0_um"], shop["K_mV_per_um"]
assert abs(shop["S_th_V"] - K * 1e-3 * (A0 - 80 - 0.5)) < 1e-9, shop
assert abs(shop["t_k_s"] - 17.0) < 1e-9, shop  # (250 − 80)/10
assert abs(shop["sigma_x_um"] - 3 / 1.5 ** 0.5) < 1e-9, shop  # 1 + β·T_f = 1.5 again
assert "Cp" not in shop
PY
expect_rc 0 "design gauge table" $bin design gauge --tolerance-um 10
for row in "free amplitude A0" "signal gain K .* 19.8439 mV/µm" "threshold S_th (23)" \
           "end of cut t_k (22) .* 7.5 s" "signal noise D_y (25)" "size scatter σ_x .* 1.63299 µm" \
           "Cp = 2·tol/(6·σ_x) .* 2.04124"; do
  grep -q "$row" "$work/out.txt" || bad "design gauge table lacks '$row': $(cat "$work/out.txt")"
done
# bad input: exit 2, one line
expect_rc 2 "design gauge target above allowance" $bin design gauge --target-um 300
grep -q "target-um.*allowance-um" "$work/err.txt" || bad "gauge target message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "gauge error message is not one line"
expect_rc 2 "design gauge no threshold left" $bin design gauge --allowance-um 400 --target-um 297
grep -q "S_th.*A0" "$work/err.txt" || bad "gauge threshold message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "gauge threshold message is not one line"
expect_rc 2 "design gauge negative mass" $bin design gauge --probe-mass-g -1
grep -q "^error: design gauge: --probe-mass-g" "$work/err.txt" || bad "gauge mass message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "gauge option message is not one line"
expect_rc 2 "design gauge not a number" $bin design gauge --filter-ms fast
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "gauge non-number message is not one line"
expect_rc 2 "design gauge zero tolerance" $bin design gauge --tolerance-um 0
# Hostile numbers end in one line naming the flag, at once (tests/cli/design_hostile.sh
# tries every flag of every calculator with 0, -1, nan, inf, 1e300, 1e-300)
expect_rc 2 "design pulse dt > T" $bin design pulse-regulator --dt-ms 60 --T-ms 50
grep -q "^error: design pulse-regulator: --dt-ms 60 exceeds the period --T-ms 50" "$work/err.txt" || bad "pulse dt > T: $(cat "$work/err.txt")"
expect_rc 2 "design pulse dt > 1/f" $bin design pulse-regulator --dt-ms 60 --f-Hz 20
grep -q "^error: design pulse-regulator: --dt-ms 60 exceeds the period 1/--f-Hz" "$work/err.txt" || bad "pulse dt > 1/f: $(cat "$work/err.txt")"
expect_rc 2 "design gauge slow filter, at once" timeout 5 $bin design gauge --filter-ms 1e6
grep -q "^error: design gauge: --filter-ms 1e6: expected a finite number in (0, 10000\]" "$work/err.txt" || bad "gauge slow filter: $(cat "$work/err.txt")"
expect_rc 2 "design gauge stiff contact, at once" timeout 5 $bin design gauge --contact-stiffness-N-per-mm 1e7 --probe-mass-g 0.01
grep -q "^error: design gauge: --contact-stiffness-N-per-mm, --probe-mass-g, --supply-Hz: the full model would simulate" "$work/err.txt" || bad "gauge stiff contact: $(cat "$work/err.txt")"
expect_rc 2 "design planned-mode tool life 1e-300" $bin design planned-mode --material steel_45 --t 3 --T-life 1e-300 --D-mm 80
grep -q "^error: design planned-mode: --T-life 1e-300: expected a finite number in \[0.1, 100000\]" "$work/err.txt" || bad "planned-mode T-life: $(cat "$work/err.txt")"
expect_rc 2 "design planned-mode limit at the smallest feed" $bin design planned-mode --material steel_45 --t 3 --force-limit 1
grep -q "^error: design planned-mode: even the smallest feed breaks the force limit (--force-limit)" "$work/err.txt" || bad "planned-mode smallest feed: $(cat "$work/err.txt")"
# A threshold below the probe's bounce floor is refused (and --force computes it);
# `check` refuses the same set-up at process.target_um, runs it with gauge.force_threshold.
expect_rc 2 "design gauge near A0" $bin design gauge --allowance-um 290 --target-um 254
grep -q "bounce floor.*safe range ends at --target-um" "$work/err.txt" || bad "gauge floor message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "gauge floor message is not one line"
expect_rc 0 "design gauge near A0 forced" $bin design gauge --allowance-um 290 --target-um 254 --force --json
grep -q '"in_range": false' "$work/out.txt" || bad "gauge forced json: $(cat "$work/out.txt")"
sed -e 's/^threshold = "seed"/threshold = "seed"/' -e '/^force_threshold = true/d' "$src/examples/scenarios/d_near_a0.toml" > "$work/near_a0.toml"
expect_rc 2 "check near A0" $bin check "$work/near_a0.toml"
grep -q "key 'process.target_um'.*force_threshold" "$work/err.txt" || bad "near A0 message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "near A0 message is not one line"

# design tracer (seed 002, linearised tracer slide). E0 = 2000 N/mm = 2e6 N/m, C0 = 20 1/s,
# M = 100 kg, i = 3, P0 = 500 N, β = 45°, α = 30°, s = 0.3 mm/rev, n = 600 rpm:
#   V_pr = 0.3·600/60 = 3 mm/s = 180 mm/min
#   v_T = 3·sin 30°/sin 75° = 1.5/0.9659258 = 1.5529143 mm/s = 93.17486 mm/min
#   P0/E0 = 500/2000 = 0.25 mm = 250 µm;  v_T/C0 = 1.5529143/20 mm = 77.64571 µm
#   h on the cone (9) = 250 + 77.64571 = 327.64571 µm; q_ss = 327.64571/3 = 109.21524 µm
#   static P0/(E0·i) = 250/3 = 83.33333 µm; dynamic v_T/(C0·i) = 25.88190 µm
#   seed (12): δx = 25.88190·sin 75°/sin 30° = 50.00000 µm (= V_pr/(C0·i) = 3/60 mm)
#   seed (13): δy = −25.88190·sin 75°/cos 30° = −28.86751 µm (= −V_pr·tan 30°/(C0·i))
#   Fig. 1a at V_k = v_T: P = E0·(h − v_T/C0) is P0 = 500 N at h = 327.64571 µm (the 11th of 21
#   points from 0 to 2h); Fig. 1b at P = P0: V_k = C0·(h − P0/E0) is v_T = 1.5529143 mm/s there
#   ζ = sqrt(2e6/(100·3))/(2·20) = sqrt(6666.667)/40 = 81.64966/40 = 2.041241 → aperiodic
#   ω_n = sqrt(3·2e6/100) = sqrt(60000) = 244.94897 rad/s → f_n = 38.98484 Hz
#   cylinder→cone, aperiodic: no overshoot, peak dynamic lag = 25.88190 µm. Roots
#   λ = −ω_n(ζ ∓ sqrt(ζ² − 1)) = −64.11011, −935.88989 1/s; with q(0) = 0, q̇(0) = v_T = 60·q_dyn:
#   slow coefficient c1 = (60 − 935.88989)/(935.88989 − 64.11011)·q_dyn = −1.0047146·q_dyn,
#   2 % band: τ = ln(1.0047146/0.02)/64.11011 = 61.094 ms (the scan samples it: ±0.1 %)
expect_rc 0 "design tracer json" $bin design tracer --E0 2000 --C0 20 --M 100 --i 3 --P0 500 \
  --beta-deg 45 --alpha-deg 30 --s 0.3 --n 600 --characteristics "$work/fig1.csv" --json
python3 - "$work/out.txt" "$work/fig1.csv" <<'PY' || bad "design tracer json values: $(cat "$work/out.txt")"
import csv, json, sys
j = json.load(open(sys.argv[1]))
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == 84 and rows[0]["figure"] == "1a" and rows[-1]["figure"] == "1b", rows[:2]
op_a = [r for r in rows if r["figure"] == "1a" and r["held"] == "V_k_mm_per_s" and float(r["held_value"]) > 0][10]
op_b = [r for r in rows if r["figure"] == "1b" and float(r["held_value"]) == 500][10]
assert abs(float(op_a["h_mm"]) - 0.32764571) < 1e-8 and abs(float(op_a["P_N"]) - 500) < 1e-6, op_a
assert abs(float(op_b["V_k_mm_per_s"]) - 1.5529143) < 1e-6, op_b
assert j["inputs"]["characteristics"] == sys.argv[2]
j["inputs"].pop("characteristics")
si, shop, inp = j["si"], j["shop"], j["inputs"]
def near(a, b, rel=1e-6): assert abs(a / b - 1) < rel, (a, b)
near(shop["V_pr_mm_per_min"], 180); near(si["V_pr_m_per_s"], 3e-3)
near(shop["v_T_mm_per_min"], 93.17486); near(si["v_T_m_per_s"], 1.5529143e-3)
near(shop["q_ss_um"], 109.21524); near(si["q_ss_m"], 109.21524e-6)
near(shop["h_cone_um"], 327.64571); near(shop["dx_um"], 50.0); near(shop["dy_um"], -28.86751)
assert "q_ss_axial_um" not in shop  # the lag's axial component is not the seed's δx (issue 48)
near(shop["q_static_um"], 83.33333); near(shop["q_dynamic_um"], 25.88190)
near(shop["zeta"], 2.041241); near(si["zeta"], 2.041241)
near(si["omega_n_rad_per_s"], 244.94897); near(shop["f_n_Hz"], 38.98484)
assert si["aperiodic"] is True and shop["aperiodic"] is True
near(shop["transient_peak_lag_um"], 25.88190)
near(shop["settling_time_ms"], 61.094, 1e-3); near(si["settling_time_s"], 61.094e-3, 1e-3)
assert inp == {"E0_N_per_mm": 2000, "C0_per_s": 20, "M_kg": 100, "i": 3, "P0_N": 500,
               "beta_deg": 45, "alpha_deg": 30, "s_mm_per_rev": 0.3, "n_rpm": 600}, inp
PY
# underdamped (C0 = 60 1/s → ζ = 0.680414 < 1): not aperiodic, and the peak overshoots v_T/(C0·i)
expect_rc 0 "design tracer underdamped" $bin design tracer --C0 60 --json
python3 - "$work/out.txt" <<'PY' || bad "design tracer underdamped json: $(cat "$work/out.txt")"
import json, sys
shop = json.load(open(sys.argv[1]))["shop"]
assert abs(shop["zeta"] - 2.041241 / 3) < 1e-6 and shop["aperiodic"] is False, shop
assert shop["transient_peak_lag_um"] > shop["q_dynamic_um"] * 1.01, shop
PY
expect_rc 0 "design tracer table" $bin design tracer
for row in "steady lag q_ss (along slide) .* 109.215 µm" "damping ratio ζ .* 2.04124" \
           "(12) δx at equal y .* 50 µm" "(13) δy at equal x .* -28.8675 µm" \
           "natural frequency ω_n/2π .* 38.9848 Hz" "aperiodic (ζ ≥ 1) .* yes"; do
  grep -q "$row" "$work/out.txt" || bad "design tracer table lacks '$row': $(cat "$work/out.txt")"
done
# bad input: exit 2, one line naming the command
expect_rc 2 "design tracer cannot follow" $bin design tracer --alpha-deg -50 --beta-deg 45
grep -q "^error: design tracer: the slide cannot follow" "$work/err.txt" || bad "tracer follow message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "tracer error message is not one line"
expect_rc 2 "design tracer alpha+beta >= 180" $bin design tracer --alpha-deg 90 --beta-deg 90
expect_rc 2 "design tracer negative mass" $bin design tracer --M -1
grep -q "^error: design tracer: --M" "$work/err.txt" || bad "tracer mass message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "tracer option message is not one line"
expect_rc 2 "design tracer not a number" $bin design tracer --E0 stiff
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "tracer non-number message is not one line"
expect_rc 2 "design tracer zero feed" $bin design tracer --s 0
expect_rc 2 "design tracer beta out of range" $bin design tracer --beta-deg 0
# on a cylinder (α = 0) there is no δx at equal y: left out, not nan
expect_rc 0 "design tracer cylinder" $bin design tracer --alpha-deg 0 --json
python3 -c 'import json,sys; s=json.load(open(sys.argv[1]))["shop"]; assert "dx_um" not in s and s["dy_um"] == 0, s' \
  "$work/out.txt" || bad "design tracer cylinder: $(cat "$work/out.txt")"

# stability lobes: the SDOF example against its closed form 2kζ(1+ζ)/(K_f cos²θ) = 7.3188 mm
expect_rc 0 "lobes" $bin lobes "$src/examples/machines/b_sdof.toml" --out "$work/lobes"
python3 - "$work/lobes/lobes.json" <<'PY' || bad "lobes.json"
import json, sys
j = json.load(open(sys.argv[1]))
assert abs(j["critical_depth_mm"] / 7.318784 - 1) < 1e-4, j["critical_depth_mm"]
assert all(k in j["lobes"][0] for k in ("N", "min_speed_rpm", "depth_mm"))
assert j["semi_discretization_max_rel_difference"] < 0.01, j["semi_discretization_max_rel_difference"]
PY
for f in lobes.csv lobes.html; do [ -s "$work/lobes/$f" ] || bad "missing $f"; done
# No inf in lobes.csv: a depth no lobe bounds is an empty cell (b_sdof's envelope is undefined at
# the range's ends).
grep -qi "inf" "$work/lobes/lobes.csv" && bad "inf in lobes.csv"
grep -q "^2000,$" "$work/lobes/lobes.csv" || bad "the unbounded envelope at 2000 rpm is not an empty cell"
# A machine measured by tap tests (CSV and UFF 58, relative to the machine file), and the
# recommendation: three pockets, each a speed, a depth and margins, within the 15 kW spindle.
expect_rc 0 "lobes --recommend on FRFs" $bin lobes "$src/examples/machines/b_frf.toml" --out "$work/lobes-frf" --recommend
grep -q "^  3\. [0-9]* rpm, depth [0-9.]* mm (power-limited" "$work/out.txt" || bad "recommendation: $(cat "$work/out.txt")"
grep -q "Measured against fitted FRF" "$work/lobes-frf/lobes.html" || bad "no measured-vs-fitted FRF plot"
printf '[cutting]\nkf_N_per_mm2 = 1000\n[speed]\nmin_rpm = 1\nmax_rpm = 2\n' > "$work/nomode.toml"
expect_rc 2 "lobes without a mode" $bin lobes "$work/nomode.toml" --out "$work/never"
grep -q "nomode.toml:.*at least one \[\[mode\]\], \[\[frf\]\] or a \[part\]" "$work/err.txt" || bad "no-mode message: $(cat "$work/err.txt")"
# the SD chart (200 speeds × 100 depths) agrees with the frequency-domain envelope
python3 - "$work/lobes/lobes.json" <<'PY' || bad "lobes.json sd_chart"
import json, sys
c = json.load(open(sys.argv[1]))["sd_chart"]
assert c["speeds"] == 200 and c["depths"] == 100, c
assert c["compared_speeds"] > 80 and c["max_rel_difference_vs_frequency_domain"] < 0.01, c
PY
grep -q "^speed_rpm,depth_mm,sd_unstable_roots$" "$work/lobes/lobes.csv" || bad "lobes.csv has no SD chart"
# two modes in different directions (Altintas' example): 7.18498 mm, chart within 1.5 %
expect_rc 0 "lobes two modes" $bin lobes "$src/examples/machines/b_two_mode.toml" --out "$work/lobes2"
python3 - "$work/lobes2/lobes.json" <<'PY' || bad "two-mode lobes.json"
import json, sys
j = json.load(open(sys.argv[1]))
assert abs(j["critical_depth_mm"] / 7.18498 - 1) < 1e-5, j["critical_depth_mm"]
assert abs(j["lobes"][0]["chatter_frequency_Hz"] - 151.5) < 0.5, j["lobes"][0]
assert j["sd_chart"]["max_rel_difference_vs_frequency_domain"] < 0.015, j["sd_chart"]
assert j["semi_discretization_max_rel_difference"] < 0.01, j["semi_discretization_max_rel_difference"]
PY
# the slender part between centres: the limit along the part, lowest mid-span, symmetric
expect_rc 0 "lobes part" $bin lobes "$src/examples/machines/b_part.toml" --out "$work/lobes3"
python3 - "$work/lobes3/lobes.json" <<'PY' || bad "part lobes.json"
import json, sys
j = json.load(open(sys.argv[1]))
a = j["part"]["along_part"]
d = {round(p["position_mm"]): p["critical_depth_mm"] for p in a}
assert min(d, key=d.get) == 250 and abs(d[250] - j["critical_depth_mm"]) < 1e-9, d
assert abs(d[100] / d[400] - 1) < 1e-6 and d[50] > 10 * d[250], d
assert abs(a[0]["first_mode_Hz"] - 243.7) < 0.5, a[0]
assert j["sd_chart"]["max_rel_difference_vs_frequency_domain"] < 0.015, j["sd_chart"]
assert j["semi_discretization_max_rel_difference"] < 0.01, j["semi_discretization_max_rel_difference"]
PY
grep -q "^position_mm,critical_depth_mm$" "$work/lobes3/lobes.csv" || bad "lobes.csv has no along-part section"
grep -q "Critical depth along the part" "$work/lobes3/lobes.html" || bad "report has no along-part plot"
# bad part input: exit 2, one line naming file, line and key
part="$src/examples/machines/b_part.toml"
sed 's/^length_mm = 500/lenght_mm = 500/' "$part" > "$work/part_key.toml"
expect_rc 2 "part unknown key" $bin lobes "$work/part_key.toml" --out "$work/never"
grep -q "part_key.toml:[0-9]*:[0-9]*: .*'part.length_mm'" "$work/err.txt" || bad "part missing-key message: $(cat "$work/err.txt")"
sed 's/^length_mm = 500/length_mm = 500\nlength_m = 0.5/' "$part" > "$work/part_extra.toml"
expect_rc 2 "part extra key" $bin lobes "$work/part_extra.toml" --out "$work/never"
grep -q "part_extra.toml:[0-9]*:[0-9]*: unknown key 'part.length_m'" "$work/err.txt" || bad "part unknown-key message: $(cat "$work/err.txt")"
[ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "part error message is not one line"
sed 's/^position_mm = 250/position_mm = 500/' "$part" > "$work/part_pos.toml"
expect_rc 2 "part position on a centre" $bin lobes "$work/part_pos.toml" --out "$work/never"
grep -q "part_pos.toml:[0-9]*:[0-9]*: key 'part.position_mm'" "$work/err.txt" || bad "part position message: $(cat "$work/err.txt")"
sed 's/^positions_mm = \[25,/positions_mm = [-25,/' "$part" > "$work/part_positions.toml"
expect_rc 2 "part positions outside" $bin lobes "$work/part_positions.toml" --out "$work/never"
grep -q "key 'part.positions_mm'" "$work/err.txt" || bad "part positions message: $(cat "$work/err.txt")"
sed 's/^modes = 3/modes = "three"/' "$part" > "$work/part_modes.toml"
expect_rc 2 "part modes not an integer" $bin lobes "$work/part_modes.toml" --out "$work/never"
grep -q "key 'part.modes'" "$work/err.txt" || bad "part modes message: $(cat "$work/err.txt")"
sed 's/^chart_speeds = 60/chart_speeds = 1/' "$part" > "$work/part_chart.toml"
expect_rc 2 "chart with one speed" $bin lobes "$work/part_chart.toml" --out "$work/never"
grep -q "key 'lobes.chart_speeds'" "$work/err.txt" || bad "chart speeds message: $(cat "$work/err.txt")"
[ ! -e "$work/never" ] || bad "a failed lobes run wrote output"
# Machine files that ended in "internal error", SIGSEGV, a hang or the OOM killer: each
# is one line at file:line:col naming its key, exit 2, before anything is computed or written.
for f in "$src"/fuzz/regressions/lobes/*.toml; do
  expect_rc 2 "lobes regression $(basename "$f")" $bin lobes "$f" --out "$work/never"
  grep -q "^error: $f:[0-9]*:[0-9]*: key '" "$work/err.txt" || bad "lobes regression $(basename "$f"): $(cat "$work/err.txt")"
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "lobes regression $(basename "$f"): not one line"
done
[ ! -e "$work/never" ] || bad "a refused lobes run wrote output"

# system B: the twin-turret example answers its claims, with the summary's required shape
expect_rc 0 "run b_twin_feed_division" $bin run "$src/examples/scenarios/b_twin_feed_division.toml" --out "$work/twin"
python3 - "$work/twin/summary.json" <<'PY' || bad "system B summary.json"
import json, sys
s = json.load(open(sys.argv[1]))
m = s["metrics"]
assert s["system"] == "B"
v = m["vibration_amplitude_um"]
assert v["without"] > 5.0 and (v["with"] < 5.0 or v["without"] / v["with"] >= 5.0), v
assert abs(m["chatter_frequency_Hz"] / m["linear_limits"]["chatter_Hz"] - 1) < 0.05, m["chatter_frequency_Hz"]
for k in ("S_min_mm_per_min", "dS_mm_per_min", "dl_mm", "n_s"):
    assert k in m["modulation"], k
assert abs(round(m["modulation"]["dS_mm_per_min"] / 0.1) * 0.1 - m["modulation"]["dS_mm_per_min"]) < 1e-9
f = m["mean_feed_mm_per_min"]
assert abs(f["right"] / f["programmed"] - 1) < 0.1, f
assert m["cutting_power_W"]["measured"] > 0
assert m["linear_limits"]["feed_division_feed_mm_per_rev"] < 0.14 < m["linear_limits"]["single_tool_feed_mm_per_rev"]
PY
sed 's/^setup = "feed_division"/setup = "twin"/' "$src/examples/scenarios/b_twin_feed_division.toml" > "$work/bad_b.toml"
expect_rc 2 "system B bad set-up" $bin check "$work/bad_b.toml"
grep -q "bad_b.toml:[0-9]*:[0-9]*: key 'cut.setup'" "$work/err.txt" || bad "system B message: $(cat "$work/err.txt")"

# --- Failures said in one line, at the key or flag that decides them ---------------------------
one_line() { [ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "$1: not one line: $(cat "$work/err.txt")"; }
scn="$src/examples/scenarios"
# cross-field (rig) checks: file:line:col and the deciding key, not "inconsistent scenario"
sed -e 's/^step_s = .*/step_s = 0.01/' -e 's/^record_interval_s = .*/record_interval_s = 0.01/' "$scn/a_finishing_aim.toml" > "$work/coarse_a.toml"
sed -e 's/^step_s = .*/step_s = 0.005/' -e 's/^record_interval_s = .*/record_interval_s = 0.005/' "$scn/c_dead_zone.toml" > "$work/coarse_c.toml"
sed -e 's/^step_s = .*/step_s = 1e-3\nrecord_interval_s = 1e-3/' "$scn/d_gauging.toml" > "$work/coarse_d.toml"
sed -e '/^\[regulator\]/,/^\[/ s/^type = "pulsed"/type = "throttle"/' "$scn/a_finishing_aim.toml" > "$work/throttle_aim.toml"
# the core names its own parameter (tool2_lag_mm, magnet_gap_m); the system maps it to its key
sed -e 's/^tool2_lag_mm = .*/tool2_lag_mm = 30.0/' "$scn/b_twin_depth_division.toml" > "$work/lag_b.toml"
sed -e 's/^magnet_gap_mm = .*/magnet_gap_mm = 0.1/' "$scn/d_gauging.toml" > "$work/gap_d.toml"
for c in "coarse_a.toml:9:[0-9]*: key 'run.step_s': step_s .* too coarse" \
         "coarse_c.toml:7:[0-9]*: key 'run.step_s': step too coarse" \
         "coarse_d.toml:16:[0-9]*: key 'run.step_s': vibro-contact gauge: step too coarse" \
         "throttle_aim.toml:66:[0-9]*: key 'controller.type': a continuous throttle" \
         "lag_b.toml:41:[0-9]*: key 'cut.tool2_lag_mm': tool2_lag_mm is more than 200 revolutions" \
         "gap_d.toml:44:[0-9]*: key 'transducer.magnet_gap_mm': vibro-contact gauge: the gap"; do
  f=${c%%:*}
  expect_rc 2 "cross-field $f" $bin check "$work/$f"
  grep -q "^error: $work/$c" "$work/err.txt" || bad "cross-field $f: $(cat "$work/err.txt")"
  grep -q "inconsistent" "$work/err.txt" && bad "cross-field $f still 'inconsistent': $(cat "$work/err.txt")"
  one_line "cross-field $f"
done
# command line: one line, the command and the flag named
expect_rc 2 "unknown command" $bin frobnicate
grep -qx "error: unknown command 'frobnicate' (run, check, demo, lobes, report, design, reference, compare, optimize, reasons, systems, sweep)" "$work/err.txt" || bad "unknown command: $(cat "$work/err.txt")"
one_line "unknown command"
expect_rc 2 "unknown design command" $bin design frob
grep -qx "error: unknown command 'design frob' (pulse-regulator, adaptive-speed, planned-mode, gauge, tracer, modulation)" "$work/err.txt" || bad "unknown design command: $(cat "$work/err.txt")"
expect_rc 2 "no command" $bin
one_line "no command"
expect_rc 2 "run without scenario" $bin run
grep -qx "error: run: scenario is required" "$work/err.txt" || bad "run without scenario: $(cat "$work/err.txt")"
expect_rc 2 "unknown option" $bin check x.toml --bogus
one_line "unknown option"
expect_rc 2 "--d-mm nan" $bin design pulse-regulator --d-mm nan --T-ms 50
grep -qx "error: design pulse-regulator: --d-mm nan: expected a finite number in \[0.001, 1000\] (spool diameter d)" "$work/err.txt" || bad "--d-mm nan: $(cat "$work/err.txt")"
expect_rc 2 "--Py nan" $bin design pulse-regulator --T-ms 50 --Py nan
grep -q "^error: design pulse-regulator: --Py nan: expected a finite number in \[-1e+07, 1e+07\] (radial cutting force Py)$" "$work/err.txt" || bad "--Py nan: $(cat "$work/err.txt")"
expect_rc 2 "run a directory" $bin run "$scn" --out "$work/never"
grep -qx "error: $scn: is a directory, expected a scenario file (.toml)" "$work/err.txt" || bad "run directory: $(cat "$work/err.txt")"
# The CPU time (user + system, ms) this shell's finished children have used so far, into $cpu_ms
# (bash's times, run in this shell: a $(...) would ask a subshell with no children).
children_cpu_ms() {
  times > "$work/times.txt"
  cpu_ms=$(awk 'NR == 2 { n = 0; for (i = 1; i <= 2; ++i) { split($i, a, /[ms]/); n += a[1] * 60000 + a[2] * 1000 } printf "%d", n }' "$work/times.txt")
}
# --out problems: found before the simulation, exit 2, one line naming the flag and the path
# (a file, and a directory of someone else's files: never the source tree, should a bug write there)
echo text > "$work/afile"; mkdir -p "$work/precious"; echo keep > "$work/precious/notes.txt"
for o in /proc/x "$work/afile" "$work/precious"; do
  for c in "run $scn/b_twin_feed_division.toml" "lobes $src/examples/machines/b_sdof.toml" "demo"; do
    [ "$o" != "$work/precious" ] || [ "${c%% *}" = run ] || continue  # only a run's set replaces a whole directory
    children_cpu_ms; c0=$cpu_ms
    expect_rc 2 "$c --out $o" $bin $c --out "$o"
    children_cpu_ms; ms=$(( cpu_ms - c0 ))
    grep -q "^error: --out $o: " "$work/err.txt" || bad "$c --out $o: $(cat "$work/err.txt")"
    one_line "$c --out $o"
    # CPU time, not wall time: a loaded machine must not fail this, a simulation run would.
    [ "$ms" -lt 3000 ] || bad "$c --out $o: found after ${ms} ms of CPU (after the simulation?)"
  done
done
expect_rc 2 "--out a foreign directory" $bin run "$scn/a_roughing_aim.toml" --out "$work/precious"
[ "$(cat "$work/precious/notes.txt")" = keep ] && [ "$(ls -A "$work/precious")" = notes.txt ] || bad "a foreign --out directory was touched"
# lobes writes its set (lobes.json/csv/html) as a whole too: the same foreign directory is refused
# untouched, and a second machine's lobes replace the first's whole (one marker, three files).
expect_rc 2 "lobes --out a foreign directory" $bin lobes "$src/examples/machines/b_sdof.toml" --out "$work/precious"
[ "$(ls -A "$work/precious")" = notes.txt ] || bad "lobes touched a foreign --out directory"
expect_rc 0 "lobes over a lobes set" $bin lobes "$src/examples/machines/b_two_mode.toml" --out "$work/lobes"
[ "$(ls -A "$work/lobes" | sort | tr '\n' ' ')" = ".lathectl-output lobes.csv lobes.html lobes.json " ] ||
  bad "lobes set after a second run: $(ls -A "$work/lobes" | tr '\n' ' ')"
grep -q '"critical_depth_mm": 7.18' "$work/lobes/lobes.json" || bad "the second machine's lobes.json replaced the first's"
if [ "$(id -u)" -ne 0 ]; then  # root writes anywhere
  mkdir -p "$work/ro"; chmod 555 "$work/ro"
  expect_rc 2 "--out not writable" $bin run "$scn/a_roughing_aim.toml" --out "$work/ro/x"
  grep -q "^error: --out $work/ro/x: " "$work/err.txt" || bad "unwritable --out: $(cat "$work/err.txt")"
  chmod 755 "$work/ro"
fi

# --- A run's output set appears as a whole; a kill never leaves a mix, nor temporaries --------
same_set() {  # dir ref: every file of dir equals ref's, and they hold the same names
  diff -r "$1" "$2" >/dev/null 2>&1
}
$bin run "$scn/a_roughing_aim.toml" --out "$work/refA" >/dev/null 2>&1 || bad "refA run"
$bin run "$scn/a_finishing_aim.toml" --out "$work/refB" >/dev/null 2>&1 || bad "refB run"
same_set "$work/refA" "$work/refB" && bad "the two reference sets do not differ"
for point in channels.csv report.html summary.json swapped; do
  rm -rf "$work/set" "$work"/set.*; cp -r "$work/refA" "$work/set"
  (LATHECTL_TEST_KILL_AT=$point exec $bin run "$scn/a_finishing_aim.toml" --out "$work/set" >/dev/null 2>&1)
  rc=$?; [ "$rc" -eq 137 ] || bad "kill at $point: exit $rc, expected 137 (SIGKILL)"
  if [ "$point" = swapped ]; then same_set "$work/set" "$work/refB" || bad "kill after the swap: not the new set"
  else same_set "$work/set" "$work/refA" || bad "kill at $point: the old set is not intact: $(diff -rq "$work/set" "$work/refA")"; fi
  # a dead run's 2 MB temporary inside the set, as older versions left them
  deadpid=$(sh -c 'echo $$'); head -c 2000000 /dev/zero > "$work/set/channels.csv.tmp.$deadpid"
  expect_rc 0 "run after a kill at $point" $bin run "$scn/a_roughing_aim.toml" --out "$work/set"
  same_set "$work/set" "$work/refA" || bad "after a kill at $point: the next run's set is not whole: $(diff -rq "$work/set" "$work/refA")"
  left=$(ls -A "$work" | grep -E '^set\.(tmp|old)-'; ls -A "$work/set" | grep -E '\.tmp[.-]')
  [ -z "$left" ] || bad "after a kill at $point: temporaries left: $left"
done
# a real kill -9 at random moments of runs writing into the same directory: old or new, never mixed
rm -rf "$work/set" "$work"/set.*; cp -r "$work/refA" "$work/set"
for delay in 0.05 0.1 0.15 0.2 0.25 0.3 0.35 0.4; do
  $bin run "$scn/a_finishing_aim.toml" --out "$work/set" >/dev/null 2>&1 & p=$!
  sleep $delay; kill -9 $p 2>/dev/null; wait $p 2>/dev/null
  if [ -e "$work/set" ]; then same_set "$work/set" "$work/refA" || same_set "$work/set" "$work/refB" || bad "kill -9 after ${delay}s: a mixed set: $(diff -rq "$work/set" "$work/refA")"; fi
  $bin run "$scn/a_roughing_aim.toml" --out "$work/set" >/dev/null 2>&1 || bad "run after kill -9"
done
left=$(ls -A "$work" | grep -E '^set\.(tmp|old)-'; ls -A "$work/set" | grep -E '\.tmp[.-]')
[ -z "$left" ] || bad "after kill -9: temporaries left: $left"
# channels.csv streams to disk as the run records: a disk-space check before the run
# replaces the row limit; no room → exit 2 at run.duration_s, nothing written, no stage left
for f in e_sensor_dropout a_finishing_aim b_twin_offset; do
  rm -rf "$work/full" "$work"/full.*
  expect_rc 2 "no room for $f's channels" env LATHECTL_TEST_FREE_BYTES=100000 $bin run "$scn/$f.toml" --out "$work/full"
  grep -q "^error: $scn/$f.toml:[0-9]*:[0-9]*: key 'run.duration_s': channels.csv of up to .* more than the 0.0001 GB free" "$work/err.txt" || bad "no room for $f: $(cat "$work/err.txt")"
  one_line "no room for $f"
  left=$(ls -A "$work" | grep -E '^full')
  [ -z "$left" ] || bad "no room for $f: left $left"
done
# C and D stream too, checked at the key that sets their length (before any simulation)
for fk in c_stepped_tapered_fast:run.record_interval_s:channels.csv d_near_a0:monte_carlo.parts:channels.csv; do
  f=${fk%%:*}; k=${fk#*:}; file=${k#*:}; k=${k%%:*}
  rm -rf "$work/full" "$work"/full.*
  expect_rc 2 "no room for $f's channels" env LATHECTL_TEST_FREE_BYTES=100000 $bin run "$scn/$f.toml" --out "$work/full"
  grep -q "^error: $scn/$f.toml:[0-9]*:[0-9]*: key '$k': $file of up to .* more than the 0.0001 GB free" "$work/err.txt" || bad "no room for $f: $(cat "$work/err.txt")"
  left=$(ls -A "$work" | grep -E '^full')
  [ -z "$left" ] || bad "no room for $f: left $left"
done

# reference: the tables generated from the one description of each key and calculator input
expect_rc 0 "reference design tracer" $bin reference design tracer
grep -q '^| `--E0` | `E0_N_per_mm` | N per mm of spool opening | > 0 | 2000 | stiffness E0' "$work/out.txt" || bad "reference design tracer: $(head -5 "$work/out.txt")"
grep -q '^| settling time (2 %) | `settling_time_s` \[s\] | `settling_time_ms` \[ms\] |$' "$work/out.txt" || bad "reference design tracer outputs: $(cat "$work/out.txt")"
expect_rc 0 "reference scenario common" $bin reference scenario common
grep -q '^| `step_s` | number | s | \[1e-07, 0.01\] | 0.0001 | fixed integration step (rule: duration_s / step_s must not exceed 5e8 steps) |$' "$work/out.txt" || bad "reference scenario common: $(cat "$work/out.txt")"
expect_rc 2 "reference unknown system" $bin reference scenario Z
grep -qx "error: reference scenario: no system 'Z' (common, A, B, C, D, E)" "$work/err.txt" || bad "reference unknown system: $(cat "$work/err.txt")"
expect_rc 2 "reference unknown calculator" $bin reference design lathe
# a stale generated block is found, named, and --update brings it back
mkdir -p "$work/docs"; cp "$src"/docs/*.md "$work/docs/"
sed -i 's/| `--E0` | `E0_N_per_mm` |/| `--E0` | `E0_stale` |/' "$work/docs/system-c-tracer.md"
expect_rc 1 "reference --check stale" $bin reference --check "$work/docs"
grep -q "system-c-tracer.md: generated block 'lathectl reference design tracer' is out of date" "$work/out.txt" || bad "stale block message: $(cat "$work/out.txt")"
grep -q "^run: lathectl reference --update $work/docs$" "$work/out.txt" || bad "stale block: no update command: $(cat "$work/out.txt")"
expect_rc 0 "reference --update" $bin reference --update "$work/docs"
diff -r "$src/docs" "$work/docs" >/dev/null || bad "reference --update did not restore the block: $(diff -r "$src/docs" "$work/docs" | head -5)"

# report: an operation log of lathectl_oplog → report.html beside it; bad logs: exit 2, one line
mkdir -p "$work/oplog"
cat > "$work/oplog/operations.json" <<'JSON'
{"unit": "N", "program": "two_tool.ngc", "missed_rows": 0, "taught": [{"tool": 2, "operation": 1, "reference": 1000.2, "unit": "N"}],
 "messages": [{"time_s": 40.1, "kind": "bad_setting", "text": "lathectl: limit above the machine's rating (9000) near program line 40: M68 E0 Q9000: feed held, not used"}],
 "rows": [{"seq": 5, "time_s": 10.5, "tool": 1, "operation": 0, "line": 17, "mode": "adaptive", "limit": 1400.0, "load_mean": 1285.0, "load_peak": 1433.6, "load_peak_pct": 102.4, "feed_min": 0.1677, "feed_mean": 0.6888, "time_in_cut_s": 4.85, "time_s_line": 5.2, "reasons": "none rate_limited", "alarm": ""}]}
JSON
expect_rc 0 "report" $bin report "$work/oplog"
grep -q "Operations" "$work/oplog/report.html" && grep -q "line 40" "$work/oplog/report.html" || bad "report.html lacks the table or the message"
sed 's/"limit": 1400.0/"limit": "high"/' "$work/oplog/operations.json" > "$work/oplog_bad.json"
expect_rc 2 "report with a bad row" $bin report "$work/oplog_bad.json" --out "$work/never.html"
grep -qx "error: .*oplog_bad.json:3:[0-9]*: key 'rows\[0\].limit': expected a number" "$work/err.txt" || bad "report bad-row message: $(cat "$work/err.txt")"
[ ! -e "$work/never.html" ] || bad "a failed report left a file behind"
# the log of a LinuxCNC session (linuxcnc_shop: two tools, teach-in, a refused value)
expect_rc 0 "report of a session's log" $bin report "$src/tests/cli/operations_two_tool.json" --out "$work/two_tool.html"
grep -q "5 operations, 2 tools" "$work/out.txt" || bad "report of a session's log: $(cat "$work/out.txt")"
# A long log (issue 49: read as a stream): the table holds the first 1000 operations and one line
# for the rest; the totals are over every row (20000 × 0.25 s in cut; the highest peak / limit,
# 150 %, and the one alarm are in rows past the table's cut).
awk 'BEGIN { printf "{\"unit\": \"N\", \"rows\": [\n";
  for (i = 0; i < 20000; i++) printf "%s{\"tool\": %d, \"operation\": 0, \"line\": %d, \"mode\": \"adaptive\", \"limit\": 1000.0, \"load_mean\": 900.0, \"load_peak\": %s, \"feed_min\": 0.5, \"feed_mean\": 0.8, \"time_in_cut_s\": 0.25, \"reasons\": \"none\", \"alarm\": \"%s\"}\n",
    i ? "," : "", i % 3 + 1, i + 1, i == 15000 ? "1500.0" : "990.0", i == 19999 ? "overload" : "";
  print "]}" }' > "$work/oplog_long.json"
expect_rc 0 "report of a 20000-operation log" $bin report "$work/oplog_long.json" --out "$work/long.html"
grep -qx "20000 operations, 3 tools, peak 150.0 % of the limit → .*long.html" "$work/out.txt" || bad "long log: $(cat "$work/out.txt")"
[ "$(grep -o '<td>adaptive</td>' "$work/long.html" | wc -l)" -eq 1000 ] || bad "long log: the table does not stop at 1000 operations"
grep -q "… 19000 more operations: see operations.csv / the log" "$work/long.html" || bad "long log: no line for the operations left out"
grep -q "5000.00 s" "$work/long.html" && grep -q "<td>alarms</td><td>1</td>" "$work/long.html" || bad "long log: totals not over every row"
printf '{"rows": [\n' > "$work/oplog_syntax.json"
expect_rc 2 "report with broken JSON" $bin report "$work/oplog_syntax.json"
grep -q "oplog_syntax.json:2:1: not JSON" "$work/err.txt" || bad "report syntax message: $(cat "$work/err.txt")"

# report: a system-D series of scripts/linuxcnc-sim-gauge (summary.json and parts.csv) → its sizes,
# Cp/Cpk and histogram; a bad size: exit 2 naming its key
mkdir -p "$work/series"
cat > "$work/series/summary.json" <<'JSON'
{"program": "gauge_plunge.ngc", "metrics": {"parts": 2, "size_mean_error_um": -0.5, "size_sigma_um": 2.1213, "cp": 1.57, "cpk": 1.49, "tolerance_um": 10.0, "backstop_um": 90.0, "backstop_trips": 0, "threshold_V": 3.9, "trip_to_stop_s_max": 0.0252},
 "parts_detail": [{"part": 1, "steps": [{"step": 1, "size_um": 159.56}, {"step": 2, "size_um": 126.49}, {"step": 3, "size_um": 98.05}], "backstop": false, "alarm": false, "trip_to_stop_s": 0.0250, "error_um": -2.0},
                  {"part": 2, "steps": [{"step": 1, "size_um": 161.48}, {"step": 2, "size_um": 128.62}, {"step": 3, "size_um": 100.37}], "backstop": false, "alarm": false, "trip_to_stop_s": 0.0252, "error_um": 1.0}]}
JSON
: > "$work/series/parts.csv"
expect_rc 0 "report of a D series" $bin report "$work/series"
grep -q "2 parts: mean -0.500 µm, σ 2.121 µm, Cpk 1.49" "$work/out.txt" || bad "D series report: $(cat "$work/out.txt")"
grep -q "Finished sizes" "$work/series/report.html" && grep -q "159.56, 126.49, 98.05" "$work/series/report.html" || bad "D series report lacks the size table"
sed 's/"error_um": 1.0/"error_um": "big"/' "$work/series/summary.json" > "$work/series/bad.json" && mv "$work/series/bad.json" "$work/series/summary.json"
expect_rc 2 "report of a D series with a bad size" $bin report "$work/series" --out "$work/never.html"
grep -q "key 'parts_detail\[1\].error_um': expected a number" "$work/err.txt" || bad "D series bad size: $(cat "$work/err.txt")"

# hostile inputs and outputs: one line, exit 2, never "internal error", nothing replaced
for dev in /dev/zero /dev/urandom; do
  expect_rc 2 "run $dev" timeout 20 $bin run "$dev" --out "$work/never"
  grep -qx "error: $dev: is a character device, expected a scenario file (.toml)" "$work/err.txt" || bad "run $dev: $(cat "$work/err.txt")"
  expect_rc 2 "report $dev" timeout 20 $bin report "$dev" --out "$work/never.html"
done
mkfifo "$work/fifo.toml"
expect_rc 2 "check a FIFO" timeout 20 $bin check "$work/fifo.toml"
grep -q "fifo.toml: is a FIFO (named pipe), expected" "$work/err.txt" || bad "check FIFO: $(cat "$work/err.txt")"
expect_rc 2 "report a FIFO" timeout 20 $bin report "$work/fifo.toml"
head -c 17000000 /dev/zero | tr '\0' '#' > "$work/huge.toml"
expect_rc 2 "check a 17 MB file" $bin check "$work/huge.toml"
grep -q "huge.toml: 16.2 MiB, more than the 16 MiB a TOML file may have" "$work/err.txt" || bad "huge: $(cat "$work/err.txt")"
rm -f "$work/huge.toml"
# report --out: never over a device, a directory, the log itself or a file lathectl did not write
cp "$src/tests/cli/operations_two_tool.json" "$work/log_keep.json"
if [ "$(id -u)" -eq 0 ]; then  # only root could replace /dev/null
  expect_rc 2 "report --out /dev/null" $bin report "$work/log_keep.json" --out /dev/null
  [ -c /dev/null ] || bad "report --out /dev/null replaced the device node"
fi
expect_rc 2 "report --out the log" $bin report "$work/log_keep.json" --out "$work/log_keep.json"
grep -q "is the input" "$work/err.txt" || bad "report --out log: $(cat "$work/err.txt")"
cmp -s "$work/log_keep.json" "$src/tests/cli/operations_two_tool.json" || bad "report --out LOG changed the log"
mkdir -p "$work/a_dir"
expect_rc 2 "report --out a directory" $bin report "$work/log_keep.json" --out "$work/a_dir"
echo "my notes" > "$work/notes.html"
expect_rc 2 "report --out a user's file" $bin report "$work/log_keep.json" --out "$work/notes.html"
grep -qx "my notes" "$work/notes.html" || bad "report replaced a user's file"
expect_rc 0 "report --out a new file" $bin report "$work/log_keep.json" --out "$work/mine.html"
expect_rc 0 "report --out its own earlier page" $bin report "$work/log_keep.json" --out "$work/mine.html"
# a full disk: one line naming the place and the reason, nothing half written (root: a 64 kB tmpfs)
trap 'umount "$work/full" 2>/dev/null' EXIT
if [ "$(id -u)" -eq 0 ] && mkdir -p "$work/full" && mount -t tmpfs -o size=64k tmpfs "$work/full" 2>/dev/null; then
  head -c 61440 /dev/zero > "$work/full/.filler"  # 4 kB left: less than any report
  expect_rc 2 "report on a full disk" $bin report "$work/log_keep.json" --out "$work/full/r.html"
  grep -q "No space left on device" "$work/err.txt" || bad "report full disk: $(cat "$work/err.txt")"
  expect_rc 2 "run on a full disk" $bin run "$src/examples/scenarios/a_regulator_flow.toml" --out "$work/full/run"
  grep -q "^error: .*\(No space left on device\|free on the output's file system\)" "$work/err.txt" || bad "run full disk: $(cat "$work/err.txt")"
  expect_rc 2 "lobes on a full disk" $bin lobes "$src/examples/machines/b_sdof.toml" --out "$work/full/lobes"
  grep -q "^error: .*No space left on device" "$work/err.txt" || bad "lobes full disk: $(cat "$work/err.txt")"
  [ "$(ls -A "$work/full")" = ".filler" ] || bad "a full disk kept half-written files: $(ls -A "$work/full")"
  umount "$work/full"
fi
# compare: runs of different systems are refused with both named
expect_rc 0 "run for compare (A)" $bin run "$src/examples/scenarios/a_regulator_flow.toml" --out "$work/cmp_a"
expect_rc 0 "run for compare (C)" $bin run "$src/examples/scenarios/c_near_aperiodic.toml" --out "$work/cmp_c"
expect_rc 2 "compare A with C" $bin compare "$work/cmp_a" "$work/cmp_c" --out "$work/cmp_out"
grep -q "is a run of system A, .*cmp_c of system C" "$work/err.txt" || bad "compare A/C: $(cat "$work/err.txt")"

# check: lathectl_adaptive's tools and taught files, told apart by what they hold
expect_rc 0 "check the sample tools file" $bin check "$src/hal/config/lathectl-tools.toml"
grep -q "OK (lathectl_adaptive tools file: 2 tools" "$work/out.txt" || bad "check tools: $(cat "$work/out.txt")"
printf '[machine]\nlimit_max = 5000.0\n[[tool]]\nnumber = 1\nlimit = 6000.0\n' > "$work/tools_bad.toml"
expect_rc 2 "check a tools file over the rating" $bin check "$work/tools_bad.toml"
grep -q "tools_bad.toml:5:[0-9]*: .*limit.*above the machine's limit_max" "$work/err.txt" || bad "check tools_bad: $(cat "$work/err.txt")"
printf '[[taught]]\ntool = 1\noperation = 2\nreference = 1432.7\nunit = "N"\n' > "$work/taught.toml"
expect_rc 0 "check a taught file" $bin check "$work/taught.toml"
grep -q "taught file: 1 references" "$work/out.txt" || bad "check taught: $(cat "$work/out.txt")"
printf '[[taught]]\ntool = 1\nreference = 1432.7\nunit = "kN"\n' > "$work/taught_bad.toml"
expect_rc 2 "check a taught file with a bad unit" $bin check "$work/taught_bad.toml"
grep -q "taught_bad.toml:4:" "$work/err.txt" || bad "check taught_bad: $(cat "$work/err.txt")"

# inputs the fuzzer once crashed on: each must be a clean input error now
# (fuzz/regressions/<target>/, which make test's fuzz step also replays through the fuzz targets;
# the lobes ones run above): through the program itself, each one line and exit 2
for f in "$src"/fuzz/regressions/scenario/*.toml; do expect_rc 2 "fuzz regression $(basename "$f")" $bin check "$f"; done

echo "cli: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
