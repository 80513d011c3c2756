"""Field checks of a TOML input (a study file): every problem collected, each naming the file,
the field and the value, then raised at once as one StudyError.

Numbers may be typed as expressions (``planar_sym.expressions``): ``expressions`` evaluates them
once, before any check, at the places the reader's schema names (``spec.NUMBERS``), so
``control_spec`` and every check after see floats; one that is no expression is a ``Bad``, which
``number`` and ``vector`` report at their field. ``names`` (the file's ``[constants]``) serve
the quantity strings of ``[parameters]``, read by the reader itself.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..errors import InputError
from ..expressions import Bad, constants, numbers
from ..model.units import factor
from ..spelling import unknown_keys


class StudyError(InputError):
    """A study file with problems; ``problems`` lists every one, each naming its field."""

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        super().__init__("invalid study:\n  " + "\n  ".join(self.problems))


class Checker:
    """Collects every problem of one file before raising; each names its field."""

    def __init__(self, path: Path | None):
        self.path, self.problems = path, []
        self.base = path.parent if path is not None else Path.cwd()
        self.names: dict[str, float] = {}  # the file's [constants]

    def expressions(self, data: dict, schema) -> dict:
        """``data`` with its expressions evaluated (``expressions.numbers``), [constants] first;
        a problem in [constants] is raised at once, with those found so far (every field using
        the constant would only repeat it)."""
        self.names, problems = constants(data.get("constants"))
        for fld, msg in problems:
            self.err(fld, msg)
        if problems:
            self.done()
        return numbers(data, schema, self.names)

    def err(self, fld: str, msg: str) -> None:
        where = f"{self.path}: " if self.path is not None else ""
        self.problems.append(f"{where}{fld}: {msg}")

    def done(self) -> None:
        if self.problems:
            raise StudyError(self.problems)

    def keys(self, tbl: dict, known: set[str], prefix: str) -> None:
        """Unknown keys of ``tbl`` reported; a misspelt one moved to the key it nearly is
        (``spelling.unknown_keys``: ``parse`` works on a copy of the file's tables)."""
        unknown_keys(tbl, known, lambda key, msg: self.err(f"{prefix}{key}", msg))

    def table(self, data: dict, key: str, required: bool = False) -> dict:
        v = data.get(key)
        if v is None:
            if required:
                self.err(key, f"missing table [{key}]")
            return {}
        if not isinstance(v, dict):
            self.err(key, f"must be a table [{key}] (got {v!r})")
            return {}
        return v

    def string(self, tbl: dict, key: str, fld: str, default: str | None = None) -> str | None:
        v = tbl.get(key, default)
        if v is None:
            self.err(fld, "missing")
        elif not isinstance(v, str) or not v:
            self.err(fld, f"must be a non-empty string (got {v!r})")
        else:
            return v
        return None

    def choice(self, tbl: dict, key: str, fld: str, options, default: str | None = None):
        v = self.string(tbl, key, fld, default)
        if v is not None and v not in options:
            self.err(fld, f"must be one of {', '.join(options)} (got {v!r})")
            return None
        return v

    def unit(self, tbl: dict, quantity: str, default: str) -> str:
        v = tbl.get(quantity, default)
        try:
            factor(quantity, v if isinstance(v, str) else repr(v))
        except KeyError as exc:
            self.err(f"units.{quantity}", f"{exc.args[0]} (got {v!r})")
            return default
        return v

    def number(self, tbl: dict, key: str, fld: str, *, positive: bool = False,
               limit: float | None = None, default: float | None = None) -> float | None:
        v = tbl.get(key, default)
        if v is None:
            self.err(fld, "missing")
            return None
        if isinstance(v, Bad):
            self.err(fld, v.message)
            return None
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not finite(v):
            self.err(fld, f"must be a finite number (got {v!r:.60})")
            return None
        if positive and not v > 0:
            self.err(fld, f"must be > 0 (got {v!r})")
            return None
        if limit is not None and v > limit:
            self.err(fld, f"must be at most {limit:g} (got {v!r})")
            return None
        return float(v)

    def integer(self, tbl: dict, key: str, fld: str, default: int, low: int, high: int) -> int:
        v = tbl.get(key, default)
        if isinstance(v, bool) or not isinstance(v, int) or not low <= v <= high:
            self.err(fld, f"must be an integer from {low} to {high} (got {v!r})")
            return default
        return v

    def flag(self, tbl: dict, key: str, fld: str, default: bool) -> bool:
        v = tbl.get(key, default)
        if not isinstance(v, bool):
            self.err(fld, f"must be true or false (got {v!r})")
            return default
        return v

    def vector(self, tbl: dict, key: str, fld: str, required: bool = False
               ) -> tuple[float, ...] | None:
        v = tbl.get(key)
        if v is None:
            if required:
                self.err(fld, "missing")
            return None
        bad = [x for x in (v if isinstance(v, list) else [v]) if isinstance(x, Bad)]
        for x in bad:
            self.err(f"{fld}{x.index}", x.message)
        if bad:
            return None
        if (not isinstance(v, list) or not v
                or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v)):
            self.err(fld, f"must be a list of numbers (got {v!r:.80})")
            return None
        if not all(finite(x) for x in v):
            self.err(fld, f"must be finite (got {v!r:.80})")
            return None
        return tuple(float(x) for x in v)

    def file(self, value, fld: str) -> Path | None:
        if not isinstance(value, str) or not value:
            self.err(fld, f"must name a file (got {value!r})")
            return None
        path = (self.base / value).resolve()
        if not path.is_file():
            self.err(fld, f"no such file {value!r} (looked for {path})")
            return None
        return path


def finite(v) -> bool:
    try:
        return math.isfinite(float(v))
    except (OverflowError, TypeError, ValueError):
        return False
