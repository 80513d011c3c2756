"""Design spaces: which parameters vary and over what, as one matrix of parameter vectors.

A design is a robot's whole parameter vector ``p`` (SI, the manifest's order). A sweep varies
some of its entries over a grid (every combination) or a random sample (uniform between two
bounds, reproducible by its seed) and keeps the rest at the base robot's values. Every design is
checked with the rules the description's own values pass (``model.parameters``), all designs at
once: a range that produces a non-physical design is refused before anything runs, naming the
parameter, the value and how many designs it spoils.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.parameters import doubts, failing, problems
from ..model.robot import Robot

#: the largest design matrix a sweep builds in memory (bytes); beyond it the sweep is refused
#: with the size it would take (split it, or sample it at random instead)
MEMORY_LIMIT_BYTES = 2e9


@dataclass(frozen=True)
class DesignSpace:
    """``names`` (varied parameters), ``values`` (D, k) their SI values per design, ``P`` (D,
    n_p) every design's whole parameter vector, and ``units`` of the varied parameters."""

    names: tuple[str, ...]
    units: tuple[str, ...]
    values: np.ndarray
    P: np.ndarray
    sample: str

    def __len__(self) -> int:
        return len(self.P)

    def columns(self) -> dict[str, np.ndarray]:
        """The varied parameters as table columns, their SI unit in the name
        (``px_link1_CS2_m``, ``m_link2_kg``, ``izz_link2_kg_m2``)."""
        return {f"{n}_{unit_suffix(u)}": self.values[:, k]
                for k, (n, u) in enumerate(zip(self.names, self.units))}


def unit_suffix(unit: str) -> str:
    """A unit as a column-name suffix: ``kg*m^2`` -> ``kg_m2``, ``m/s^2`` -> ``m_s2``."""
    return unit.lower().replace("*", "_").replace("/", "_").replace("^", "") or "1"


def _names(key) -> tuple[str, ...]:
    """The parameters one entry of ``vary`` sets: a name, or several tied to the same values
    (a tuple of names, or one string of names separated by commas: both proximal links of a
    symmetric 5-bar)."""
    names = tuple(n.strip() for n in key.split(",")) if isinstance(key, str) else tuple(key)
    if not names or not all(isinstance(n, str) and n for n in names):
        raise InputError(f"vary: {key!r} is not a parameter name (or names tied together)")
    if len(set(names)) < len(names):
        raise InputError(f"vary: {key!r} names a parameter twice")
    return names


def _values(name: str, spec, sample: str) -> np.ndarray | tuple[float, float]:
    """One parameter's values: a list of numbers; ``(low, high, count)`` on a grid; ``(low,
    high)`` for a random sample."""
    where = f"vary[{name!r}]"
    try:
        arr = np.asarray(spec, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{where} must be numbers: a list of values, (low, high, count) or, "
                         f"for a random sample, (low, high); got {spec!r}") from None
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{where} must be finite (got {spec!r})")
    if isinstance(spec, tuple) and sample == "random":
        if len(arr) != 2 or not arr[0] < arr[1]:
            raise InputError(f"{where}: a random sample needs (low, high) with low < high "
                             f"(got {spec!r})")
        return float(arr[0]), float(arr[1])
    if isinstance(spec, tuple):
        if len(arr) != 3 or not arr[0] < arr[1] or arr[2] != int(arr[2]) or arr[2] < 2:
            raise InputError(f"{where}: a grid range is (low, high, count) with low < high and "
                             f"an integer count >= 2 (got {spec!r}); or give the values as a list")
        return np.linspace(arr[0], arr[1], int(arr[2]))
    if len(arr) == 0:
        raise InputError(f"{where} has no values")
    if sample == "random":
        raise InputError(f"{where}: a random sample draws between two bounds: give (low, high) "
                         f"as a tuple (got the list {spec!r})")
    return arr


def design_space(robot: Robot, vary: dict, *, sample: str = "grid", count: int | None = None,
                 seed: int = 0) -> DesignSpace:
    """Every design of a sweep, checked.

    Parameters
    ----------
    robot : Robot
        The base design: parameters not varied keep its values.
    vary : dict
        Parameter name -> values (SI, the robot's ``parameter_list`` units): a list of values,
        ``(low, high, count)`` (evenly spaced, ends included), or for ``sample="random"``
        ``(low, high)``. A key naming several parameters (a tuple, or names separated by
        commas) gives them all the same values.
    sample : {"grid", "random"}
        Every combination of the values, or ``count`` designs drawn uniformly between the
        bounds (numpy's ``default_rng(seed)``).

    Raises
    ------
    InputError
        An unknown parameter (with the known ones), a malformed range, a design matrix larger
        than ``MEMORY_LIMIT_BYTES`` (with its size), or a non-physical design (named).
    """
    if sample not in ("grid", "random"):
        raise InputError(f"sample must be 'grid' or 'random' (got {sample!r})")
    if not isinstance(vary, dict) or not vary:
        raise InputError("vary must name at least one parameter: {name: values}")
    known = [par.name for par in robot.parameter_list]
    tied = {key: _names(key) for key in vary}
    unknown = [n for names in tied.values() for n in names if n not in known]
    if unknown:
        raise InputError(f"unknown parameter{'s' * (len(unknown) > 1)} {', '.join(map(repr, unknown))}"
                         f" of {robot.name}; known: {', '.join(known)}")
    twice = [n for n in known if sum(n in names for names in tied.values()) > 1]
    if twice:
        raise InputError(f"parameter {twice[0]!r} is varied twice in vary")
    specs = {tied[k]: _values(",".join(tied[k]), v, sample) for k, v in vary.items()}
    if sample == "random":
        if not isinstance(count, (int, np.integer)) or count < 1:
            raise InputError(f"a random sample needs a count of designs >= 1 (got {count!r})")
        D = int(count)
    else:
        if count is not None:
            raise InputError("count is for random samples; a grid has every combination")
        D = math.prod(len(v) for v in specs.values())
    size = 8.0 * D * len(known)
    if size > MEMORY_LIMIT_BYTES:
        raise InputError(f"{D:.3g} designs of {len(known)} parameters would take "
                         f"{size / 1e9:.3g} GB for their parameter vectors alone (limit "
                         f"{MEMORY_LIMIT_BYTES / 1e9:g} GB): fewer values per parameter, or a "
                         "random sample")
    if sample == "random":
        rng = np.random.default_rng(seed)
        per_key = [rng.uniform(lo, hi, D) for lo, hi in specs.values()]
    else:
        per_key = [g.reshape(-1) for g in np.meshgrid(*specs.values(), indexing="ij")]
    names = tuple(n for group in specs for n in group)  # tied names share their key's values
    values = np.column_stack([v for group, v in zip(specs, per_key) for _ in group])
    P = np.tile(robot.p, (D, 1))
    for k, name in enumerate(names):
        P[:, known.index(name)] = values[:, k]
    _check_physical(robot, names, values, P)
    units = tuple(robot.parameter_list[known.index(n)].unit for n in names)
    _warn_unit_slip(robot, names, units, values)
    return DesignSpace(names, units, values, np.ascontiguousarray(P), sample)


def _warn_unit_slip(robot: Robot, names, units, values: np.ndarray) -> None:
    """Warn, once per parameter, where a range's end is likely a slip: the table's rules
    (``model.parameters.doubts``) that every other route applies, on the smallest and the
    largest value of the range."""
    import warnings

    own = {**robot.parameters.fixed, **{p.name: p.value for p in robot.parameter_list}}
    for k, (name, unit) in enumerate(zip(names, units)):
        ends = (values[:, k].min(), values[:, k].max())
        for end in dict.fromkeys(ends):
            found = doubts([name], {**own, name: float(end)}, {name: unit}, own,
                           robot.body_names)
            if found:
                warnings.warn(f"sweep range {name} from {ends[0]:.6g} to {ends[1]:.6g}: "
                              f"{found[0]} (sweeps take SI units)", RuntimeWarning,
                              stacklevel=3)
                break


def _check_physical(robot: Robot, names, values: np.ndarray, P: np.ndarray) -> None:
    """Refuse the sweep at its first non-physical design, naming the values that make it so
    (the rules checked on whole columns at once, ``model.parameters.failing``)."""
    known = [par.name for par in robot.parameter_list]
    units = {par.name: par.unit for par in robot.parameter_list}
    fixed = robot.parameters.fixed  # body points that are no parameter: constant columns
    bad = failing([*known, *fixed], np.hstack([P, np.tile(list(fixed.values()), (len(P), 1))]),
                  robot.body_names, units)
    if bad.any():
        k = int(np.argmax(bad))
        found = problems({**fixed, **dict(zip(known, map(float, P[k])))}, robot.body_names,
                         units)
        what = ", ".join(f"{n} = {values[k, i]:.6g}" for i, n in enumerate(names))
        raise InputError(f"design {k} ({what}) is not physical: {'; '.join(found)} "
                         f"({int(bad.sum())} of {len(P)} designs are not); narrow the range")
