#!/usr/bin/env bash
# LinuxCNC's own lathe programs (shipped with linuxcnc-uspace) through lathectl optimize, each on
# a blank that fits it (tests/optimize/shipped/*.toml): metric programs on the simulated lathe,
# inch programs (G20) on LinuxCNC's own inch lathe, sim/axis/lathe.ini with its lathe.tbl (--ini).
# Each is either optimised (exit 0, a shorter predicted cycle; an inch program's optimized.ngc
# keeps its G20 and writes its F words in inches), refused by LinuxCNC's interpreter with its
# own words, or refused by lathectl with a refusal a user can act on (exit 2, one line naming the
# program). About 6 s. Skips (77) without rs274 or the programs.
set -uo pipefail
bin=$1 src=$2 work=$3
nc=/usr/share/linuxcnc/ncfiles
lathe_ini=/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/lathe.ini
command -v rs274 >/dev/null || { echo "rs274 (linuxcnc-uspace) not installed: skipped"; exit 77; }
[ -f "$nc/lathe_pawn.ngc" ] && [ -f "$lathe_ini" ] ||
  { echo "LinuxCNC's sample programs and configurations not installed: skipped"; exit 77; }
rm -rf "$work" && mkdir -p "$work"
sc=$src/tests/optimize/shipped
fail=0
# NAME PROGRAM SCENARIO EXPECTED [ARGS...]: EXPECTED is "optimised" or a pattern of the one line.
check() {
  local name=$1 prog=$2 scen=$3 want=$4
  shift 4
  "$bin" optimize "$prog" "$scen" --out "$work/$name" "$@" >"$work/$name.out" 2>"$work/$name.err"
  local rc=$? msg
  if [ "$want" = optimised ]; then
    msg=$(grep -o 'predicted cycle [0-9.]* s → [0-9.]* s, [0-9]* lines changed' "$work/$name.out")
    if [ $rc -ne 0 ] || ! awk -v m="$msg" 'BEGIN { split(m, w, " "); exit !(w[6] < w[3]) }'; then
      echo "FAIL $name: exit $rc, expected optimised: $(cat "$work/$name.out" "$work/$name.err")"
      fail=1
      return
    fi
    if grep -qi '^g20' "$prog" && { ! grep -qi '^g20' "$work/$name/optimized.ngc" ||
        ! grep -Eq '"program_units": *"inch"' "$work/$name/summary.json"; }; then
      echo "FAIL $name: optimized.ngc lost the program's G20, or summary.json's program_units"
      fail=1
      return
    fi
    echo "ok   $name: $msg"
  else
    if [ $rc -ne 2 ] || [ "$(wc -l <"$work/$name.err")" -ne 1 ] ||
       ! grep -Eq -- "$want" "$work/$name.err" || [ -e "$work/$name" ]; then
      echo "FAIL $name: exit $rc, expected one line matching '$want':"
      cat "$work/$name.err"
      fail=1
      return
    fi
    echo "ok   $name: $(cat "$work/$name.err")"
  fi
}
inch=(--ini "$lathe_ini")
rapid="a rapid \\(G0\\) drives the tool through the blank"
check lathe_pawn "$nc/lathe_pawn.ngc" "$sc/lathe_pawn.toml" optimised --z-origin-mm 1
# Compensation started before positioning: LinuxCNC's G70 enters through the roughed part
# (docs/optimize.md).
check g70_71_demo "$nc/lathe_g70_71_demo.ngc" "$src/examples/linuxcnc/pawn_optimize.toml" \
  "lathe_g70_71_demo.ngc:32: $rapid" --spindle-rpm 1600 --z-origin-mm 2
# G72 plunges into the face's centre at rapid before each facing pass.
check face_boring "$nc/lathe_g7x_face_boring.ngc" "$sc/face_boring.toml" \
  "lathe_g7x_face_boring.ngc:13: $rapid" --spindle-rpm 800
# Beyond the simulated lathe's X soft limit; on LinuxCNC's lathe.ini (X ±10 in) the G72 cycle's
# rapids run through the blank.
check quadrants_lathectl "$nc/lathe_g7x_quadrants.ngc" "$sc/quadrants.toml" \
  "lathe_g7x_quadrants.ngc:16: the move reaches machine X -5.3000, beyond the soft limit \\[AXIS_X\\] MIN_LIMIT = -5" \
  --spindle-rpm 800
check quadrants "$nc/lathe_g7x_quadrants.ngc" "$sc/quadrants.toml" \
  "lathe_g7x_quadrants.ngc:15: $rapid" --spindle-rpm 800 "${inch[@]}"
# G20 on LinuxCNC's inch lathe (its T7); on the simulated lathe T7 is not in the table.
check lathecomp "$nc/lathecomp.ngc" "$sc/lathecomp.toml" optimised \
  --spindle-rpm 800 --z-origin-mm 44 "${inch[@]}"
# lathe.ini has no [JOINT_n]HOME: LinuxCNC homes at X0 Z0, inside this blank; the run starts at
# the simulated lathe's X60 Z60 and says so, naming the INI and its keys (docs/optimize.md).
grep -q "^note: $lathe_ini: \[JOINT_0\]HOME absent (0), \[JOINT_1\]HOME absent (0): LinuxCNC homes the tool at X0 Z0 inch, in the blank" \
  "$work/lathecomp.out" || { echo "FAIL lathecomp: no note on lathe.ini's home"; fail=1; }
check lathecomp_lathectl "$nc/lathecomp.ngc" "$sc/lathecomp.toml" \
  "lathecomp.ngc:30: LinuxCNC's interpreter \\(rs274\\) rejects the program: Requested tool 7 not found" \
  --spindle-rpm 800 --z-origin-mm 44
for p in lathe-g76 g76; do
  check "$p" "$nc/$p.ngc" "$sc/g76.toml" \
    "$p.ngc:26: LinuxCNC's interpreter \\(rs274\\) rejects the program: Length of cutter compensation entry move is not greater than the tool radius" \
    --z-origin-mm 0.254 "${inch[@]}"
done
check threading "$nc/threading.ngc" "$sc/threading.toml" optimised --z-origin-mm 17.78 "${inch[@]}"
# AXIS's splash: letters drawn at depth, each entered by a rapid ("Not intended for actual milling").
check axis_lathe /usr/share/axis/images/axis-lathe.ngc "$sc/axis_lathe.toml" \
  "axis-lathe.ngc:10: $rapid" --spindle-rpm 800 --z-origin-mm 95.25 "${inch[@]}"
# A subroutine the file never calls.
check gmoccapy_threading \
  /usr/share/doc/linuxcnc/examples/sample-configs/sim/gmoccapy/lathe_configs/threading.ngc \
  "$sc/gmoccapy_threading.toml" "threading.ngc: the program has no feed moves \\(nothing to optimise\\)"
exit $fail
