"""lathectl.sweep_dask (the Dask engine of `lathectl sweep`) on a real cluster on 127.0.0.1: a
`dask scheduler` and two `dask worker`s, started and stopped here. The store is made here with the
schema of docs/sweep.md (independent of the C++ command); the cases are example scenarios' texts
with small edits. Checked: the cluster's summaries are byte for byte the local engine's
(lathectl._lathectl._run of the same text under the same label); a worker killed mid-sweep and a
driver killed mid-sweep lose no case and record none twice, and a rerun does not run the cases
already recorded (counted from the scheduler's task stream, one record per execution)."""
import io
import json
import os
import pathlib
import re
import shutil
import signal
import sqlite3
import subprocess
import sys
import threading
import time

import pytest

distributed = pytest.importorskip("distributed")  # python3-distributed
pytestmark = pytest.mark.filterwarnings(  # Debian 12's distributed on its tornado
    "ignore:make_current is deprecated:DeprecationWarning")

import lathectl
from lathectl import _lathectl, sweep_dask

EXAMPLES = pathlib.Path(lathectl.examples_dir())
DASK = shutil.which("dask", path="/usr/bin:" + os.environ.get("PATH", "")) or "dask"
SCHEMA = """
CREATE TABLE cases(case_id INTEGER PRIMARY KEY, scenario TEXT NOT NULL, base_dir TEXT NOT NULL,
                   vars TEXT NOT NULL);
CREATE TABLE results(case_id INTEGER PRIMARY KEY REFERENCES cases(case_id),
                     status TEXT NOT NULL CHECK(status IN ('ok','error')),
                     message TEXT NOT NULL, elapsed_s REAL NOT NULL, summary TEXT);
"""


def a_case(duration_s, feed):
    """a_finishing_aim as a sweep's case: its [compare] and [sweep] off, run.duration_s and
    controller.feed_mm_per_min set."""
    t = (EXAMPLES / "a_finishing_aim.toml").read_text()
    t = re.sub(r"(?m)^\[(compare|sweep)\]\n(?:[^\[\n].*\n|\n)*", "", t)
    t = re.sub(r"(?m)^duration_s = .*$", f"duration_s = {duration_s}", t)
    t = re.sub(r"(?m)^feed_mm_per_min = .*$", f"feed_mm_per_min = {feed}", t)
    assert "[sweep]" not in t and "[compare]" not in t and "[metrics]" in t
    return t


def make_store(d, texts, base_dir=EXAMPLES):
    """DIR/sweep.sqlite with the cases 0..n-1; returns [(case_id, text, base_dir)]."""
    d.mkdir(parents=True, exist_ok=True)
    db = sqlite3.connect(d / "sweep.sqlite")
    db.execute("PRAGMA journal_mode=WAL")
    db.executescript(SCHEMA)
    cases = [(i, t, str(base_dir)) for i, t in enumerate(texts)]
    with db:
        db.executemany("INSERT INTO cases VALUES (?, ?, ?, ?)",
                       [(i, t, b, json.dumps({"i": i})) for i, t, b in cases])
    db.close()
    return cases


def results(d):
    """{case_id: (status, message, elapsed_s, summary)} and the number of rows."""
    db = sqlite3.connect(d / "sweep.sqlite")
    rows = db.execute("SELECT case_id, status, message, elapsed_s, summary FROM results").fetchall()
    db.close()
    return {r[0]: r[1:] for r in rows}, len(rows)


def local(cases):
    """{case_id: (status, message, summary)}: the local engine's path, in this process."""
    out = {}
    for i, text, base in cases:
        try:
            r, _ = _lathectl._run(text, os.path.join(base, f"case {i}"), None, False)
            out[i] = ("ok", "", r.summary_json)
        except lathectl.InputError as e:
            out[i] = ("error", str(e).replace("\n", " "), None)
    return out


class Cluster:
    """A scheduler and workers on 127.0.0.1 (no nanny: a SIGKILLed worker stays dead)."""

    def __init__(self, root):
        root.mkdir(parents=True, exist_ok=True)
        self.root = root
        self.procs = []
        self.workers = []
        self.names = {}  # pid → name
        self.env = dict(os.environ, DASK_CONFIG=str(root / "dask-config"))
        self.client = None
        try:
            self._up(root / "scheduler.json")
        except BaseException:
            self.close()
            raise

    def _up(self, sched):
        self._start([DASK, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                     "--scheduler-file", str(sched)], "scheduler")
        deadline = time.monotonic() + 60
        while not sched.exists() or not sched.read_text().strip().endswith("}"):
            log = self.root / "scheduler.log"
            assert time.monotonic() < deadline and self.procs[0].poll() is None, log.read_text()
            time.sleep(0.1)
        self.address = json.loads(sched.read_text())["address"]
        self.client = distributed.Client(self.address, set_as_default=False, timeout=30)
        self.client.get_task_stream()  # the scheduler records every execution from now on
        self.two_workers()

    def _start(self, argv, name):
        with open(self.root / f"{name}.log", "wb") as log:
            p = subprocess.Popen(argv, stdout=log, stderr=subprocess.STDOUT, env=self.env,
                                 stdin=subprocess.DEVNULL, start_new_session=True)
        self.procs.append(p)
        self.names[p.pid] = name
        return p

    def two_workers(self):
        self.workers = [w for w in self.workers if w.poll() is None]
        while len(self.workers) < 2:
            n = len(self.procs)
            (self.root / f"w{n}").mkdir()
            self.workers.append(self._start(
                [DASK, "worker", self.address, "--nworkers", "1", "--nthreads", "1", "--no-nanny",
                 "--no-dashboard", "--host", "127.0.0.1", "--name", f"w{n}",
                 "--local-directory", str(self.root / f"w{n}")], f"w{n}"))
        deadline = time.monotonic() + 60
        while len(self.client.scheduler_info()["workers"]) != 2:
            assert time.monotonic() < deadline, "the workers did not join"
            time.sleep(0.1)

    def executions(self):
        """{token: [case_id, ...]}: one entry per task the workers finished (or raised)."""
        out = {}
        for rec in self.client.get_task_stream():
            m = re.fullmatch(r"lathectl-case-(\d+)-(\w+)", str(rec["key"]))
            if m:
                out.setdefault(m.group(2), []).append(int(m.group(1)))
        return out

    def close(self):
        try:
            if self.client is not None:
                self.client.close()
        finally:
            for p in self.procs:
                if p.poll() is None:
                    p.kill()
                p.wait()


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    c = Cluster(tmp_path_factory.mktemp("cluster"))
    try:
        yield c
    finally:
        c.close()


def wait_rows(d, n, thread_or_proc):
    deadline = time.monotonic() + 60
    while results(d)[1] < n:
        alive = (thread_or_proc.is_alive() if isinstance(thread_or_proc, threading.Thread)
                 else thread_or_proc.poll() is None)
        assert alive and time.monotonic() < deadline, "the sweep ended or stalled early"
        time.sleep(0.02)


def test_small_sweep_equals_the_local_engine(cluster, tmp_path):
    texts = [a_case(8.0, f) for f in (40.0, 50.0, 60.0, 70.0, 80.0, 90.0)]
    texts.append(a_case(8.0, -1.0))  # a bad value: an error row, not the end of the sweep
    texts.append((EXAMPLES / "c_csv_template.toml").read_text())  # names a CSV beside it
    cases = make_store(tmp_path, texts)
    t0 = time.perf_counter()
    want = local(cases)
    t_local = time.perf_counter() - t0
    t0 = time.perf_counter()
    progress = io.StringIO()
    counts = sweep_dask.run(tmp_path, cluster.address, progress=progress)
    t_cluster = time.perf_counter() - t0
    print(f"{len(cases)} cases: locally in one process {t_local:.2f} s, "
          f"on the 2-worker cluster {t_cluster:.2f} s")
    assert counts == {"total": 8, "ran": 8, "ok": 7, "error": 1, "missing": 0}
    assert progress.getvalue().splitlines()[-1] == "sweep: 8/8 cases done (1 error)"
    got, n = results(tmp_path)
    assert n == 8
    for i, (status, message, summary) in want.items():
        assert (got[i][0], got[i][1], got[i][3]) == (status, message, summary), i
        assert got[i][2] > 0
    assert "/case 6:" in got[6][1] and "feed_mm_per_min" in got[6][1]
    assert json.loads(got[7][3])["file"] == str(EXAMPLES / "case 7")
    # Everything recorded: the same command again runs nothing.
    assert sweep_dask.run(tmp_path, cluster.address, progress=None)["ran"] == 0
    assert results(tmp_path) == (got, 8)


def test_files_travel_to_a_worker_without_base_dir(tmp_path):
    """A case whose base_dir the worker does not have: the files it names (the CSV) are shipped,
    written in a temporary directory, and the summary still names base_dir."""
    base = tmp_path / "study"
    shutil.copytree(EXAMPLES / "templates", base / "templates")
    text = (EXAMPLES / "c_csv_template.toml").read_text()
    files = sweep_dask.files_named(text, str(base))
    assert list(files) == ["templates/blended_shaft.csv"]
    want = local([(3, text, str(base))])[3]
    shutil.rmtree(base)  # the worker's machine has no such directory
    got = sweep_dask.run_case(3, text, str(base), files)
    assert (got[1], got[2], got[4]) == want
    assert not base.exists()
    # A file named through '..' keeps its place relative to the scenario.
    shutil.copytree(EXAMPLES / "templates", tmp_path / "shared")
    sub = text.replace('"templates/blended_shaft.csv"', '"../shared/blended_shaft.csv"')
    files = sweep_dask.files_named(sub, str(base))
    assert list(files) == ["../shared/blended_shaft.csv"]
    base.mkdir()
    want = local([(4, sub, str(base))])[4]
    shutil.rmtree(tmp_path / "shared")
    got = sweep_dask.run_case(4, sub, str(base), files)
    assert (got[1], got[2], got[4]) == want
    # A file that is missing is the reader's error, naming the case's label.
    got = sweep_dask.run_case(5, sub, str(base), {})
    assert got[1] == "error" and str(base / "case 5") in got[2] and got[4] is None


def b_case_with_machine_file():
    """b_twin_feed_division, a short cut, its structure from ../machines/b_frf.toml (which names
    two measured FRFs in turn)."""
    t = (EXAMPLES / "b_twin_feed_division.toml").read_text()
    t = re.sub(r"(?m)^\[(compare|sweep|study)\]\n(?:[^\[\n].*\n|\n)*", "", t)
    t = re.sub(r"(?m)^duration_s = .*$", "duration_s = 0.6", t)
    t = re.sub(r"(?m)^z_end_mm = .*$", "z_end_mm = 251", t)
    return t + '\n[structure]\nmachine_file = "../machines/b_frf.toml"\n'


def test_a_machine_file_travels_with_the_files_it_names(tmp_path):
    shutil.copytree(EXAMPLES.parent / "machines", tmp_path / "machines")
    base = tmp_path / "scenarios"
    base.mkdir()
    text = b_case_with_machine_file()
    files = sweep_dask.files_named(text, str(base))
    assert sorted(files) == ["../machines/b_frf.toml", "../machines/frf/tool_xx.csv",
                             "../machines/frf/tool_yy.uff"]
    want = local([(1, text, str(base))])[1]
    assert want[0] == "ok"
    shutil.rmtree(tmp_path / "machines")
    shutil.rmtree(base)
    got = sweep_dask.run_case(1, text, str(base), files)
    assert (got[1], got[2], got[4]) == want


def test_every_file_key_of_the_reader_is_shipped():
    """The reader's own reference (generated from its documented keys): every key whose value is
    a file relative to something is one files_named looks for (a name ending in file or csv)."""
    docs = pathlib.Path(__file__).resolve().parents[2] / "docs"
    rows = []
    for ref in ("scenario-reference.md", "machine-file-reference.md"):
        for line in (docs / ref).read_text().splitlines():
            m = re.match(r"\| `([^`]+)` \|.*relative to\b", line)
            if m:
                rows.append(m.group(1))
    assert sorted(set(rows)) == ["csv", "file", "machine_file"]
    assert all(k.endswith(("file", "csv")) for k in rows)


def test_a_task_the_cluster_gives_up_on_is_an_error_row(cluster, tmp_path, monkeypatch):
    """A task that raises something not the case's own is retried (Dask's retries=2), then
    recorded as an error; the other cases are not held up."""
    ns = {"__name__": "__main__"}  # pickled by value: the workers cannot import this file
    exec("def flaky(case_id, scenario, base_dir, files=None):\n"
         "    from lathectl import sweep_dask\n"
         f"    with open({str(tmp_path / 'runs')!r}, 'a') as f:\n"
         "        f.write(f'{case_id}\\n')\n"
         "    if case_id == 1:\n"
         "        raise KeyError('no such thing')\n"
         "    return sweep_dask.run_case(case_id, scenario, base_dir, files)\n", ns)
    monkeypatch.setattr(sweep_dask, "run_case", ns["flaky"])
    make_store(tmp_path, [a_case(8.0, f) for f in (50.0, 60.0, 70.0)])
    counts = sweep_dask.run(tmp_path, cluster.address, progress=None)
    assert counts == {"total": 3, "ran": 3, "ok": 2, "error": 1, "missing": 0}
    got, _ = results(tmp_path)
    assert got[1][:2] == ("error", "the cluster gave up on this case: KeyError: 'no such thing'")
    assert got[1][3] is None
    runs = (tmp_path / "runs").read_text().split()
    assert sorted(runs) == ["0", "1", "1", "1", "2"]  # case 1: once and RETRIES times again


def test_worker_killed_mid_sweep(cluster, tmp_path):
    n = 16
    cases = make_store(tmp_path, [a_case(40.0, 40.0 + 2.0 * i) for i in range(n)])
    box = {}
    t = threading.Thread(target=lambda: box.update(
        counts=sweep_dask.run(tmp_path, cluster.address, progress=None)))
    t.start()
    wait_rows(tmp_path, 4, t)
    victim = cluster.workers[0]
    workers = cluster.client.scheduler_info()["workers"]
    addr = next(a for a, w in workers.items() if w["name"] == cluster.names[victim.pid])
    busy = cluster.client.processing([addr])[addr]
    assert busy, "the victim has no case"  # one running, the rest queued behind it
    victim.send_signal(signal.SIGKILL)
    victim.wait()
    t.join(120)
    assert not t.is_alive()
    got, rows = results(tmp_path)
    assert box["counts"] == {"total": n, "ran": n, "ok": n, "error": 0, "missing": 0}
    assert rows == n and sorted(got) == list(range(n))  # none lost, none twice
    want = local(cases[::3])  # the numbers too (a third of them: the test's time)
    assert all(got[i][3] == want[i][2] for i in want)
    print(f"worker killed with {len(busy)} cases on it: {n - len(got)} cases lost, "
          f"{rows - len(got)} recorded twice")
    cluster.two_workers()


def test_driver_killed_and_rerun(cluster, tmp_path):
    n = 16
    cases = make_store(tmp_path, [a_case(40.0, 41.0 + 2.0 * i) for i in range(n)])
    env = dict(os.environ)
    p = subprocess.Popen([sys.executable, "-m", "lathectl.sweep_dask", "--scheduler",
                          cluster.address, "--quiet", str(tmp_path)], env=env)
    try:
        wait_rows(tmp_path, 4, p)
    finally:
        p.send_signal(signal.SIGKILL)
        p.wait()
    before, rows = results(tmp_path)
    assert 4 <= rows < n and rows == len(before)
    seen = set(cluster.executions())
    t0 = time.perf_counter()
    assert sweep_dask.main(["--scheduler", cluster.address, "--quiet", str(tmp_path)]) == 0
    t_rerun = time.perf_counter() - t0
    rerun = [c for tok, ids in cluster.executions().items() if tok not in seen for c in ids]
    got, rows = results(tmp_path)
    assert rows == n and sorted(got) == list(range(n))
    assert all(got[i] == before[i] for i in before)  # the recorded rows as they were
    assert not set(rerun) & set(before), "a recorded case ran again"
    assert sorted(rerun) == sorted(set(range(n)) - set(before))
    want = local(cases[::3])
    assert all(got[i][3] == want[i][2] for i in want)
    print(f"driver killed after {len(before)} of {n}: rerun ran {len(rerun)} cases in "
          f"{t_rerun:.2f} s; 0 lost, 0 twice")


def gone(pid):
    """True when the process has ended (gone, or a zombie nobody reaps)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] in "ZX"
    except FileNotFoundError:
        return True


def test_driver_ends_with_lathectl_sweep(cluster, tmp_path):
    """`lathectl sweep` killed with SIGKILL while its driver runs: the driver ends with it (no
    orphan goes on beside the rerun's driver); the rerun completes."""
    fake = tmp_path / "lathectl"  # a parent whose program is named lathectl: python3 itself
    shutil.copy("/usr/bin/python3", fake)
    d = tmp_path / "sweep"
    n = 16
    make_store(d, [a_case(40.0, 43.0 + 2.0 * i) for i in range(n)])
    spawn = ("import subprocess, sys\n"
             "p = subprocess.Popen(['/usr/bin/python3', '-m', 'lathectl.sweep_dask', '--quiet',"
             " '--scheduler', sys.argv[1], sys.argv[2]])\n"
             "print(p.pid, flush=True)\n"
             "p.wait()\n")
    parent = subprocess.Popen([str(fake), "-c", spawn, cluster.address, str(d)],
                              stdout=subprocess.PIPE, text=True)
    driver = int(parent.stdout.readline())
    try:
        wait_rows(d, 4, parent)
    finally:
        parent.kill()
        parent.wait()
    deadline = time.monotonic() + 10
    while not gone(driver):
        assert time.monotonic() < deadline, "the driver outlived lathectl sweep"
        time.sleep(0.05)
    _, rows = results(d)
    time.sleep(0.5)
    assert results(d)[1] == rows < n  # nothing recorded after it ended
    assert sweep_dask.run(d, cluster.address, progress=None)["missing"] == 0
    assert results(d)[1] == n


def test_no_store_and_no_scheduler(tmp_path, capsys):
    assert sweep_dask.main(["--scheduler", "tcp://127.0.0.1:9", str(tmp_path)]) == 2
    assert "sweep.sqlite: no such file" in capsys.readouterr().err
    make_store(tmp_path, [a_case(8.0, 60.0)])
    with pytest.raises(sweep_dask.SweepError, match="no Dask scheduler answers"):
        sweep_dask.run(tmp_path, "tcp://127.0.0.1:9", timeout=1)


def test_scheduler_lost_then_rerun_on_another_cluster(tmp_path):
    """The scheduler killed mid-sweep: the driver exits 1 with one line (no traceback), the cases
    recorded stay; the same command against a new cluster runs the rest."""
    n = 16
    d = tmp_path / "sweep"
    cases = make_store(d, [a_case(40.0, 45.0 + i) for i in range(n)])
    first = Cluster(tmp_path / "c1")
    try:
        p = subprocess.Popen([sys.executable, "-m", "lathectl.sweep_dask", "--scheduler",
                              first.address, str(d)], stderr=subprocess.PIPE, text=True)
        wait_rows(d, 4, p)
        first.procs[0].kill()  # the scheduler
        _, err = p.communicate(timeout=90)
    finally:
        first.close()
    before, rows = results(d)
    assert p.returncode == 1, err
    assert "Traceback" not in err and f"of {n} cases have no result" in err, err
    assert 4 <= rows < n
    second = Cluster(tmp_path / "c2")
    try:
        counts = sweep_dask.run(d, second.address, progress=None)
    finally:
        second.close()
    got, rows = results(d)
    assert counts["ran"] == n - len(before) and counts["missing"] == 0
    assert rows == n and all(got[i] == before[i] for i in before)
    want = local(cases[::3])
    assert all(got[i][3] == want[i][2] for i in want)
