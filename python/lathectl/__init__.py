"""lathectl — automatic and adaptive lathe control from Python (docs/python.md).

The same C++ as the `lathectl` program: scenarios of the five systems run closed-loop
(:func:`run`, :func:`check`), stability lobes of a machine file (:func:`lobes`), measured FRFs
(:func:`read_frf`, :func:`fit_modes`), the papers' design calculators (:mod:`lathectl.design`)
and the machine-side objects for one's own loops.

Units are in the names, as in the scenario files: ``depth_mm``, ``speed_rpm``,
``chatter_frequency_Hz``; channels' columns carry the units of ``channels.csv``.
"""
import os
import sys
import warnings as _warnings

from . import _lathectl
from ._lathectl import InputError
from . import _scenario
from ._lobes import Lobes, FittedModes, lobes, read_frf, fit_modes
from . import design

__version__ = _lathectl.__version__
__all__ = ["__version__", "InputError", "ScenarioWarning", "Run", "run", "check",
           "examples_dir", "data_dir",
           "Lobes", "FittedModes", "lobes", "read_frf", "fit_modes", "design"]


class ScenarioWarning(UserWarning):
    """A value a scenario's reader accepted but a shop would not mean (``lathectl run`` prints
    it as ``warning: ...``)."""


def examples_dir():
    """The example scenarios' directory (installed: /usr/share/lathectl/examples/scenarios)."""
    return _lathectl._examples_dir()


def data_dir():
    """The data directory (materials.toml); $LATHECTL_DATA_DIR overrides it."""
    return _lathectl._data_dir()


def _source(scenario, base_dir):
    """(text or None, label, {line: key path} or None) of a path or a dict."""
    if isinstance(scenario, dict):
        text, at = _scenario.to_toml(scenario)
        base = os.path.abspath(os.fspath(base_dir) if base_dir is not None else os.getcwd())
        return text, os.path.join(base, _scenario.DICT_LABEL), at
    if isinstance(scenario, (str, os.PathLike)):
        return None, os.fspath(scenario), None
    raise TypeError(f"scenario: a path or a dict of tables, not {type(scenario).__name__}")


def _call(fn, label, at, *args):
    try:
        return fn(*args)
    except InputError as e:
        if at is None:
            raise
        raise InputError(_scenario.relocate(str(e), label, at)) from None


def _warn(ws, label, at):
    for w in ws:
        if at is not None:
            w = _scenario.relocate(w, label, at)
        _warnings.warn(w, ScenarioWarning, stacklevel=3)


def check(scenario, *, base_dir=None):
    """Read and validate a scenario without running it; returns None.

    scenario: a path to a scenario file (TOML), or a dict of tables exactly as the file
        (``{"system": "A", "run": {"duration_s": 5}, ...}``).
    base_dir: where the files a dict names (``csv``, ``machine_file``, ...) are; default the
        current directory. A file's own relative names are relative to the file, as for
        ``lathectl check``.
    Raises InputError (a ValueError) with the one line ``lathectl check`` prints: file, line and
    key for a file; the key's path (``cut.rpm: ...``) for a dict. Warnings as ScenarioWarning.
    """
    text, label, at = _source(scenario, base_dir)
    ws, _system, _name, _cost = _call(_lathectl._check, label, at, text, label)
    _warn(ws, label, at)


class Run:
    """One closed-loop run of a scenario (:func:`run`).

    summary: dict — what summary.json holds (same keys, same numbers).
    channels: dict of column name → 1-D numpy.ndarray of float64, one value per recorded row
        (the columns of channels.csv at full precision; the CSV rounds to 9 digits). Units are in
        the names (``time_s``, ``force_N``, ...).
    ok: bool — the acceptance verdict (no criterion unmet, no alarm, the part finished), what
        ``lathectl run --strict`` exits 3 on.
    write(dir): writes summary.json, channels.csv and report.html as ``lathectl run --out dir``.
    """

    def __init__(self, result):
        self._r = result
        self._summary = None
        self._channels = None

    @property
    def summary(self):
        if self._summary is None:
            self._summary = self._r.summary
        return self._summary

    @property
    def channels(self):
        if self._channels is None:
            self._channels = self._r.channels()
        return self._channels

    @property
    def ok(self):
        return self._r.ok

    @property
    def name(self):
        """The scenario's name."""
        return self._r.name

    @property
    def system(self):
        """The scenario's system letter, "A" … "E"."""
        return self._r.system

    @property
    def headline(self):
        """The run's one line (as ``lathectl run`` prints it)."""
        return self._r.headline

    @property
    def verdict(self):
        """The verdict as one line of text."""
        return self._r.verdict

    def write(self, dir):
        """Write summary.json, channels.csv and report.html into `dir`, as ``lathectl run --out``
        does (the set replaces `dir` as a whole; `dir` must be empty, absent or an output set)."""
        self._r.write(os.fspath(dir))

    def __repr__(self):
        rows = 0
        if self._channels is not None and self._channels:
            rows = len(next(iter(self._channels.values())))
        extra = f", {rows} rows" if rows else ""
        return (f"<lathectl.Run {self.name!r} system {self.system}: "
                f"{'ok' if self.ok else 'NOT ok'} — {self.headline}{extra}>")


def run(scenario, *, seed=None, base_dir=None, progress=None):
    """Run a scenario closed-loop, as ``lathectl run``; returns a :class:`Run`.

    scenario: a path to a scenario file (TOML), or a dict of tables exactly as the file.
    seed: the run's random seed (int ≥ 0) in place of the scenario's ``run.seed``.
    base_dir: where the files a dict names are; default the current directory.
    progress: a progress line on stderr (the process's, not a notebook's); default on only when
        stderr is a terminal.
    The GIL is released while it runs; Ctrl-C stops it (KeyboardInterrupt) with nothing written.
    Raises InputError for a bad scenario (as :func:`check`), RuntimeError for a numerical
    failure (a diverging simulation).
    """
    if seed is not None:
        seed = int(seed)
        if seed < 0:
            raise InputError(f"seed {seed}: expected an integer >= 0")
    if progress is None:
        progress = bool(getattr(sys.stderr, "isatty", lambda: False)())
    text, label, at = _source(scenario, base_dir)
    result, ws = _call(_lathectl._run, label, at, text, label, seed, bool(progress))
    _warn(ws, label, at)
    return Run(result)


from .machines import (SlideMachine, GaugeMachine, AdaptiveMachine, ModulationMachine,  # noqa: E402
                       reason_name, reasons)
__all__ += ["SlideMachine", "GaugeMachine", "AdaptiveMachine", "ModulationMachine",
            "reason_name", "reasons"]
