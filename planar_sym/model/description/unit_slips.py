"""Loops left open by lengths typed in another unit (a user trial: a coupler typed in m in a
description in mm gave "its points stay 119.4 mm apart" and no word about units).

Only clear evidence makes a hint: a body (or the ground) whose size is more than ``OUTLIER``
times larger or smaller than the median of the others', which one of the other length units
brings within ``NEAR`` times of that median, and, read so, every loop closes. A link that is
merely too short (a few times the others') is no unit slip, and is not called one. numpy only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..units import UNITS
from .assembly import ASSEMBLY_TOL_M, close_loops, sizes
from .types import Body

#: a body this many times larger or smaller than the median of the others' sizes is suspect
#: (a mechanism's links differ by a few times, the Jansen linkage's by 8; mm typed as m: 1000)
OUTLIER = 30.0
#: ... when another length unit brings it within this many times of that median
NEAR = 3.0


@dataclass(frozen=True)
class Slip:
    """A body's points likely typed in ``unit``: its size as read (m), read in ``unit`` (m),
    and the median of the other bodies' sizes (m)."""

    unit: str
    size_m: float
    meant_m: float
    others_m: float


def scaled(body: Body, k: float) -> Body:
    """``body`` with its points and centre of gravity multiplied by ``k``."""
    return replace(body, points_m={p: (x * k, y * k) for p, (x, y) in body.points_m.items()},
                   cg_m=(body.cg_m[0] * k, body.cg_m[1] * k))


def unit_slips(bodies: dict[str, Body], tree, loops, start_of, unit: str) -> dict[str, Slip]:
    """The bodies (by name, "ground" too) whose points read in another length unit close every
    loop, or {} where the evidence is not clear (see the module docstring).

    ``start_of`` gives the joints' starting coordinates for a set of bodies (the given angles,
    or for ``pose = "world"`` the angles of the bodies as drawn); ``unit`` is the description's
    ``[units].length``."""
    size = sizes(bodies)
    if len(size) < 3:  # a body against one other: no telling which is off
        return {}
    per = UNITS["length"][unit]
    picks: dict[str, Slip] = {}
    for name, s in size.items():
        others = float(np.exp(np.median([math.log(v) for n, v in size.items() if n != name])))
        if max(s / others, others / s) <= OUTLIER:
            continue
        u, f = min(((u, f) for u, f in UNITS["length"].items() if u != unit),
                   key=lambda uf: abs(math.log(s * uf[1] / per / others)))
        meant = s * f / per
        if max(meant / others, others / meant) <= NEAR:
            picks[name] = Slip(u, s, meant, others)
    if not picks:
        return {}
    trial = {n: scaled(b, picks[n].meant_m / picks[n].size_m) if n in picks else b
             for n, b in bodies.items()}
    passive = [j.name for j in tree if j.moves and not j.actuated]
    gap = close_loops(trial, tree, loops, start_of(trial), passive)[2]
    return picks if np.max(np.abs(gap)) < ASSEMBLY_TOL_M else {}
