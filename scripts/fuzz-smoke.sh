#!/usr/bin/env bash
# Builds the libFuzzer targets with clang and runs each for a while on a corpus seeded from the
# examples. `make test` runs it briefly; `make fuzz` (or a larger SECONDS) runs it longer.
set -euo pipefail
SECONDS_PER_TARGET=${1:-20}
cd "$(dirname "$0")/.."
cmake --preset fuzz -DLATHECTL_WERROR="${LATHECTL_WERROR:-OFF}" >/dev/null
targets=(scenario materials lobes tool_limits channels_csv canon json_file)
# Only the fuzz targets and what they link (not the program): the libraries are built with
# -fsanitize=fuzzer-no-link (CMakePresets.json), so the parsers in them are what libFuzzer's
# coverage and ASan/UBSan see.
cmake --build --preset fuzz -j "$(nproc)" --target "${targets[@]/%/_fuzz}" >/dev/null || {
  echo "fuzz: the clang build of the fuzz targets failed; rerun: cmake --build --preset fuzz" >&2
  exit 1
}
work=build/fuzz/corpus
mkdir -p "$work/scenario" "$work/materials" "$work/lobes" "$work/tool_limits" "$work/channels_csv" \
  "$work/canon" "$work/json_file"
cp examples/scenarios/*.toml examples/linuxcnc/step_allowance_modes.toml "$work/scenario/"
cp data/materials.toml "$work/materials/"
cp examples/machines/*.toml "$work/lobes/"
cp hal/config/lathectl-tools.toml "$work/tool_limits/"
# A few rows of a channels.csv as lathectl writes it (header, numbers, nan, inf).
printf 'time_s,x_mm,force_N\n0,1.5,-2e-05\n0.001,nan,inf\n0.002,-inf,3\n' >"$work/channels_csv/seed.csv"
cp tests/optimize/canon_example.txt "$work/canon/"
# An operation log lathectl_oplog wrote in a LinuxCNC session, and two runs' summary.json.
cp tests/cli/operations_two_tool.json tests/golden/summaries/{c_csv_template,a_regulator_flow}.json \
  "$work/json_file/"
# One target per core at a time: each libFuzzer run is single-threaded.
fuzz_one() {
  local target=$1 seconds=$SECONDS_PER_TARGET
  # The CSV, canonical-command and JSON readers are small grammars: a quarter of the time covers
  # them (make test: 5 s each).
  [[ $target == channels_csv || $target == canon || $target == json_file ]] &&
    seconds=$(((SECONDS_PER_TARGET + 3) / 4))
  ./build/fuzz/fuzz/${target}_fuzz -max_total_time="$seconds" -max_len=16384 \
    -timeout=10 -rss_limit_mb=4096 -print_final_stats=0 "$work/$target" \
    -artifact_prefix=build/fuzz/${target}- >"$work/$target.log" 2>&1
  echo $? >"$work/$target.rc"
}
export -f fuzz_one
export SECONDS_PER_TARGET work
rm -f "$work"/*.rc
printf '%s\n' "${targets[@]}" | xargs -P "$(nproc)" -I{} bash -c 'fuzz_one {}'
failed=0
for target in "${targets[@]}"; do
  if [[ $(cat "$work/$target.rc" 2>/dev/null) != 0 ]]; then
    echo "fuzz: ${target}_fuzz failed ($work/$target.log):" >&2
    tail -n 40 "$work/$target.log" >&2
    failed=1
  else
    echo "fuzz: ${target}_fuzz: $(tail -n 1 "$work/$target.log")"
  fi
done
if ((failed)); then
  echo "fuzz: a target failed; its input is in build/fuzz/<target>-crash-* (rerun the target on it)" >&2
  exit 1
fi
echo "fuzz: no crashes"
