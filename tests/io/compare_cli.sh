#!/usr/bin/env bash
# `lathectl compare` on two runs of one example that differ in one parameter:
#
#   tests/io/compare_cli.sh LATHECTL EXAMPLE.toml WORKDIR
#
# Runs the example, and again with [controller] feed_mm_per_min raised by half; compares them and
# checks from the comparison's summary.json that exactly that setting differs (60 → 90), that
# every metric's difference is its second value minus its first, and that the report carries the
# interactive plots' data. Then bad input: a missing directory, a directory that is not a run's
# output, channels.csv with a bad header and with a bad row — each exit 2, one line naming the
# file (and line and column), and no output directory written.
set -euo pipefail
[[ $# -eq 3 ]] || { echo "usage: $0 LATHECTL EXAMPLE.toml WORKDIR" >&2; exit 2; }
lathectl=$1
example=$2
work=$3
rm -rf -- "$work"
mkdir -p -- "$work"
cd -- "$work"
sed 's/^feed_mm_per_min = 60.0$/feed_mm_per_min = 90.0/' "$example" >changed.toml
grep -q '^feed_mm_per_min = 90.0$' changed.toml || { echo "FAIL: $example has no feed_mm_per_min = 60.0" >&2; exit 1; }
"$lathectl" run "$example" --out run1 >/dev/null
"$lathectl" run changed.toml --out run2 >/dev/null
"$lathectl" compare run1 run2 --out cmp
python3 - cmp/summary.json <<'PY'
import json, math, sys
s = json.load(open(sys.argv[1]))
changed = s["settings_changed"]
assert list(changed) == ["controller.feed_mm_per_min"], changed
assert changed["controller.feed_mm_per_min"]["values"] == [60.0, 90.0], changed
assert changed["controller.feed_mm_per_min"]["differences"] == [30.0], changed
numeric = 0
for key, m in s["metrics"].items():
    a, b = m["values"]
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        assert math.isclose(m["differences"][0], b - a, rel_tol=1e-12, abs_tol=1e-300), key
        numeric += 1
assert numeric >= 5, numeric
assert s["claims"] and all(len(c["met"]) == 2 for c in s["claims"]), s["claims"]
assert s["claims_changed"] == sum(c["changed"] for c in s["claims"])
print(f"ok: 1 setting differs (feed 60 → 90 mm/min), {numeric} numeric metrics, "
      f"{len(s['claims'])} claims, {s['claims_changed']} changed verdict")
PY
grep -q 'id="lathectl-plot-data"' cmp/report.html || { echo "FAIL: no interactive plot data" >&2; exit 1; }

# A run longer than compare keeps whole (16384 rows; issue 49: channels.csv is streamed into a
# bounded plot per channel): run2's rows three times over, 18000 rows; each of its series' plot
# data covers every row, to the last time.
mkdir -p long && cp run2/summary.json long/
python3 - run2/channels.csv long/channels.csv <<'PY'
import sys
lines = open(sys.argv[1]).read().splitlines()
rows = [r.split(",", 1) for r in lines[1:]]
span = float(rows[-1][0])
with open(sys.argv[2], "w") as f:
    f.write(lines[0] + "\n")
    for k in range(3):
        f.writelines(f"{float(t) + k * span!r},{rest}\n" for t, rest in rows)
PY
"$lathectl" compare run1 long --out cmp_long >/dev/null
python3 - cmp_long/report.html long/channels.csv <<'PY'
import json, re, sys
html = open(sys.argv[1]).read()
text = re.search(r'id="lathectl-plot-data"[^>]*>(.*?)</script>', html, re.S).group(1)
data = json.loads(text.replace("<\\/", "</"))
lines = open(sys.argv[2]).read().splitlines()
rows, last = lines[1:], float(lines[-1].split(",", 1)[0])
assert len(data["plots"]) == len(lines[0].split(",")) - 1, len(data["plots"])
blobs = {s["blob"] for p in data["plots"] for s in p["series"] if s["name"] == "run 2"}
for b in blobs:
    blob = data["blobs"][b]
    assert blob["n"] == len(rows) == 18000 and blob["x1"] == last, (blob["n"], blob["x1"], last)
    assert blob["levels"][0]["b"] > 1, blob["levels"][0]["b"]  # the pyramid, not the rows
print(f"ok: a {len(rows)}-row run streamed, {len(blobs)} series to t = {last} s")
PY

# Bad input: exit 2, one line naming what is wrong, nothing written.
expect_bad() {  # expect_bad WHAT_THE_MESSAGE_NAMES ARGS...
  local names=$1
  shift
  local rc=0
  "$lathectl" compare "$@" --out bad 2>err.txt >/dev/null || rc=$?
  if [[ $rc -ne 2 || $(wc -l <err.txt) -ne 1 ]] || ! grep -qF -- "$names" err.txt || [[ -e bad ]]; then
    echo "FAIL: compare $* → exit $rc, expected 2, one line naming '$names', no bad/:" >&2
    cat err.txt >&2
    exit 1
  fi
}
expect_bad "nowhere: not a directory" run1 nowhere
mkdir -p notarun && echo x >notarun/summary.json
expect_bad "notarun: not a lathectl run's output (no channels.csv)" run1 notarun
cp -r run2 badrow
awk 'NR == 5 { sub(/,[^,]*$/, ",x1") } { print }' run2/channels.csv >badrow/channels.csv
last=$(head -1 run2/channels.csv | awk -F, '{print $NF}')
expect_bad "badrow/channels.csv:5: column '$last': expected a number, got 'x1'" run1 badrow
cp -r run2 badhead
{ head -1 run2/channels.csv | sed 's/^time_s,/time_s,time_s,/'; tail -n +2 run2/channels.csv; } >badhead/channels.csv
expect_bad "badhead/channels.csv:1: column 2 'time_s': named twice" run1 badhead
cp -r run2 badjson
printf '{\n"metrics": {}\n' >badjson/summary.json
expect_bad "badjson/summary.json:3:1: not JSON" run1 badjson
printf '{\n"metrics": {},\n"claims": {}\n}\n' >badjson/summary.json
expect_bad "badjson/summary.json:3:1: key 'claims': expected an array" run1 badjson
# --out an earlier output set holding the runs compared (issue 49: it succeeded and replaced the
# set, the runs with it): refused before anything is written, the runs kept.
cp -r run1 run2 cmp/
rc=0
"$lathectl" compare cmp/run1 cmp/run2 --out cmp 2>err.txt >/dev/null || rc=$?
if [[ $rc -ne 2 ]] || ! grep -qF -- "--out cmp: holds the input cmp/run1" err.txt ||
   [[ ! -f cmp/run1/summary.json || ! -f cmp/run2/channels.csv ]]; then
  echo "FAIL: compare cmp/run1 cmp/run2 --out cmp → exit $rc: $(cat err.txt)" >&2
  exit 1
fi
echo "ok: bad input → exit 2, one line, nothing written"
