"""A control study's sweep has two parameter sets: the controller's model and the plant
(``[control.plant]``). ``on`` says which the designs change; here are both sets' designs, a
design's plant as a ``[control.plant]`` table, and the sentence saying what was varied."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import InputError
from ..model.robot import Robot
from ..study import spec as specs
from .designs import DesignSpace, design_space

#: which parameter set of a control study the designs change
ON = ("both", "model", "plant")


def plant_designs(st: specs.Study, robot: Robot, vary: dict, on: str, *, sample: str,
             count: int | None, seed: int, control: bool) -> tuple[DesignSpace, np.ndarray | None]:
    """The designs' model parameter vectors (``space.P``: what the worker robot is set to) and,
    for a control study, the plant's (D, n_p). Each set a design changes is checked as a
    design of its own base: the study's robot, or the study's plant (``[control.plant]``)."""
    from ..study.parameters import with_overrides

    if not control:
        return design_space(robot, vary, sample=sample, count=count, seed=seed), None
    plant = with_overrides(robot, st.control.plant, f"{st.path or st.name}: control.plant")
    if on == "plant":
        try:
            space = design_space(plant, vary, sample=sample, count=count, seed=seed)
        except InputError as exc:
            raise InputError(f"the plant: {exc}") from None
        plant_P = space.P
        model = np.tile(robot.p, (len(space), 1))
        values = model[:, [parameter_index(robot, n) for n in space.names]]
        return DesignSpace(space.names, space.units, values, model, space.sample), plant_P
    space = design_space(robot, vary, sample=sample, count=count, seed=seed)
    if on == "model":
        return space, np.tile(plant.p, (len(space), 1))
    # both: the plant's other [control.plant] values stay; the varied ones are the design's
    plant_P = np.tile(plant.p, (len(space), 1))
    for k, name in enumerate(space.names):
        plant_P[:, parameter_index(robot, name)] = space.values[:, k]
    if not np.array_equal(plant_P, space.P):  # the plant is a design of its own base too
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a unit slip was said once, for the model
            try:
                design_space(plant, vary, sample=sample, count=count, seed=seed)
            except InputError as exc:
                raise InputError(f"the plant: {exc}") from None
    return space, plant_P


def parameter_index(robot: Robot, name: str) -> int:
    return [par.name for par in robot.parameter_list].index(name)


def plant_overrides(robot: Robot, p: np.ndarray, plant: np.ndarray) -> dict:
    """A design's ``[control.plant]``: every parameter where the plant differs from the model,
    in SI with its SI unit (so that ``to_si`` multiplies by exactly 1)."""
    return {par.name: (float(plant[k]), par.unit) for k, par in enumerate(robot.parameter_list)
            if plant[k] != p[k]}


def on_note(st: specs.Study, robot: Robot, space: DesignSpace, plant_P: np.ndarray,
             on: str) -> str:
    """What the designs changed on which parameter set, and what the other one kept."""
    names = ", ".join(space.names)
    if on == "both":
        replaced = [n for n in space.names if n in st.control.plant]
        extra = (f" ([control.plant]'s {', '.join(replaced)} replaced by the design's)"
                 if replaced else "")
        return f"{names} varied on the controller's model and the plant{extra}"
    units = {par.name: par.unit for par in robot.parameter_list}
    kept = plant_P[0] if on == "model" else space.P[0]
    held = ", ".join(f"{n} = {kept[parameter_index(robot, n)]:.6g} {units[n]}" for n in space.names)
    if on == "model":
        return f"{names} varied on the controller's model only: the plant keeps {held}"
    return f"{names} varied on the plant only: the controller's model keeps {held}"
