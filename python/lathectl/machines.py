"""The machine-side objects for one's own loops (docs/python.md, "Machine objects").

Each class is the C++ object that ``lathectl run``'s rig and the LinuxCNC component run — the
same code, configured by its system's one ``machine_params()`` from a scenario (a path or a dict,
read as :func:`lathectl.run` reads it) — with this host's additions as keyword options whose
defaults are the rig's:

=====================  ======  ============================  ==================================
class                  system  HAL component                 one call of update() is
=====================  ======  ============================  ==================================
``SlideMachine``       A       lathectl_slide                one control period (``period_s``)
``ModulationMachine``  B       lathectl_modfeed              one module period (``period_s``)
``GaugeMachine``       D       lathectl_gauge                one sample (``period_s``)
``AdaptiveMachine``    E       lathectl_adaptive             one servo period (``period_s``)
=====================  ======  ============================  ==================================

``update(**inputs)`` takes the machine's inputs by keyword, named as the HAL component's pins
with their units (``sensor_V``, ``spindle_rpm``, ``x_pos_mm``); an input not given keeps the
value it had (as a HAL pin keeps its value), so a loop passes only what changes. It returns the
outputs' object: its attributes (``reason``, ``alarm``, ``feed_factor``, ...) read the machine's
outputs *live* — the same object comes back from every call, and reading an attribute costs
nothing until read. ``outputs.as_dict()`` copies them. ``reason`` is the int code of
``lathectl reasons`` (hal/reasons.json): :func:`reason_name` names it, :func:`reasons` lists the
table. ``help(M.update)`` lists every input with its unit; the outputs' class lists its outputs.

update() does not allocate: a loop of 10⁶ calls keeps the process's memory flat.
"""
import os

from . import _lathectl

__all__ = ["SlideMachine", "GaugeMachine", "AdaptiveMachine", "ModulationMachine",
           "reason_name", "reasons"]


def reason_name(code):
    """The name of a reason code (an output's ``reason``, ``alarm_reason``): ``"output_high"``
    for 1, ``"unknown"`` for a code not in the table."""
    return _lathectl._reason_name(int(code))


def reasons():
    """The reason table as ``lathectl reasons --json`` gives it: a list of dicts with ``code``,
    ``name``, ``alarm`` (it latches an alarm), ``systems`` (``"A E"``) and ``meaning``."""
    return _lathectl._reasons()


def _make(base_init, self, scenario, base_dir, *options):
    from . import _call, _source  # the package's: dict scenarios, their messages at key paths
    text, label, at = _source(scenario, base_dir)
    _call(base_init, label, at, self, text, label, *options)
    self._made = True  # a constructor that raised leaves an object only a traceback sees


def _file(path, base_dir):
    if path is None:
        return None
    path = os.fspath(path)
    if base_dir is not None and not os.path.isabs(path):
        path = os.path.join(os.fspath(base_dir), path)
    return path


def _repr(m, system, extra=None):
    if not m.__dict__.get("_made"):
        return f"<lathectl.{type(m).__name__} (not made)>"
    o = m.outputs
    return (f"<lathectl.{type(m).__name__} {m.name!r} system {system}, period "
            f"{m.period_s * 1e3:g} ms{extra() if extra else ''}: reason {reason_name(o.reason)}"
            f"{', ALARM' if getattr(o, 'alarm', False) else ''}>")


class SlideMachine(_lathectl._SlideMachine):
    """System A's machine side (seed 000): the pulse regulator's controller with the programming
    device, sensor checks and roughing's overload and breakage alarms (control::SlideMachine).

    SlideMachine(scenario, *, base_dir=None, machine_io=False)
        scenario: a system-A scenario, a path or a dict of tables (as :func:`lathectl.run`).
        base_dir: where the files a dict names are (default: the current directory).
        machine_io: True as lathectl_slide (only a pulsed regulator under AIM or FIM, which has
            the valve and actuator it drives); False as the rig (any regulator).
    It starts as the rig starts it: enabled, bumpless at the scenario's nominal force
    (``start_force_N``); ``start(force_N)`` starts it again.

    update(**inputs) -> SlideOutputs, every ``period_s`` (controller.period_ms) [s]. Inputs:
    sensor_V [V], enable, roughing, feed_set_m_per_s [m/s], force_set_N [N], position_m [m],
    reset (rising edge). Outputs: slot_m [m], frequency_Hz [Hz], pulses, feed_cmd_m_per_s
    [m/s], force_estimate_N [N], feed_set_m_per_s, force_set_N, roughing, enabled, reason,
    alarm, alarm_reason. ``help(SlideMachine.update)`` says each.
    Raises InputError for a bad scenario or another system's.
    """

    def __init__(self, scenario, *, base_dir=None, machine_io=False):
        _make(_lathectl._SlideMachine.__init__, self, scenario, base_dir, bool(machine_io))

    def __repr__(self):
        return _repr(self, "A")


class GaugeMachine(_lathectl._GaugeMachine):
    """System D's machine side (seed 003): the vibro-contact gauge's rectifier, filter,
    thresholds with their commands (rough → fine → spark-out → size), relay, backstop and
    signal checks (control::GaugeMachine).

    GaugeMachine(scenario, *, base_dir=None, threshold_V=None, period_s=None, target_x_m=None,
                 signal_lost=0.0)
        scenario: a system-D scenario, a path or a dict of tables.
        threshold_V: the size threshold [V]; None: the plan's, (23) on the scenario's line, as
            lathectl_gauge takes it (a study with threshold = "calibrated_dynamic" moves its
            own by calibration: pass the summary's to use that one).
        period_s: the sample period [s]; None: the transducer's step (run.step_s).
        target_x_m: the host's position of the target size [m] (the backstop follows it);
            None: the process's own coordinate, position_m = the size left to remove.
        signal_lost: signal lost below this fraction of the free signal for a supply period
            (lathectl_gauge: 0.05); 0: not checked (the rig's).
    The steps before size are the scenario's [sequence] (``thresholds_V``, ``commands``);
    ``rate_factor[command]`` × ``removal_m_per_s`` is each command's removal rate.

    update(**inputs) -> GaugeOutputs, every ``period_s``. Inputs: generator_V [V],
    position_m [m], rearm (rising edge), gate. Outputs: signal_V [V], step, command, armed,
    tripped, trip_time_s [s], tripped_steps, size, backstop, stop, alarm, unreachable,
    next_threshold_V [V], time_s [s], bridged, reason. ``reset()``: a new part.
    """

    def __init__(self, scenario, *, base_dir=None, threshold_V=None, period_s=None,
                 target_x_m=None, signal_lost=0.0):
        _make(_lathectl._GaugeMachine.__init__, self, scenario, base_dir, threshold_V, period_s,
              target_x_m, float(signal_lost))

    def __repr__(self):
        return _repr(self, "D", lambda: f", {len(self.thresholds_V)} steps")


class AdaptiveMachine(_lathectl._AdaptiveMachine):
    """System E's machine side (seed 004): adaptive control of the force by the feed and of
    the cutting speed, with the per-operation settings, overload levels, teach-in, operation
    records, the stock model's breakage detector and feed-forward (control::AdaptiveMachine).

    AdaptiveMachine(scenario, *, base_dir=None, sensor=None, z_origin_mm=0.0,
                    feed_programmed_mm_per_rev=None, tools=None, taught=None, period_s=None)
        scenario: a system-E scenario, a path or a dict of tables.
        sensor: "force" (sensor 4 on the force input) or "power" (the spindle drive's power on
            spindle_power_W, the idle power learned); None: as the scenario's parameter.
        z_origin_mm: machine z of the stock's face [mm], for the stock model on the scenario's
            blank (the rig's 0); None: no stock model.
        feed_programmed_mm_per_rev: the program's feed [mm/rev] when the host writes the
            program; None: the scenario's controller.feed_programmed.
        tools, taught: a tool table and taught references (files, as lathectl_adaptive's).
        period_s: the servo period update() runs at [s]; None: run.step_s (the rig's).
    ``load_unit`` is "N" or "W"; ``control_period_s`` the control law's period (a whole
    number of servo periods).

    update(**inputs) -> AdaptiveOutputs, every ``period_s``: the inputs are lathectl_adaptive's
    pins (force, spindle_rpm, motion_type, x_pos_mm, limit_cmd, ...; ``help(update)``); the
    outputs its pins (adaptive_feed, feed_factor, feed_per_rev_mm, spindle_speed_out,
    feed_hold, reason, alarm, load, ...) and ``op`` / ``teach``, the last operation's and
    teach-in's records. ``end_operation()`` publishes the running operation's record;
    ``taught`` lists the references taught.
    """

    def __init__(self, scenario, *, base_dir=None, sensor=None, z_origin_mm=0.0,
                 feed_programmed_mm_per_rev=None, tools=None, taught=None, period_s=None):
        _make(_lathectl._AdaptiveMachine.__init__, self, scenario, base_dir, sensor, z_origin_mm,
              feed_programmed_mm_per_rev, _file(tools, base_dir), _file(taught, base_dir),
              period_s)

    def __repr__(self):
        return _repr(self, "E", lambda: f", load in {self.load_unit}")


class ModulationMachine(_lathectl._ModulationMachine):
    """System B's machine side (seed 001): the vibration chain (amplifier, dead zone, amplitude
    and frequency detectors), the power chain with its idle compensation, and the planner of
    the modulated feed (control::ModulationMachine).

    ModulationMachine(scenario, *, base_dir=None, output="drives", ceiling=1.0,
                      module_period_s=None, sample_period_s=None)
        scenario: a system-B scenario, a path or a dict of tables.
        output: how the feed reaches the flagged turret: "drives" (its drive's feed, the rig's),
            "factor" (one factor on every axis, motion.adaptive-feed) or "offset" (an external
            offset on its axial axis), as lathectl_modfeed's output=.
        ceiling: ("factor") the program's F over the mean feed to keep (lathectl_modfeed: 2).
        module_period_s, sample_period_s: update()'s and sense()'s periods [s]; None: 1 ms and
            0.1 ms.
    Three calls, as the machine has them: ``sense(displacement_m)`` every ``sample_period_s``
    (``sense_many(array)`` for a block of samples), ``servo(**inputs)`` every servo period and
    ``update(**inputs)`` every ``period_s``, after servo(). Inputs and outputs: help(update),
    help(servo); outputs: feed_right_mm_per_min, feed_left_mm_per_min, the plan (s_min, ds,
    dl, n_s), engaged, reason, a0_m, cut_power_W, factor, feed_ratio, offset_mm, ...
    """

    def __init__(self, scenario, *, base_dir=None, output="drives", ceiling=1.0,
                 module_period_s=None, sample_period_s=None):
        _make(_lathectl._ModulationMachine.__init__, self, scenario, base_dir, str(output),
              float(ceiling), module_period_s, sample_period_s)

    def __repr__(self):
        return _repr(self, "B")


def _reason_name_of(outputs):
    return reason_name(outputs.reason)


for _outputs in (_lathectl.SlideOutputs, _lathectl.GaugeOutputs, _lathectl.AdaptiveOutputs,
                 _lathectl.ModulationOutputs):
    _outputs.reason_name = property(_reason_name_of, doc="the reason's name (reason_name)")
del _outputs
