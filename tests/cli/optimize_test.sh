#!/usr/bin/env bash
# lathectl optimize's bad inputs: a program LinuxCNC's interpreter rejects, a program
# whose tool never touches the blank, a scenario of another system — each exits 2 with one line
# on stderr naming the file, and leaves no output directory; and it leaves the user's
# $HOME/.tool.mmap alone. Skips (77) without LinuxCNC's rs274.
set -uo pipefail
bin=$1 src=$2 work=$3
command -v rs274 >/dev/null || { echo "rs274 (linuxcnc-uspace) not installed: skipped"; exit 77; }
rm -rf "$work" && mkdir -p "$work"
fail=0
expect_bad() {  # NAME PROGRAM SCENARIO WORD-IN-MESSAGE [ARGS...]
  local name=$1 prog=$2 sc=$3 word=$4
  shift 4
  "$bin" optimize "$prog" "$sc" --out "$work/$name" "$@" >"$work/$name.out" 2>"$work/$name.err"
  local rc=$?
  local lines
  lines=$(wc -l <"$work/$name.err")
  if [ $rc -ne 2 ] || [ "$lines" -ne 1 ] || ! grep -q -- "$word" "$work/$name.err" ||
     [ -e "$work/$name" ]; then
    echo "FAIL $name: exit $rc, $lines line(s) on stderr, output left: $([ -e "$work/$name" ] && echo yes || echo no)"
    cat "$work/$name.err"
    fail=1
  else
    echo "ok   $name: $(cat "$work/$name.err")"
  fi
}
printf 'G18 G21 G95\nM3 S1000\nG0 X25 Z5\nG2 X3 Z1 I1 J100 F0.2\nM2\n' >"$work/rejected.ngc"
expect_bad rejected "$work/rejected.ngc" "$src/examples/linuxcnc/step_allowance.toml" \
  "rejected.ngc:4: LinuxCNC's interpreter"
printf 'G18 G21 G95\nM3 S1000\nG0 X50 Z5\nG1 Z-50 F0.2\nM2\n' >"$work/air.ngc"
expect_bad untouched "$work/air.ngc" "$src/examples/linuxcnc/step_allowance.toml" "never touches"
expect_bad not_e "$src/examples/linuxcnc/cautious_roughing.ngc" \
  "$src/examples/linuxcnc/b_chatter_single.toml" "system-E scenario"
# [chatter] (the chatter margin): a part without its headstock centre, and a section with no
# mode and no part — the reader names the file, the line and the key.
{ cat "$src/examples/linuxcnc/step_allowance.toml"
  printf '\n[chatter]\n[[chatter.mode]]\nstiffness_N_per_m = 3e7\ndamping_ratio = 0.03\n'
  printf 'natural_frequency_Hz = 1500\n[chatter.part]\ndamping_ratio = 0.02\n'; } >"$work/no_centre.toml"
expect_bad no_centre "$src/examples/linuxcnc/cautious_roughing.ngc" "$work/no_centre.toml" \
  "no_centre.toml:.*headstock_at_mm"
{ cat "$src/examples/linuxcnc/step_allowance.toml"; printf '\n[chatter]\n'; } >"$work/no_modes.toml"
expect_bad no_modes "$src/examples/linuxcnc/cautious_roughing.ngc" "$work/no_modes.toml" \
  "no_modes.toml:.*chatter"
# LinuxCNC's rs274 (2.9 ≤ 2.9.10) recreates $HOME/.tool.mmap, truncated: the tool table of a
# LinuxCNC session of the same user, which then runs on with rs274's table or loses its task
# process mid-part. lathectl runs it with a HOME of its own: the user's is left alone.
mkdir -p "$work/home"
if HOME="$work/home" "$bin" optimize "$src/examples/linuxcnc/cautious_roughing.ngc" \
     "$src/examples/linuxcnc/step_allowance.toml" --out "$work/home_run" >"$work/home.out" 2>&1 &&
   [ ! -e "$work/home/.tool.mmap" ]; then
  echo "ok   rs274 left \$HOME/.tool.mmap alone"
else
  echo "FAIL rs274 and \$HOME/.tool.mmap: $(ls -A "$work/home") $(tail -n 1 "$work/home.out")"
  fail=1
fi
exit $fail
