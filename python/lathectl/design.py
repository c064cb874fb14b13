"""The papers' design calculators (``lathectl design NAME``), one function each, named with
underscores: ``pulse_regulator``, ``adaptive_speed``, ``planned_mode``, ``gauge``, ``tracer``,
``modulation`` (docs/python.md, "Design calculators").

Each takes its inputs as keyword arguments named as the keys of ``--json``'s "inputs" (shop
units in the names: ``d_mm``, ``dp_MPa``), missing ones at the CLI's defaults, and returns the
whole ``--json`` object as a dict: "inputs" (every input used: pass them back with
``**result["inputs"]`` for the same result) and the results ("si" and "shop", or "results"). A
call is ``lathectl design NAME --json`` run by the same program (same checks, same numbers); a
bad key or value raises :class:`lathectl.InputError` naming the key, what the CLI prints as a
note comes as a :class:`DesignNote` warning.
"""
import inspect
import json
import numbers
import re
import warnings

from . import _lathectl
from ._lathectl import InputError


class DesignNote(UserWarning):
    """A calculator's note (``note: ...`` on the CLI's stderr): a result not computed for want of
    an input, a value at the edge of what the model means."""


_FLAG = re.compile(r"--[A-Za-z0-9][A-Za-z0-9_-]*")


def _keys_in(message, rows):
    """The CLI's message with each flag replaced by its keyword (``--d-mm`` → ``d_mm``)."""
    by_flag = {r["flag"]: r for r in rows}

    def key(m):
        r = by_flag.get(m.group(0))
        if r is None:
            return m.group(0)
        return f"{r['key']}=True" if r["kind"] == "flag" else r["key"]

    return _FLAG.sub(key, message)


def _argument(py_name, r, value):
    """The command-line words of one keyword argument."""
    k = r["key"]
    if r["kind"] == "flag":
        if not isinstance(value, (bool, int)):
            raise InputError(f"design.{py_name}: {k} = {value!r}: expected True or False")
        return [r["flag"]] if value else []
    if r["kind"] == "text":
        if not isinstance(value, str):
            raise InputError(f"design.{py_name}: {k} = {value!r}: expected a string "
                             f"({r['doc']})")
        return [f"{r['flag']}={value}"]
    if hasattr(value, "item") and callable(value.item):  # a numpy scalar
        value = value.item()
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise InputError(f"design.{py_name}: {k} = {value!r}: expected a number"
                         f"{' ' + r['range'] if r['range'] else ''} ({r['doc']})")
    return [f"{r['flag']}={float(value)!r}"]


def _doc(cli_name, description, rows):
    lines = [description + ".", "",
             f"As ``lathectl design {cli_name} --json``. Inputs (keyword arguments, the keys of "
             "the result's \"inputs\"; missing ones at their defaults):", ""]
    for r in rows:
        unit = f" [{r['unit']}]" if r["unit"] else ""
        if r["kind"] == "number":
            rng = f", {r['range']}" if r["range"] else ""
            dflt = (f", default {r['default']:g}" if r["default"] is not None
                    else ", no default (given or absent)")
            lines.append(f"    {r['key']}: {r['doc']}{unit}{rng}{dflt}")
        elif r["kind"] == "flag":
            lines.append(f"    {r['key']}: {r['doc']} (True/False, default False)")
        else:
            dflt = f", default {r['default']!r}" if r["default"] else ""
            lines.append(f"    {r['key']}: {r['doc']} (a string{dflt})")
    reference = _lathectl._design_reference(cli_name)
    at = reference.find("\nResults")
    lines += ["", "Returns a dict: \"inputs\" (every input used) and the results."]
    if at >= 0:
        lines += ["", reference[at + 1:].rstrip()]
    lines += ["", "Raises lathectl.InputError (a ValueError) naming the key: an unknown key, a "
              "value out of range, inputs that do not go together."]
    return "\n".join(lines)


def _signature(rows):
    params = []
    for r in rows:
        default = r["default"]
        if r["kind"] == "flag":
            default = False
        params.append(inspect.Parameter(r["key"], inspect.Parameter.KEYWORD_ONLY,
                                        default=default))
    return inspect.Signature(params, return_annotation=dict)


def _calculator(cli_name, description):
    py_name = cli_name.replace("-", "_")
    rows = _lathectl._design_inputs(cli_name)
    by_key = {r["key"]: r for r in rows}

    def calculate(**inputs):
        words = []
        for k, v in inputs.items():
            r = by_key.get(k)
            if r is None:
                raise InputError(f"design.{py_name}: unknown input '{k}' (known: "
                                 f"{', '.join(by_key)})")
            if v is not None:
                words += _argument(py_name, r, v)
        rc, out, err = _lathectl._design_run(cli_name, words)
        for line in err.splitlines():
            if line.startswith("note: "):
                warnings.warn(_keys_in(line[6:], rows), DesignNote, stacklevel=2)
        if rc == 0:
            return json.loads(out)
        message = next((ln for ln in err.splitlines() if "error: " in ln), err.strip())
        message = re.sub(r"^(internal )?error: ", "", message)
        message = message.replace(f"design {cli_name}:", f"design.{py_name}:", 1)
        message = _keys_in(message, rows)
        if rc == 2:
            raise InputError(message)
        raise RuntimeError(message)

    calculate.__name__ = calculate.__qualname__ = py_name
    calculate.__module__ = __name__
    calculate.__doc__ = _doc(cli_name, description, rows)
    calculate.__signature__ = _signature(rows)
    return py_name, calculate


__all__ = ["DesignNote"]
for _cli_name, _description in _lathectl._design_names():
    _name, _fn = _calculator(_cli_name, _description)
    globals()[_name] = _fn
    __all__.append(_name)
del _cli_name, _description, _name, _fn
