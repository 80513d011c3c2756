"""A study table written back as TOML (``planar-sym move --save-study``): the few value types a
study holds (strings, booleans, numbers, lists of numbers, one level of tables), read back by
``tomllib`` to the same table (tested)."""

from __future__ import annotations

import json


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)  # a JSON string is a valid TOML basic string
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {v!r} as TOML")


def dumps(table: dict) -> str:
    """TOML text of ``table``: top-level values first, then each sub-table."""
    lines = [f"{k} = {_value(v)}" for k, v in table.items() if not isinstance(v, dict)]
    for key, sub in table.items():
        if isinstance(sub, dict):
            lines += ["", f"[{key}]", *(f"{k} = {_value(v)}" for k, v in sub.items())]
    return "\n".join(lines) + "\n"
