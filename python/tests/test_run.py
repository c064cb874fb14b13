"""lathectl.run and lathectl.check against the program: the example scenarios run from Python
gives the files `lathectl demo` wrote for it (summary.json, channels.csv, channels_compare.csv byte
for byte), Run.summary is summary.json's dict bit for bit, Run.channels are channels.csv's columns
at full precision; dict scenarios read as their files do and fail with the same messages."""
import copy
import json
import math
import os
import pathlib
import re
import subprocess
import tomllib

import numpy as np
import pytest

import lathectl

EXAMPLES = pathlib.Path(lathectl.examples_dir())
SCENARIOS = sorted(p for p in EXAMPLES.glob("*.toml"))
# The program's output for every example: `lathectl demo` (ctest's `demo` test; this test depends
# on it). Without it (run by hand) the program is run here, into a scratch directory.
DEMO_OUT = os.environ.get("LATHECTL_DEMO_OUT")
LATHECTL = os.environ.get("LATHECTL", "lathectl")
# The Python run is the program's own code (the same registry and systems); running every example
# twice cost the suite 95 s of CPU. The suite runs every example whose run takes under 2 s, and of
# the slower ones those that bring a kind of run the others do not ([compare] with [cost], E's
# planned-depth [sweep], B's [study]); the rest are checked against the goldens by
# golden_summaries (the program's output), and here with LATHECTL_PY_ALL_EXAMPLES=1.
SLOW_LIKE_OTHERS = {"e_stepped_fixed", "a_obliteration", "e_stepped_seed004_depth", "e_worn_tool",
                    "c_dead_zone", "c_stick_slip", "d_cycle_keyway",
                    "e_stepped_life", "d_gauging", "d_cycle_flats", "b_twin_depth_division",
                    "d_low_resonance"}
CHECKED = [p for p in SCENARIOS
           if os.environ.get("LATHECTL_PY_ALL_EXAMPLES") or p.stem not in SLOW_LIKE_OTHERS]


def cli_output(scenario, tmp_path):
    if DEMO_OUT:
        d = pathlib.Path(DEMO_OUT) / scenario.stem
        if d.is_dir():
            return d
    d = tmp_path / "cli"
    subprocess.run([LATHECTL, "run", str(scenario), "--out", str(d)], check=True,
                   stdout=subprocess.DEVNULL)
    return d


def test_version_and_names():
    assert re.match(r"^\d+\.\d+\.\d+", lathectl.__version__)
    assert issubclass(lathectl.InputError, ValueError)
    for name in ("run", "check", "Run", "InputError"):
        assert hasattr(lathectl, name), name
    assert "seed" in lathectl.run.__doc__ and "dict" in lathectl.run.__doc__
    assert (pathlib.Path(lathectl.data_dir()) / "materials.toml").is_file()
    assert len(SCENARIOS) >= 30


@pytest.mark.parametrize("scenario", CHECKED, ids=lambda p: p.stem)
def test_example_equals_the_program(scenario, tmp_path):
    r = lathectl.run(scenario)
    cli = cli_output(scenario, tmp_path)
    out = tmp_path / "py"
    r.write(out)
    for name in ("summary.json", "channels.csv", "channels_compare.csv"):
        a, b = out / name, cli / name
        assert a.exists() == b.exists(), name
        if a.exists():
            assert a.read_bytes() == b.read_bytes(), f"{scenario.stem}: {name} differs"
    # The dict is summary.json's: same keys, same numbers (json.loads of the file).
    assert r.summary == json.loads((cli / "summary.json").read_text())
    assert r.ok == r.summary["verdict"]["ok"]
    # Channels: channels.csv's columns, which round the full-precision values to 9 digits.
    with open(cli / "channels.csv") as f:
        head = f.readline().strip().split(",")
        table = np.loadtxt(f, delimiter=",", ndmin=2)
    assert list(r.channels) == head
    for i, name in enumerate(head):
        col = r.channels[name]
        assert col.dtype == np.float64 and col.ndim == 1 and col.flags.c_contiguous
        assert col.shape == (table.shape[0],), name
        rounded = np.array([float(f"{v:.9g}") for v in col[:: max(1, len(col) // 500)]])
        assert np.array_equal(rounded, table[:: max(1, len(col) // 500), i], equal_nan=True), name


def test_report_equals_the_programs(tmp_path):
    s = EXAMPLES / "a_finishing_aim.toml"
    lathectl.run(s).write(tmp_path / "py")
    subprocess.run([LATHECTL, "run", str(s), "--out", str(tmp_path / "cli")], check=True,
                   stdout=subprocess.DEVNULL)
    for name in ("report.html", "summary.json", "channels.csv"):
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()


def test_seed_replaces_the_scenarios():
    s = EXAMPLES / "d_gauging.toml"
    a, b = lathectl.run(s, seed=7), lathectl.run(s, seed=7)
    assert a.summary == b.summary
    assert a.summary != lathectl.run(s).summary  # the scenario's own seed gives another part
    with pytest.raises(lathectl.InputError, match="seed"):
        lathectl.run(s, seed=-1)


def test_dict_runs_as_its_file():
    for stem in ("a_finishing_aim", "c_csv_template", "d_gauging"):
        path = EXAMPLES / f"{stem}.toml"
        d = tomllib.loads(path.read_text())
        a = lathectl.run(path).summary
        b = lathectl.run(d, base_dir=EXAMPLES).summary
        a.pop("file", None), b.pop("file", None)
        assert a == b, stem


def located_rest(msg):
    """(location, the rest) of 'file:line:col: rest' or 'key.path: rest'."""
    m = re.match(r"^(.*?):(\d+)(?::\d+)?: (.*)$", msg) or re.match(r"^([^ :]+): (.*)$", msg)
    return (m.group(1), m.groups()[-1]) if m else (None, msg)


def mutations(doc):
    """Bad scenarios made from a good one: a value out of every range (negative, huge, NaN), a
    wrong type, an unknown key, in every table of the file."""
    for table, body in doc.items():
        if not isinstance(body, dict):
            continue
        numeric = [k for k, v in body.items() if isinstance(v, (int, float)) and not isinstance(v, bool)]
        for k in numeric[:3]:
            for bad in (-1e9, 1e300, float("nan"), "text"):
                d = copy.deepcopy(doc)
                d[table][k] = bad
                yield f"{table}.{k}", d
        d = copy.deepcopy(doc)
        d[table]["no_such_key_mm"] = 1.0
        yield f"{table}.no_such_key_mm", d


def toml_text(d):
    from lathectl import _scenario
    return _scenario.to_toml(d)[0]


@pytest.mark.parametrize("scenario", SCENARIOS[::3], ids=lambda p: p.stem)
def test_dict_errors_are_the_files(scenario, tmp_path):
    doc = tomllib.loads(scenario.read_text())
    checked = 0
    for key, bad in mutations(doc):
        f = tmp_path / "bad.toml"
        f.write_text(toml_text(bad))
        try:
            lathectl.check(f, base_dir=EXAMPLES)
            file_msg = None
        except lathectl.InputError as e:
            file_msg = str(e)
        try:
            lathectl.check(bad, base_dir=EXAMPLES)
            dict_msg = None
        except lathectl.InputError as e:
            dict_msg = str(e)
        assert (file_msg is None) == (dict_msg is None), (key, file_msg, dict_msg)
        if file_msg is None:
            continue
        floc, frest = located_rest(file_msg)
        dloc, drest = located_rest(dict_msg)
        assert floc == str(f), file_msg
        assert frest == drest, (file_msg, dict_msg)
        assert "<scenario dict>" not in dict_msg and str(tmp_path) not in dict_msg
        checked += 1
    assert checked > 0


def test_dict_error_names_the_key_path():
    d = tomllib.loads((EXAMPLES / "a_finishing_aim.toml").read_text())
    d["run"]["step_s"] = -1.0
    with pytest.raises(lathectl.InputError) as e:
        lathectl.check(d)
    assert str(e.value).startswith("run.step_s: "), str(e.value)
    with pytest.raises(TypeError):
        lathectl.check({"system": "A", "run": {"step_s": object()}})
    with pytest.raises(TypeError):
        lathectl.check(42)


def test_check_returns_none_and_bad_file_names_it(tmp_path):
    assert lathectl.check(EXAMPLES / "e_stepped_seed004.toml") is None
    f = tmp_path / "x.toml"
    f.write_text('system = "Q"\n')
    with pytest.raises(lathectl.InputError, match=re.escape(str(f))):
        lathectl.check(f)
    with pytest.raises(lathectl.InputError):
        lathectl.check(tmp_path)  # a directory is refused before a byte is read


def test_write_refuses_a_foreign_directory(tmp_path):
    r = lathectl.run(EXAMPLES / "a_finishing_aim.toml")
    (tmp_path / "mine.txt").write_text("keep")
    with pytest.raises(lathectl.InputError):
        r.write(tmp_path)
    assert (tmp_path / "mine.txt").read_text() == "keep"
    assert "a_finishing_aim" in repr(r) and "system A" in repr(r)


INTERRUPTED = r'''
import sys, time, lathectl
print("start", flush=True)
try:
    lathectl.run(sys.argv[1])
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted", flush=True)
'''


@pytest.mark.parametrize("stem", ["b_twin_depth_division", "d_low_resonance", "e_worn_tool"])
def test_ctrl_c_stops_a_long_run(stem):
    """SIGINT while the GIL is released: KeyboardInterrupt within a second or so, not at the
    run's end (each of these runs takes 8-25 s)."""
    import signal
    import sys
    import time
    p = subprocess.Popen([sys.executable, "-c", INTERRUPTED, str(EXAMPLES / f"{stem}.toml")],
                         stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "start"
    time.sleep(1.0)
    t = time.monotonic()
    p.send_signal(signal.SIGINT)
    out = p.communicate(timeout=60)[0]
    took = time.monotonic() - t
    assert out.strip() == "interrupted", out
    assert took < 4.0, f"{stem}: stopped {took:.2f} s after Ctrl-C"
