"""What a route hands to code generation: every generated quantity as CasADi SX, and the
functions built from them.

Two routes fill a ``Quantities``: the expanded SymPy closed forms (``closed_route.py``, the
teaching output, within ``size.closed_forms_fit``) and algorithmic differentiation of the
recursive kinematics (``ad_dynamics.py``, any size). Both use the same input symbols, so the
functions built from either have the same signature; ``choose`` keeps, per function, the one
with fewer operations.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import casadi as ca

from planar_sym.model.description import Description

from . import block_triangular
from .articulated import Articulated
from .factor import solve_spd
from .recursion import Symbols, walk
from .tracking import tracking

CLOSED, AD = "closed form", "algorithmic differentiation"


@dataclass(frozen=True)
class Quantities:
    route: str
    desc: Description
    sym: Symbols
    mass_matrix: ca.SX
    bias: ca.SX  # h = C qd + g + D
    gravity: ca.SX
    inverse_dynamics: ca.SX  # M qdd + h, in sym.qdd
    kinetic: ca.SX
    potential: ca.SX
    frames: ca.SX  # (bodies, 3): origin x, y (m), angle (rad)
    accelerations: ca.SX  # (3, bodies): cg acceleration x, y (m/s^2), angular (rad/s^2)
    cg: ca.SX  # (2, bodies)
    joint_points: ca.SX  # (2, points)
    task: ca.SX  # (rows, 1); 0 rows without [task]
    task_jacobian: ca.SX
    task_jdot_qd: ca.SX
    phi: ca.SX  # (2 * cuts, 1)
    phi_q: ca.SX
    gamma: ca.SX  # -(Phi_q qd)_q qd


@dataclass(frozen=True)
class Generated:
    """One CasADi function and what the manifest says about it."""

    quantity: str
    function: ca.Function
    doc: str
    route: str = AD

    @property
    def operations(self) -> int:
        """Arithmetic and trigonometric operations per sample (inputs, outputs and constants
        not counted): what the choice of route compares."""
        f = self.function
        skip = (ca.OP_INPUT, ca.OP_OUTPUT, ca.OP_CONST, ca.OP_PARAMETER)
        return sum(1 for k in range(f.n_instructions()) if f.instruction_id(k) not in skip)


def functions(qs: Quantities) -> list[Generated]:
    """The CasADi functions generated for one robot, from one route's quantities."""
    s, name = qs.sym, qs.desc.name
    q, qd, qdd, p = s.q, s.qd, s.qdd, s.p
    M, h = qs.mass_matrix, qs.bias

    def fn(quantity, ins, outs, doc):
        # densify: CasADi drops structural zeros (e.g. dqdd/dq of a gravity-free arm), but the
        # runtime and the C batch layout read every output as a dense column-major block
        f = ca.Function(f"{name}_{quantity}", [v for _, v in ins],
                        [ca.densify(v) for _, v in outs], [k for k, _ in ins],
                        [k for k, _ in outs], {"cse": True})
        return Generated(quantity, f, doc, qs.route)

    out = [
        fn("mass_matrix", [("q", q), ("p", p)], [("M", M)], "mass matrix M(q)"),
        fn("bias", [("q", q), ("qd", qd), ("p", p)], [("h", h)],
           "h(q, qd) = C(q, qd) qd + g(q): velocity and gravity terms"),
        fn("gravity", [("q", q), ("p", p)], [("g", qs.gravity)], "gravity terms g(q) = dV/dq"),
        fn("inverse_dynamics", [("q", q), ("qd", qd), ("qdd", qdd), ("p", p)],
           [("tau", qs.inverse_dynamics)], "tree inverse dynamics tau = M qdd + h"),
        fn("energy", [("q", q), ("qd", qd), ("p", p)],
           [("kinetic", qs.kinetic), ("potential", qs.potential)],
           "kinetic and potential energy (J)"),
        fn("frames", [("q", q), ("p", p)], [("frames", qs.frames)],
           "every body's frame: origin x, origin y (m), angle (rad); one row per body"),
        # component rows, one column per body or point: each component of all bodies is
        # contiguous per sample, which is how the runtime's Newton-Euler reads them
        fn("body_motion", [("q", q), ("qd", qd), ("qdd", qdd), ("p", p)],
           [("accelerations", qs.accelerations), ("cg", qs.cg),
            ("joint_points", qs.joint_points)],
           "what Newton-Euler needs, exact, one column per body (as frames' rows): cg "
           "acceleration x, y (m/s^2) and angular acceleration (rad/s^2) rows; cg x, y (m) rows; "
           "joint_points x, y rows, one column per joint's child point (m; the manifest's "
           "joints: tree joints, then cuts), then per cut's parent point, then per prismatic "
           "joint's slide axis in world axes"),
    ]
    if qs.task.shape[0]:  # a robot without [task] has no tool point to report
        out.insert(5, fn("task", [("q", q), ("qd", qd), ("p", p)],
                         [("x", qs.task), ("J", qs.task_jacobian), ("jdot_qd", qs.task_jdot_qd)],
                         "task coordinates x(q) (m, rad), Jacobian J = dx/dq and Jdot qd"))
    if qs.task.shape[0]:  # Newton's inverse kinematics: one call, every sine computed once
        out.append(fn("ik_terms", [("q", q), ("p", p)],
                      [("F", ca.vertcat(qs.phi, qs.task)),
                       ("dF_dq", ca.vertcat(qs.phi_q, qs.task_jacobian))],
                      "inverse kinematics' Newton terms in one call: F = [Phi; x] (m; m, rad) "
                      "and its Jacobian dF/dq = [Phi_q; J]"))
    if qs.phi.shape[0] == 0:
        out += _forward(fn, qs)
    else:
        out += [
            fn("constraint", [("q", q), ("p", p)], [("phi", qs.phi)],
               "loop-closure residual Phi(q) (m)"),
            fn("constraint_jacobian", [("q", q), ("p", p)], [("phi_q", qs.phi_q)],
               "constraint Jacobian Phi_q = dPhi/dq"),
            fn("constraint_bias", [("q", q), ("qd", qd), ("p", p)], [("gamma", qs.gamma)],
               "acceleration term gamma = -(Phi_q qd)_q qd, so Phi_q qdd = gamma"),
            fn("constrained_terms", [("q", q), ("qd", qd), ("p", p)],
               [("M", M), ("h", h), ("phi_q", qs.phi_q), ("gamma", qs.gamma)],
               "M, h, Phi_q and gamma in one call: everything a KKT solve needs"),
            _closed_inverse_dynamics(fn, qs),
        ]
    return out


def _forward(fn, qs: Quantities) -> list[Generated]:
    """qdd = M^-1 (tau - h), and its Jacobian from the inverse dynamics' own:
    ``d qdd/dx = -M^-1 d(ID)/dx`` at ``qdd`` (x = q, qd), one factorisation for all 2n
    columns instead of differentiating through the solve (O(n^3), not O(n^4)).

    ``M^-1 (tau - h)`` two ways, the one with fewer operations kept: ``L D L^T`` of ``M``
    (small robots: a 2 x 2 solve is a handful of products) and the articulated-body recursion
    (``articulated.py``: O(n), ahead from four links of a chain). The Jacobian keeps
    ``L D L^T``: the recursion saves 28% of its operations at 20 links, but gcc took 1.8x the
    time and 1.46x the memory on it (479 against 329 MiB at ``-O1``, measured with the
    energies' ``h``), and it is called once per implicit step, not per sample."""
    s = qs.sym
    q, qd, tau, p = s.q, s.qd, s.tau, s.p
    n = q.shape[0]
    articulated = Articulated(qs.desc, walk(qs.desc, s))
    candidates = []
    for qdd, how in ((solve_spd(qs.mass_matrix, tau - qs.bias), ""),
                     (articulated.solve(tau - qs.bias), ", M^-1 by articulated bodies")):
        g = fn("forward_dynamics", [("q", q), ("qd", qd), ("tau", tau), ("p", p)],
               [("qdd", qdd)], "forward dynamics qdd = M^-1 (tau - h)")
        candidates.append(replace(g, route=g.route + how))
    forward = min(candidates, key=_operations)  # L D L^T on a tie
    partial = ca.horzcat(ca.jacobian(qs.inverse_dynamics, q),
                         ca.jacobian(qs.inverse_dynamics, qd))
    partial = ca.substitute(partial, s.qdd, solve_spd(qs.mass_matrix, tau - qs.bias))
    both = -solve_spd(qs.mass_matrix, partial)
    return [forward,
            fn("forward_dynamics_jacobian", [("q", q), ("qd", qd), ("tau", tau), ("p", p)],
               [("dqdd_dq", both[:, :n]), ("dqdd_dqd", both[:, n:])],
               "Jacobian of the forward dynamics, for implicit integrators"),
            *tracking(fn, qs.desc, s, qs.gravity, qs.inverse_dynamics, forward.function)]


def _closed_inverse_dynamics(fn, qs: Quantities) -> Generated:
    """Torques, cut-joint forces, the singularity measure and the loop residuals, fused.

    ``[S^T Phi_q^T][tau; lambda] = b`` splits into ``Phi_p^T lambda = b_p`` (passive rows)
    and ``tau = b_a - Phi_a^T lambda``; the whole matrix is singular exactly when ``Phi_p`` is,
    so its 1-norm condition number ``||Phi_p^T||_1 ||Phi_p^-T||_1`` is the measure. The
    residuals ``Phi``, ``Phi_q qd`` and ``Phi_q qdd - gamma`` let the runtime refuse a state
    that is off the loops, at the cost of a few products: one function shares every sine and
    cosine between the dynamics and the constraints.
    """
    s, desc = qs.sym, qs.desc
    act = list(desc.actuated)
    pas = [i for i in range(s.q.shape[0]) if i not in act]
    b, jac = qs.inverse_dynamics, qs.phi_q
    pt = jac[:, pas].T
    inv = block_triangular.inverse(pt)  # explicit: the condition number needs it anyway
    lam = ca.mtimes(inv, b[pas])
    tau = b[act] - ca.mtimes(jac[:, act].T, lam)

    def norm1(a):
        return ca.mmax(ca.sum1(ca.fabs(a)))

    return fn("closed_inverse_dynamics", [("q", s.q), ("qd", s.qd), ("qdd", s.qdd), ("p", s.p)],
              [("tau", tau), ("lambda", lam), ("cond", norm1(pt) * norm1(inv)),
               ("phi", qs.phi), ("phi_v", ca.mtimes(jac, s.qd)),
               ("phi_a", ca.mtimes(jac, s.qdd) - qs.gamma)],
              "closed-chain torques tau (actuated), cut-joint forces lambda and the 1-norm "
              "condition number of Phi_p, from M qdd + h = S^T tau + Phi_q^T lambda; and the "
              "loop residuals Phi (m), Phi_q qd (m/s), Phi_q qdd - gamma (m/s^2)")


def _operations(g: Generated) -> int:
    return g.operations


def choose(*routes: list[Generated]) -> list[Generated]:
    """Per function, the route with the fewest operations (the first route on a tie)."""
    return [min(candidates, key=lambda g: g.operations) for candidates in zip(*routes)]
