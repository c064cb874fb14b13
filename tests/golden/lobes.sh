#!/bin/bash
# lobes for every machine file into WORK/<machine>/, then compared with tests/golden/lobes/.
set -euo pipefail
bin=$1 src=$2 work=$3
rm -rf "$work"; mkdir -p "$work"
for f in "$src"/examples/machines/*.toml; do
  n=$(basename "$f" .toml)
  "$bin" lobes "$f" --out "$work/$n" >/dev/null
done
exec python3 "$src/tests/golden/compare.py" "$src/tests/golden/lobes" "$work"
