#!/usr/bin/env bash
# Builds the libFuzzer targets with clang and runs each for a while on a corpus seeded from the
# examples. `make test` runs it briefly; `make fuzz` (or a larger SECONDS) runs it longer.
set -euo pipefail
SECONDS_PER_TARGET=${1:-20}
cd "$(dirname "$0")/.."
cmake --preset fuzz -DLATHECTL_WERROR="${LATHECTL_WERROR:-OFF}" >/dev/null
cmake --build --preset fuzz -j "$(nproc)" >/dev/null
work=build/fuzz/corpus
mkdir -p "$work/scenario" "$work/materials" "$work/lobes" "$work/tool_limits" "$work/canon"
cp examples/scenarios/*.toml "$work/scenario/"
cp data/materials.toml "$work/materials/"
cp examples/machines/*.toml "$work/lobes/"
cp hal/config/lathectl-tools.toml "$work/tool_limits/"
cp tests/optimize/canon_example.txt "$work/canon/"
for target in scenario materials lobes tool_limits canon; do
  echo "fuzz: ${target}_fuzz for ${SECONDS_PER_TARGET} s"
  ./build/fuzz/fuzz/${target}_fuzz -max_total_time="$SECONDS_PER_TARGET" -max_len=16384 \
    -timeout=10 -rss_limit_mb=4096 -print_final_stats=0 "$work/$target" \
    -artifact_prefix=build/fuzz/ 2>&1 | tail -n 2
done
echo "fuzz: no crashes"
