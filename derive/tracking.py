"""A tracking controller and the plant in one function: the controlled loop's right-hand side.

At every right-hand side of a tracking run the C integrator (``_integrate.c``) needs the
controller's torques, from the controller's model (parameters ``p_nom``), and the plant's
accelerations under them (parameters ``p``). Called as two functions they compute every sine
and cosine of ``q`` twice (and make two calls); one CasADi function with common
subexpressions computes them once. The arithmetic is not shared (the two parameter vectors
are different symbols: 101 operations against 69 + 15 under PD on the 2-DOF arm), but the
trigonometry is most of the time: per call, PD + gravity 92-136 ns as two functions against
60-91 fused; computed torque 101-179 against 68-101 (a C harness).

Two laws, on the actuated coordinates ``act`` (na of them; a passive joint gets no torque):

* ``tracking_pd``: ``tau_cmd = tau_in + kp (q_ref - q_a) + kd (qd_ref - qd_a) + g(q; p_nom)_a``
* ``tracking_ct``: ``tau_cmd = tau_in + ID(q, qd, v; p_nom)_a`` with
  ``v_a = qdd_ref + kd (qd_ref - qd_a) + kp (q_ref - q_a)`` and ``v`` zero at passive joints;

then ``tau_app = min(max(tau_cmd, lo), hi)`` (the actuator limits, or +-inf without
saturation) and ``qdd = M^-1 (S tau_app - h)`` with the plant's parameters ``p``. Trees only
(a closed chain's controller solves its loops in C), and only up to ``TRACKING_MAX_N``
coordinates: past that, every big robot would compile one more function of its size (forward
plus inverse dynamics, ~880 operations at 8 links of a chain), where the sines are a smaller
share of the work. The rule reads the robot, not a route's operation count, so both routes
(closed forms and algorithmic differentiation) list the same functions for
``quantities.choose``.
"""

from __future__ import annotations

import casadi as ca

from planar_sym.model.description import Description

from .recursion import Symbols

#: coordinates past which no fused function is generated
TRACKING_MAX_N = 8


def tracking(fn, desc: Description, s: Symbols, gravity: ca.SX, inverse_dynamics: ca.SX,
             forward: ca.Function) -> list:
    """``tracking_pd`` and ``tracking_ct`` of a tree with an actuated joint and at most
    TRACKING_MAX_N coordinates (else none): ``gravity`` g(q) and ``inverse_dynamics``
    M qdd + h in the symbols ``s``, around the forward dynamics ``forward`` (q, qd, tau, p).
    ``fn`` builds each function and what the manifest says of it (``quantities.functions``)."""
    act = list(desc.actuated)
    n, na = s.q.shape[0], len(act)
    if not act or n > TRACKING_MAX_N:
        return []
    q, qd, p = s.q, s.qd, s.p
    p_nom = ca.SX.sym("p_nom", p.shape[0])
    q_ref, qd_ref, qdd_ref, kp, kd, tau_in, lo, hi = (
        ca.SX.sym(k, na) for k in ("q_ref", "qd_ref", "qdd_ref", "kp", "kd", "tau_in", "lo",
                                   "hi"))
    error = kp * (q_ref - q[act]) + kd * (qd_ref - qd[act])

    def closed_loop(tau_cmd):
        tau_app = ca.fmin(ca.fmax(tau_cmd, lo), hi)
        full = ca.SX.zeros(n)
        full[act] = tau_app
        return [("qdd", forward(q, qd, full, p)), ("tau_cmd", tau_cmd),
                ("tau_app", tau_app)]

    gravity = ca.substitute(gravity, p, p_nom)
    v = ca.SX.zeros(n)
    v[act] = qdd_ref + kd * (qd_ref - qd[act]) + kp * (q_ref - q[act])
    computed = ca.substitute(inverse_dynamics, ca.vertcat(s.qdd, p), ca.vertcat(v, p_nom))
    common = [("q", q), ("qd", qd), ("q_ref", q_ref), ("qd_ref", qd_ref)]
    limits = [("kp", kp), ("kd", kd), ("tau_in", tau_in), ("lo", lo), ("hi", hi), ("p", p),
              ("p_nom", p_nom)]
    return [
        fn("tracking_pd", common + limits, closed_loop(tau_in + error + gravity[act]),
           "PD + gravity compensation and the plant in one call: tau_cmd = tau_in + kp (q_ref "
           "- q) + kd (qd_ref - qd) + g(q; p_nom) on the actuated joints, tau_app = tau_cmd "
           "clipped to [lo, hi], qdd = forward dynamics (p) under tau_app"),
        fn("tracking_ct", common + [("qdd_ref", qdd_ref)] + limits,
           closed_loop(tau_in + computed[act]),
           "computed torque and the plant in one call: tau_cmd = tau_in + ID(q, qd, v; p_nom) "
           "on the actuated joints, v = qdd_ref + kd (qd_ref - qd) + kp (q_ref - q), tau_app "
           "= tau_cmd clipped to [lo, hi], qdd = forward dynamics (p) under tau_app"),
    ]
