#!/usr/bin/env bash
# Every `lathectl design` calculator, every number flag set to a hostile value (0, −1,
# nan, inf, 1e300, 1e-300) over a working set of the others: exit 0 with finite results, or exit 2
# with one line that names a flag — never exit 1 ("internal error"), a hang (20 s), inf or nan.
# Usage: design_hostile.sh LATHECTL WORK_DIR
set -uo pipefail
bin=$1; work=$2
rm -rf "$work"; mkdir -p "$work"
fail=0; runs=0
bad() { echo "FAIL: $*"; fail=$((fail + 1)); }

declare -A base=(
  [pulse-regulator]="--d-mm 8 --h-mm 0.04 --dp-MPa 0.5 --dt-ms 10 --T-ms 50 --leak 2 --Py 500 --dPy 100"
  [adaptive-speed]="--Vp 150 --Sp 0.3 --yv 0.35 --S 0.15 --Cv 350 --m 0.2 --xv 0.15 --t 3 --s 0.5 --V 100 --T-target 60 --F 150 --n 1000 --D-mm 80"
  [planned-mode]="--material steel_45 --t 3 --force-limit 2500 --D-mm 80"
  [gauge]="--tolerance-um 10"
  [tracer]=""
  [modulation]="--L-mm 600 --x-mm 285"
  # design gauge from a measured calibration: the process flags, and the physical ones refused
  [gauge-calibration]="--tolerance-um 10 --allowance-um 200 --calibration $(dirname "$0")/../../examples/gauges/d_calibration.csv"
)
values=(0 -1 nan inf 1e300 1e-300)

for calc in pulse-regulator adaptive-speed planned-mode gauge tracer modulation gauge-calibration; do
  cmd=${calc%-calibration}
  flags=$("$bin" reference design "$cmd" | sed -n 's/^| `\(--[A-Za-z0-9-]*\)` | `.*/\1/p')
  [ -n "$flags" ] || bad "$calc: no flags in its reference"
  for flag in $flags; do
    for v in "${values[@]}"; do
      # the working set without this flag (and its value), then the hostile value
      args=$(echo " ${base[$calc]} " | sed "s/ $flag [^ ]* / /")
      [ "$calc" = pulse-regulator ] && [ "$flag" = --f-Hz ] && args=$(echo "$args" | sed 's/ --T-ms [^ ]* / /')
      runs=$((runs + 1))
      # shellcheck disable=SC2086
      timeout 20 "$bin" design "$cmd" $args "$flag" "$v" --json >"$work/out.txt" 2>"$work/err.txt"
      rc=$?
      what="design $calc $flag $v"
      case $rc in
        0)
          # (Cp without noise is unbounded by design: JSON null, documented)
          if grep -v '"Cp": null' "$work/out.txt" | grep -qiE '(^|[^a-z])(inf|nan|null)([^a-z]|$)'; then
            bad "$what: exit 0 with a non-finite result: $(grep -iE 'inf|nan|null' "$work/out.txt" | head -3 | tr '\n' ' ')"
          fi ;;
        2)
          [ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "$what: not one line: $(head -3 "$work/err.txt" | tr '\n' ' ')"
          grep -q -- '--' "$work/err.txt" || bad "$what: names no flag: $(cat "$work/err.txt")" ;;
        124) bad "$what: still running after 20 s" ;;
        *) bad "$what: exit $rc: $(head -3 "$work/err.txt" | tr '\n' ' ')" ;;
      esac
    done
  done
done
echo "design hostile: $runs runs, $fail failures"
[ "$fail" -eq 0 ]
