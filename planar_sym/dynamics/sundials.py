"""The same controlled run on SUNDIALS (CVODES: BDF; IDAS: the DAE with the accelerations, and
a closed chain's multipliers, as algebraic unknowns), through CasADi's ``integrator``.

The right-hand side is a CasADi graph over the robot's compiled functions (``casadi.external``
on the library already built: nothing is derived or compiled again), with the controller, the
saturation and the signals written as in ``_integrate.c``: the two routes share the
polynomials of ``signals`` and the gains, and must agree (tested). The externals carry no
derivatives, so CasADi differentiates them by finite differences for the Newton iterations;
that only affects convergence, not the answer. Events are found on the output grid (the time
by linear interpolation between the two samples around it); the C integrator locates them
within a step.
"""

from __future__ import annotations

import numpy as np

from ..errors import SimulationError
from ..model.robot import Robot
from ..motion.signals import Signal
from .laws import Controller
from .segments import friction, run_segments


def _externals(robot: Robot) -> dict:
    """The robot's compiled functions as CasADi Functions (the library already built); with no
    compiler, the saved functions themselves."""
    import casadi as ca

    lib = robot.library
    if not lib.compiled:
        return {q: f.function for q, f in lib.functions.items()}

    class Externals(dict):  # each made when first used: a big robot compiles it then
        def __missing__(self, quantity: str):
            symbol = lib.manifest["functions"][quantity]["symbol"]
            f = self[quantity] = ca.external(symbol, str(lib.exact_path(quantity)),
                                             {"enable_fd": True})
            return f

    return Externals()


def signal_mx(sig: Signal, t):
    """Values, first and second derivatives of ``sig`` at the symbolic time ``t``: the
    segment by ``casadi.low``, its coefficients by a one-hot product."""
    import casadi as ca

    nseg, ch, dp = sig.coefficients.shape
    k = ca.low(ca.DM(sig.knots_s), t)
    onehot = ca.DM(np.arange(nseg)) == k
    coef = ca.mtimes(ca.DM(sig.coefficients.reshape(nseg, ch * dp)).T, onehot)
    x = t - ca.dot(ca.DM(sig.knots_s[:-1]), onehot)
    out = []
    for der in range(3):
        rows = []
        for c in range(ch):
            acc = 0
            for j in range(dp - 1, der - 1, -1):
                fac = float(np.prod(np.arange(j - der + 1, j + 1))) if der else 1.0
                acc = acc * x + fac * coef[c * dp + j]
            rows.append(acc)
        out.append(ca.vertcat(*rows))
    return out


def closed_loop_rhs(robot: Robot, plant: Robot, ctl: Controller, ref: Signal | None,
                    u, bound: np.ndarray, friction) -> tuple:
    """Symbols (t, x) and the torques, accelerations and work rates of the closed loop."""
    import casadi as ca

    ext_nom = _externals(robot)  # the plant differs in its parameters only: same functions
    ext = ext_nom if plant.library is robot.library else _externals(plant)
    n, na, m = robot.n, len(robot.actuated), robot.n_constraints
    act = list(robot.actuated)
    pas = [i for i in range(n) if i not in act]
    p_nom, p = ca.DM(robot.p), ca.DM(plant.p)
    t, x = ca.MX.sym("t"), ca.MX.sym("x", 2 * n + 2)
    q, qd = x[:n], x[n:2 * n]
    tau = ca.MX.zeros(na)
    if isinstance(u, Signal):
        tau += signal_mx(u, t)[0]
    elif u is not None:
        tau += ca.DM(u)
    if ctl.kind == "lqr" and ctl.schedule is not None:  # as _integrate.c's mode 3, of time
        v = signal_mx(ctl.schedule, t)[0]
        x_ref, u_ref = v[:2 * n], v[2 * n:2 * n + na]
        k = ca.reshape(v[2 * n + na:], 2 * n, na).T  # row-major (na, 2n)
        tau += u_ref + ca.mtimes(k, x_ref - x[:2 * n])
    elif ctl.kind == "lqr":  # as _integrate.c's mode 3
        k = ca.DM(np.reshape(ctl.gain, (na, 2 * n)))
        tau += ca.DM(ctl.u_ref) + ca.mtimes(k, ca.DM(ctl.x_ref) - x[:2 * n])
    elif ctl.kind != "none":
        qr, qdr, qddr = signal_mx(ref, t)
        kp, kd = ca.DM(ctl.kp), ca.DM(ctl.kd)
        e, ed = qr - q[act], qdr - qd[act]
        if ctl.kind == "pd":
            tau += kp * e + kd * ed
            if m == 0:
                tau += ext_nom["gravity"](q, p_nom)[act]
            else:
                z = ca.DM.zeros(n)
                tau += ext_nom["closed_inverse_dynamics"](q, z, z, p_nom)[0]
        else:
            v = qddr + kd * ed + kp * e
            qdd = ca.MX.zeros(n)
            qdd[act] = v
            if m == 0:
                tau += ext_nom["inverse_dynamics"](q, qd, qdd, p_nom)[act]
            else:
                J = ext_nom["constraint_jacobian"](q, p_nom)
                gam = ext_nom["constraint_bias"](q, qd, p_nom)
                qdd[pas] = ca.solve(J[:, pas], gam - ca.mtimes(J[:, act], v))
                tau += ext_nom["closed_inverse_dynamics"](q, qd, qdd, p_nom)[0]
    tau_cmd = tau
    if ctl.saturate and np.isfinite(bound).any():
        tau = ca.fmin(ca.fmax(tau, ca.DM(-bound)), ca.DM(bound))
    tau_full = ca.MX.zeros(n)
    tau_full[act] = tau
    fv, fc, vs = (ca.DM(a) for a in friction)
    work = ca.dot(tau, qd[act])
    loss = ca.dot(fv * qd + fc * ca.tanh(qd / vs), qd)
    return t, x, tau_cmd, tau_full, work, loss, ext, p


def integrate(robot: Robot, plant: Robot, setup, ctl: Controller, ref, u, y0: np.ndarray,
              t_out: np.ndarray, method: str, rtol: float, atol: float):
    """States (len, 2n + 2) at ``t_out`` on CVODES or IDAS; as ``loop._dopri5`` returns."""
    import casadi as ca

    t, x, _, tau_full, work, loss, ext, p = closed_loop_rhs(
        robot, plant, ctl, ref, u, setup.bound, friction(plant))
    n, m = plant.n, plant.n_constraints
    q, qd = x[:n], x[n:2 * n]
    opts = {"abstol": atol, "reltol": rtol, "max_num_steps": 1_000_000}
    if method == "idas":  # the accelerations are outputs of the state, not its error
        opts["suppress_algebraic"] = True
    if method == "cvodes":
        if m == 0:
            qdd = ext["forward_dynamics"](q, qd, tau_full, p)
        else:
            M, h, J, gam = ext["constrained_terms"](q, qd, p)
            kkt = ca.blockcat([[M, -J.T], [J, ca.DM.zeros(m, m)]])
            qdd = ca.solve(kkt, ca.vertcat(tau_full - h, gam))[:n]
        dae = {"t": t, "x": x, "ode": ca.vertcat(qd, qdd, work, loss)}
    else:
        z = ca.MX.sym("z", n + m)
        if m == 0:
            M, h = ext["mass_matrix"](q, p), ext["bias"](q, qd, p)
            alg = ca.mtimes(M, z) + h - tau_full
        else:
            M, h, J, gam = ext["constrained_terms"](q, qd, p)
            alg = ca.vertcat(ca.mtimes(M, z[:n]) - ca.mtimes(J.T, z[n:]) + h - tau_full,
                             ca.mtimes(J, z[:n]) - gam)
        dae = {"t": t, "x": x, "z": z, "ode": ca.vertcat(qd, z[:n], work, loss), "alg": alg}
    count = [0]
    if method == "idas":  # consistent accelerations to start from: alg is linear in z
        lin = ca.Function("alg", [t, x, z], [alg, ca.jacobian(alg, z)])

    def segment(tt: np.ndarray, y: np.ndarray):
        try:
            F = ca.integrator("closed_loop", method, dae, float(tt[0]), tt[1:], opts)
            if method == "idas":
                r0, j0 = lin(float(tt[0]), y, np.zeros(n + m))
                z0 = -np.linalg.solve(np.array(j0), np.array(r0).ravel())
                res = F(x0=y, z0=z0)
            else:
                res = F(x0=y)
        except RuntimeError as exc:
            raise SimulationError(f"{robot.name}: {method} failed between t = {tt[0]:.6g} and "
                                  f"{tt[-1]:.6g} s: {str(exc).splitlines()[-1]}") from None
        count[0] += int(F.stats().get("nfevals", 0) or 0)
        ys = np.vstack([y, np.array(res["xf"]).T])
        return ys, len(tt), None

    return run_segments(plant, setup, y0, t_out, segment, count)

