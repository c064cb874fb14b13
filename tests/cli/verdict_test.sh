#!/bin/sh
# The verdict on the command line: run's console line ends with what went wrong, --strict exits
# 3 on it, demo prints its summary line and marks index.html; no progress line when stderr is
# not a terminal (this script's stderr is a file).
bin=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
fail=0
bad() { echo "FAIL: $*"; fail=1; }
# A part never cut (0.2 s: still approaching): exit 0, but the line says so; --strict: 3.
sed 's/^duration_s = .*/duration_s = 0.2/' "$src/examples/scenarios/e_stepped_seed004.toml" > "$work/e.toml"
"$bin" run "$work/e.toml" --out "$work/e" > "$work/out.txt" 2> "$work/err.txt" || bad "run without --strict: exit $?"
grep -q "— ✘ 6 of 6 claims not met: .* · part not finished (" "$work/out.txt" || bad "console line: $(cat "$work/out.txt")"
[ ! -s "$work/err.txt" ] || bad "stderr not empty off a terminal: $(cat "$work/err.txt")"
"$bin" run --strict "$work/e.toml" --out "$work/e2" > /dev/null 2>&1; rc=$?
[ "$rc" -eq 3 ] || bad "run --strict on unmet claims: exit $rc, expected 3"
grep -q 'id="claim-1"' "$work/e/report.html" || bad "report has no claim anchors"
# An example whose claims are all met: ✔, and --strict exits 0.
"$bin" run --strict "$src/examples/scenarios/a_roughing_aim.toml" --out "$work/a" > "$work/out.txt" 2>&1 || bad "strict on a clean example: exit $?"
grep -q "— ✔ 2 of 2 claims met" "$work/out.txt" || bad "clean console line: $(cat "$work/out.txt")"
# demo over two examples, one with an alarm: summary line, index marks, strict exit 3.
mkdir -p "$work/ex"; cp "$src/examples/scenarios/a_roughing_aim.toml" "$src/examples/scenarios/a_sensor_dropout.toml" "$work/ex/"
"$bin" demo --examples "$work/ex" --out "$work/d" > "$work/out.txt" 2> "$work/err.txt" || bad "demo: exit $?"
grep -q "^demo: 2 scenarios, 1 with unmet claims, alarms or unfinished parts (a_sensor_dropout) → " "$work/out.txt" || bad "demo line: $(cat "$work/out.txt")"
grep -q "a_sensor_dropout: .* — ✘ alarm sensor_not_finite (code 10) at 5 s" "$work/out.txt" || bad "dropout line: $(cat "$work/out.txt")"
grep -q '<span class="mark bad">✘</span>' "$work/d/index.html" || bad "index has no ✘"
grep -q '<span class="mark ok">✔</span>' "$work/d/index.html" || bad "index has no ✔"
[ ! -s "$work/err.txt" ] || bad "demo stderr not empty off a terminal"
"$bin" demo --strict --examples "$work/ex" --out "$work/d2" > /dev/null 2>&1; rc=$?
[ "$rc" -eq 3 ] || bad "demo --strict: exit $rc, expected 3"
"$bin" --help | grep -q "3 with --strict" || bad "--help does not document exit code 3"
[ "$fail" -eq 0 ] && echo "verdict cli: ok"
[ "$fail" -eq 0 ]
