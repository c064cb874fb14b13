"""Stability lobes of a machine file, and measured FRFs (docs/python.md, "Lobes and FRFs"):
the same reader and computation as ``lathectl lobes``, the same FRF readers and modal fit as the
machine file's ``[[frf]]`` tables."""
import math
import os
import re
import sys

import numpy as np

from . import _lathectl
from ._lathectl import InputError
from . import _scenario

#: The name a dict machine file has in messages (its relative files are found in base_dir).
MACHINE_LABEL = "<machine dict>"


def _machine_source(machine, base_dir):
    """(text or None, label, {line: key path} or None) of a path or a dict."""
    if isinstance(machine, dict):
        text, at = _scenario.to_toml(machine)
        base = os.path.abspath(os.fspath(base_dir) if base_dir is not None else os.getcwd())
        return text, os.path.join(base, MACHINE_LABEL), at
    if isinstance(machine, (str, os.PathLike)):
        return None, os.fspath(machine), None
    raise TypeError(f"machine: a path or a dict of tables, not {type(machine).__name__}")


def _relocated(message, label, at):
    """The reader's message about a dict's text, placed at the dict's key path."""
    if re.match(re.escape(label) + r":\d+", message):
        return _scenario.relocate(message, label, at)
    return message.replace(label, MACHINE_LABEL)


def _number(v, none):
    return none if v is None else float(v)


class Lobes:
    """The stability lobes of a machine file (:func:`lobes`), as ``lathectl lobes`` computes them.

    speed_rpm: 1-D float64 array, the spindle speeds of the frequency-domain boundary (1001
        speeds evenly over [speed] min_rpm..max_rpm: the first block of rows of lobes.csv).
    depth_mm: 1-D float64 array, same shape: the limit depth of cut [mm] there (the lower
        envelope of the lobes); NaN where no lobe bounds the depth (an empty cell in lobes.csv).
    sd_speed_rpm, sd_depth_mm: 1-D float64 arrays, the semi-discretization limit depth [mm] by
        bisection at [lobes] sd_speeds speeds (lobes.csv's second block; NaN where unbounded);
        None where semi-discretization did not run (sd_speeds = 0, [process_damping]).
    chart_speed_rpm, chart_depth_mm: the SD stability chart's boundary (ρ = 1) [rpm, mm]; None
        without a chart.
    critical_depth_mm: float, the absolute stability limit [mm] (inf when no mode can chatter:
        lobes.json's null); chatter_frequency_Hz: float, the chatter frequency there [Hz] (NaN
        when lobes.json has null).
    recommendation: dict, lobes.json's "recommendation" (safety factor, feed, diameter, the best
        "pockets": speed_rpm, depth_mm, limited_by, removal rate, power, torque, margins).
    json: dict, the whole of lobes.json (same keys, same numbers).
    warnings: list of str, what the envelope cannot say (as ``lathectl lobes`` prints them).
    """

    def __init__(self, json, curves):
        self.json = json
        env, sd, chart = curves["envelope"], curves["sd"], curves["chart"]
        self.speed_rpm = env["speed_rpm"]
        self.depth_mm = env["depth_mm"]
        has_sd = len(sd["speed_rpm"]) > 0
        self.sd_speed_rpm = sd["speed_rpm"] if has_sd else None
        self.sd_depth_mm = sd["depth_mm"] if has_sd else None
        has_chart = len(chart["speed_rpm"]) > 0
        self.chart_speed_rpm = chart["speed_rpm"] if has_chart else None
        self.chart_depth_mm = chart["depth_mm"] if has_chart else None
        self.critical_depth_mm = _number(json.get("critical_depth_mm"), math.inf)
        self.chatter_frequency_Hz = _number(json.get("chatter_frequency_Hz"), math.nan)
        self.recommendation = json["recommendation"]
        self.warnings = list(json.get("warnings", []))

    @property
    def lobes(self):
        """lobes.json's "lobes": one dict per lobe N (min_speed_rpm, depth_mm,
        chatter_frequency_Hz, minimum_inside_range)."""
        return self.json["lobes"]

    def __repr__(self):
        head = (f"critical depth {self.critical_depth_mm:.4g} mm at "
                f"{self.chatter_frequency_Hz:.5g} Hz" if math.isfinite(self.critical_depth_mm)
                else "no critical depth (no mode can chatter)")
        n = len(self.speed_rpm)
        span = (f"{n} speeds {self.speed_rpm[0]:.0f}–{self.speed_rpm[-1]:.0f} rpm" if n
                else "no speeds")
        sd = f", SD at {len(self.sd_speed_rpm)} speeds" if self.sd_speed_rpm is not None else ""
        pockets = self.recommendation.get("pockets") or []
        best = (f"; best pocket {pockets[0]['speed_rpm']:.0f} rpm at "
                f"{pockets[0]['depth_mm']:.3g} mm ({pockets[0]['limited_by']}-limited)"
                if pockets else "; no pocket")
        return f"<lathectl.Lobes: {head}, {len(self.lobes)} lobes, {span}{sd}{best}>"


def lobes(machine, *, base_dir=None, progress=None):
    """Stability lobes of a machine file, as ``lathectl lobes``; returns a :class:`Lobes`.

    machine: a path to a machine file (TOML: [cutting], [[mode]], [[frf]], [part], [speed],
        [lobes]; docs/machine-file-reference.md), or a dict of tables exactly as the file
        (``{"cutting": {"kf_N_per_mm2": 1000}, "mode": [{...}], "speed": {...}}``).
    base_dir: where the files a dict names ([[frf]] ``file``) are; default the current
        directory. A file's own relative names are relative to the file.
    progress: a progress line on stderr (the process's, not a notebook's); default on only when
        stderr is a terminal.
    The GIL is released while it computes; Ctrl-C stops it (KeyboardInterrupt). Nothing is
    written (``lathectl lobes --out DIR`` writes lobes.json, lobes.csv, lobes.html).
    Raises InputError (a ValueError) with ``lathectl lobes``' one line: file, line and key for
    a file; the key's path (``cutting.kf_N_per_mm2: ...``) for a dict.
    """
    if progress is None:
        progress = bool(getattr(sys.stderr, "isatty", lambda: False)())
    text, label, at = _machine_source(machine, base_dir)
    try:
        j, curves = _lathectl._lobes(text, label, bool(progress))
    except InputError as e:
        if at is None:
            raise
        raise InputError(_relocated(str(e), label, at)) from None
    return Lobes(j, curves)


def read_frf(path):
    """A measured FRF (tap test) as the machine file's [[frf]] tables read it.

    path: a CSV file (header ``frequency_Hz,real_<unit>,imag_<unit>``: receptance, mobility or
        accelerance) or a universal file (UFF 58/58b, ASCII or binary; the first dataset 58);
        the format is told by the content. docs/machine-file-reference.md says more.
    Returns (frequency_Hz, H): 1-D numpy arrays of the same length n, frequency_Hz float64 [Hz]
    strictly ascending, H complex128, the receptance [m/N] (mobility and accelerance converted).
    Raises InputError naming file, line and what is wrong.
    """
    return _lathectl._read_frf(os.fspath(path))


class FittedModes(list):
    """The modes fitted to an FRF (:func:`fit_modes`): a list of dicts shaped like the machine
    file's [[mode]] tables, and ``residual``, the fit's relative residual
    √(Σ|H−Ĥ|²/Σ|H|²)."""

    def __init__(self, modes, residual):
        super().__init__(modes)
        self.residual = residual


def fit_modes(frequency_Hz, H, *, max_modes=6):
    """Modes fitted to a measured FRF by the code the machine file's [[frf]] tables use
    (peak picking refined by least squares; dynamics/frf.hpp).

    frequency_Hz: 1-D array of n frequencies [Hz], strictly ascending, > 0.
    H: 1-D complex array of n receptances [m/N] (e.g. from :func:`read_frf`), along the chip
        thickness as the lobes will see it.
    max_modes: at most this many modes (the [[frf]] path: 6).
    Returns a list (:class:`FittedModes`, with ``.residual``) of dicts with the [[mode]] keys:
    ``stiffness_N_per_m`` [N/m], ``damping_ratio`` [-], ``natural_frequency_Hz`` [Hz],
    ``angle_deg`` (0: the fit is of H as given) — ready to pass as a machine dict's "mode" list.
    Raises InputError when H has no peak to fit or the arrays are not a valid FRF.
    """
    f = np.ascontiguousarray(frequency_Hz, dtype=np.float64)
    h = np.ascontiguousarray(H, dtype=np.complex128)
    modes, residual = _lathectl._fit_modes(f, h, int(max_modes))
    return FittedModes(modes, residual)
