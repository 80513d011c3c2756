"""A compiled robot cross-checked against independent routes: each check returns table rows.

(a) every output of every compiled function against the SymPy model it was generated from
    (needs SymPy and the description file);
(b) a second route to the dynamics that never uses the symbolic M and h: Lagrange's equations
    by finite differences of the compiled *energy* (rotors included), plus the drive train's
    friction from the parameters, ``tau = d/dt dL/dqd - dL/dq + D(qd)``; for closed chains also
    the multiplier solve against the null-space projection ``G^T (M qdd + h)``;
(c) energy of free motion (zero torque, from the drawn pose): conserved, or with friction
    ``E(t) + F(t) = E(0)``, F the friction's work integrated with the state;
(d) power balance along a trajectory: ``sum tau_i qd_i = dE/dt + D(qd) . qd`` (a tree with a
    passive joint: its tree torques at every joint, a passive one's as an applied torque);
(e) closed chains: the loop residual, and the passive rates against differences of q(t).

Relative errors are normwise: at random states per sample, ``max_k ||a_k - b_k||_inf /
||b_k||_inf``; along a motion relative to the peak, ``max_k ||a_k - b_k|| / max_k ||b_k||``.
A quantity that can be zero at every state (the velocity Jacobian of a 1-DOF robot, the
gravity of a robot in a horizontal plane) is measured against its physical scale instead: the
sampled accelerations per unit rate or angle, so rounding noise is never divided by itself.
The forward dynamics' accelerations are compared as the torques they imply, ``M qdd + h``
(M and h from the energy), against the torques they came from: a backward error, which an
ill-conditioned M (a geared joint's reflected rotor a million times a light link's inertia)
does not inflate, while a wrong solve still shows in full.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path

import numpy as np

from ..errors import PlanarSymError
from ..model.robot import Robot
from .validate_rows import (
    TOL_ENERGY,
    TOL_PHI_M,
    TOL_POWER,
    TOL_RATES,
    TOL_ROUTE,
    TOL_SYMBOLIC,
    Row,
    random_states,
    rel_err,
    row,
    worst_key,
)
from .validate_symbolic import check_symbolic, find_description

__all__ = ["TOL_ENERGY", "TOL_PHI_M", "TOL_POWER", "TOL_RATES", "TOL_ROUTE", "TOL_SYMBOLIC",
           "Row", "check_symbolic", "find_description", "random_states", "rel_err", "row"]

#: 4th-order central differences: f'(0) ~ sum c f(k s) / s, f''(0) ~ sum c f(k s) / s^2.
#: Truncation ~ s^4 f^(5), rounding ~ eps f / s: s = 1e-3 keeps both near 1e-12 relative.
D1 = {-2: 1 / 12, -1: -8 / 12, 1: 8 / 12, 2: -1 / 12}
D2 = {-2: -1 / 12, -1: 16 / 12, 0: -30 / 12, 1: 16 / 12, 2: -1 / 12}
STEP = 1e-3  # rad for q, s for time


# -- (b) Lagrange from the energy ---------------------------------------------------------------
def _diff(f, x: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """d/ds f(x + s direction) at s = 0, 4th-order central differences, batched over samples."""
    return sum(c * f(x + k * STEP * direction) for k, c in D1.items()) / STEP


def mass_from_energy(robot: Robot, q: np.ndarray) -> np.ndarray:
    """M(q) from the kinetic energy alone: T = qd^T M qd / 2, so by polarisation at unit rates
    M_ii = 2 T(e_i) and M_ij = T(e_i + e_j) - T(e_i) - T(e_j); exact up to rounding.

    ``q`` (N, n) in rad; returns M, shape (N, n, n), in kg*m^2.
    """
    n, eye = robot.n, np.eye(robot.n)
    t_of = {(i, j): robot.energy(q, np.broadcast_to(eye[i] + eye[j] * (i != j), q.shape))[0]
            for i in range(n) for j in range(i, n)}
    M = np.empty((len(q), n, n))
    for (i, j), t in t_of.items():
        M[:, i, j] = M[:, j, i] = 2 * t if i == j else t - t_of[i, i] - t_of[j, j]
    return M


def lagrange_from_energy(robot: Robot, q, qd, qdd) -> dict[str, np.ndarray]:
    """M, g = dV/dq, h and tau = d/dt dL/dqd - dL/dq + D(qd), from the compiled energy
    function (rotors included) and the drive train's friction D (``Robot.drive_train``).

    ``q``, ``qd``, ``qdd`` (N, n) in rad, rad/s, rad/s^2; returns ``"M"`` (N, n, n) in
    kg*m^2 and ``"g"``, ``"h"``, ``"tau"`` (N, n) in N*m.
    """
    eye = np.eye(robot.n)
    M = mass_from_energy(robot, q)
    dT = np.column_stack([_diff(lambda x: robot.energy(x, qd)[0], q, e) for e in eye])
    dV = np.column_stack([_diff(lambda x: robot.energy(x, qd)[1], q, e) for e in eye])
    # d/dt (M qd) at qdd = 0 is the derivative of M(q + s qd) qd along s
    mdot_qd = _diff(lambda x: np.einsum("kij,kj->ki", mass_from_energy(robot, x), qd), q, qd)
    h = mdot_qd - dT + dV + robot.drive_train.friction(qd)
    return {"M": M, "g": dV, "h": h, "tau": np.einsum("kij,kj->ki", M, qdd) + h}


def compiled_paths(robot: Robot) -> list[tuple[str, Robot]]:
    """Every compiled path a robot's methods may take: the exact CasADi functions and, where
    the robot uses them, the vectorised fast loops (labelled 'fast')."""
    exact = robot if robot.exact else Robot(robot.name, robot.library, robot.p, exact=True)
    return [("", exact)] + ([] if robot.exact else [("fast ", robot)])


def check_energy_route(robot: Robot, samples: int = 20, seed: int = 2) -> Row:
    """(b) The compiled M, g, h, tau (and forward dynamics with its Jacobian) against
    Lagrange's equations by finite differences of the compiled energy alone."""
    q, qd, qdd, _ = random_states(robot, samples, seed)
    ref = lagrange_from_energy(robot, q, qd, qdd)
    fns = robot.library.functions
    # physical scales of the forward dynamics' Jacobians: the sampled accelerations per unit
    # rate (1/s) and per radian (1/s^2); a 1-DOF arm's dqdd/dqd is zero at every state
    accel = float(np.max(np.abs(qdd)))
    scales = {"forward_dynamics_jacobian.dqdd_dq": accel / np.pi,
              "forward_dynamics_jacobian.dqdd_dqd": accel / float(np.max(np.abs(qd)))}
    got = {}
    for prefix, r in compiled_paths(robot):
        got.update({f"{prefix}mass_matrix.M": (r.mass_matrix(q), ref["M"]),
                    f"{prefix}gravity.g": (r.gravity(q), ref["g"]),
                    f"{prefix}bias.h": (r.bias(q, qd), ref["h"]),
                    f"{prefix}inverse_dynamics.tau": (r.tree_inverse_dynamics(q, qd, qdd),
                                                      ref["tau"])})
        if not robot.is_closed_chain:
            # as the torque it implies, M qdd + h (a backward error): where M is ill
            # conditioned (a geared joint's rotor 1e6 times a light wrist's inertia), a right
            # solve's qdd is off by cond(M) times the torques' rounding, a wrong one is not
            qdd_c = r.tree_forward_dynamics(q, qd, ref["tau"])
            got[f"{prefix}forward_dynamics.qdd"] = (
                np.einsum("kij,kj->ki", ref["M"], qdd_c) + ref["h"], ref["tau"])
    if robot.is_closed_chain:
        terms = fns["constrained_terms"](samples, {"q": q, "qd": qd, "p": robot.p})
        got.update({"constrained_terms.M": (terms["M"], ref["M"]),
                    "constrained_terms.h": (terms["h"], ref["h"])})
    else:
        tau = ref["tau"]
        args = {"q": q, "qd": qd, "tau": tau, "p": robot.p}
        jac = fns["forward_dynamics_jacobian"](samples, args)
        eye = np.eye(robot.n)
        by_q = [_diff(lambda x: robot.tree_forward_dynamics(x, qd, tau), q, e) for e in eye]
        by_qd = [_diff(lambda x: robot.tree_forward_dynamics(q, x, tau), qd, e) for e in eye]
        got["forward_dynamics_jacobian.dqdd_dq"] = (jac["dqdd_dq"], np.stack(by_q, axis=2))
        got["forward_dynamics_jacobian.dqdd_dqd"] = (jac["dqdd_dqd"], np.stack(by_qd, axis=2))
    errs = {k: rel_err(a, b, scale=scales.get(k, 0.0)) for k, (a, b) in got.items()}
    where = worst_key(errs)
    return row(f"(b) Lagrange from the energy (finite differences), {samples} states",
               errs[where], TOL_ROUTE, f"worst: {where}; vs compiled M, g, h, tau"
               + ("" if robot.is_closed_chain else ", forward dynamics"))


# -- a smooth motion, at t and at t + k * STEP for the time differences ---------------------------
def motion(robot: Robot, samples: int, amplitude: float) -> dict:
    """Joint motion ``q0 + A sin(2 pi t + phase_i)`` over 1 s from the drawn pose, at the times
    t + k STEP (k = -2..2); closed chains move their actuated joints and solve the others."""
    from ..motion.closure import from_actuated
    from ..motion.profiles import JointTrajectory

    idx = np.array(robot.actuated if robot.is_closed_chain else range(robot.n), dtype=int)
    phase = np.linspace(0.0, np.pi, len(idx), endpoint=False)
    t0 = np.linspace(0.0, 1.0, samples)
    out = {}
    w = 2 * np.pi
    for k in D2:
        t = t0 + k * STEP
        arg = w * t[:, None] + phase
        s, c = amplitude * np.sin(arg), amplitude * np.cos(arg)
        q, qd, qdd = robot.q_drawn[idx] + s, w * c, -w**2 * s
        out[k] = (from_actuated(robot, t, q, qd, qdd, robot.q_drawn) if robot.is_closed_chain
                  else JointTrajectory(t, q, qd, qdd))
    return out


def check_power(robot: Robot, traj: dict) -> Row:
    """Power in, ``sum tau_i qd_i``, against dE/dt from the energy plus the power the drive
    train's friction takes: the actuated joints' torques of a closed chain, or a tree's torques
    at every joint (at a passive joint, the torque that would make it follow: a check of M and
    h, not a motor's)."""
    energy = {k: sum(robot.energy(j.q, j.qd)) for k, j in traj.items()}
    j = traj[0]
    needed = sum(c * energy[k] for k, c in D1.items()) / STEP
    needed = needed + robot.drive_train.friction_power(j.qd)
    if robot.is_closed_chain:
        tau, _ = robot.closed_chain_inverse_dynamics(j.q, j.qd, j.qdd)
        power = np.sum(tau * j.qd[:, list(robot.actuated)], axis=1)
    else:
        power = np.sum(robot.tree_inverse_dynamics(j.q, j.qd, j.qdd) * j.qd, axis=1)
    friction = " + friction" if robot.drive_train.has_friction else ""
    passive = len(robot.actuated) < robot.n and not robot.is_closed_chain
    return row(f"(d) power balance sum tau qd = dE/dt{friction}, {len(power)} samples",
               rel_err(power[:, None], needed[:, None], peak=True), TOL_POWER,
               f"relative to peak power {np.max(np.abs(needed)):.3g} W"
               + ("; tree torques at every joint, passive ones included" if passive else ""))


def check_null_space(robot: Robot, traj: dict) -> Row:
    """Torques from the multiplier solve against ``G^T (M qdd + h)``, G = dq/dq_actuated, with
    M qdd + h from the energy route: the constraint forces do no work along G."""
    from ..motion.closure import partition

    act, pas = partition(robot)
    j = traj[0]
    tau, _ = robot.closed_chain_inverse_dynamics(j.q, j.qd, j.qdd)
    jac = robot.constraint_jacobian(j.q).reshape(len(j.q), robot.n_constraints, robot.n)
    G = np.zeros((len(j.q), robot.n, len(act)))
    G[:, act, np.arange(len(act))] = 1.0
    G[:, pas, :] = -np.linalg.solve(jac[:, :, pas], jac[:, :, act])
    tree = lagrange_from_energy(robot, j.q, j.qd, j.qdd)["tau"]
    worst = rel_err(tau, np.einsum("kia,ki->ka", G, tree), peak=True)
    return row("(b) closed chain: multipliers vs null space G^T (M qdd + h)", worst, TOL_ROUTE,
               "M qdd + h from the energy route, along the motion of (d)")


def check_constraints(robot: Robot, traj: dict, sim=None) -> list[Row]:
    """(e) Closed chains: the loop residual along the motion ``traj`` (and the free motion
    ``sim``'s drift), and the passive rates against differences of the solved positions."""
    j = traj[0]
    phi = float(np.max(np.abs(robot.constraint(j.q))))
    where = "along the motion of (d)"
    if sim is not None and sim.constraint_drift_m > phi:
        phi, where = sim.constraint_drift_m, "in the free motion of (c)"
    qd = sum(c * traj[k].q for k, c in D1.items()) / STEP
    qdd = sum(c * traj[k].q for k, c in D2.items()) / STEP ** 2
    rates = max(rel_err(j.qd, qd, peak=True), rel_err(j.qdd, qdd, peak=True))
    return [row("(e) loop residual max |Phi| (m)", phi, TOL_PHI_M, f"worst {where}"),
            row("(e) passive qd, qdd vs differences of q(t)", rates, TOL_RATES,
                "checks Phi_q and gamma against the Newton-solved positions")]


# -- (c) free motion ----------------------------------------------------------------------------
def free_motion(robot: Robot, seconds: float = 1.0):
    """Zero torque from the drawn pose at rest; pushed (actuated joints 1 rad/s) if that pose
    does not move by itself (an equilibrium, or no gravity). With friction, the run integrates
    the friction's work with the state (``simulate_controlled`` under controller "none"), so
    the energy balance holds to the integrator's tolerance, not a quadrature's."""
    t = np.linspace(0.0, seconds, 201)
    if robot.drive_train.has_friction:
        from ..control.laws import controller
        from ..dynamics.engine import simulate_controlled

        def run(qd0):
            return simulate_controlled(robot, controller("none"), (0.0, seconds),
                                       q0=robot.q_drawn, qd0=qd0, t_eval=t, rtol=1e-11,
                                       atol=1e-12)
    else:
        from ..dynamics.forward import simulate

        def run(qd0):
            return simulate(robot, robot.q_drawn, qd0, (0.0, seconds), t_eval=t)
    sim = run(np.zeros(robot.n))
    if not _moves(sim):
        # pushed at the actuated joints; a tree with none (a free pendulum hanging at rest) at
        # every joint: its 1e-30 J of kinetic energy once passed (c) with a drift of 0
        push = list(robot.actuated) or ([] if robot.is_closed_chain else list(range(robot.n)))
        qd0 = np.zeros(robot.n)
        qd0[push] = 1.0
        sim = run(qd0)
    return sim


def _moves(sim) -> bool:
    """Whether a free motion moves: kinetic energy above rounding against the energy's size."""
    return bool(np.max(sim.kinetic_j) > 1e-12 * max(np.max(np.abs(sim.energy_j)), 1e-300))


def check_energy(sim) -> Row:
    """(c) The free motion's relative energy drift (``Simulation.energy_drift``), or with
    friction its energy balance E(t) - E(0) + F(t) = 0 (``Simulation.balance_residual``, a
    controlled run's: it integrates the friction's work)."""
    peak = f"peak kinetic energy {np.max(sim.kinetic_j):.3g} J"
    if not _moves(sim):  # nothing moved: a drift of 0 proves nothing
        return Row(f"(c) energy drift, free motion {sim.t_s[-1]:g} s", None, TOL_ENERGY,
                   "skipped", f"the free motion does not move ({peak})")
    if sim.friction_j is not None and np.any(sim.friction_j != 0.0):
        return row(f"(c) energy balance with friction, free motion {sim.t_s[-1]:g} s",
                   sim.balance_residual, TOL_ENERGY,
                   f"relative; {peak}, friction work {sim.friction_j[-1]:.3g} J")
    return row(f"(c) energy drift, free motion {sim.t_s[-1]:g} s", sim.energy_drift, TOL_ENERGY,
               f"relative; {peak}")


# -- everything ---------------------------------------------------------------------------------
def run_all(robot: Robot, description: Path | None = None, *, samples: int = 20,
            seconds: float = 1.0, progress=None) -> list[Row]:
    """Every check that applies to ``robot``; a check that raises becomes a FAIL row."""
    if not isinstance(robot, Robot):
        raise PlanarSymError(f"validate needs a Robot (planar_sym.load), got "
                             f"{type(robot).__name__}")
    closed = robot.is_closed_chain
    # shared by several checks, computed once; 0.05 rad keeps closed chains inside the workspace
    traj = functools.cache(lambda: motion(robot, 41, 0.05 if closed else 0.3))
    sim = functools.cache(lambda: free_motion(robot, seconds))
    steps = [("(a) compiled vs SymPy", lambda: check_symbolic(robot, description, samples)),
             ("(b) Lagrange from the energy", lambda: check_energy_route(robot, samples))]
    if closed:
        steps.append(("(b) null-space torques", lambda: check_null_space(robot, traj())))
    steps += [("(c) free motion", lambda: check_energy(sim())),
              ("(d) power balance", lambda: check_power(robot, traj()))]
    if closed:  # the free motion's drift too, unless it failed (then (c) says so)
        steps.append(("(e) constraints", lambda: check_constraints(
            robot, traj(), sim() if sim.cache_info().currsize else None)))
    rows: list[Row] = []
    if progress is not None:
        progress.total = len(steps)
    for label, fn in steps:
        if progress is not None:
            progress.step(f"{robot.name}: {label}")
        try:
            result = fn()
        except (PlanarSymError, np.linalg.LinAlgError) as exc:
            result = Row(label, math.inf, None, "FAIL", f"raised {type(exc).__name__}: {exc}")
        rows += result if isinstance(result, list) else [result]
    return rows
