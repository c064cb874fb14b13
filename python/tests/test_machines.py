"""The machine objects (lathectl.SlideMachine, ModulationMachine, GaugeMachine, AdaptiveMachine)
against the C++ the rig runs: every example of each system makes one whose parameters equal
those of the rig `lathectl run` builds (A, B, E: Params::operator== in C++); the same input
sequence through update() from Python and through a C++ loop on the same machine (inputs set and
outputs read field by field in C++, not through the binding's tables) gives the same outputs bit
for bit; wrong systems and bad inputs fail with the reader's messages; a 10⁶-call update() loop
keeps the process's memory flat."""
import json
import os
import pathlib
import re
import resource
import time
import tomllib

import numpy as np
import pytest

import lathectl
from lathectl import _lathectl

EXAMPLES = pathlib.Path(lathectl.examples_dir())
CLASSES = {"A": lathectl.SlideMachine, "B": lathectl.ModulationMachine,
           "D": lathectl.GaugeMachine, "E": lathectl.AdaptiveMachine}
REASONS_JSON = pathlib.Path(__file__).resolve().parents[2] / "hal" / "reasons.json"


def examples(letter):
    return sorted(EXAMPLES.glob(f"{letter.lower()}_*.toml"))


def example(name):
    return EXAMPLES / name


@pytest.mark.parametrize("path", examples("A") + examples("B") + examples("E"),
                         ids=lambda p: p.stem)
def test_parameters_are_the_rigs(path):
    letter = path.stem[0].upper()
    m = CLASSES[letter](path)
    assert m.name == path.stem
    if path.stem == "e_stepped_fixed":
        # The fixed mode's rig writes its program at the worst-case feed; a host writing its
        # own program says so (feed_programmed_mm_per_rev), and then it is the rig's machine.
        assert not _lathectl._rig_params_equal(m)
        feed = _lathectl._rig_feed_programmed(m)
        m = CLASSES[letter](path, feed_programmed_mm_per_rev=feed)
        assert m.feed_programmed_mm_per_rev == feed
    assert _lathectl._rig_params_equal(m)


@pytest.mark.parametrize("path", examples("D"), ids=lambda p: p.stem)
def test_gauge_from_every_example(path):
    m = lathectl.GaugeMachine(path)
    sc = tomllib.loads(path.read_text())
    assert m.period_s == sc["run"]["step_s"]
    th = m.thresholds_V
    assert th == sorted(th) and len(th) == len(m.commands) and m.commands[-1] == 3
    assert 0.0 < th[-1] < m.free_signal_V
    # threshold_V given: the size step's threshold is that one (as lathectl_gauge threshold_V=).
    given = 0.5 * (th[-1] + m.free_signal_V)
    g = lathectl.GaugeMachine(path, threshold_V=given)
    assert g.thresholds_V[-1] == given
    assert g.thresholds_V[:-1] == th[:-1] or len(th) == 1


def test_dict_scenario_is_the_file():
    path = example("a_roughing_aim.toml")
    d = tomllib.loads(path.read_text())
    m = lathectl.SlideMachine(d, base_dir=path.parent)
    assert _lathectl._rig_params_equal(m)
    f = lathectl.SlideMachine(path)
    for k in range(50):
        assert m.update(sensor_V=2.0 + 0.01 * k).as_dict() == f.update(sensor_V=2.0 + 0.01 * k).as_dict()


def replay_both(m, seq, each=None):
    """update() from Python with the rows of `seq`, and the C++ loop: their output columns."""
    names = list(seq)
    cols = [np.asarray(seq[n]) for n in names]  # ints stay ints: integer inputs take no float
    n = len(cols[0])
    want = _lathectl._replay(m, {k: np.asarray(v, dtype=float) for k, v in seq.items()})
    got = {k: np.empty(n) for k in want}
    for i in range(n):
        kw = {name: c[i] for name, c in zip(names, cols)}
        o = each(m, kw) if each else m.update(**kw)
        for k in want:
            got[k][i] = getattr(o, k)
    return got, want


def assert_same(got, want):
    for k in want:
        np.testing.assert_array_equal(got[k], want[k], err_msg=k)


def test_slide_same_outputs_as_cpp():
    m = lathectl.SlideMachine(example("a_roughing_aim.toml"))
    n = 3000
    k = np.arange(n)
    seq = {"sensor_V": 2.0 + 0.4 * np.sin(2 * np.pi * k / 300) + 0.8 * (k > 2000),
           "position_m": 2e-6 * k,
           "force_set_N": np.where(k < 1500, 0.0, 300.0)}
    got, want = replay_both(m, seq)
    assert_same(got, want)
    assert len(set(want["reason"])) > 1  # the sequence reaches more than one decision
    assert np.ptp(want["slot_m"]) > 0


def test_gauge_same_outputs_as_cpp():
    m = lathectl.GaugeMachine(example("d_gauging.toml"))
    free = m.free_signal_V
    n = 60000
    t = np.arange(n) * m.period_s
    # The probe's 2ω signal (100 Hz at a 50 Hz supply) whose mean rectified value rises from
    # 0.2 to 1.1 times the free signal: every threshold is crossed on the way up.
    amp = free * np.pi / 2 * (0.2 + 0.9 * np.arange(n) / n)
    seq = {"generator_V": amp * np.sin(2 * np.pi * 100.0 * t)}
    got, want = replay_both(m, seq)
    assert_same(got, want)
    assert want["stop"][-1] == 1.0 and want["step"][-1] == len(m.thresholds_V)
    assert lathectl.reason_name(int(want["reason"][-1])) in ("gauge_size", "none")


def test_adaptive_same_outputs_as_cpp():
    m = lathectl.AdaptiveMachine(example("e_stepped_seed004.toml"))
    n = 20000
    k = np.arange(n)
    lim = m.load_limit
    seq = {"motion_type": np.where(k < 2000, 1, 2),
           "spindle_rpm": np.full(n, 600.0), "spindle_rpm_programmed": np.full(n, 600.0),
           "requested_vel": np.full(n, m.feed_programmed_mm_per_rev),
           "current_vel_mm_per_s": np.full(n, 2.0),
           "force": np.where(k < 4000, 0.0, lim * (0.6 + 0.7 * (k > 10000) + 0.1 * np.sin(k / 50))),
           "x_pos_mm": np.full(n, 40.0), "z_pos_mm": -0.002 * k, "program_line": np.full(n, 1),
           "tool_number": np.full(n, 1)}
    got, want = replay_both(m, seq)
    assert_same(got, want)
    assert len(set(want["reason"])) > 2 and np.ptp(want["feed_factor"]) > 0


def test_modulation_same_outputs_as_cpp():
    m = lathectl.ModulationMachine(example("b_twin_feed_division.toml"))
    n = 3000
    k = np.arange(n)
    seq = {"displacement_m": 30e-6 * np.sin(2 * np.pi * k * 0.37) * (k > 1000),
           "feed_block": (k >= 500).astype(float), "idle_block": (k < 500).astype(float),
           "spindle_power_W": np.where(k < 500, 800.0, 5000.0),
           "spindle_rpm": np.full(n, 500.0), "speed_m_per_min": np.full(n, 120.0),
           "requested_vel": np.full(n, 0.2), "feed_per_rev_mode": np.ones(n),
           "feed_rpm": np.full(n, 500.0), "path_right_mm": 0.01 * k}

    def each(mm, kw):
        for _ in range(10):
            mm.sense(kw["displacement_m"])
        mm.servo(feed_block=kw["feed_block"])
        return mm.update(**{k: v for k, v in kw.items() if k != "displacement_m"})

    got, want = replay_both(m, seq, each)
    assert_same(got, want)
    assert want["cut_power_W"][-1] > 0 and want["a0_m"].max() > 0


@pytest.mark.parametrize("letter,other", [("A", "d_gauging.toml"), ("B", "a_roughing_aim.toml"),
                                          ("D", "e_stepped_seed004.toml"),
                                          ("E", "b_twin_offset.toml")])
def test_wrong_system(letter, other):
    cls = CLASSES[letter]
    with pytest.raises(lathectl.InputError) as e:
        cls(example(other))
    msg = str(e.value)
    assert re.match(re.escape(str(example(other))) + r":\d+:\d+: key 'system': ", msg)
    assert f"key 'system': system {other[0].upper()}: lathectl.{cls.__name__} is system {letter}'s" in msg
    d = tomllib.loads(example(other).read_text())
    with pytest.raises(lathectl.InputError) as e:
        cls(d)
    assert str(e.value).startswith("system: key 'system': system ")  # the dict's key path


def test_bad_inputs():
    m = lathectl.SlideMachine(example("a_roughing_aim.toml"))
    before = m.inputs
    with pytest.raises(TypeError, match="no input 'sensorV'"):
        m.update(sensorV=1.0)
    with pytest.raises(TypeError, match="input 'sensor_V': expected a number"):
        m.update(position_m=0.5, sensor_V="2")
    assert m.inputs == before  # nothing half set
    with pytest.raises(TypeError, match="expected an integer"):
        lathectl.AdaptiveMachine(example("e_stepped_seed004.toml")).update(motion_type=2.5)
    with pytest.raises(lathectl.InputError, match="sensor='dynamometer'"):
        lathectl.AdaptiveMachine(example("e_stepped_seed004.toml"), sensor="dynamometer")
    with pytest.raises(lathectl.InputError, match="output='pwm'"):
        lathectl.ModulationMachine(example("b_twin_offset.toml"), output="pwm")
    d = tomllib.loads(example("a_roughing_aim.toml").read_text())
    d["controller"]["period_ms"] = -1.0
    with pytest.raises(lathectl.InputError, match=r"^controller\.period_ms: "):
        lathectl.SlideMachine(d)


def test_inputs_persist_and_outputs_are_live():
    m = lathectl.SlideMachine(example("a_roughing_aim.toml"))
    o = m.update(sensor_V=2.5)
    assert m.inputs["sensor_V"] == 2.5 and m.update() is o and m.outputs is o
    snap = o.as_dict()
    assert set(snap) == set(type(o)._fields)
    m.update(sensor_V=9.0)
    assert m.inputs["sensor_V"] == 9.0 and o.as_dict() != snap  # o reads the machine now
    assert o.reason_name == lathectl.reason_name(o.reason)
    assert "SlideMachine 'a_roughing_aim' system A" in repr(m) and "slot_m=" in repr(o)


def test_sensor_alarm_latches_and_resets():
    m = lathectl.SlideMachine(example("a_roughing_aim.toml"))
    o = m.update(sensor_V=float("nan"))
    assert o.alarm and lathectl.reason_name(o.alarm_reason) == "sensor_not_finite"
    assert m.update(sensor_V=2.0).alarm  # latched
    m.update(reset=False)
    assert not m.update(reset=True).alarm


def test_reason_names_are_the_table():
    table = json.loads(REASONS_JSON.read_text())["reasons"]
    assert lathectl.reasons() == table
    for r in table:
        assert lathectl.reason_name(r["code"]) == r["name"]
    assert lathectl.reason_name(9999) == "unknown"


def test_docstrings_say_units():
    for cls in CLASSES.values():
        doc = cls.update.__doc__
        assert doc and "Inputs not given keep" in doc
    assert "sensor_V: U_D [V]" in lathectl.SlideMachine.update.__doc__
    assert "spindle_rpm: the measured spindle speed [rpm]" in lathectl.AdaptiveMachine.update.__doc__
    assert "[m/s]" in _lathectl.SlideOutputs.feed_cmd_m_per_s.__doc__


def rss_kB():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * resource.getpagesize() // 1024


def test_update_loop_does_not_leak():
    """RSS after 10⁶ update() calls minus RSS after the first 10⁴: below 256 kB."""
    m = lathectl.GaugeMachine(example("d_gauging.toml"))
    update = m.update
    for i in range(10_000):
        update(generator_V=0.5)
    start = rss_kB()
    t = time.perf_counter()
    for i in range(990_000):
        update(generator_V=0.5)
    elapsed = time.perf_counter() - t
    grown = rss_kB() - start
    print(f"10^6 GaugeMachine.update: {elapsed:.2f} s ({elapsed / 990_000 * 1e9:.0f} ns a call), "
          f"RSS grew {grown} kB")
    assert grown < 256


def test_adaptive_host_options():
    path = example("e_stepped_seed004.toml")
    hal = pathlib.Path(__file__).resolve().parents[2] / "hal"
    m = lathectl.AdaptiveMachine(path, sensor="power", z_origin_mm=None,
                                 tools="config/lathectl-tools.toml", base_dir=hal)
    assert m.load_unit == "W" and lathectl.AdaptiveMachine(path).load_unit == "N"
    assert not _lathectl._rig_params_equal(m)  # another host's machine than the rig's
    with pytest.raises(lathectl.InputError, match="nope.toml"):
        lathectl.AdaptiveMachine(path, tools="nope.toml")
    assert lathectl.AdaptiveMachine(path, period_s=1e-3).period_s == 1e-3


def test_adaptive_operation_records():
    """Two program lines in feed moves at a constant load: line 1's record when line 2 begins
    (its mean load the load, 2 s in cut = 4000 servo periods of 0.5 ms), line 2's at
    end_operation(); a load that never moves in a cut is a stuck sensor (alarm)."""
    m = lathectl.AdaptiveMachine(example("e_stepped_seed004.toml"))
    load = 0.8 * m.load_limit
    for k in range(8000):
        o = m.update(motion_type=2 if k > 500 else 1, spindle_rpm=600.0,
                     spindle_rpm_programmed=600.0, requested_vel=m.feed_programmed_mm_per_rev,
                     current_vel_mm_per_s=2.0, force=0.0 if k < 1000 else load, x_pos_mm=40.0,
                     z_pos_mm=-0.002 * k, program_line=1 if k < 5000 else 2, tool_number=1)
    assert o.op_seq == 1 and o.op["line"] == 1 and o.op["tool"] == 1
    assert o.op["load_mean"] == pytest.approx(load, rel=1e-12)
    assert o.op["time_in_cut_s"] == pytest.approx(4000 * m.period_s, rel=1e-9)
    assert lathectl.reason_name(o.op["alarm"]) == "sensor_stuck" and o.alarm
    o = m.end_operation()
    assert o.op_seq == 2 and o.op["line"] == 2
    assert o.op["time_in_cut_s"] == pytest.approx(3000 * m.period_s, rel=1e-9)
