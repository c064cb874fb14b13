#!/bin/sh
# The verdict on the command line: run's console line ends with the acceptance verdict (the
# scenario's [acceptance] criteria or its system's defaults, alarms, unfinished parts) and then
# the model checks (the seeds' claims); --strict exits 3 on the acceptance verdict only; demo
# prints its summary line and marks index.html; no progress line when stderr is not a terminal
# (this script's stderr is a file).
bin=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
fail=0
bad() { echo "FAIL: $*"; fail=1; }
ex=$src/examples/scenarios
# A part never cut (0.1 s: still approaching): exit 0, but the line says so; --strict: 3.
sed 's/^duration_s = .*/duration_s = 0.1/' "$ex/e_stepped_seed004.toml" > "$work/e.toml"
"$bin" run "$work/e.toml" --out "$work/e" > "$work/out.txt" 2> "$work/err.txt" || bad "run without --strict: exit $?"
grep -q "— ✘ 1 of 1 acceptance criterion not met: largest per-revolution force (or power) above its limit — (limit ≤ 10 %, default) · part not finished (.* · model checks: 0 of 6 met (not met: " "$work/out.txt" || bad "console line: $(cat "$work/out.txt")"
[ ! -s "$work/err.txt" ] || bad "stderr not empty off a terminal: $(cat "$work/err.txt")"
"$bin" run --strict "$work/e.toml" --out "$work/e2" > /dev/null 2>&1; rc=$?
[ "$rc" -eq 3 ] || bad "run --strict on an unfinished part: exit $rc, expected 3"
grep -q 'id="claim-1"' "$work/e/report.html" || bad "report has no claim anchors"
grep -q '<h2>Verdict: acceptance criteria</h2>' "$work/e/report.html" || bad "report has no acceptance section"
grep -q 'id="model-checks"' "$work/e/report.html" || bad "report has no model-checks section"
# An example whose criteria and claims are all met: ✔, and --strict exits 0.
"$bin" run --strict "$ex/a_roughing_aim.toml" --out "$work/a" > "$work/out.txt" 2>&1 || bad "strict on a clean example: exit $?"
grep -q "— ✔ 1 of 1 acceptance criterion met · model checks: 3 of 3 met$" "$work/out.txt" || bad "clean console line: $(cat "$work/out.txt")"
# The user's limit decides: the same run against a force limit it exceeds → 3.
{ cat "$ex/a_roughing_aim.toml"; printf '\n[acceptance]\nmax_force_over_set_pct = 5\n'; } > "$work/a5.toml"
"$bin" run --strict "$work/a5.toml" --out "$work/a5" > "$work/out.txt" 2>&1; rc=$?
[ "$rc" -eq 3 ] || bad "run --strict on an unmet acceptance criterion: exit $rc, expected 3"
grep -q "— ✘ 1 of 1 acceptance criterion not met: largest force above its set value (roughing) .* (limit ≤ 5 %, the scenario's) · model checks: 3 of 3 met" "$work/out.txt" || bad "unmet criterion line: $(cat "$work/out.txt")"
# A model check not met does not fail --strict: a finishing pass (0.5 mm) on a tracer whose
# friction barely falls (110 → 100 N) shows no stick-slip (the seed's claim ✘), and its profile
# is well within the default 100 µm.
sed -e 's/^static_N = .*/static_N = 110.0/' -e 's/^coulomb_N = .*/coulomb_N = 100.0/' \
    -e 's/^blank_diameter_mm = .*/blank_diameter_mm = 41.0/' "$ex/c_stick_slip.toml" > "$work/c.toml"
"$bin" run --strict "$work/c.toml" --out "$work/c" > "$work/out.txt" 2>&1 || bad "strict on an unmet model check: exit $?"
grep -q "— ✔ 1 of 1 acceptance criterion met · model checks: 0 of 1 met (not met: falling friction: cone waviness nonlinear / linear model)" "$work/out.txt" || bad "model check line: $(cat "$work/out.txt")"
# A bad acceptance key is bad input (2), named.
{ cat "$ex/a_roughing_aim.toml"; printf '\n[acceptance]\nmax_force_pct = 5\n'; } > "$work/abad.toml"
"$bin" run --strict "$work/abad.toml" --out "$work/abad" > "$work/out.txt" 2>&1; rc=$?
[ "$rc" -eq 2 ] || bad "unknown acceptance key: exit $rc, expected 2"
grep -q "acceptance.max_force_pct" "$work/out.txt" || bad "unknown key message: $(cat "$work/out.txt")"
# demo over two examples, one with an alarm (a_sensor_dropout without its demonstrates_failure):
# summary line, index marks, strict exit 3.
mkdir -p "$work/ex"; cp "$ex/a_roughing_aim.toml" "$work/ex/"
grep -v '^demonstrates_failure' "$ex/a_sensor_dropout.toml" > "$work/ex/a_sensor_dropout.toml"
"$bin" demo --examples "$work/ex" --out "$work/d" > "$work/out.txt" 2> "$work/err.txt" || bad "demo: exit $?"
grep -q "^demo: 2 scenarios, 1 with unmet acceptance criteria, alarms or unfinished parts (a_sensor_dropout) → " "$work/out.txt" || bad "demo line: $(cat "$work/out.txt")"
grep -q "a_sensor_dropout: .* — ✘ alarm sensor_not_finite (code 10) at 5 s" "$work/out.txt" || bad "dropout line: $(cat "$work/out.txt")"
grep -q '<span class="mark bad">✘</span>' "$work/d/index.html" || bad "index has no ✘"
grep -q '<span class="mark ok">✔</span>' "$work/d/index.html" || bad "index has no ✔"
[ ! -s "$work/err.txt" ] || bad "demo stderr not empty off a terminal"
"$bin" demo --strict --examples "$work/ex" --out "$work/d2" > /dev/null 2>&1; rc=$?
[ "$rc" -eq 3 ] || bad "demo --strict: exit $rc, expected 3"
"$bin" demo --strict --examples "$work/ex" --out "$work/d3" a_roughing_aim > /dev/null 2>&1; rc=$?
[ "$rc" -eq 0 ] || bad "demo --strict on a clean example: exit $rc, expected 0"
# The shipped a_sensor_dropout is a demonstration of failure (demonstrates_failure = true): said
# so on the console and in the index, no ✘, and --strict passes while it fails as it should.
mkdir -p "$work/exd"; cp "$ex/a_roughing_aim.toml" "$ex/a_sensor_dropout.toml" "$work/exd/"
"$bin" demo --strict --examples "$work/exd" --out "$work/d4" > "$work/out.txt" 2>&1; rc=$?
[ "$rc" -eq 0 ] || bad "demo --strict with a demonstration of failure: exit $rc, expected 0"
grep -q "^demo: 2 scenarios, 0 with unmet acceptance criteria, alarms or unfinished parts; 1 demonstrations of failure, failing as they should (a_sensor_dropout) → " "$work/out.txt" || bad "demo line with a demonstration: $(cat "$work/out.txt")"
grep -q "demonstration of failure, on purpose: ✘ 1 alarm" "$work/d4/index.html" || bad "index does not name the demonstration"
! grep -q '<span class="mark bad">✘</span>' "$work/d4/index.html" || bad "index marks a demonstration of failure ✘"
"$bin" --help | grep -q "3 with --strict (run, demo): an acceptance criterion not met" || bad "--help does not document exit code 3"
[ "$fail" -eq 0 ] && echo "verdict cli: ok"
[ "$fail" -eq 0 ]
