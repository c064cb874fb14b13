"""Scenarios given as dicts: written as TOML text for the same reader as a file, and the reader's
messages placed at the dict's key path instead of the text's line."""
import json
import math
import numbers
import os
import re

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")

#: The name a dict scenario has in messages (its relative files are found in base_dir).
DICT_LABEL = "<scenario dict>"


def _key(k):
    if not isinstance(k, str):
        raise TypeError(f"scenario dict: key {k!r} is not a string")
    return k if _BARE.match(k) else json.dumps(k, ensure_ascii=False)


def _is_table(v):
    return isinstance(v, dict)


def _is_table_array(v):
    return isinstance(v, (list, tuple)) and len(v) > 0 and all(isinstance(e, dict) for e in v)


def _value(v, where):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        x = float(v)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return repr(x)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, os.PathLike):
        return json.dumps(os.fspath(v), ensure_ascii=False)
    if hasattr(v, "tolist"):  # numpy arrays and scalars
        return _value(v.tolist(), where)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(e, where) for e in v) + "]"
    raise TypeError(f"scenario dict: key '{where}': a {type(v).__name__} is not a TOML value "
                    "(numbers, strings, booleans, lists and dicts are)")


class _Writer:
    def __init__(self):
        self.lines = []
        self.at = {}  # line number (1-based) -> key path

    def emit(self, text, path):
        self.lines.append(text)
        self.at[len(self.lines)] = path

    def table(self, d, path, header):
        # A table's own keys first (TOML puts them before any sub-table), then its sub-tables
        # and arrays of tables.
        if header is not None:
            self.emit(header, path)
        later = []
        for k, v in d.items():
            kp = f"{path}.{k}" if path else k
            if _is_table(v) or _is_table_array(v):
                later.append((k, v, kp))
            else:
                self.emit(f"{_key(k)} = {_value(v, kp)}", kp)
        for k, v, kp in later:
            hk = ".".join(_key(p) for p in self._parts(path) + [k])
            if _is_table(v):
                self.table(v, kp, f"[{hk}]")
            else:
                for i, e in enumerate(v):
                    self.table(e, f"{kp}[{i}]", f"[[{hk}]]")

    def _parts(self, path):
        # "frf[0].x" → ["frf", "x"] (TOML's header names the array, not the element)
        return [re.sub(r"\[\d+\]$", "", p) for p in path.split(".")] if path else []


def to_toml(d):
    """(text, {line: key path}) for a scenario dict of tables, as its TOML file would write it."""
    if not isinstance(d, dict):
        raise TypeError("a scenario is a path or a dict of tables")
    w = _Writer()
    w.table(d, "", None)
    return "\n".join(w.lines) + "\n", w.at


def relocate(message, label, at):
    """The reader's message about the text made of a dict, placed at the dict's key path."""
    m = re.match(re.escape(label) + r":(\d+)(?::\d+)?: ", message)
    if m:
        rest = message[m.end():]
        # The key the message is about (a missing one is placed at its table's line), else the
        # key written on that line.
        k = re.match(r"key '([^']+)'", rest)
        where = k.group(1) if k else at.get(int(m.group(1)), "scenario dict")
        return f"{where}: {rest}"
    return message.replace(label, DICT_LABEL)
