"""Base parameters: the combinations of standard parameters the torques determine.

Gautier's numerical method: stack the regressor at random states, W (rows, columns), and keep
the columns independent of those before them, in a fixed order of preference (per body the
inertia about its origin, its first moments, then its mass; then the drive train's), so the
classical regrouping comes out (a serial arm's masses lumped into the links before them):

.. code:: text

    W_dep = W_ind K          (least squares; exact for a generic W)
    beta  = pi_ind + K pi_dep,   tau = Y_ind beta

A column that is zero everywhere is a parameter with no effect on any torque; the others that
are not kept are regrouped into the kept ones. The count is checked against the rank of W by
an SVD in tests/test_identify.py.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model.robot import Robot
from .regressor import regressor
from .standard import StandardParameters, standard_parameters
from .states import random_states

#: a column (scaled to unit norm) counts as independent when its distance from the span of
#: the columns before it exceeds this; generic states give about 1e-2 or more, or rounding
#: (below 1e-12): the gap is reported as ``margin``
RANK_TOL = 1e-8
#: coefficients of K below this (relative to its largest) are rounding, set to zero
CLEAN_TOL = 1e-10
_ORDER = {"izo": 0, "mcx": 1, "mcy": 2, "m": 3, "jm": 4, "fv": 5, "fc": 6}


@dataclass(frozen=True)
class BaseParameters:
    """The base parameters of a robot's torque regressor.

    ``standard``: the robot's StandardParameters, shape (columns,), in SI; ``kept``, shape
    (base,), indexes
    the standard parameters each base parameter is named after;
    ``regrouping`` (base, standard) maps the standard parameters to the base ones
    (``beta = regrouping @ pi``; its ``kept`` columns are the identity); ``unidentifiable``
    names the standard parameters with no effect on any torque; ``margin`` is the smallest
    kept column's distance from the others against the largest dropped one's (scaled columns):
    the larger the gap, the surer the count.
    """

    standard: StandardParameters
    kept: tuple[int, ...]
    regrouping: np.ndarray
    unidentifiable: tuple[str, ...]
    margin: tuple[float, float]

    def __len__(self) -> int:
        return len(self.kept)

    @property
    def names(self) -> tuple[str, ...]:
        """Each base parameter named after its kept standard parameter, with ``R`` added where
        others are regrouped into it (``izo_link1R``, after Khalil's notation)."""
        out = []
        for row, k in zip(self.regrouping, self.kept):
            name = self.standard.names[k]
            out.append(name + "R" if np.count_nonzero(row) > 1 else name)
        return tuple(out)

    @property
    def units(self) -> tuple[str, ...]:
        """Each base parameter's unit: its kept standard parameter's."""
        return tuple(self.standard.units[k] for k in self.kept)

    def values(self, pi=None) -> np.ndarray:
        """The base parameters, shape (base,), in their units (SI), of standard parameters
        ``pi``, shape (columns,), in SI (the robot's own by default)."""
        return self.regrouping @ (self.standard.values if pi is None else np.asarray(pi, float))

    def expressions(self, digits: int = 6) -> list[str]:
        """Each base parameter as a sum of standard ones, e.g. ``izo_link1R = izo_link1 +
        izo_motor2 + 0.0625 m_link2`` (coefficients in SI: lengths in m)."""
        out = []
        for name, row in zip(self.names, self.regrouping):
            terms = []
            for c, std in zip(row, self.standard.names):
                if c == 0:
                    continue
                mag = f"{abs(c):.{digits}g} " if not np.isclose(abs(c), 1.0, rtol=1e-12) else ""
                terms.append(("- " if c < 0 else "+ ") + mag + std)
            text = " ".join(terms)
            out.append(f"{name} = {text[2:] if text.startswith('+ ') else '-' + text[2:]}")
        return out

    def regrouped(self) -> dict[str, str]:
        """Each dropped standard parameter (not unidentifiable) and the base parameters it is
        part of."""
        names = self.names
        out = {}
        for j, std in enumerate(self.standard.names):
            if j in self.kept or std in self.unidentifiable:
                continue
            into = [names[i] for i in np.flatnonzero(self.regrouping[:, j])]
            out[std] = ", ".join(into)
        return out


def base_parameters(robot: Robot, samples: int = 200, seed: int = 0) -> BaseParameters:
    """The robot's base parameters, from its regressor at ``samples`` random states
    (``states.random_states``)."""
    std = standard_parameters(robot)
    q, qd, qdd = random_states(robot, samples, seed)
    w = regressor(robot, q, qd, qdd).y.reshape(-1, len(std))
    return from_stacked(w, std)


def from_stacked(w: np.ndarray, std: StandardParameters) -> BaseParameters:
    """``BaseParameters`` of a stacked regressor ``w``, shape (rows, columns) in N*m (N at a
    slider) per unit of each standard parameter of ``std``."""
    norms = np.linalg.norm(w, axis=0)
    zero = norms <= 1e-12 * max(norms.max(), 1e-300)
    owners = list(dict.fromkeys(n.split("_", 1)[1] for n in std.names))  # bodies, then joints

    def preference(j: int) -> tuple[int, int]:
        kind, owner = std.names[j].split("_", 1)
        return owners.index(owner), _ORDER[kind]

    order = sorted(np.flatnonzero(~zero), key=preference)
    scaled = w[:, order] / norms[order]
    r = np.abs(np.diag(np.linalg.qr(scaled, mode="r")))
    keep = r > RANK_TOL
    kept = sorted(int(order[i]) for i in np.flatnonzero(keep))
    dropped = [int(order[i]) for i in np.flatnonzero(~keep)]
    reg = np.zeros((len(kept), len(std)))
    reg[np.arange(len(kept)), kept] = 1.0
    if dropped:
        k, *_ = np.linalg.lstsq(w[:, kept], w[:, dropped], rcond=None)
        k[np.abs(k) < CLEAN_TOL * max(np.abs(k).max(), 1e-300)] = 0.0
        reg[:, dropped] = k
    margin = (float(r[keep].min()) if keep.any() else 0.0,
              float(r[~keep].max()) if (~keep).any() else 0.0)
    return BaseParameters(std, tuple(kept), reg,
                          tuple(std.names[j] for j in np.flatnonzero(zero)), margin)

