#!/usr/bin/env bash
# The libFuzzer targets (fuzz/*.cpp, one per parser), built with clang.
#
#   scripts/fuzz-smoke.sh            make test's step. Every target first replays its committed
#                                    regression corpus (fuzz/regressions/<target>/: every input
#                                    that ever crashed it) and its seed corpus (the project's own
#                                    examples): exactly the same inputs every time. Then it fuzzes
#                                    a fixed number of runs from a fixed seed, no longer a random
#                                    seed for a time. That part is not bit-reproducible: libFuzzer
#                                    14's exploration from one seed was measured to differ between
#                                    runs (new units ±5 %, even single-threaded, ASLR, -reload,
#                                    the RSS and timeout threads off), so a rare finding can still
#                                    appear in one run only; it then goes to fuzz/regressions/.
#   scripts/fuzz-smoke.sh --explore [SECONDS]
#                                    make fuzz: random seeds, SECONDS per target (default 600),
#                                    a corpus kept between runs in build/fuzz/explore/. What it
#                                    finds is saved as build/fuzz/<target>-crash-*: fix it and
#                                    add the input to fuzz/regressions/<target>/ in the same
#                                    commit, so make test replays it from then on.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=replay
seconds=600
case "${1:-}" in
  "") ;;
  --explore) mode=explore; seconds=${2:-600} ;;
  *) echo "usage: scripts/fuzz-smoke.sh [--explore [SECONDS]]" >&2; exit 2 ;;
esac
# The fixed seed and the runs per target of make test's step: each about 5-25 s of one core on
# the 2-core CI machine (measured 2026-11-26; about 100 s of CPU in all, 60 s on two cores). The
# budget is runs, not seconds, so a slow or loaded machine does the same work and finds the same.
# Remeasured 2026-11-27: a lobes run had become 17.5 ms of CPU (machine files with [[frf]] are
# fitted to modes), 6000 runs 105 s, and a scenario run 5.3 ms (8000: 43 s); back in the budget
# with 1500 and 5000 runs. The recorded signals' reader (signal, 2026-12-06): 100000 runs 6 s.
# A machine's INI (linuxcnc_ini, 2026-12-06): 50000 runs 9 s.
SEED=20261126
declare -A RUNS=([scenario]=5000 [materials]=60000 [lobes]=1500 [tool_limits]=100000
                 [channels_csv]=200000 [canon]=50000 [json_file]=30000 [frf]=20000
                 [calibration]=20000 [signal]=100000 [linuxcnc_ini]=50000 [tool_table]=50000
                 [tool_file]=30000)
targets=(scenario materials lobes tool_limits channels_csv canon json_file frf calibration signal
         linuxcnc_ini tool_table tool_file)

cmake --preset fuzz -DLATHECTL_WERROR="${LATHECTL_WERROR:-OFF}" >/dev/null
# Only the fuzz targets and what they link (not the program): the libraries are built with
# -fsanitize=fuzzer-no-link (CMakePresets.json), so the parsers in them are what libFuzzer's
# coverage and ASan/UBSan see.
cmake --build --preset fuzz -j "$(nproc)" --target "${targets[@]/%/_fuzz}" >/dev/null || {
  echo "fuzz: the clang build of the fuzz targets failed; rerun: cmake --build --preset fuzz" >&2
  exit 1
}

# The seed corpus: inputs as the project writes them.
seeds=build/fuzz/seeds
rm -rf "$seeds"
mkdir -p "${targets[@]/#/$seeds/}"
cp examples/scenarios/*.toml examples/linuxcnc/*.toml "$seeds/scenario/"
cp data/materials.toml "$seeds/materials/"
cp examples/machines/*.toml "$seeds/lobes/"
# Measured FRFs as a tap test exports them: the examples' CSV, and UFF 58 ASCII and 58b files.
cp examples/machines/frf/*.csv examples/machines/frf/*.uff "$seeds/frf/"
cp hal/config/lathectl-tools.toml "$seeds/tool_limits/"
cp examples/gauges/*.csv "$seeds/calibration/"
# lathectl optimize's LinuxCNC tool table and tool file as the project writes them.
cp hal/config/lathectl-lathe.tbl "$seeds/tool_table/"
cp tests/optimize/programs/user_part_tools.toml "$seeds/tool_file/"
# A few rows of a channels.csv as lathectl writes it (header, numbers, nan, inf).
printf 'time_s,x_mm,force_N\n0,1.5,-2e-05\n0.001,nan,inf\n0.002,-inf,3\n' >"$seeds/channels_csv/seed.csv"
cp tests/optimize/canon_example.txt "$seeds/canon/"
# lathectl_vibsensor's recordings: a 16-bit mono WAV of four frames, a CSV of time,acceleration.
printf 'RIFF\x2c\0\0\0WAVEfmt \x10\0\0\0\x01\0\x01\0\x80\xbb\0\0\0\x77\x01\0\x02\0\x10\0data\x08\0\0\0\0\0\xff\x7f\0\x80\x01\0' \
  >"$seeds/signal/seed.wav"
printf 'time_s,acceleration_m_s2\n0,1.5\n2.0833e-05,-20\n4.1667e-05,3e1\n' >"$seeds/signal/seed.csv"
cp hal/config/*.ini "$seeds/linuxcnc_ini/"
# An operation log lathectl_oplog wrote in a LinuxCNC session, and two runs' summary.json.
cp tests/cli/operations_two_tool.json tests/golden/summaries/{c_csv_template,a_regulator_flow}.json \
  "$seeds/json_file/"

if [[ $mode == replay ]]; then
  work=build/fuzz/replay
  rm -rf "$work"  # a fresh working corpus every time: what an earlier run added changes nothing
else
  work=build/fuzz/explore  # kept: a long campaign continues where the last one stopped
fi
mkdir -p "${targets[@]/#/$work/}"

fuzz_one() {
  local target=$1 bin=./build/fuzz/fuzz/${1}_fuzz
  local regress=fuzz/regressions/$target args=()
  mkdir -p "$regress"
  if [[ $mode == replay ]]; then
    args=(-seed="$SEED" -runs="${RUNS[$target]}")
  else
    args=(-seed=0 -max_total_time="$seconds")
  fi
  # New inputs go to the first directory ($work); the others are read only. Loading the corpus
  # runs every input in it first: the regressions and seeds are replayed before any mutation.
  "$bin" "${args[@]}" -max_len=16384 -timeout=10 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="build/fuzz/${target}-" "$work/$target" "$seeds/$target" "$regress" \
    >"$work/$target.log" 2>&1
  echo $? >"$work/$target.rc"
}
export -f fuzz_one
export mode seconds SEED work seeds
export RUNS_DECL="$(declare -p RUNS)"
rm -f "$work"/*.rc
# One target per core at a time: each libFuzzer run is single-threaded.
printf '%s\n' "${targets[@]}" |
  xargs -P "$(nproc)" -I{} bash -c 'eval "$RUNS_DECL"; fuzz_one {}'
failed=0
for target in "${targets[@]}"; do
  log=$work/$target.log
  replayed=$(find fuzz/regressions/$target "$seeds/$target" -type f | wc -l)
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
  if [[ $(cat "$work/$target.rc" 2>/dev/null) != 0 ]]; then
    echo "fuzz: ${target}_fuzz failed ($log):" >&2
    tail -n 40 "$log" >&2
    failed=1
  else
    echo "fuzz: ${target}_fuzz: $replayed inputs replayed, ${runs:-?} runs" \
      "$([[ $mode == replay ]] && echo "(seed $SEED)" || echo "in $seconds s")"
  fi
done
if ((failed)); then
  echo "fuzz: a target failed; its input is build/fuzz/<target>-crash-* (rerun: the target binary" \
    "in build/fuzz/fuzz/ with that file). Fix the defect and add the input to" \
    "fuzz/regressions/<target>/ in the same commit." >&2
  exit 1
fi
echo "fuzz: no crashes"
