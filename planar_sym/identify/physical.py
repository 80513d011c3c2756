"""A physically consistent set of standard parameters that reproduces estimated base ones.

The base parameters fix only combinations of the standard ones; a robot to simulate needs them
all, each physical: a positive mass, a positive inertia about the centre of gravity (in the
plane that is the whole condition: m I_o - (m cx)^2 - (m cy)^2 > 0, a convex cone) and
non-negative rotor inertia and friction. Of the sets within those limits, the one closest to
the estimate in its own covariance is taken, and among equally close ones (the combinations the
data cannot see) the one nearest the description's values:

.. code:: text

    min  (B pi - beta)^T C^-1 (B pi - beta) + LAMBDA |(pi - pi_0) / s|^2
    s.t. m > 0,  m I_o - |m c|^2 >= 0,  J_m, f_v, f_c >= 0,  the description's structure
         (a centre of gravity on a body axis keeps it there, a point mass stays one)

A convex problem (quadratic objective, cone and bound constraints): SciPy's SLSQP finds its
minimum from the description's values.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.robot import Robot
from .estimate import Estimate
from .standard import StandardParameters, standard_parameters

#: weight of the pull towards the description's values: small enough that the data decide
#: everything they can see (the fit's Mahalanobis distance changes by less than this)
LAMBDA = 1e-6
#: the smallest mass and inertia about the centre of gravity accepted, relative to the
#: description's largest of each
FLOOR = 1e-6


@dataclass(frozen=True)
class PhysicalFit:
    """``standard``: the consistent standard parameters; ``distance``: the fit's Mahalanobis
    distance sqrt((B pi - beta)^T C^-1 (B pi - beta)) to the estimate (about sqrt(b) or less
    when the estimate is itself consistent); ``active``: the limits the solution sits on."""

    standard: StandardParameters
    distance: float
    active: tuple[str, ...]


def physical_parameters(robot: Robot, estimate: Estimate) -> PhysicalFit:
    """The consistent standard parameters nearest ``estimate`` (see the module docstring)."""
    from scipy.optimize import minimize

    std0 = standard_parameters(robot)
    names = std0.names
    base = estimate.base
    kinds = [n.split("_", 1)[0] for n in names]
    owners = [n.split("_", 1)[1] for n in names]
    par = robot.parameters
    m_scale = max((abs(v) for v, k in zip(std0.values, kinds) if k == "m"), default=1.0)
    i_scale = max((abs(v) for v, k in zip(std0.values, kinds) if k == "izo"), default=1.0)
    s = np.array([max(abs(v), {"m": m_scale, "izo": i_scale}.get(k, 1e-3) * 1e-2)
                  for v, k in zip(std0.values, kinds)])
    b = base.regrouping
    cov_inv = np.linalg.inv(np.diag(estimate.std ** 2))

    def objective(x):
        pi = x * s
        r = b @ pi - estimate.values
        d = pi - std0.values
        return float(r @ cov_inv @ r + LAMBDA * len(names) * np.sum((d / s) ** 2))

    def gradient(x):
        pi = x * s
        r = b @ pi - estimate.values
        return (2 * b.T @ cov_inv @ r + 2 * LAMBDA * len(names) * (pi - std0.values) / s**2) * s

    cons, fixed, bounds = [], [], [(None, None)] * len(names)
    for body in dict.fromkeys(o for o, k in zip(owners, kinds) if k == "m"):
        im, ix, iy, io = (names.index(f"{k}_{body}") for k in ("m", "mcx", "mcy", "izo"))
        bounds[im] = (FLOOR * m_scale / s[im], None)
        for i, axis in ((ix, "x"), (iy, "y")):
            if f"cg{axis}_{body}" not in par:  # structural: the centre stays on that axis
                fixed.append(i)
        point_mass = f"izz_{body}" not in par

        def cone(x, im=im, ix=ix, iy=iy, io=io, point_mass=point_mass):
            m, cx, cy, i_o = x[im] * s[im], x[ix] * s[ix], x[iy] * s[iy], x[io] * s[io]
            # m Izz_cg = m I_o - |m c|^2: zero for a point mass, else at least m FLOOR i_scale
            return np.array([(m * i_o - cx * cx - cy * cy) / (m_scale * i_scale)
                             - (0.0 if point_mass else FLOOR * m / m_scale)])
        cons.append({"type": "eq" if point_mass else "ineq", "fun": cone})
    for i, k in enumerate(kinds):
        if k in ("jm", "fv", "fc"):
            bounds[i] = (0.0, None)
    for i in fixed:
        bounds[i] = (0.0, 0.0)
    x0 = np.clip(std0.values / s, [lo if lo is not None else -np.inf for lo, _ in bounds],
                 [hi if hi is not None else np.inf for _, hi in bounds])
    f0 = max(objective(x0), 1.0)  # SLSQP's tolerance is absolute: the objective scaled to ~1
    res = minimize(lambda x: objective(x) / f0, x0, jac=lambda x: gradient(x) / f0,
                   bounds=bounds, constraints=cons, method="SLSQP",
                   options={"maxiter": 1000, "ftol": 1e-12})
    if not res.success:
        raise InputError(f"{robot.name}: no physically consistent parameters were found near "
                         f"the estimate ({res.message})")
    pi = res.x * s
    active = tuple(names[i] for i, (lo, hi) in enumerate(bounds)
                   if i not in fixed and lo is not None and abs(res.x[i] - lo) < 1e-9)
    r = b @ pi - estimate.values
    return PhysicalFit(StandardParameters(names, std0.units, std0.meanings, pi),
                       float(np.sqrt(r @ cov_inv @ r)), active)


def identified_robot(robot: Robot, fit: PhysicalFit, estimate: Estimate) -> Robot:
    """``robot`` with the fit's values: masses, centres of gravity and inertias about them, and
    the drive train's rotor inertia and friction where the description has a place for them.

    A friction or rotor inertia the description has no place for is left out, with a warning,
    when the data cannot tell it from zero (within 3 standard deviations of its base
    parameter); otherwise InputError names it and says where it would go.
    """
    v = fit.standard.as_dict()
    std = dict(zip((n.removesuffix("R") for n in estimate.base.names), estimate.std))
    dropped = []
    par = robot.parameters
    values, homeless = {}, []
    for name, value in v.items():
        kind, owner = name.split("_", 1)
        if kind == "m":
            m = value
            cx, cy = v[f"mcx_{owner}"] / m, v[f"mcy_{owner}"] / m
            values[name] = m
            for axis, c in (("x", cx), ("y", cy)):
                if f"cg{axis}_{owner}" in par:
                    values[f"cg{axis}_{owner}"] = c
            if f"izz_{owner}" in par:
                values[f"izz_{owner}"] = v[f"izo_{owner}"] - m * (cx * cx + cy * cy)
        elif kind in ("jm", "fv", "fc"):
            if name in par:
                values[name] = value
            elif abs(value) > 3 * std.get(name, 0.0):
                homeless.append(f"{name} = {value:.6g}")
            elif value != 0.0:
                dropped.append(f"{name} = {value:.3g}")
    if homeless:
        raise InputError(f"{robot.name}: the description has no place for the identified "
                         f"{', '.join(homeless)}: give the joints' [joints.actuator] "
                         "viscous_friction and coulomb_friction (0 will do) and identify again")
    if dropped:
        warnings.warn(f"{robot.name}: left out {', '.join(dropped)} (within 3 standard "
                      "deviations of zero; the description has no place for them)",
                      RuntimeWarning, stacklevel=2)
    return robot.with_parameters(**values)
