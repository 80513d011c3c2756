"""Tables written back as TOML: a study (``planar-sym move --save-study``) and a robot
description (``planar-sym identify``'s identified robot). The value types these hold (strings,
booleans, numbers, lists, tables, arrays of tables), read back by ``tomllib`` to the same
table (tested)."""

from __future__ import annotations

import json

import numpy as np


def _value(v) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):  # NumPy 2's repr is np.float64(0.3): not TOML
        return repr(float(v))
    if isinstance(v, str):
        return json.dumps(v)  # a JSON string is a valid TOML basic string
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):  # inline: a body's points, a joint's actuator
        return "{ " + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + " }"
    raise TypeError(f"cannot write {v!r} as TOML")


#: the characters of a bare TOML key (ASCII only: str.isalnum would pass "é", which TOML
#: refuses unquoted)
_BARE = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-")


def _key(k: str) -> str:
    return k if k and set(k) <= _BARE else json.dumps(k)


def _tables(v) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def dumps(table: dict) -> str:
    """TOML text of ``table``: top-level values first, then each sub-table and array of
    tables (``[[bodies]]``), whose own tables are written inline."""
    lines = [f"{_key(k)} = {_value(v)}" for k, v in table.items()
             if not isinstance(v, dict) and not _tables(v)]
    for key, sub in table.items():
        if isinstance(sub, dict):
            lines += ["", f"[{_key(key)}]", *(f"{_key(k)} = {_value(v)}" for k, v in sub.items())]
        elif _tables(sub):
            for item in sub:
                lines += ["", f"[[{_key(key)}]]",
                          *(f"{_key(k)} = {_value(v)}" for k, v in item.items())]
    return "\n".join(lines) + "\n"
