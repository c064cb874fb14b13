#!/usr/bin/env bash
# `lathectl reasons`: the table an operator reads a reason pin's number in, its --json, and the
# copy published for the Python side (hal/reasons.json) that lathectl_oplog.py decodes the
# operation log's op-reasons bits with.
# Usage: reasons_test.sh LATHECTL SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
fail=0
bad() { echo "FAIL: $*"; fail=1; }

"$bin" reasons > "$work/table.txt" 2> "$work/err.txt" || bad "lathectl reasons: exit $?: $(cat "$work/err.txt")"
head -1 "$work/table.txt" | grep -Eq '^code +bit +name +alarm +systems +meaning$' ||
  bad "header: $(head -1 "$work/table.txt")"
# Codes ≥ 31 have a bit of their own (a 1 << code mask lost them); alarms say so.
grep -Eq '^  31  12  engaged +no +E +The tool has just entered the cut' "$work/table.txt" ||
  bad "engaged row: $(grep engaged "$work/table.txt")"
grep -Eq '^  60  21  gauge_backstop +yes +D ' "$work/table.txt" || bad "gauge_backstop row"
grep -Eq '^  11   5  sensor_out_of_range +yes +A E ' "$work/table.txt" || bad "sensor_out_of_range row"
# One line a row of the core's table (include/lathectl/control/types.hpp, kReasons).
rows=$(grep -c '^    {Reason::' "$src/include/lathectl/control/types.hpp")
[ "$rows" -ge 26 ] || bad "$rows rows counted in types.hpp's kReasons, expected at least 26"
[ "$(($(wc -l < "$work/table.txt") - 1))" -eq "$rows" ] ||
  bad "$(wc -l < "$work/table.txt") lines, expected $rows reasons and a header"
grep -Eq '^  62  23  gauge_size +no +D ' "$work/table.txt" || bad "gauge_size row"

"$bin" reasons --json > "$work/reasons.json" || bad "lathectl reasons --json: exit $?"
python3 - "$work/reasons.json" <<'PY' || bad "--json content"
import json, sys
rows = json.load(open(sys.argv[1]))["reasons"]
assert [r["bit"] for r in rows] == list(range(len(rows))), "bits are positions"
assert len({r["code"] for r in rows}) == len(rows) and len({r["name"] for r in rows}) == len(rows)
by = {r["name"]: r for r in rows}
assert by["spindle_power_limit"]["code"] == 41 and not by["spindle_power_limit"]["alarm"]
assert by["tool_breakage"]["alarm"] and by["tool_breakage"]["systems"] == "A E"
assert by["slide_off"]["code"] == 70 and not by["slide_off"]["alarm"]
assert all(r["meaning"].endswith(".") for r in rows)
PY
cmp -s "$work/reasons.json" "$src/hal/reasons.json" ||
  bad "hal/reasons.json is not what this lathectl publishes: run \`lathectl reasons --json > hal/reasons.json\`"

# lathectl_oplog decodes op-reasons with the published table (its hal module stubbed: no LinuxCNC).
python3 - "$src/hal" <<'PY' || bad "lathectl_oplog's decoding of op-reasons"
import os, sys, types
sys.modules["hal"] = types.ModuleType("hal")
sys.path.insert(0, sys.argv[1])
import lathectl_oplog as o
by_code, by_bit = o.reason_table(os.path.join(sys.argv[1], "reasons.json"))
assert by_code[31] == "engaged" and by_code[60] == "gauge_backstop", by_code
# engaged (bit 12), spindle_power_limit (bit 15) and gauge_backstop (bit 21): codes ≥ 31.
mask = 1 << 12 | 1 << 15 | 1 << 21 | 1 << 0
assert o.reasons_of(mask, by_bit) == ["none", "engaged", "spindle_power_limit", "gauge_backstop"], \
    o.reasons_of(mask, by_bit)
assert o.reasons_of(-(1 << 31), by_bit) == ["bit31"]  # the s32 pin's top bit
PY
exit $fail
