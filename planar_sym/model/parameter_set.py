"""A robot's parameters as one immutable value: every name with its SI value, unit and meaning,
checked once by the description's rules (``model.parameters``) whichever route changed them.

``with_parameters``, a study's ``[parameters]``, ``[control.plant]``, ``move --set`` and a
sweep's designs all make a new ``Parameters`` through ``replace`` (or ``with_vector``), so one
rule and one message hold on every route. It reads as a mapping name -> value (SI), and its
``vector`` (read-only) is what the compiled functions take.
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Iterator, Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..expressions import ExpressionError, quantity
from ..spelling import did_you_mean
from .arrays import as_samples
from .parameters import doubts, problems
from .units import factor

#: SI unit of a parameter (as the manifest writes it) -> the quantity of the units table
QUANTITY = {"kg": "mass", "kg*m^2": "inertia", "m": "length", "m/s^2": "acceleration",
            "rad": "angle"}


@dataclass(frozen=True)
class Parameter:
    """One physical parameter of a robot, as its generated manifest lists it.

    Attributes
    ----------
    name : str
        Its name in ``Robot.parameters`` and ``with_parameters`` (``m_link1``, ``izz_link1``,
        ``g``, ...).
    value : float
        The value the robot was derived with, in SI (``unit``).
    unit : str
        Its SI unit: ``"kg"``, ``"m"``, ``"kg*m^2"``, ``"m/s^2"``, ...
    meaning : str
        What it is, in words ("mass of link1").
    """

    name: str
    value: float
    unit: str
    meaning: str


class Parameters(Mapping):
    """Name -> SI value of every parameter of one robot, immutable and checked.

    Parameters
    ----------
    entries : tuple of Parameter
        The parameters as derived: names, derived values, units and meanings, in the order of
        the compiled functions' parameter vector.
    vector : array_like, shape (len(entries),), optional
        The values in use (SI); default the derived ones (which passed the description's checks
        at derive time, so they are not checked again).
    bodies : tuple of str
        The robot's moving bodies, which the inertial rules read (``m_<body>``, ...).
    owner : str
        What the values belong to (the robot's name), at the head of a refusal.
    fixed : dict of str to float, optional
        The bodies' points that are no parameter, named as parameters would be
        (``px_<body>_<point>``, m, body frame; ``fixed_points``): the inertial rules measure a
        body's extent from all its points, as the description's do.

    Attributes
    ----------
    entries : tuple of Parameter
    vector : ndarray, shape (len(entries),)
        The values (SI), read-only: the array every compiled call reads.
    bodies : tuple of str
    fixed : dict of str to float
    """

    __slots__ = ("_index", "bodies", "entries", "fixed", "owner", "vector")

    def __init__(self, entries: tuple[Parameter, ...], vector=None, *,
                 bodies: tuple[str, ...] = (), owner: str = "",
                 fixed: dict[str, float] | None = None):
        self.entries = tuple(entries)
        self.bodies = tuple(bodies)
        self.fixed = dict(fixed or {})
        self.owner = owner
        self._index = {p.name: k for k, p in enumerate(self.entries)}
        derived = vector is None
        if derived:
            vector = [p.value for p in self.entries]
        elif np.ndim(vector) != 1:
            raise InputError(f"parameters must be a vector of {len(self.entries)} values "
                             f"(got shape {np.shape(vector)})")
        v = as_samples("parameters", vector, len(self.entries))[0].copy()
        v.flags.writeable = False  # a value: a change makes a new Parameters
        self.vector = v
        if not derived:
            self.check()

    # -- the mapping ---------------------------------------------------------------------------
    def __getitem__(self, name: str) -> float:
        return float(self.vector[self._index[name]])

    def __iter__(self) -> Iterator[str]:
        return iter(self._index)

    def __setitem__(self, name: str, value) -> None:
        raise TypeError(f"{self.owner}: parameters are read-only (a robot is an immutable "
                        f"model): robot.with_parameters({name}={value!r}) gives a robot with "
                        "the new value")

    def __len__(self) -> int:
        return len(self.entries)

    def __repr__(self) -> str:
        return f"Parameters({self.owner}: " + ", ".join(
            f"{p.name}={v:.6g} {p.unit}" for p, v in zip(self.entries, self.vector)) + ")"

    # -- checks and changes --------------------------------------------------------------------
    def unit(self, name: str) -> str:
        """The SI unit of parameter ``name`` (``"kg"``, ``"m"``, ...)."""
        return self.entries[self._index[name]].unit

    def check(self, where: str = "") -> None:
        """Raise InputError naming every value the description's rules refuse (finite; masses
        > 0; plausible inertias and gravity; the drive train's ratios, rotors and friction),
        after ``where`` (a file and table) or the owner."""
        self._judge((), where)

    def warn_doubtful(self, names, where: str = "", typed: dict | None = None) -> None:
        """A RuntimeWarning for each of ``names`` whose value is likely a slip (the table's
        plausibility rules, and far from the derived value where another reading lands near
        it: ``model.parameters.doubts``), after ``where`` or the owner."""
        self._warn(self._values(), list(names), where, typed)

    def _judge(self, changed, where: str = "", typed: dict | None = None) -> None:
        """``check``, then ``warn_doubtful`` of the ``changed`` names, on one dict of values."""
        values = self._values()
        found = problems(values, self.bodies, _units(self.entries), changed)
        if found:
            for name, (v, unit) in (typed or {}).items():  # what was typed, where not SI
                if unit != _units(self.entries)[name]:
                    found = [f"{m} (typed {v:g} {unit})" if m.startswith(f"parameter {name} ")
                             else m for m in found]
            raise InputError(f"{where or self.owner}: " + "; ".join(found))
        if changed:
            self._warn(values, list(changed), where, typed)

    def _warn(self, values: dict, names: list, where: str, typed: dict | None) -> None:
        derived = {**self.fixed, **{p.name: p.value for p in self.entries}}
        for msg in doubts(names, values, _units(self.entries), derived, self.bodies, typed):
            warnings.warn(f"{where or self.owner}: {msg}", RuntimeWarning, stacklevel=5)

    def _values(self) -> dict[str, float]:
        """Name -> SI value of every parameter, and the fixed body points (``fixed``)."""
        return {**self.fixed, **dict(zip(self._index, self.vector.tolist()))}

    def read(self, name: str, text: str) -> tuple[float, tuple[float, str]]:
        """(SI value, (value, unit) as typed) of a value typed with its unit, ``"500 g"``, by
        the rule a study's [parameters] and ``--set`` use; a bare number is SI. InputError
        names the parameter."""
        try:
            value, unit = quantity(text)
        except ExpressionError as exc:
            raise InputError(f"{self.owner}: parameter {name}: {exc}") from None
        si = self.unit(name)
        unit = unit or si
        kind = QUANTITY.get(si)
        try:
            return value * (factor(kind, unit) if kind else 1.0), (value, unit)
        except KeyError as exc:
            raise InputError(f"{self.owner}: parameter {name}: {exc.args[0]}") from None

    def replace_typed(self, **values) -> Parameters:
        """``replace`` of values in SI or typed with their unit (``"500 g"``, ``read``)."""
        si, typed = {}, {}
        for name, v in values.items():
            if isinstance(v, str) and name in self._index:
                si[name], typed[name] = self.read(name, v)
            else:
                si[name] = v
        return self.replace(typed=typed or None, **si)

    def replace(self, where: str = "", typed: dict | None = None, **values: float) -> Parameters:
        """A new Parameters with ``values`` (name -> SI value) changed, checked: an unknown
        name, a value that is not a finite number or one a rule refuses raises InputError
        (after ``where``, the file and table the values came from, where given). ``typed``
        names the value as the user typed it and the unit it was read in ({name: (value,
        unit)}), for the warnings about a likely slip."""
        p = self.vector.copy()
        head = f"{where}: " if where else ""
        for name, value in values.items():
            if name not in self._index:
                raise InputError(f"{head}unknown parameter {name!r} of {self.owner}; known: "
                                 f"{', '.join(self._index)}{did_you_mean(name, self._index)}")
            try:
                if isinstance(value, (bool, np.bool_)):  # as a description refuses it
                    raise TypeError
                p[self._index[name]] = float(value)
            except (TypeError, ValueError, OverflowError):
                raise InputError(f"{head}parameter {name} must be a number in "
                                 f"{self.unit(name)} (SI; got {value!r})") from None
            if not np.isfinite(p[self._index[name]]):
                raise InputError(f"{head}{self.owner}: parameter {name} must be finite (got "
                                 f"{value!r})")
        out = self._sibling(p)
        out._judge(list(values), where, typed)
        return out

    def with_vector(self, vector, *, checked: bool = False, warn: bool = True) -> Parameters:
        """A new Parameters with every value from ``vector`` (SI, in ``entries`` order),
        checked by the rules unless ``checked`` says the caller already did (a sweep checks
        its designs' columns at once with ``model.parameters.failing``, the same rules), with
        the table's warnings on changed values unless ``warn`` is False (values that were
        judged already, a robot coming back from a pickle)."""
        if not checked:
            out = Parameters(self.entries, vector, bodies=self.bodies, owner=self.owner,
                             fixed=self.fixed)
            if warn:  # (the constructor checked the values)
                out._warn(out._values(), [p.name for p, a, b in zip(
                    self.entries, out.vector, self.vector) if a != b], "", None)
            return out
        return self._sibling(as_samples("parameters", vector, len(self.entries))[0].copy())

    def _sibling(self, vector: np.ndarray) -> Parameters:
        """The same parameters with ``vector`` (a float64 copy of its own, as given: checked by
        the caller), sharing entries and index (no derived values built to be replaced)."""
        out = object.__new__(Parameters)
        out.entries, out.bodies, out.owner, out._index = (self.entries, self.bodies, self.owner,
                                                          self._index)
        out.fixed = self.fixed
        vector.flags.writeable = False
        out.vector = vector
        return out


def fixed_points(manifest: dict) -> dict[str, float]:
    """The manifest's body points that are no parameter, named as parameters would be
    (``px_<body>_<point>``, ``py_...``; m, body frame): a carriage's corners that only show
    its size count in its extent at run time as in the description (a manifest from before
    ``body_points``: none)."""
    names = {p["name"] for p in manifest["parameters"]}
    out = {}
    for body, points in manifest.get("body_points", {}).items():
        for point, xy in points.items():
            for axis, v in zip("xy", xy):
                name = f"p{axis}_{body}_{point}"
                if name not in names:
                    out[name] = float(v)
    return out


@functools.lru_cache(maxsize=64)
def _units(entries: tuple[Parameter, ...]) -> dict[str, str]:
    """Name -> SI unit of a robot's parameters: the same for every Parameters of one robot
    (a sweep makes one per design), so made once."""
    return {p.name: p.unit for p in entries}
