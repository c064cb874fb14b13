#!/bin/sh
# lathectl sweep (docs/sweep.md) end to end on a fast example (A, short runs): a spec's errors
# name its line and write nothing; the cases' order; a case's metrics equal `lathectl run` of the
# scenario edited by hand to the same values; a failing combination is a row, not the end; a
# sweep killed with SIGKILL and rerun completes with every case once, the finished ones not rerun.
bin=$1; src=$2; work=$3
py=/usr/bin/python3
rm -rf "$work"; mkdir -p "$work"
fail=0
bad() { echo "FAIL: $*"; fail=1; }
sc=$src/examples/scenarios/a_finishing_aim.toml

# 1. A key the system does not know, a value out of range, a bad distribution, a scenario that is
#    not there: exit 2, one line naming the spec's line, no DIR.
printf 'scenario = "%s"\n[grid]\n"run.duration_s" = [0.5]\n"slide.mas_kg" = [50]\n' "$sc" > "$work/e1.toml"
printf 'scenario = "%s"\n[grid]\n"controller.feed_mm_per_min" = [60,\n  -5]\n' "$sc" > "$work/e2.toml"
printf 'scenario = "%s"\n[random]\nsamples = 2\n"slide.mass_kg" = { gauss = [1, 2] }\n' "$sc" > "$work/e3.toml"
printf 'scenario = "missing.toml"\n[grid]\n"run.seed" = [1]\n' > "$work/e4.toml"
for e in e1:4 e2:4 e3:4 e4:1; do
  f=${e%%:*}; line=${e#*:}
  "$bin" sweep "$work/$f.toml" --out "$work/$f" > /dev/null 2> "$work/err.txt"; rc=$?
  [ "$rc" -eq 2 ] || bad "$f: exit $rc, expected 2"
  grep -q "^error: $work/$f.toml:$line:" "$work/err.txt" || bad "$f: not at line $line: $(cat "$work/err.txt")"
  [ "$(wc -l < "$work/err.txt")" -eq 1 ] || bad "$f: more than one line: $(cat "$work/err.txt")"
  [ ! -e "$work/$f" ] || bad "$f: wrote $work/$f"
done

# The Dask engine without its driver, or with an address that is not one: exit 2, nothing written.
printf 'scenario = "%s"\n[grid]\n"run.duration_s" = [0.5]\n' "$sc" > "$work/v.toml"
LATHECTL_PYTHON_DIR=$work/nowhere "$bin" sweep "$work/v.toml" --out "$work/d" --scheduler tcp://127.0.0.1:8786 > /dev/null 2> "$work/err.txt"; rc=$?
[ "$rc" -eq 2 ] && grep -q "^error: --scheduler: the Dask driver lathectl.sweep_dask is not in $work/nowhere" "$work/err.txt" || bad "no driver: exit $rc: $(cat "$work/err.txt")"
"$bin" sweep "$work/v.toml" --out "$work/d" --scheduler 127.0.0.1:8786 > /dev/null 2> "$work/err.txt"; rc=$?
[ "$rc" -eq 2 ] && grep -q "^error: --scheduler 127.0.0.1:8786: expected" "$work/err.txt" || bad "bad address: exit $rc: $(cat "$work/err.txt")"
[ ! -e "$work/d" ] || bad "--scheduler errors wrote $work/d"

# The hand-over to the Dask driver (a stand-in here: the real one is python/lathectl/
# sweep_dask.py): its arguments, PYTHONPATH, and the outputs written from the rows it recorded.
mkdir -p "$work/py/lathectl"
: > "$work/py/lathectl/__init__.py"
cat > "$work/py/lathectl/sweep_dask.py" <<'EOT'
import json, os, sqlite3, sys
assert sys.argv[1:3] == ["--scheduler", "tcp://127.0.0.1:8786"], sys.argv
assert os.environ["PYTHONPATH"].split(":")[0] == os.path.dirname(os.path.dirname(__file__))
db = sqlite3.connect(os.path.join(sys.argv[3], "sweep.sqlite"), isolation_level=None)
for (c,) in db.execute("SELECT case_id FROM cases").fetchall():
    db.execute("INSERT OR IGNORE INTO results VALUES (?, 'ok', '', 0.5, ?)",
               (c, json.dumps({"metrics": {"x": {"y": c + 0.25}}})))
EOT
LATHECTL_PYTHON_DIR=$work/py "$bin" sweep "$work/v.toml" --out "$work/d" --scheduler tcp://127.0.0.1:8786 > /dev/null 2> "$work/err.txt" || bad "hand-over: exit $?: $(cat "$work/err.txt")"
grep -qx '0,0.5,ok,,0.5,0.25' "$work/d/results.csv" || bad "hand-over results: $(cat "$work/d/results.csv")"

# 2. The cases, grid in the spec's order (the last fastest) × the random samples.
cat > "$work/s.toml" <<EOT
scenario = "$sc"
[grid]
"run.duration_s" = [0.5, 0.7]
"controller.feed_mm_per_min" = [50, 65.5]
[random]
samples = 2
seed = 7
"slide.mass_kg" = { choice = [55, 65] }
EOT
"$bin" sweep "$work/s.toml" --out "$work/s" --workers 2 > "$work/out.txt" 2>&1 || bad "sweep: exit $? $(cat "$work/out.txt")"
cut -d, -f1-3 "$work/s/cases.csv" > "$work/order.txt"
printf 'case,run.duration_s,controller.feed_mm_per_min\n0,0.5,50\n1,0.5,50\n2,0.5,65.5\n3,0.5,65.5\n4,0.7,50\n5,0.7,50\n6,0.7,65.5\n7,0.7,65.5\n' > "$work/order-expected.txt"
cmp -s "$work/order.txt" "$work/order-expected.txt" || bad "cases.csv order: $(cat "$work/order.txt")"
head -1 "$work/s/results.csv" | grep -q '^case,run.duration_s,controller.feed_mm_per_min,slide.mass_kg,status,message,elapsed_s,feed_drift_pct,' || bad "results.csv header: $(head -1 "$work/s/results.csv")"
[ "$(grep -c ',ok,' "$work/s/results.csv")" -eq 8 ] || bad "not 8 ok rows"
grep -q '<svg' "$work/s/report.html" || bad "report.html has no plot"

# 3. Case 6 against `lathectl run` of the scenario edited by hand (its studies removed).
$py - "$sc" "$work/s/cases.csv" 6 > "$work/c6.toml" <<'EOT' || bad "editing the scenario"
import csv, re, sys
text = open(sys.argv[1]).read()
row = list(csv.DictReader(open(sys.argv[2])))[int(sys.argv[3])]
text = re.sub(r"(?m)^duration_s = .*$", "duration_s = " + row["run.duration_s"], text)
text = re.sub(r"(?m)^feed_mm_per_min = .*$", "feed_mm_per_min = " + row["controller.feed_mm_per_min"], text)
text = re.sub(r"(?m)^mass_kg = .*$", "mass_kg = " + row["slide.mass_kg"], text)
text = re.sub(r"(?ms)^\[compare\].*?(?=^\[metrics\])", "", text)
print(text)
EOT
"$bin" run "$work/c6.toml" --out "$work/c6" > /dev/null 2>&1 || bad "run of case 6: exit $?"
$py - "$work/s/sweep.sqlite" "$work/c6/summary.json" <<'EOT' || bad "case 6's metrics differ from lathectl run's"
import json, sqlite3, sys
db = sqlite3.connect(sys.argv[1])
(s,) = db.execute("SELECT summary FROM results WHERE case_id = 6").fetchone()
a, b = json.loads(s)["metrics"], json.load(open(sys.argv[2]))["metrics"]
sys.exit(0 if a == b and a else 1)
EOT

# 4. A combination the reader refuses (each value alone is fine) is a row with its message.
printf 'scenario = "%s"\n[grid]\n"run.duration_s" = [0.3]\n"run.step_s" = [1e-4, 1e-3]\n"run.record_interval_s" = [2e-3, 5e-4]\n' "$sc" > "$work/c.toml"
"$bin" sweep "$work/c.toml" --out "$work/c" > /dev/null 2>&1 || bad "sweep with a failing case: exit $?"
grep -q "^3,0.3,0.001,0.0005,error,.*record_interval_s.*must be ≥ step_s" "$work/c/results.csv" || bad "no error row: $(cat "$work/c/results.csv" | cut -c1-120)"
[ "$(grep -c ',ok,' "$work/c/results.csv")" -eq 3 ] || bad "the other cases did not run"
grep -q "Failed cases" "$work/c/report.html" || bad "report does not list the failed case"

# 5. kill -9 mid-sweep, then the same command: every case once, the finished ones not rerun.
printf 'scenario = "%s"\n[grid]\n"run.duration_s" = [30.0]\n"controller.feed_mm_per_min" = [50, 52, 54, 56, 58, 60, 62, 64, 66, 68]\n' "$sc" > "$work/k.toml"
"$bin" sweep "$work/k.toml" --out "$work/k" --workers 1 > /dev/null 2>&1 &
pid=$!
n=0
for i in $(seq 1 300); do
  n=$($py -c "import sqlite3,sys; print(sqlite3.connect(sys.argv[1]).execute('SELECT count(*) FROM results').fetchone()[0])" "$work/k/sweep.sqlite" 2>/dev/null || echo 0)
  [ "$n" -ge 2 ] && break
  sleep 0.05
done
kill -9 $pid; wait $pid 2>/dev/null
$py -c "import sqlite3,sys; [print(*r) for r in sqlite3.connect(sys.argv[1]).execute('SELECT case_id, elapsed_s FROM results ORDER BY case_id')]" "$work/k/sweep.sqlite" > "$work/before.txt"
done_before=$(wc -l < "$work/before.txt")
[ "$done_before" -ge 2 ] && [ "$done_before" -lt 10 ] || bad "kill: $done_before cases done when killed (expected 2..9)"
"$bin" sweep "$work/k.toml" --out "$work/k" --workers 2 > "$work/out.txt" 2>&1 || bad "rerun: exit $?"
grep -q "10 cases, 10 ok, 0 failed ($((10 - done_before)) run now, $done_before done before)" "$work/out.txt" || bad "rerun line: $(cat "$work/out.txt")"
$py - "$work/k/sweep.sqlite" "$work/before.txt" <<'EOT' || bad "after the rerun: cases missing, twice, or rerun"
import sqlite3, sys
rows = sqlite3.connect(sys.argv[1]).execute("SELECT case_id, elapsed_s FROM results").fetchall()
ids = [r[0] for r in rows]
assert sorted(ids) == list(range(10)), ids
now = {c: e for c, e in rows}
for line in open(sys.argv[2]):
    c, e = line.split()
    assert now[int(c)] == float(e), (c, e, now[int(c)])  # the same row: not rerun
EOT
[ "$(tail -n +2 "$work/k/results.csv" | wc -l)" -eq 10 ] || bad "results.csv has not 10 rows"

[ $fail -eq 0 ] && echo "sweep: all checks passed"
exit $fail
