"""Identification's standard parameters of a robot: what its dynamics is linear in.

Per body the mass, its first moments about the body frame's origin and the inertia about that
origin; per actuated joint the rotor inertia (where the description gives one) and the viscous
and Coulomb friction. The columns of the generated regressors (``derive/regressor.py``) are
these, in the manifest's ``standard_parameters`` order:

.. code:: text

    m_<body>    kg        mass
    mcx_<body>  kg*m      m cx   (body x of the centre of gravity, times the mass)
    mcy_<body>  kg*m      m cy
    izo_<body>  kg*m^2    Izz + m (cx^2 + cy^2): inertia about the body frame's origin
    jm_<joint>  kg*m^2    rotor inertia (motor side)
    fv_<joint>  N*m*s/rad viscous friction (N*s/m at a slider)
    fc_<joint>  N*m       Coulomb friction (N at a slider)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import LibraryError
from ..model.robot import Robot


@dataclass(frozen=True)
class StandardParameters:
    """The standard parameters in column order: ``names``, ``units`` and ``meanings``, each a
    tuple of strings, and ``values``, shape (columns,), in SI (kg, kg*m, kg*m^2, N*m*s/rad,
    N*m)."""

    names: tuple[str, ...]
    units: tuple[str, ...]
    meanings: tuple[str, ...]
    values: np.ndarray

    def __len__(self) -> int:
        return len(self.names)

    def as_dict(self) -> dict[str, float]:
        """{name: value (SI)}."""
        return dict(zip(self.names, self.values.tolist()))

    def index(self, name: str) -> int:
        """The column of ``name`` (ValueError for another name)."""
        return self.names.index(name)


def columns(robot: Robot) -> list[dict]:
    """The manifest's ``standard_parameters`` (name, unit, meaning), or LibraryError for code
    generated before the regressors were."""
    cols = robot.library.manifest.get("standard_parameters")
    if cols is None:
        raise LibraryError(f"{robot.name}: its generated code has no regressor (derived before "
                           "identification was added): run `make derive` (or load its TOML "
                           "again, which re-derives it)")
    return cols


def standard_parameters(robot: Robot) -> StandardParameters:
    """The robot's own standard parameters, from its parameters (SI).

    A centre of gravity or inertia the description makes structural (exactly zero, so not a
    parameter) counts as zero; so does a friction or rotor inertia it does not give.
    """
    cols = columns(robot)
    par = robot.parameters

    def get(name: str) -> float:
        return float(par[name]) if name in par else 0.0

    values = []
    for c in cols:
        kind, owner = c["name"].split("_", 1)
        m = get(f"m_{owner}")
        if kind == "mcx":
            values.append(m * get(f"cgx_{owner}"))
        elif kind == "mcy":
            values.append(m * get(f"cgy_{owner}"))
        elif kind == "izo":
            values.append(get(f"izz_{owner}") + m * (get(f"cgx_{owner}") ** 2
                                                     + get(f"cgy_{owner}") ** 2))
        else:  # m, jm, fv, fc: the robot's parameter of the same name
            values.append(get(c["name"]))
    return StandardParameters(tuple(c["name"] for c in cols), tuple(c["unit"] for c in cols),
                              tuple(c["meaning"] for c in cols), np.array(values))
