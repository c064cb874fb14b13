#!/bin/sh
# The stability map (docs/sweep.md, "The stability map"), small: 3 feeds × 3 speeds of
# examples/sweeps/b_single_tool.toml with [report] lobes = its machine file. The report draws the
# lobes' boundary (frequency domain and semi-discretization) over the heat map, and the
# simulated verdict (depth_swing.growth > 1) agrees with the lobes at every grid point away from
# the boundary, of which there are both stable and chattering ones. [report]'s bad values are
# refused at their line, nothing written.
bin=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
fail=0
bad() { echo "FAIL: $*"; fail=1; }
ex=$src/examples/sweeps
report() {
  printf '[report]\nlobes = "%s"\nspeed = "%s"\ndepth = "%s"\n' "$1" "$2" "$3"
  printf 'depth_reference = 0.10\ndepth_exponent = %s\nchatter = "depth_swing.growth"\n' "${4:-0.49}"
}
grid='[grid]\n"cut.feed_mm_per_rev" = [0.04, 0.12, 0.2]\n"cut.rpm" = [2300, 2650, 3000]\n'

# 1. [report]'s errors: exit 2, one line at the key's line, nothing written.
{ printf 'scenario = "%s"\n' "$ex/b_single_tool.toml"; printf "$grid"; report "$ex/b_single_tool_bar.toml" cut.rpm cut.depth_mm; } > "$work/e1.toml"
{ printf 'scenario = "%s"\n' "$ex/b_single_tool.toml"; printf "$grid"; report "$ex/nowhere.toml" cut.rpm cut.feed_mm_per_rev; } > "$work/e2.toml"
{ printf 'scenario = "%s"\n' "$ex/b_single_tool.toml"; printf "$grid"; report "$ex/b_single_tool_bar.toml" cut.rpm cut.feed_mm_per_rev 1.5; } > "$work/e3.toml"
for e in e1:8:report.depth e2:6:report.lobes e3:10:report.depth_exponent; do
  f=${e%%:*}; rest=${e#*:}; line=${rest%%:*}; key=${rest#*:}
  "$bin" sweep "$work/$f.toml" --out "$work/$f" > /dev/null 2> "$work/err.txt"; rc=$?
  [ "$rc" -eq 2 ] || bad "$f: exit $rc, expected 2: $(cat "$work/err.txt")"
  grep -q "^error: $work/$f.toml:$line:.*$key" "$work/err.txt" || bad "$f: not $key at line $line: $(cat "$work/err.txt")"
  [ ! -e "$work/$f" ] || bad "$f: wrote $work/$f"
done

# 2. The small map on one core.
{ printf 'scenario = "%s"\n' "$ex/b_single_tool.toml"; printf "$grid"
  printf '[output]\nmetrics = ["depth_swing.growth"]\n'
  report "$ex/b_single_tool_bar.toml" cut.rpm cut.feed_mm_per_rev; } > "$work/map.toml"
"$bin" sweep "$work/map.toml" --out "$work/map" --workers 1 > "$work/map.log" 2>&1 || bad "map: exit $?: $(cat "$work/map.log")"
html=$work/map/report.html
for line in "lobes, frequency domain" "lobes, semi-discretization chart" "lobes, semi-discretization (bisection)"; do
  grep -q "</span> $line" "$html" || bad "the report has no line '$line'"
done
grep -q '<path d="M' "$html" || bad "no boundary drawn over the heat map"
# Away from the boundary (beyond ±25 % of the limit) every grid point agrees, both methods.
for m in "frequency domain" "semi-discretization chart"; do
  a=$(grep -A1 "agreement with the lobes, $m</td>" "$html" | grep -o "away from the boundary (beyond ±25 % of the limit)</td><td>[^<]*" | sed 's/.*<td>//')
  k=${a%% of *}; n=${a#* of }; n=${n%% *}
  { [ -n "$k" ] && [ "$k" = "$n" ] && [ "$n" -ge 6 ]; } || bad "$m: away from the boundary '$a'"
done
# Both verdicts occur: the agreement is not that of an all-stable map.
chatter=$(awk -F, 'NR > 1 && $7 > 1' "$work/map/results.csv" | wc -l)
stable=$(awk -F, 'NR > 1 && $7 != "" && $7 < 1' "$work/map/results.csv" | wc -l)
{ [ "$chatter" -ge 2 ] && [ "$stable" -ge 2 ]; } || bad "chatter $chatter, stable $stable cases: $(cat "$work/map/results.csv")"
[ $fail -eq 0 ] && echo "sweep map: ok"
exit $fail
