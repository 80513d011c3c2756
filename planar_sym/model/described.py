"""A robot's description with its own parameter values: what its pictures and exports show.

A ``Robot`` from ``with_parameters`` (a study's ``[parameters]``, a control study's plant, a
sweep's design) keeps the description it was derived from, whose numbers are the description's.
Every feature that draws or writes the machine's bodies (drawings, animations, notebooks, the
explore page, MJCF and URDF) takes them from here, so a changed link length moves the drawn
point as it moves the joint the dynamics sees (a user trial: the drawing kept the description's
0.1 m link while the next joint sat at 0.15 m).

A body-frame coordinate that is not a parameter is an exact structural zero or a point the
equations never use (drawn only): it keeps the description's value.
"""

from __future__ import annotations

import warnings
from dataclasses import replace
from typing import TYPE_CHECKING

from ..errors import InputError, LibraryError
from .description import GROUND, Body, Description
from .description import load as load_description

if TYPE_CHECKING:
    from collections.abc import Mapping

    from .robot import Robot


def with_values(desc: Description, values: Mapping[str, float]) -> Description:
    """``desc`` with ``values`` (SI, by parameter name) in place of its masses, inertias,
    centres of gravity and body-frame points."""
    bodies = {}
    for name, body in desc.bodies.items():
        b = _points(body, values)
        if name != GROUND:
            b = replace(b, mass_kg=values.get(f"m_{name}", body.mass_kg),
                        izz_kg_m2=(0.0 if body.point_mass
                                   else values.get(f"izz_{name}", body.izz_kg_m2)),
                        cg_m=(values.get(f"cgx_{name}", body.cg_m[0]),
                              values.get(f"cgy_{name}", body.cg_m[1])))
        bodies[name] = b
    return replace(desc, bodies=bodies)


def described(robot: Robot, purpose: str = "draw it") -> Description:
    """The description ``robot`` was derived from, with ``robot.parameters`` in place.

    Raises
    ------
    InputError
        The robot has no description at hand (a generated folder without description.toml).
    LibraryError
        The description no longer matches the generated code (other parameters or joints).
    """
    path = robot.description_file
    if path is None:
        raise InputError(f"{robot.name}: no description at hand to {purpose} (its generated "
                         f"folder {robot.library.folder} has no description.toml): {purpose} "
                         "from its description file ROBOT.toml")
    with warnings.catch_warnings():  # the derived folder's copy: its warnings were said when
        warnings.simplefilter("ignore")  # the user's file was read (a trial's export said
        desc = load_description(path)    # them twice, the second under a cache path)
    names = [p.name for p in desc.parameters()]
    if names != [p.name for p in robot.parameter_list] or desc.coordinates != robot.coordinates:
        raise LibraryError(f"{robot.name}: its description {path} no longer matches its "
                           f"generated code in {robot.library.folder} (other parameters or "
                           "joints): re-derive it (`make derive`, or `planar-sym derive` for "
                           "your own robot)")
    return with_values(desc, robot.parameters)


def _points(body: Body, values: Mapping[str, float]) -> Body:
    """``body`` with its point coordinates taken from ``values`` where they are parameters."""
    pts = {p: (values.get(f"px_{body.name}_{p}", x), values.get(f"py_{body.name}_{p}", y))
           for p, (x, y) in body.points_m.items()}
    return replace(body, points_m=pts)
