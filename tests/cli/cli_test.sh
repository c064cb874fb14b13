#!/usr/bin/env bash
# End-to-end checks of the lathectl program: exit codes, error messages, outputs, atomic writes.
# Usage: cli_test.sh LATHECTL SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1; src=$2; work=$3
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
for c in "" run check demo design "design pulse-regulator"; do
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

echo "cli: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
