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
# Every numeric flag refuses NaN and infinities by name (a NaN passed CLI::Range and dropped the
# force limit: every piece at feed_max, 3330 N against 1600 N, exit 0).
for flag in --spindle-rpm --z-origin-mm --air-feed --finish-depth-mm --finish-ra-um \
            --limit-fraction --timeout --interp-timeout; do
  for v in nan inf -inf; do
    expect_bad "flag${flag}_$v" "$src/examples/linuxcnc/cautious_roughing.ngc" \
      "$src/examples/linuxcnc/step_allowance.toml" "$flag" "$flag=$v"
  done
done
sa="$src/examples/linuxcnc/step_allowance.toml"
# A rapid through the blank (the bar is Ø40 from Z0): an error naming the line, unless allowed;
# allowed, a warning on the console, first among the report's notes, and the cut after it keeps
# its feed.
printf 'G18 G21 G95\nM3 S1194\nG0 X25 Z2\nG0 X17\nG1 Z-50 F0.15\nG0 X25\nG0 Z2\nG0 X15 Z-20\nG1 Z-50 F0.15\nG0 X25\nM2\n' >"$work/rapid.ngc"
expect_bad rapid "$work/rapid.ngc" "$sa" "rapid.ngc:8: .*through the blank"
if "$bin" optimize "$work/rapid.ngc" "$sa" --out "$work/rapid_allowed" --allow-rapid-in-material \
     >"$work/rapid_allowed.out" 2>&1 && grep -q "WARNING: .*rapid.ngc: A rapid (G0) of line 8 passes through material" "$work/rapid_allowed.out" &&
   grep -q '"why": "after the rapid through material of line 8 (kept)"' "$work/rapid_allowed/summary.json" &&
   grep -q "^G1 Z-50 F0.15$" "$work/rapid_allowed/optimized.ngc" &&
   grep -q 'class="mark">A rapid (G0) of line 8 passes through material' "$work/rapid_allowed/report.html"; then
  echo "ok   rapid allowed: warned, the cut after it kept"
else
  echo "FAIL rapid allowed: $(cat "$work/rapid_allowed.out")"
  fail=1
fi
# A move beyond the INI's soft limit ([AXIS_Z] MIN_LIMIT = -400): LinuxCNC refuses it, so does
# optimize.
printf 'G18 G21 G95\nM3 S1000\nG0 X15 Z2\nG1 Z-500 F0.2\nG0 X30\nM2\n' >"$work/soft.ngc"
expect_bad soft_limit "$work/soft.ngc" "$sa" "soft.ngc:4: .*\[AXIS_Z\] MIN_LIMIT"
# Work that grows with the cycle time is bounded (issue 49: G76 P0.001 ran 67 s to 3.5 GB, G95
# F0.0001 70 s to 4 GB): over an hour of servo periods is refused before a sample, at the line.
printf 'G18 G21 G95\nM3 S1194\nG0 X25 Z2\nG0 X18.5\nG1 Z-50 F0.0001\nG0 X25\nM2\n' >"$work/slow_feed.ngc"
expect_bad slow_feed "$work/slow_feed.ngc" "$sa" "slow_feed.ngc:5: the program runs about 7.* h .* over the 1 h"
printf 'G18 G21 G95\nM3 S1194\nG0 X25 Z2\nG0 X20\nG76 P0.001 Z-30 I-1 J0.2 K1.2 Q29.5 H1\nG0 X25\nM2\n' >"$work/fine_thread.ngc"
expect_bad fine_thread "$work/fine_thread.ngc" "$sa" "fine_thread.ngc:5: .*at a pitch of 0.001 mm"
# More moves than optimize holds (a 10⁶-line program took 1.6 GB): refused at the first beyond
# (a loop rs274 expands to 500 001 moves: the program itself is short).
printf 'G18 G21 G95\nM3 S1194\nG0 X25 Z2\nG0 X19.9\no100 repeat [250001]\nG1 Z1.999 F0.3\nG1 Z2\no100 endrepeat\nG0 X25\nM2\n' >"$work/many_moves.ngc"
expect_bad many_moves "$work/many_moves.ngc" "$sa" "many_moves.ngc:[67]: the program has 50000[0-9] moves, more than the 500000"
# A thread with no F before it (G76 and G33 need none) and a valid 250-character line (the line
# marker used to push it past rs274's 252): both read, the thread line left as written.
long=$(printf 'G1 Z-50 F0.15 (%0234d)' 0)
printf 'G18 G21 G95\nM3 S1194\nG0 X25 Z2\nG0 X18.5\n%s\nG0 X25 Z2\nG0 X20\nG33 Z-30 K1.5\nG0 X25\nM2\n' "$long" >"$work/thread.ngc"
if [ "$(sed -n 5p "$work/thread.ngc" | wc -c)" -eq 251 ] &&
   "$bin" optimize "$work/thread.ngc" "$sa" --out "$work/thread" >"$work/thread.out" 2>&1 &&
   grep -qx "G33 Z-30 K1.5" "$work/thread/optimized.ngc"; then
  echo "ok   thread without F and a 250-character line: $(head -n 1 "$work/thread.out")"
else
  echo "FAIL thread without F / long line: $(cat "$work/thread.out")"
  fail=1
fi
# An endless o-word loop: stopped at --interp-timeout with an error; nothing left behind in the
# temporary directory, no rs274 left running.
printf 'G18 G21 G95\nM3 S1000\nG0 X15 Z2\no100 while [1 GT 0]\nG1 Z-10 F0.2\nG1 Z0\no100 endwhile\nM2\n' >"$work/loop.ngc"
mkdir -p "$work/tmp"
TMPDIR="$work/tmp" expect_bad loop "$work/loop.ngc" "$sa" "did not finish within 2 s" --interp-timeout 2
if [ -n "$(ls -A "$work/tmp")" ]; then echo "FAIL loop: left $(ls -A "$work/tmp")"; fail=1; fi
# Killed while rs274 runs (SIGTERM): its process group goes and the temporary directory with it.
# Killed outright (SIGKILL): rs274 dies with it (PR_SET_PDEATHSIG), and the next run removes the
# directory it left.
for sig in TERM KILL; do
  mkdir -p "$work/tmp_$sig"
  TMPDIR="$work/tmp_$sig" "$bin" optimize "$work/loop.ngc" "$sa" --out "$work/loop_$sig" \
    >/dev/null 2>&1 &
  pid=$!
  for _ in $(seq 50); do pgrep -f "$work/tmp_$sig" >/dev/null && break; sleep 0.1; done
  kill -s "$sig" "$pid"
  wait "$pid" 2>/dev/null
  sleep 0.5
  if pgrep -f "$work/tmp_$sig" >/dev/null; then
    echo "FAIL SIG$sig: rs274 still running"; pgrep -af "$work/tmp_$sig"; fail=1
    for p in $(pgrep -f "$work/tmp_$sig"); do kill -KILL "$p"; done  # this test's own: its directory
  elif [ "$sig" = TERM ] && [ -n "$(ls -A "$work/tmp_$sig")" ]; then
    echo "FAIL SIGTERM: left $(ls -A "$work/tmp_$sig")"; fail=1
  elif [ "$sig" = KILL ]; then
    TMPDIR="$work/tmp_$sig" "$bin" optimize "$work/rejected.ngc" "$sa" --out "$work/x" >/dev/null 2>&1
    if [ -n "$(ls -A "$work/tmp_$sig")" ]; then
      echo "FAIL SIGKILL: the next run left $(ls -A "$work/tmp_$sig")"; fail=1
    else
      echo "ok   SIGKILL: rs274 gone, the directory removed by the next run"
    fi
  else
    echo "ok   SIGTERM: rs274 and the temporary directory gone"
  fi
done
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
# [[stock.passes]] is optional: a scenario of the blank alone (the user's part) is optimised;
# `lathectl run`, whose rig cuts the passes, refuses it naming the file and the key.
up="$src/tests/optimize/programs"
if "$bin" optimize "$up/user_part.ngc" "$up/user_part_c45.toml" --out "$work/no_passes" \
     >"$work/no_passes.out" 2>&1 && [ -s "$work/no_passes/optimized.ngc" ]; then
  echo "ok   a scenario without [[stock.passes]] is optimised"
else
  echo "FAIL a scenario without [[stock.passes]]: $(tail -n 2 "$work/no_passes.out")"; fail=1
fi
"$bin" run "$up/user_part_c45.toml" --out "$work/no_passes_run" >"$work/no_passes_run.out" 2>"$work/no_passes_run.err"
rc=$?
if [ $rc -ne 0 ] && grep -q "user_part_c45.toml:.*stock.passes.*lathectl run cuts the scenario's passes" "$work/no_passes_run.err"; then
  echo "ok   lathectl run without passes: $(head -n 1 "$work/no_passes_run.err")"
else
  echo "FAIL lathectl run without passes: exit $rc: $(cat "$work/no_passes_run.err")"; fail=1
fi
# Issue 47: a shaft end faced 1 mm at Z0 (the blank's face at Z1), past the centre, then G0 Z2.
# The programmed point is the tool tip (T1: Q2), so the face is cut at Z0 and the rapid leaves
# it; with the nose's lowest point programmed (before) the rapid ran through a ring the facing
# left at Z0.8-1: "a rapid drives the tool through the blank (0.004 s in material)".
if "$bin" optimize "$up/facing.ngc" "$up/user_part_c45.toml" --z-origin-mm 1 --out "$work/facing" \
     >"$work/facing.out" 2>&1 && grep -q 'predicted cycle' "$work/facing.out" &&
   grep -Eq '"predicted_rapid_in_material_s": *0(\.0)?,' "$work/facing/summary.json"; then
  echo "ok   the user's facing program: $(head -n 1 "$work/facing.out")"
else
  echo "FAIL the user's facing program: $(cat "$work/facing.out")"; fail=1
fi
# The same with a 0.4 mm nose (scenario and table: T1 D0.8, a CNMG in a 95-degree holder, I85
# J5): the nose covers Z0-0.8 and its straight edge the rest of the 1 mm face; the nose alone
# left a ring at Z0.8-1 for the retract ("line 10: a rapid (G0) drives the tool through the
# blank").
sed 's/^nose_radius_mm = 0.8$/nose_radius_mm = 0.4/' "$up/user_part_c45.toml" >"$work/c45_r04.toml"
printf 'T1 P1 D0.8 Z0 I85 J5 Q2 ;\n' >"$work/t1_r04.tbl"
if grep -q '^nose_radius_mm = 0.4$' "$work/c45_r04.toml" &&
   "$bin" optimize "$up/facing.ngc" "$work/c45_r04.toml" --z-origin-mm 1 --out "$work/facing04" \
     --tool-table "$work/t1_r04.tbl" >"$work/facing04.out" 2>&1 &&
   grep -q 'predicted cycle' "$work/facing04.out" &&
   grep -Eq '"predicted_rapid_in_material_s": *0(\.0)?,' "$work/facing04/summary.json"; then
  echo "ok   the user's facing program, 0.4 mm nose: $(head -n 1 "$work/facing04.out")"
else
  echo "FAIL the user's facing program, 0.4 mm nose: $(cat "$work/facing04.out")"; fail=1
fi
# Its T1 without I and J (the nose alone): the ring is left and the retract refused.
printf 'T1 P1 D0.8 Z0 Q2 ;\n' >"$work/t1_r04_nose.tbl"
expect_bad facing04_nose_alone "$up/facing.ngc" "$work/c45_r04.toml" \
  "facing.ngc:10: a rapid (G0) drives the tool through the blank" --z-origin-mm 1 \
  --tool-table "$work/t1_r04_nose.tbl"
# LinuxCNC's tool table and the tool file must agree: T2's nose in the table is D0.8 (r 0.4).
printf '[[tool]]\nnumber = 2\nkind = "grooving"\ninsert_width_mm = 3.0\nnose_radius_mm = 0.2\n' >"$work/tools_r02.toml"
expect_bad tool_table_disagrees "$up/user_part.ngc" "$up/user_part_c45.toml" \
  "tools_r02.toml: .*tool 2: nose_radius_mm = 0.2 mm, but LinuxCNC's tool table .*lathectl-lathe.tbl:2 gives D0.8" \
  --tool-file "$work/tools_r02.toml"
printf 'T1 P1 D0.8 Q1\nT2 P2 D0.4 K3\n' >"$work/bad.tbl"
expect_bad tool_table_word "$up/user_part.ngc" "$up/user_part_c45.toml" \
  "bad.tbl:2: tool table word 'K3'" --tool-file "$up/user_part_tools.toml" --tool-table "$work/bad.tbl"
# The tool table on the checked path (issue 49): a FIFO (it blocked for ever), /dev/zero, a
# directory, a missing or an empty file is one line naming --tool-table and the file, no output,
# no temporary directory left; --rs274 that is not rs274 is named, not "no feed moves".
cr="$src/examples/linuxcnc/cautious_roughing.ngc"
mkfifo "$work/fifo.tbl"; mkdir -p "$work/dir.tbl" "$work/tmp_tbl"; : >"$work/empty.tbl"
for t in fifo:"$work/fifo.tbl" zero:/dev/zero dir:"$work/dir.tbl" missing:"$work/none.tbl" \
         empty:"$work/empty.tbl"; do
  TMPDIR="$work/tmp_tbl" expect_bad "tbl_${t%%:*}" "$cr" "$sa" "${t#*:}: .*(--tool-table)" \
    --tool-table "${t#*:}"
done
[ -z "$(ls -A "$work/tmp_tbl")" ] || { echo "FAIL a bad tool table left $(ls "$work/tmp_tbl")"; fail=1; }
expect_bad rs274_true "$cr" "$sa" "^error: --rs274 '/bin/true' exited with status 0 without" --rs274 /bin/true
# --ini (issue 47) on the same checked path: a FIFO, a directory, a missing file are one line
# naming --ini and the file; a bad value names the file, line, section and key; an INI without
# [EMCIO]TOOL_TABLE (and no --tool-table) is named.
mkfifo "$work/fifo.ini"; mkdir -p "$work/dir.ini"
for t in fifo:"$work/fifo.ini" dir:"$work/dir.ini" missing:"$work/none.ini"; do
  expect_bad "ini_${t%%:*}" "$cr" "$sa" "${t#*:}: .*(--ini)" --ini "${t#*:}"
done
printf '[TRAJ]\nLINEAR_UNITS = mm\n[AXIS_X]\nMIN_LIMIT = -5\nMAX_LIMIT = 12O\n' >"$work/bad.ini"
expect_bad ini_value "$cr" "$sa" "bad.ini:5: \\[AXIS_X\\]MAX_LIMIT = '12O': not a number" --ini "$work/bad.ini"
printf '[TRAJ]\nLINEAR_UNITS = furlong\n' >"$work/unit.ini"
expect_bad ini_unit "$cr" "$sa" "unit.ini:2: \\[TRAJ\\]LINEAR_UNITS = 'furlong'" --ini "$work/unit.ini"
printf '[TRAJ]\nLINEAR_UNITS = inch\n' >"$work/notable.ini"
expect_bad ini_no_table "$cr" "$sa" "notable.ini: \\[EMCIO\\]TOOL_TABLE missing" --ini "$work/notable.ini"
exit $fail
