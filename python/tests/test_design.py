"""lathectl.design.<name> against `lathectl design NAME --json`: every calculator at its defaults
and with changed inputs gives the program's JSON (the same dict, bit for bit), a result's "inputs"
given back give the same result, bad keys and values raise InputError naming the key."""
import inspect
import json
import os
import pathlib
import subprocess
import warnings

import pytest

import lathectl
from lathectl import design

LATHECTL = os.environ.get("LATHECTL", "lathectl")
CALIBRATION = str(pathlib.Path(__file__).resolve().parents[2] / "examples/gauges/d_calibration.csv")
NAMES = ["pulse_regulator", "adaptive_speed", "planned_mode", "gauge", "tracer", "modulation"]
# Inputs each calculator is tried with beside its defaults (the first three with a default are
# also changed by 10 % each, one at a time).
CASES = {
    "pulse_regulator": [{"T_ms": 20}, {"f_Hz": 40, "d_mm": 10, "leak_cm3_per_min_per_MPa": 3,
                                       "Py_N": 800, "dPy_N": -200}],
    "adaptive_speed": [{"material": "steel_45", "t_mm": 2, "s_mm_per_rev": 0.2,
                        "V_m_per_min": 150},
                       {"Vp_m_per_min": 120, "Sp_mm_per_rev": 0.3, "yv": 0.35,
                        "S_mm_per_rev": 0.2, "D_mm": 50, "F_mm_per_min": 100, "n_rpm": 1000}],
    "planned_mode": [{"t_mm": 2, "material": "steel_45"},
                     {"t_mm": 3, "material": "cast_iron_SCh20", "power_limit_kW": 5,
                      "D_mm": 60}],
    "gauge": [{"target_um": 150, "tolerance_um": 10},
              {"filter": "second_order"}, {"target_um": 240, "force": True},
              {"calibration": CALIBRATION, "tolerance_um": 10},
              {"calibration": CALIBRATION, "coil_turns": 900}],
    "tracer": [{"i": 4, "alpha_deg": 20}, {"alpha_deg": 0}],
    "modulation": [{"x_mm": 300, "n_rpm": 700}],
}


def rows(name):
    return lathectl._lathectl._design_inputs(name.replace("_", "-"))


def words(name, inputs):
    """The command line a user would type for these inputs (flags from the calculator's table)."""
    by_key = {r["key"]: r for r in rows(name)}
    w = []
    for k, v in inputs.items():
        r = by_key[k]
        if r["kind"] == "flag":
            w += [r["flag"]] if v else []
        else:
            w += [f"{r['flag']}={v if isinstance(v, str) else repr(float(v))}"]
    return w


def program(name, inputs):
    p = subprocess.run([LATHECTL, "design", name.replace("_", "-"), *words(name, inputs),
                        "--json"], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def as_python(message, name, inputs):
    """The program's message with the calculator and the flags of `inputs` named as in Python."""
    m = message.removeprefix("error: ").strip()
    m = m.replace(f"design {name.replace('_', '-')}:", f"design.{name}:", 1)
    for r in sorted(rows(name), key=lambda r: -len(r["flag"])):
        m = m.replace(r["flag"], f"{r['key']}=True" if r["kind"] == "flag" else r["key"])
    return m


def changed(name):
    out = []
    for r in [r for r in rows(name) if r["kind"] == "number" and r["default"]][:3]:
        out.append({**CASES[name][0], r["key"]: r["default"] * 1.1})
    return out


def test_every_calculator_is_there():
    assert sorted(design.__all__) == sorted(["DesignNote", *NAMES])
    cli_names = [n.replace("-", "_") for n, _ in lathectl._lathectl._design_names()]
    assert sorted(cli_names) == sorted(NAMES)


@pytest.mark.parametrize("name", NAMES)
def test_equals_the_program(name):
    fn = getattr(design, name)
    for inputs in [{}, *CASES[name], *changed(name)]:
        rc, out, err = program(name, inputs)
        with warnings.catch_warnings(record=True) as notes:
            warnings.simplefilter("always")
            try:
                got = fn(**inputs)
            except lathectl.InputError as e:
                assert rc == 2, (inputs, str(e))
                assert str(e) == as_python(err, name, inputs)
                continue
        assert rc == 0, (inputs, err)
        assert got == json.loads(out), inputs
        # The program's notes as DesignNote warnings.
        expected = [ln[6:] for ln in err.splitlines() if ln.startswith("note: ")]
        assert [str(n.message) for n in notes if n.category is design.DesignNote] == \
            [as_python(e, name, inputs) for e in expected]
        # Its inputs given back: the same result.
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", design.DesignNote)
            assert fn(**got["inputs"]) == got, inputs


def test_at_defaults_the_calculators_that_need_none():
    for name in ("gauge", "tracer", "modulation"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", design.DesignNote)
            r = getattr(design, name)()
        assert set(r) == {"inputs", "si", "shop"}
        defaults = {x["key"]: x["default"] for x in rows(name)
                    if x["kind"] == "number" and x["default"] is not None}
        assert {k: r["inputs"][k] for k in defaults} == defaults


def test_bad_keys_and_values_name_the_key():
    with pytest.raises(lathectl.InputError, match=r"^design\.pulse_regulator: unknown input "
                       r"'d' \(known: d_mm, h_mm"):
        design.pulse_regulator(d=8, T_ms=10)
    with pytest.raises(lathectl.InputError, match=r"^design\.pulse_regulator: d_mm 0\.0: "
                       r"expected a finite number in \[0\.001, 1000\] \(spool diameter d\)$"):
        design.pulse_regulator(d_mm=0, T_ms=10)
    with pytest.raises(lathectl.InputError, match=r"^design\.pulse_regulator: d_mm nan: "):
        design.pulse_regulator(d_mm=float("nan"), T_ms=10)
    with pytest.raises(lathectl.InputError, match=r"^design\.pulse_regulator: d_mm = 'x': "
                       r"expected a number"):
        design.pulse_regulator(d_mm="x", T_ms=10)
    with pytest.raises(lathectl.InputError, match=r"^design\.pulse_regulator: T_ms excludes f_Hz$"):
        design.pulse_regulator(T_ms=10, f_Hz=5)
    with pytest.raises(lathectl.InputError, match=r"dt_ms 10 exceeds the period T_ms 5"):
        design.pulse_regulator(T_ms=5)
    with pytest.raises(lathectl.InputError, match=r"^design\.gauge: filter bad not in"):
        design.gauge(filter="bad")
    with pytest.raises(lathectl.InputError, match=r"target_um 240: .*\(force=True to compute "
                       r"anyway\)$"):
        design.gauge(target_um=240)
    with pytest.raises(lathectl.InputError, match=r"^design\.planned_mode: unknown material "
                       r"'nope' \(known: "):
        design.planned_mode(t_mm=2, material="nope")
    with pytest.raises(lathectl.InputError, match=r"give material"):
        design.planned_mode(t_mm=2)
    # A message never names a flag the user did not type.
    try:
        design.adaptive_speed()
    except lathectl.InputError as e:
        assert "--" not in str(e) and "Vp_m_per_min Sp_mm_per_rev yv S_mm_per_rev" in str(e)
    # --force does not outlive its call (the calculator's flags are reset for each call).
    design.gauge(target_um=240, force=True)
    with pytest.raises(lathectl.InputError):
        design.gauge(target_um=240)


def test_docs_and_signatures():
    for name in NAMES:
        fn = getattr(design, name)
        sig = inspect.signature(fn)
        assert all(p.kind is p.KEYWORD_ONLY for p in sig.parameters.values())
        for r in rows(name):
            assert r["key"] in sig.parameters and f"    {r['key']}: " in fn.__doc__
        assert "Returns a dict" in fn.__doc__ and "InputError" in fn.__doc__
    doc = design.pulse_regulator.__doc__
    assert "d_mm: spool diameter d [mm], in [0.001, 1000], default 8" in doc
    assert "T_ms: pulse period T [ms], in [0.001, 1e+06], no default" in doc
    assert "`Q_cm3_per_min` [cm³/min]" in doc
    assert inspect.signature(design.pulse_regulator).parameters["d_mm"].default == 8.0
    assert inspect.signature(design.gauge).parameters["force"].default is False
    assert "material" in inspect.signature(design.planned_mode).parameters
