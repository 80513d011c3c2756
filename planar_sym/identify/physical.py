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

from ..errors import DescriptionError, InputError
from ..model.robot import Robot
from .estimate import Estimate
from .standard import StandardParameters, standard_parameters

#: weight of the pull towards the description's values: small enough that the data decide
#: everything they can see (the fit's Mahalanobis distance changes by less than this)
LAMBDA = 1e-6
#: the smallest mass and inertia about the centre of gravity accepted, relative to the
#: description's largest of each
FLOOR = 1e-6
#: the smallest standard deviation the fit counts with, relative (see physical_parameters)
STD_FLOOR = 1e-9


@dataclass(frozen=True)
class PhysicalFit:
    """``standard``: the consistent standard parameters, (columns,) in SI; ``distance``: the
    fit's Mahalanobis distance sqrt((B pi - beta)^T C^-1 (B pi - beta)) to the estimate
    (dimensionless: about sqrt(b) or less when the estimate is itself consistent);
    ``active``: the drive parameters the solution holds at zero."""

    standard: StandardParameters
    distance: float
    active: tuple[str, ...]


def physical_parameters(robot: Robot, estimate: Estimate) -> PhysicalFit:
    """The consistent standard parameters nearest ``estimate`` (see the module docstring).

    Solved in variables that make both terms well scaled, whatever the data's accuracy: the
    base parameters in standard deviations from the estimate, ``beta = beta^ + sigma y``, and
    the standard parameters the base ones do not keep, over their sizes, ``pi_d = s z``; the
    kept ones follow, ``pi_k = beta - K pi_d``. The objective is then ``|y|^2`` plus the pull.
    """
    from scipy.optimize import minimize

    std0 = standard_parameters(robot)
    names, base = std0.names, estimate.base
    kinds = [n.split("_", 1)[0] for n in names]
    par = robot.parameters
    m_scale = max((abs(v) for v, k in zip(std0.values, kinds) if k == "m"), default=1.0)
    i_scale = max((abs(v) for v, k in zip(std0.values, kinds) if k == "izo"), default=1.0)
    size = np.array([max(abs(v), {"m": m_scale, "izo": i_scale}.get(k, 1e-3) * 1e-2)
                     for v, k in zip(std0.values, kinds)])
    kept = list(base.kept)
    dropped = [j for j in range(len(names)) if j not in kept]
    k_mat = base.regrouping[:, dropped]
    # exact data give standard deviations at rounding: the fit is asked to match within
    # STD_FLOOR of the size that gives torques of the data's size, no closer
    sigma = np.sqrt(estimate.std ** 2 + (STD_FLOOR * estimate.scale) ** 2)
    nb = len(kept)
    pull = LAMBDA * len(names)

    def standard(x) -> np.ndarray:
        y, z = x[:nb], x[nb:]
        pi = np.empty(len(names))
        pi[dropped] = size[dropped] * z
        pi[kept] = estimate.values + sigma * y - k_mat @ pi[dropped]
        return pi

    def objective(x):
        return float(x[:nb] @ x[:nb] + pull * np.sum(((standard(x) - std0.values) / size) ** 2))

    def gradient(x):
        g = 2 * pull * (standard(x) - std0.values) / size**2  # d/d pi of the pull
        return np.concatenate([2 * x[:nb] + sigma * g[kept],
                               size[dropped] * (g[dropped] - k_mat.T @ g[kept])])

    ineq, eq, structural = [], [], []  # functions of pi, each scaled to about 1
    for body in (o.split("_", 1)[1] for o in names if o.startswith("m_")):
        im, ix, iy, io = (names.index(f"{k}_{body}") for k in ("m", "mcx", "mcy", "izo"))
        ineq.append(lambda pi, im=im: pi[im] / m_scale - FLOOR)
        for i, axis in ((ix, "x"), (iy, "y")):
            if f"cg{axis}_{body}" not in par:  # structural: the centre stays on that axis
                eq.append(lambda pi, i=i: pi[i] / size[i])
                structural.append(i)
        point_mass = f"izz_{body}" not in par

        # m Izz_cg = m I_o - |m c|^2: zero for a point mass, else at least m FLOOR i_scale
        def cone(pi, im=im, ix=ix, iy=iy, io=io, point_mass=point_mass):
            value = (pi[im] * pi[io] - pi[ix] ** 2 - pi[iy] ** 2) / (m_scale * i_scale)
            return value - (0.0 if point_mass else FLOOR * pi[im] / m_scale)
        (eq if point_mass else ineq).append(cone)
    ineq += [lambda pi, i=i: pi[i] / size[i] for i, k in enumerate(kinds)
             if k in ("jm", "fv", "fc")]
    cons = [{"type": "ineq", "fun": lambda x: np.array([f(standard(x)) for f in ineq])}]
    if eq:
        cons.append({"type": "eq", "fun": lambda x: np.array([f(standard(x)) for f in eq])})
    x0 = np.concatenate([np.zeros(nb), std0.values[dropped] / size[dropped]])
    # far from a consistent estimate the objective is large (hundreds of standard deviations
    # squared) and SLSQP's absolute tolerance stalls its line search: scaled down and again
    for scale in (1.0, 1e2, 1e4, 1e6):
        res = minimize(lambda x, f=scale: objective(x) / f, x0,
                       jac=lambda x, f=scale: gradient(x) / f, constraints=cons,
                       method="SLSQP", options={"maxiter": 1000, "ftol": 1e-12})
        if res.success:
            break
    if not res.success:
        raise InputError(f"{robot.name}: no physically consistent parameters were found near "
                         f"the estimate ({res.message})")
    pi = standard(res.x)
    # SLSQP meets the equalities to its tolerance (5e-23 kg*m seen on one CPU, 0 on another):
    # a first moment the description fixes at zero is zero
    pi[structural] = 0.0
    # and its inequalities to its tolerance too: a joint without friction or rotor came out at
    # -1.7e-21 N*m, which the parameter checks refused (20 of 30 noisy fits in a user trial)
    drive = [i for i, k in enumerate(kinds) if k in ("jm", "fv", "fc")]
    pi[drive] = np.maximum(pi[drive], 0.0)
    active = tuple(n for n, k, v in zip(names, kinds, pi) if k in ("jm", "fv", "fc")
                   and abs(v) <= 1e-9 * max(abs(v0) for v0 in std0.values))
    return PhysicalFit(StandardParameters(names, std0.units, std0.meanings, pi),
                       float(np.linalg.norm(res.x[:nb])), active)


#: drive-train values no robot has, SI (N*m or N of friction, N*m*s of viscous friction,
#: kg*m^2 of rotor inertia): an estimate this small is zero to rounding, even where noiseless
#: data make its standard deviation smaller still (4e-18 N*m of Coulomb friction from a
#: simulated S3 move, which asked the user to change the description)
ROUNDING = {"fc": 1e-9, "fv": 1e-9, "jm": 1e-12}
#: an estimate whose torques are below this share of the data's (|value| against
#: ``Estimate.scale``, the size that alone would give torques of the data's size) is too small
#: to matter: left out where the description has no place for it, with the warning
NEGLIGIBLE = 1e-3  # (1e-4 refused a trial's noise-free cart-pole: 0.07 % of its torques)


def identified_robot(robot: Robot, fit: PhysicalFit, estimate: Estimate) -> Robot:
    """``robot`` with the fit's values: masses, centres of gravity and inertias about them, and
    the drive train's rotor inertia and friction where the description has a place for them.

    A friction or rotor inertia the description has no place for is left out, with a warning,
    when the data cannot tell it from zero (within 3 standard deviations of its base
    parameter, not a base parameter of this data at all, or below ``ROUNDING``);
    otherwise InputError names it and says where it would go.
    """
    v = fit.standard.as_dict()
    std = dict(zip((n.removesuffix("R") for n in estimate.base.names), estimate.std))
    # what a value alone would add to the torques, against their size: a trial's noise-free
    # data gave fv = 6e-7 N*m*s (0.0006 % of the torques), above 3 sigma and refused
    scale = dict(zip((n.removesuffix("R") for n in estimate.base.names), estimate.scale))
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
            elif name in std and abs(value) > max(3 * std[name], ROUNDING[kind],
                                                  NEGLIGIBLE * scale[name]):
                homeless.append(f"{name} = {value:.6g}")
            elif value != 0.0:  # near zero, or not a base parameter: the data cannot tell
                dropped.append(f"{name} = {value:.3g}")  # (or too small to matter)
    if homeless:
        raise InputError(f"{robot.name}: the description has no place for the identified "
                         f"{', '.join(homeless)}: give the joints' [joints.actuator] "
                         "viscous_friction and coulomb_friction (0 will do) and identify again")
    if dropped:
        warnings.warn(f"{robot.name}: left out {', '.join(dropped)} (within 3 standard "
                      "deviations of zero, below 0.1 % of the torques, or not determined by "
                      "this data; the description has no place for them)",
                      RuntimeWarning, stacklevel=2)
    try:
        return robot.with_parameters(**values)
    except (InputError, DescriptionError) as exc:
        if not estimate.poor_fit:
            raise
        # the description's rules refuse what a fit of the wrong data gives: say so, or the
        # refusal blames the parameters (a trial: angles in degrees under rad headers)
        why = (f"these are the fit's values, and the fit leaves {estimate.poor_fit} of the "
               "torque unexplained: the data, more likely than the robot, are off (angles in "
               "degrees under rad headers, torques in another unit, another robot's data)")
        if isinstance(exc, DescriptionError):
            raise DescriptionError([*exc.problems, why]) from None
        raise InputError(f"{exc}. {why[0].upper()}{why[1:]}") from None
