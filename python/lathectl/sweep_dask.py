"""The Dask engine of ``lathectl sweep`` (docs/sweep.md, "On a Dask cluster").

Run as ``/usr/bin/python3 -m lathectl.sweep_dask --scheduler tcp://HOST:PORT DIR`` (what
``lathectl sweep SPEC --out DIR --scheduler ...`` does after it has filled DIR/sweep.sqlite's
``cases``), or from Python as :func:`run`. Every case without a ``results`` row goes to the
cluster as one task; the task runs the case's scenario text with the same reader and the same
registry as the local engine (``lathectl._lathectl._run(text, "<base_dir>/case N", None,
False, report=False)``, the label the local engine reads it under; like the local engine, for
summary.json alone: no report built) and returns summary.json's text. Only
this driver writes the store: one ``INSERT OR IGNORE`` per case, in its own transaction, as the
cases complete; a case is recorded once or not at all, whatever is killed when, and a rerun runs
only the cases without a row.

What travels with a case: its scenario text and base_dir, and the bytes of the relative files it
names (keys ending in ``file`` or ``csv``, and those a named TOML file names in turn, e.g. a
machine file's ``[[frf]] file``). A worker that sees the same files under base_dir runs the case
there; one that does not writes them into a temporary directory of its own, runs the case there
and gives the temporary directory's name back as base_dir in summary.json and in messages.
Absolute file names are not shipped: they must exist on every worker.
"""
import argparse
import hashlib
import logging
import os
import sqlite3
import sys
import tempfile
import threading
import time
import tomllib
import uuid

__all__ = ["run", "main", "case_label", "files_named", "run_case", "SweepError"]

RETRIES = 2  # Dask's retries of a task whose exception is not the case's own
STORE = "sweep.sqlite"


class SweepError(RuntimeError):
    """The sweep cannot go on: no store in DIR, no cluster at the address, or the cluster lost."""


def case_label(base_dir, case_id):
    """The name a case is read under: its relative files are found beside it, messages name it."""
    return os.path.join(base_dir, f"case {case_id}")


# --- what travels with a case --------------------------------------------------------------

def _file_values(node):
    """The string values of every key ending in 'file' or 'csv' in a parsed TOML tree."""
    if isinstance(node, dict):
        for k, v in node.items():
            if isinstance(v, str) and (k.endswith("file") or k.endswith("csv")):
                yield v
            else:
                yield from _file_values(v)
    elif isinstance(node, list):
        for v in node:
            yield from _file_values(v)


def files_named(text, base_dir, cache=None):
    """{path relative to base_dir: bytes} of the relative files a scenario's text names.

    A named TOML file (a machine file) is read in turn for the files it names, relative to its own
    folder. Files that do not exist are left out: the reader says so when the case runs.
    cache: a dict {absolute path: bytes} kept across calls, so that a sweep reads each file once.
    """
    found = {}
    cache = {} if cache is None else cache

    def walk(doc_text, doc_dir):
        try:
            doc = tomllib.loads(doc_text)
        except (tomllib.TOMLDecodeError, UnicodeDecodeError):
            return
        for name in _file_values(doc):
            if os.path.isabs(name):
                continue
            path = os.path.normpath(os.path.join(doc_dir, name))
            rel = os.path.relpath(path, base_dir)
            if rel in found:
                continue
            if path not in cache:
                if not os.path.isfile(path):
                    continue
                with open(path, "rb") as f:
                    cache[path] = f.read()
            found[rel] = cache[path]
            if path.endswith(".toml"):
                walk(found[rel].decode("utf-8", "replace"), os.path.dirname(path))

    walk(text, base_dir)
    return found


def _in_place(base_dir, files):
    """True when every shipped file is under base_dir here with the same bytes."""
    for rel, data in files.items():
        path = os.path.join(base_dir, rel)
        try:
            if os.path.getsize(path) != len(data):
                return False
            with open(path, "rb") as f:
                if f.read() != data:
                    return False
        except OSError:
            return False
    return True


def _shipped_base(root, files):
    """A base directory under `root` deep enough that every '..' of the files stays inside it."""
    depth = 0
    for rel in files:
        parts = rel.split(os.sep)
        ups = 0
        while ups < len(parts) and parts[ups] == os.pardir:
            ups += 1
        depth = max(depth, ups)
    return os.path.join(root, *[f"d{i}" for i in range(depth)])


def _ancestor(path, n):
    for _ in range(n):
        path = os.path.dirname(path)
    return path


# --- the task ------------------------------------------------------------------------------

def run_case(case_id, scenario, base_dir, files=None):
    """Runs one case (on a worker): (case_id, status, message, elapsed_s, summary text or None).

    status 'error' with the reader's or the run's one-line message for a case that fails (a bad
    combination, a diverging simulation): those are the case's own and are not retried. elapsed_s:
    the run's wall time in seconds on the worker.
    """
    files = files or {}
    t0 = time.perf_counter()
    if _in_place(base_dir, files):
        return _run_in(case_id, scenario, base_dir, t0, None)
    with tempfile.TemporaryDirectory(prefix="lathectl-case-") as tmp:
        fake = _shipped_base(tmp, files)
        os.makedirs(fake, exist_ok=True)
        for rel, data in files.items():
            path = os.path.normpath(os.path.join(fake, rel))
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "wb") as f:
                f.write(data)
        # The names the worker's files have → the driver's (summary.json's 'file', messages).
        depth = len(os.path.relpath(fake, tmp).split(os.sep)) if fake != tmp else 0
        back = [(fake, base_dir), (tmp, _ancestor(base_dir, depth))]
        return _run_in(case_id, scenario, fake, t0, back)


def _run_in(case_id, scenario, base_dir, t0, back):
    from lathectl import _lathectl

    def restore(s):
        for a, b in back or ():
            s = s.replace(a, b)
        return s

    try:
        result, _warnings = _lathectl._run(scenario, case_label(base_dir, case_id), None, False,
                                           report=False)
        summary = result.summary_json
    except (ValueError, OSError, RuntimeError) as e:  # InputError is a ValueError
        message = " ".join(restore(str(e)).replace("\r", "\n").split("\n"))  # one line
        return case_id, "error", message, time.perf_counter() - t0, None
    return case_id, "ok", "", time.perf_counter() - t0, restore(summary)


# --- the store -----------------------------------------------------------------------------

def _open_store(directory):
    path = os.path.join(directory, STORE)
    if not os.path.isfile(path):
        raise SweepError(f"{path}: no such file (`lathectl sweep SPEC --out {directory}` "
                         "writes it before any case runs)")
    db = sqlite3.connect(path, timeout=60.0, isolation_level=None)
    db.execute("PRAGMA busy_timeout = 60000")
    try:
        db.execute("SELECT case_id, scenario, base_dir FROM cases LIMIT 0")
        db.execute("SELECT case_id, status, message, elapsed_s, summary FROM results LIMIT 0")
    except sqlite3.DatabaseError as e:
        db.close()
        raise SweepError(f"{path}: not a sweep's store ({e})") from None
    return db


def _pending(db):
    """[(case_id, scenario, base_dir)] of the cases without a results row, in case order."""
    return db.execute("SELECT case_id, scenario, base_dir FROM cases WHERE case_id NOT IN "
                      "(SELECT case_id FROM results) ORDER BY case_id").fetchall()


def _record(db, row):
    """One finished case, in its own transaction: recorded once or not at all."""
    db.execute("BEGIN IMMEDIATE")
    try:
        cur = db.execute("INSERT OR IGNORE INTO results(case_id, status, message, elapsed_s, "
                         "summary) VALUES (?, ?, ?, ?, ?)", row)
        db.execute("COMMIT")
    except BaseException:
        db.execute("ROLLBACK")
        raise
    return cur.rowcount == 1


# --- progress ------------------------------------------------------------------------------

def _duration(s):
    s = int(round(s))
    if s >= 3600:
        return f"{s // 3600} h {s % 3600 // 60:02d} min"
    if s >= 60:
        return f"{s // 60} min {s % 60:02d} s"
    return f"{s} s"


class _Progress:
    """'sweep: 37/120 cases done (2 errors), 1 min 20 s left' on stderr, at most every `every` s."""

    def __init__(self, total, done, todo, stream, every=3.0):
        self.total, self.done, self.todo = total, done, todo
        self.ran = self.errors = 0
        self.stream, self.every = stream, every
        self.t0 = self.last = time.monotonic()

    def step(self, status):
        self.ran += 1
        self.done += 1
        self.errors += status == "error"
        now = time.monotonic()
        if self.stream is not None and (now - self.last >= self.every or self.ran == self.todo):
            self.last = now
            left = (now - self.t0) / self.ran * (self.todo - self.ran)
            errs = f" ({self.errors} error{'s' if self.errors != 1 else ''})" if self.errors else ""
            tail = f", {_duration(left)} left" if self.ran < self.todo else ""
            print(f"sweep: {self.done}/{self.total} cases done{errs}{tail}", file=self.stream,
                  flush=True)


# --- the driver ----------------------------------------------------------------------------

def _submit(client, cases, retries):
    """{future: case_id}: one task per case; the files a case names scattered once per set."""
    shipped, read, digests = {}, {}, {}
    futures = {}
    token = uuid.uuid4().hex[:12]
    for case_id, scenario, base_dir in cases:
        files = files_named(scenario, base_dir, read)
        handle = None
        if files:
            for d in files.values():  # the same bytes object for the same file: hashed once
                if id(d) not in digests:
                    digests[id(d)] = hashlib.sha256(d).digest()
            k = (base_dir, tuple(sorted((r, digests[id(d)]) for r, d in files.items())))
            if k not in shipped:
                # broadcast: every worker holds a copy, so a worker that dies loses none
                shipped[k] = client.scatter([files], broadcast=True, hash=False)[0]
            handle = shipped[k]
        f = client.submit(run_case, case_id, scenario, base_dir, handle, retries=retries,
                          key=f"lathectl-case-{case_id}-{token}", pure=False)
        futures[f] = case_id
    return futures


_LOST = object()  # the cluster cannot give a completed case's outcome: its scheduler is gone


def _outcome(future, case_id):
    """The row of a completed task; None for a task cancelled (no row: the next run runs it);
    _LOST when the scheduler cannot be asked. A task in error is a case the cluster gave up on (its
    worker died too often, or its exception outlived the retries): an `error` row."""
    import asyncio
    import concurrent.futures

    try:
        if future.status == "finished":
            return future.result()
        if future.status == "error":
            e = future.exception()
            msg = " ".join(f"the cluster gave up on this case: {type(e).__name__}: {e}".split())
            return case_id, "error", msg, 0.0, None
    except (OSError, TimeoutError, asyncio.CancelledError, concurrent.futures.CancelledError):
        return _LOST
    return None


def run(directory, scheduler, *, retries=RETRIES, progress=sys.stderr, client=None,
        timeout=30.0):
    """Runs every case of DIR/sweep.sqlite without a results row on the Dask cluster.

    directory: the sweep's DIR (holding sweep.sqlite). scheduler: the scheduler's address,
    ``tcp://HOST:PORT`` (ignored when `client`, a distributed.Client, is given). retries: Dask's
    retries of a task whose exception is not the case's own. progress: a stream for the progress
    lines (None: silent). timeout: seconds to wait for the scheduler.
    Returns a dict: total (cases), ran (recorded now), ok, error, missing (cases still without a
    row: 0 unless the cluster was lost). Raises SweepError for a DIR without a store or a
    scheduler that does not answer.
    """
    db = _open_store(directory)
    try:
        total = db.execute("SELECT count(*) FROM cases").fetchone()[0]
        cases = _pending(db)
        counts = {"total": total, "ran": 0, "ok": 0, "error": 0}
        if cases:
            own = client is None
            if own:
                client = _connect(scheduler, timeout)
            try:
                _drive(db, client, cases, retries, counts,
                       _Progress(total, total - len(cases), len(cases), progress))
            finally:
                if own:
                    client.close()
        counts["missing"] = len(_pending(db))
        return counts
    finally:
        db.close()


def _connect(scheduler, timeout):
    try:
        from distributed import Client
    except ImportError:
        raise SweepError("the Dask client is not installed (Debian: apt install "
                         "python3-distributed)") from None
    try:
        client = Client(scheduler, timeout=timeout, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as e:
        raise SweepError(f"--scheduler {scheduler}: no Dask scheduler answers ({e})") from None
    try:
        _same_lathectl(client)
    except BaseException:
        client.close()
        raise
    return client


def _worker_lathectl():
    from lathectl import _lathectl

    return f"{_lathectl.__version__} ({_lathectl.commit})"


def _same_lathectl(client):
    """Every worker present imports the same lathectl as this driver: the same reader, the same
    numbers (a worker that joins later is not asked)."""
    own = _worker_lathectl()
    try:
        theirs = client.run(_worker_lathectl)
    except Exception as e:
        raise SweepError(f"a Dask worker cannot import lathectl ({type(e).__name__}: {e}): "
                         "install python3-lathectl on every node") from None
    for worker, v in sorted(theirs.items()):
        if v != own:
            raise SweepError(f"the Dask worker {worker} has lathectl {v}, this driver {own}: "
                             "install the same python3-lathectl on every node")


def _drive(db, client, cases, retries, counts, prog):
    from distributed import as_completed

    futures = _submit(client, cases, retries)
    for f in as_completed(list(futures), loop=client.loop):
        row = _outcome(f, futures.pop(f))
        f.release()
        if row is _LOST:
            break  # the cases not recorded run next time
        if row is None:
            continue
        if _record(db, row):
            counts["ran"] += 1
            counts[row[1]] += 1
        prog.step(row[1])


class _OneLine:
    """A logging filter: Dask's messages without their tracebacks (a lost scheduler logs several
    of asyncio's CancelledError); empty messages dropped."""

    @staticmethod
    def filter(record):
        record.exc_info = record.exc_text = None
        return bool(record.getMessage().strip())


def _follow_parent():
    """Started by `lathectl sweep` (the parent process is the program): end when it ends, even
    by SIGKILL, as if killed with it (the store keeps every case recorded, one transaction each),
    so that a rerun's driver is the only one. Run by hand, the driver is left alone."""
    ppid = os.getppid()
    try:
        if os.path.basename(os.readlink(f"/proc/{ppid}/exe")) != "lathectl":
            return
    except OSError:
        return

    def watch():
        while os.getppid() == ppid:
            time.sleep(0.2)
        os._exit(1)

    threading.Thread(target=watch, name="lathectl-parent", daemon=True).start()


def main(argv=None):
    """The command line: exit 0 when every case has a row, 1 when some have none (the cluster
    was lost), 2 on bad input (no store, no scheduler, a worker with another lathectl), 130 when
    interrupted (Ctrl-C)."""
    ap = argparse.ArgumentParser(
        prog="python3 -m lathectl.sweep_dask",
        description="Run the cases of DIR/sweep.sqlite without a result on a Dask cluster.")
    ap.add_argument("--scheduler", required=True, help="the scheduler's address, tcp://HOST:PORT")
    ap.add_argument("--retries", type=int, default=RETRIES,
                    help="Dask's retries of a task that raised (default %(default)s)")
    ap.add_argument("--quiet", action="store_true", help="no progress lines")
    ap.add_argument("dir", help="the sweep's output directory (holding sweep.sqlite)")
    a = ap.parse_args(argv)
    _follow_parent()
    try:
        import distributed  # noqa: F401  (sets up its logging: a handler on 'distributed')
    except ImportError:
        pass
    # Dask's handler (of all its loggers) and the last resort (asyncio's, tornado's messages)
    for h in logging.getLogger("distributed").handlers + [logging.lastResort]:
        if h is not None:
            h.addFilter(_OneLine)
    try:
        c = run(a.dir, a.scheduler, retries=a.retries, progress=None if a.quiet else sys.stderr)
    except SweepError as e:
        print(f"lathectl sweep: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("lathectl sweep: interrupted; the cases recorded are kept, the same command runs "
              "the rest", file=sys.stderr)
        return 130
    if c["missing"]:
        print(f"lathectl sweep: {c['missing']} of {c['total']} cases have no result (the "
              "cluster was lost?): run the same command again to run them", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
