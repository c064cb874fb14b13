"""lathectl.lobes, read_frf and fit_modes against the program: for every machine file, Python's
Lobes is lobes.json's dict bit for bit and its arrays are lobes.csv's curves at full precision;
read_frf reads what a machine file's [[frf]] reads, fit_modes fits what its path fits; dict
machines read and fail as their files do."""
import json
import math
import os
import pathlib
import signal
import subprocess
import threading
import time
import tomllib

import numpy as np
import pytest

import lathectl
from lathectl import _scenario

MACHINES = pathlib.Path(lathectl.examples_dir()).parent / "machines"
MACHINE_FILES = sorted(MACHINES.glob("*.toml"))
LATHECTL = os.environ.get("LATHECTL", "lathectl")
# Each machine file as it is costs 2-8 s twice (Python and the program); the comparison of
# every file runs them with fewer semi-discretization speeds and a small chart, and only the
# fastest (b_sdof, 1.7 s) is compared as it is, its full chart included.
# Under ctest the program's own output of every machine file as it is exists (the golden_lobes
# test's, LATHECTL_GOLDEN_LOBES_OUT): then every file is compared as it is, Python's side only.
GOLDEN_OUT = os.environ.get("LATHECTL_GOLDEN_LOBES_OUT")
AS_IS = [p.stem for p in MACHINE_FILES] if GOLDEN_OUT else ["b_sdof"]
SMALL = {"sd_speeds": 4, "chart_speeds": 5, "chart_depths": 4}


def load(path):
    with open(path, "rb") as f:
        return tomllib.load(f)


def small(machine):
    """The machine dict with fewer SD speeds and a small chart, its [[frf]] files absolute."""
    d = dict(machine)
    d["lobes"] = {**d.get("lobes", {}), **SMALL}
    if "frf" in d:
        d["frf"] = [{**f, "file": str(MACHINES / f["file"])} for f in d["frf"]]
    return d


def cli_lobes(path, out):
    given = pathlib.Path(GOLDEN_OUT) / path.stem if GOLDEN_OUT else None
    if given and path.parent == MACHINES and (given / "lobes.json").is_file():
        out = given  # the program's files for this machine file, written by golden_lobes
    else:
        subprocess.run([LATHECTL, "lobes", str(path), "--out", str(out)], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    blocks = {}
    for block in (out / "lobes.csv").read_text().split("\n\n"):
        lines = block.strip("\n").split("\n")
        blocks[lines[0]] = [ln.split(",") for ln in lines[1:]]
    return json.loads((out / "lobes.json").read_text()), blocks


def cells(speed, depth):
    """Rows as lobes.csv writes them: speed to 6 digits, depth to 9, NaN an empty cell."""
    return [[f"{s:.6g}", "" if math.isnan(d) else f"{d:.9g}"] for s, d in zip(speed, depth)]


def assert_equals_program(lobes, j, csv):
    assert lobes.json == j  # same keys, same numbers (JSON at full precision)
    assert cells(lobes.speed_rpm, lobes.depth_mm) == csv["speed_rpm,frequency_domain_depth_mm"]
    sd = csv["speed_rpm,semi_discretization_depth_mm"]
    if lobes.sd_depth_mm is None:
        assert sd == []
    else:
        assert cells(lobes.sd_speed_rpm, lobes.sd_depth_mm) == sd
        assert len(lobes.sd_depth_mm) == len(j["semi_discretization"])
        for k, row in enumerate(j["semi_discretization"]):
            assert lobes.sd_speed_rpm[k] == row["speed_rpm"]
            if row["depth_mm"] is not None:
                assert lobes.sd_depth_mm[k] == row["depth_mm"]
    chart = csv.get("speed_rpm,sd_chart_boundary_depth_mm")
    assert (lobes.chart_depth_mm is None) == (chart is None)
    if chart is not None:
        assert cells(lobes.chart_speed_rpm, lobes.chart_depth_mm) == chart
    crit = j["critical_depth_mm"]
    assert lobes.critical_depth_mm == (math.inf if crit is None else crit)
    assert lobes.chatter_frequency_Hz == j["chatter_frequency_Hz"]
    assert lobes.recommendation == j["recommendation"]
    assert lobes.warnings == j["warnings"]


def test_names_and_docs():
    for name in ("lobes", "read_frf", "fit_modes", "Lobes", "design"):
        assert hasattr(lathectl, name) and name in lathectl.__all__, name
    assert "rpm" in lathectl.Lobes.__doc__ and "NaN" in lathectl.Lobes.__doc__
    assert "m/N" in lathectl.read_frf.__doc__ and "complex" in lathectl.read_frf.__doc__
    assert "stiffness_N_per_m" in lathectl.fit_modes.__doc__
    assert "base_dir" in lathectl.lobes.__doc__
    assert len(MACHINE_FILES) >= 6


@pytest.mark.parametrize("machine", MACHINE_FILES, ids=lambda p: p.stem)
def test_machine_equals_the_program(machine, tmp_path):
    d = small(load(machine))
    text, _ = _scenario.to_toml(d)
    (tmp_path / "m.toml").write_text(text)
    j, csv = cli_lobes(tmp_path / "m.toml", tmp_path / "cli")
    from_dict = lathectl.lobes(d, base_dir=MACHINES)
    assert_equals_program(from_dict, j, csv)
    # The file and the dict are the same machine: the same result.
    assert lathectl.lobes(tmp_path / "m.toml").json == from_dict.json


@pytest.mark.parametrize("name", AS_IS)
def test_machine_as_it_is_equals_the_program(name, tmp_path):
    j, csv = cli_lobes(MACHINES / f"{name}.toml", tmp_path / "cli")
    lobes = lathectl.lobes(MACHINES / f"{name}.toml")
    assert_equals_program(lobes, j, csv)
    if name == "b_sdof":
        assert lobes.chart_depth_mm is not None and len(lobes.sd_depth_mm) == 40


def test_lobes_object():
    m = load(MACHINES / "b_sdof.toml")
    m["lobes"] = {"sd_speeds": 0, "chart_speeds": 0, "chart_depths": 0}
    lobes = lathectl.lobes(m, progress=False)
    assert lobes.sd_depth_mm is None and lobes.sd_speed_rpm is None
    assert lobes.chart_depth_mm is None and lobes.chart_speed_rpm is None
    for a in (lobes.speed_rpm, lobes.depth_mm):
        assert a.dtype == np.float64 and a.shape == (1001,) and a.flags.c_contiguous
    assert lobes.speed_rpm[0] == 2000 and lobes.speed_rpm[-1] == 14000
    # The SDOF closed form 2kζ(1+ζ)/(K_f·cos²θ) (the file's comment: 7.319 mm at 252.98 Hz).
    k, z, c2 = 2.26e8, 0.012, math.cos(math.radians(30)) ** 2
    assert lobes.json["closed_form_sdof"]["depth_mm"] == pytest.approx(
        2 * k * z * (1 + z) / (1000e6 * c2) * 1e3, rel=1e-12)
    assert round(lobes.critical_depth_mm, 3) == 7.319
    assert round(lobes.chatter_frequency_Hz, 2) == 252.98
    assert np.nanmin(lobes.depth_mm) >= lobes.critical_depth_mm * (1 - 1e-9)
    assert lobes.lobes is lobes.json["lobes"]
    assert [lb["N"] for lb in lobes.lobes] == sorted(lb["N"] for lb in lobes.lobes)
    r = repr(lobes)
    assert r.startswith("<lathectl.Lobes: critical depth 7.319 mm at 252.98 Hz") and "pocket" in r


def test_dict_errors_are_the_files(tmp_path):
    good = load(MACHINES / "b_two_mode.toml")
    cases = [("cutting", "kf_N_per_mm2", -5, "cutting.kf_N_per_mm2"),
             ("speed", "max_rpm", 500, "speed.max_rpm"),
             ("mode", "bogus", 1, "mode[1].bogus")]
    for table, key, value, where in cases:
        d = json.loads(json.dumps(good))
        (d[table][1] if table == "mode" else d[table])[key] = value
        text, _ = _scenario.to_toml(d)
        (tmp_path / "bad.toml").write_text(text)
        with pytest.raises(lathectl.InputError) as from_file:
            lathectl.lobes(tmp_path / "bad.toml")
        with pytest.raises(lathectl.InputError) as from_dict:
            lathectl.lobes(d)
        file_msg, dict_msg = str(from_file.value), str(from_dict.value)
        assert file_msg.startswith(str(tmp_path / "bad.toml") + ":")
        assert dict_msg.startswith(where + ": "), dict_msg
        # The same message after the location.
        assert file_msg.split(": ", 1)[1] == dict_msg.split(": ", 1)[1]
    with pytest.raises(TypeError):
        lathectl.lobes(42)


def test_dict_frf_relative_to_base_dir():
    d = load(MACHINES / "b_frf.toml")
    d["lobes"] = {"sd_speeds": 0, "chart_speeds": 0, "chart_depths": 0}
    assert lathectl.lobes(d, base_dir=MACHINES).json["measured_frf"]["files"][0]["file"] == \
        "frf/tool_xx.csv"
    with pytest.raises(lathectl.InputError, match=r"^frf\[0\]\.file: .*tool_xx.csv: no such file"):
        lathectl.lobes(d, base_dir=MACHINES / "frf")


@pytest.mark.parametrize("name", ["tool_xx.csv", "tool_yy.uff"])
def test_read_frf_and_fit_are_the_machine_files(name, tmp_path):
    f, h = lathectl.read_frf(MACHINES / "frf" / name)
    assert f.dtype == np.float64 and h.dtype == np.complex128 and f.shape == h.shape
    assert f.ndim == 1 and np.all(np.diff(f) > 0)
    # One [[frf]] along the chip thickness (weight cos²0 = 1): the machine file's path reads,
    # orients and fits exactly this FRF.
    machine = {"cutting": {"kf_N_per_mm2": 1000},
               "frf": [{"file": str(MACHINES / "frf" / name)}],
               "speed": {"min_rpm": 1000, "max_rpm": 12000},
               "lobes": {"sd_speeds": 0, "chart_speeds": 0, "chart_depths": 0}}
    (tmp_path / "m.toml").write_text(_scenario.to_toml(machine)[0])
    j, csv = cli_lobes(tmp_path / "m.toml", tmp_path / "cli")
    measured = j["measured_frf"]
    assert measured["files"][0]["points"] == len(f)
    assert measured["files"][0]["min_Hz"] == f[0] and measured["files"][0]["max_Hz"] == f[-1]
    rows = next(v for k, v in csv.items() if k.startswith("frequency_Hz,measured_real"))
    assert [r[:3] for r in rows] == [[f"{a:.9g}", f"{b.real:.9g}", f"{b.imag:.9g}"]
                                     for a, b in zip(f, h)]
    modes = lathectl.fit_modes(f, h)
    assert isinstance(modes, list) and modes.residual == measured["fit_relative_residual"]
    assert [{k: m[k] for k in ("stiffness_N_per_m", "damping_ratio", "natural_frequency_Hz")}
            for m in modes] == measured["fitted_modes"]
    assert all(m["angle_deg"] == 0.0 for m in modes)
    # The example's known modes (frf/make_frf.py): x 250 Hz, y 150 Hz.
    assert modes[0]["natural_frequency_Hz"] == pytest.approx(250 if "xx" in name else 150, rel=1e-2)


def test_fitted_modes_as_mode_tables():
    """The fitted modes given back as [[mode]] tables are the modal system of the [[frf]] machine
    (what semi-discretization and the time-domain rigs use); the frequency-domain lobes differ,
    as the [[frf]] machine reads the measured FRF itself against its fit."""
    base = {"cutting": {"kf_N_per_mm2": 1000}, "speed": {"min_rpm": 1000, "max_rpm": 12000},
            "lobes": {"sd_speeds": 6, "chart_speeds": 0, "chart_depths": 0}}
    measured = lathectl.lobes({**base, "frf": [{"file": "frf/tool_xx.csv"}]}, base_dir=MACHINES)
    modes = lathectl.fit_modes(*lathectl.read_frf(MACHINES / "frf" / "tool_xx.csv"))
    modal = lathectl.lobes({**base, "mode": list(modes)})
    assert modal.json["modes_at_tool"] == measured.json["modes_at_tool"]
    # The same modal system bisected from different brackets (3 × each one's own envelope):
    # equal to the bisection's relative tolerance, 1e-3.
    np.testing.assert_allclose(modal.sd_depth_mm, measured.sd_depth_mm, rtol=1e-3, atol=0)


def test_fit_modes_errors():
    f = np.linspace(10, 100, 50)
    with pytest.raises(ValueError, match="one H per frequency"):
        lathectl.fit_modes(f, np.ones(49, complex))
    with pytest.raises(lathectl.InputError, match="fit_modes"):
        lathectl.fit_modes(f, np.ones(50, complex))
    with pytest.raises(lathectl.InputError, match=r"absent.csv: no such file"):
        lathectl.read_frf(MACHINES / "frf" / "absent.csv")
    with pytest.raises(lathectl.InputError, match=r"b_sdof\.toml:\d+"):
        lathectl.read_frf(MACHINES / "b_sdof.toml")


def test_ctrl_c_stops_lobes():
    pid = os.getpid()
    timer = threading.Timer(0.5, lambda: os.kill(pid, signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        lathectl.lobes(MACHINES / "b_slow_high_freq.toml")
    timer.join()
    assert time.monotonic() - start < 3.0  # the whole machine takes 7 s or more
