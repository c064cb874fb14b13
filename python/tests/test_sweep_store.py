"""The DIR contract of `lathectl sweep` (docs/sweep.md) seen from Python: the store's schema and
cases as the Dask driver reads them, and a case run by lathectl._lathectl._run (what the driver
calls) from its text under its label gives the summary.json text the local engine recorded, byte
for byte; an error row's message is the same too."""
import json
import os
import pathlib
import sqlite3
import subprocess

import lathectl
from lathectl import _lathectl

LATHECTL = os.environ.get("LATHECTL", "lathectl")
SCENARIO = pathlib.Path(lathectl.examples_dir()) / "a_finishing_aim.toml"


def test_local_rows_equal_the_drivers_run(tmp_path):
    spec = tmp_path / "s.toml"
    spec.write_text(f'scenario = "{SCENARIO}"\n[grid]\n"run.duration_s" = [0.3]\n'
                    '"run.step_s" = [1e-4, 1e-3]\n"run.record_interval_s" = [2e-3, 5e-4]\n')
    out = tmp_path / "out"
    subprocess.run([LATHECTL, "sweep", str(spec), "--out", str(out), "--workers", "2"],
                   check=True, stdout=subprocess.DEVNULL)
    db = sqlite3.connect(out / "sweep.sqlite")
    assert db.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    cols = [r[1] for r in db.execute("PRAGMA table_info(results)")]
    assert cols == ["case_id", "status", "message", "elapsed_s", "summary"]
    cases = db.execute("SELECT case_id, scenario, base_dir, vars FROM cases ORDER BY case_id")
    rows = {r[0]: r[1:] for r in db.execute("SELECT case_id, status, message, summary FROM results")}
    n = 0
    for case_id, text, base_dir, vars_ in cases:
        assert base_dir == str(SCENARIO.parent)
        assert list(json.loads(vars_)) == ["run.duration_s", "run.step_s", "run.record_interval_s"]
        label = f"{base_dir}/case {case_id}"
        status, message, summary = rows[case_id]
        try:
            result, _ = _lathectl._run(text, label, None, False)
        except ValueError as e:  # lathectl.InputError: the reader refused the combination
            assert status == "error" and message == str(e), (message, str(e))
        else:
            assert status == "ok" and summary is not None
            assert result.summary_json == summary  # byte for byte
        n += 1
    assert n == 4 and sorted(r[0] for r in rows.values()) == ["error", "ok", "ok", "ok"]
