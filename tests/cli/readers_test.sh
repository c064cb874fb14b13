#!/usr/bin/env bash
# Issue 49's classes on the command line, each exit 2 with one printable line naming the file,
# key or flag (never exit 1, a huge allocation or a terminal escape), and nothing replaced:
# a D series' tolerance ≤ 0 and a part 1e9 µm off (bins bounded), design flags that only clash
# together, a file name with an escape and a 10 MB header line, and --out holding an input.
# Usage: readers_test.sh LATHECTL SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
fail=0
bad() { echo "FAIL: $*"; fail=1; }
expect2() {  # DESCRIPTION GREP-PATTERN COMMAND...: exit 2, one line matching PATTERN
  local what=$1 pat=$2; shift 2
  "$@" >"$work/out.txt" 2>"$work/err.txt"; local rc=$?
  [ $rc -eq 2 ] || bad "$what: exit $rc: $(head -c 300 "$work/err.txt")"
  [ "$(wc -l <"$work/err.txt")" -eq 1 ] || bad "$what: not one line: $(head -c 300 "$work/err.txt")"
  grep -q -- "$pat" "$work/err.txt" || bad "$what: no '$pat': $(head -c 300 "$work/err.txt")"
  LC_ALL=C grep -q $'[\x01-\x08\x0b-\x1f\x7f]' "$work/err.txt" && bad "$what: a control byte"
  [ "$(wc -c <"$work/err.txt")" -le 1100 ] || bad "$what: $(wc -c <"$work/err.txt") bytes"
}

# A system-D series (scripts/linuxcnc-sim-gauge's summary.json) with TOL and a part ERROR µm off.
series() {  # DIR TOL ERROR
  mkdir -p "$1" && : >"$1/parts.csv"
  printf '{"metrics": {"parts": 2, "size_mean_error_um": 0.5, "size_sigma_um": 2.1, "cp": 1.5, "cpk": 1.4, "tolerance_um": %s, "backstop_um": 90, "backstop_trips": 0, "threshold_V": 3.9},\n "parts_detail": [{"part": 1, "error_um": %s}, {"part": 2, "error_um": 1.0}]}\n' "$2" "$3" >"$1/summary.json"
}
series "$work/neg" -10 1
expect2 "D tolerance -10" "summary.json:1:[0-9]*: key 'metrics.tolerance_um': expected a tolerance above 0" \
  "$bin" report "$work/neg"
series "$work/zero" 0 1
expect2 "D tolerance 0" "key 'metrics.tolerance_um'" "$bin" report "$work/zero"
series "$work/huge" 10 1e300
expect2 "D part 1e300 µm off" "key 'parts_detail\[0\].error_um'" "$bin" report "$work/huge"
# 1e9 µm off: read, in at most 400 bins (was 10⁸ bins, 21 GB and a kill); the histogram's
# series holds two points a bin.
series "$work/far" 10 1e9
timeout 20 "$bin" report "$work/far" >/dev/null 2>"$work/err.txt" || bad "D part 1e9 µm off: $(cat "$work/err.txt")"
[ "$(wc -c <"$work/far/report.html")" -lt 2000000 ] || bad "D part 1e9 µm off: a report of $(wc -c <"$work/far/report.html") bytes"

# Flags that are only wrong together are named.
expect2 "tracer --s 1e300 --n 1e300" "--s · --n" "$bin" design tracer --s 1e300 --n 1e300
expect2 "planned-mode --s-min > --s-max" "--s-min 1 mm/rev exceeds --s-max 0.1" \
  "$bin" design planned-mode --material steel_45 --t 3 --force-limit 2500 --s-min 1 --s-max 0.1

# What a file or a flag holds is escaped and cut: an escape sequence in a file name, a 10 MB line.
expect2 "an escape in a file name" 'x\\x1b\[31mred\\x07.toml: no such file' \
  "$bin" check "$work/x"$'\x1b[31mred\x07.toml'
head -c 10000000 /dev/zero | tr '\0' 'A' >"$work/tap.csv"
printf '\n1,1,1\n' >>"$work/tap.csv"
printf '[cutting]\nkf_N_per_mm2 = 2000\n[speed]\nmin_rpm = 1200\nmax_rpm = 3000\n[[frf]]\nfile = "tap.csv"\n' >"$work/m.toml"
expect2 "a 10 MB header line" "tap.csv:1: column 'AAAA*…': expected" "$bin" lobes "$work/m.toml" --out "$work/never"

# --out may not be an input nor hold one: nothing is written, the inputs stay.
mkdir -p "$work/P"
cp "$src/examples/scenarios/a_roughing_aim.toml" "$work/P/a.toml"
expect2 "run --out holding the scenario" "--out $work/P: holds the input $work/P/a.toml" \
  "$bin" run "$work/P/a.toml" --out "$work/P"
cp "$src/examples/machines/b_sdof.toml" "$work/P/m.toml"
expect2 "lobes --out the machine file's folder" "holds the input" "$bin" lobes "$work/P/m.toml" --out "$work/P/"
[ -f "$work/P/a.toml" ] && [ ! -e "$work/never" ] || bad "--out: an input gone or an output written"
ls -a "$work" | grep -q tmp- && bad "--out: a staging directory left"

# A scenario's name is one printable path component: "../escaped" made the demo write a
# directory beside its --out.
mkdir -p "$work/ex" "$work/demo"
sed '2s/^name = .*/name = "..\/escaped"/' "$src/examples/scenarios/a_regulator_switching.toml" >"$work/ex/x.toml"
expect2 "a name ../escaped" "x.toml:2:8: key 'name': must be printable text without /" \
  "$bin" demo --examples "$work/ex" --out "$work/demo/out"
[ ! -e "$work/demo/escaped" ] && [ ! -e "$work/demo/out" ] || bad "demo: a directory written"

# Inputs held whole are bounded up front (issue 49: a 200 MB operation log took 2.4 GB); compare
# streams channels.csv (two 700 MB files held as columns ran out of memory), its lines bounded:
# sparse files, refused at their first line.
mkdir -p "$work/r1" "$work/r2"
for r in r1 r2; do echo '{"metrics": {}, "claims": []}' >"$work/$r/summary.json"; truncate -s 600M "$work/$r/channels.csv"; done
expect2 "compare a 600 MB channels.csv of one line" "r1/channels.csv:1: a line longer than 1 MiB" \
  "$bin" compare "$work/r1" "$work/r2" --out "$work/never"
# The operation log is streamed too (its 32 MiB bound dropped): a sparse one is refused at its
# first byte, one past the 8 GiB that bound the time up front.
truncate -s 33M "$work/big_log.json"
expect2 "a 33 MiB operation log of NULs" "big_log.json:1:1: not JSON" \
  "$bin" report "$work/big_log.json" --out "$work/never.html"
truncate -s 9G "$work/big_log.json"
expect2 "a 9 GiB operation log" "big_log.json: 9216 MiB, more than the 8192 MiB" \
  "$bin" report "$work/big_log.json" --out "$work/never.html"
rm -f "$work/big_log.json"
[ ! -e "$work/never" ] && [ ! -e "$work/never.html" ] || bad "bounded inputs: an output written"

[ $fail -eq 0 ] && echo "readers: every case held"
exit $fail
