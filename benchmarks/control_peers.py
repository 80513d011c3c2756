"""Section 5's peers: SciPy and MuJoCo running the control loop with the controller in Python.

``RefEval`` and ``PyController`` evaluate the reference and the compiled loop's control law in
Python (around planar_sym's compiled single-sample functions); ``scipy_run`` is baseline (a),
SciPy DOP853 on that right-hand side; ``MujocoPlant`` and ``mujoco_run`` are baseline (b),
MuJoCo RK4 with the controller in a Python loop or as ``mjcb_control``. Apart from
``control.py`` (the timing rounds and the report section) because they are the methods compared
with, not the measurement; the problems and settings are in ``control_problem.py``.
"""

from __future__ import annotations

import bisect
import math

import numpy as np

from planar_sym.model.library import SingleCall

from .control_problem import ATOL, GATE_MODEL, MJ_SOLIMP, OUT_DT, RTOL, Problem
from .inverse import rel_err
from .report import Check

# -- the controller in Python (for SciPy and MuJoCo) ---------------------------------------------

class RefEval:
    """A Signal's value, rate and acceleration at one time: the segment by bisection, then one
    small matrix product with the powers of (t - T_k) (the same polynomials the C loop reads)."""

    def __init__(self, sig):
        c = sig.coefficients  # (segments, channels, degree + 1), ascending powers
        j = np.arange(sig.degree + 1)
        d1, d2 = np.zeros_like(c), np.zeros_like(c)
        d1[..., :-1] = c[..., 1:] * j[1:]
        d2[..., :-2] = c[..., 2:] * (j[2:] * (j[2:] - 1))
        self.table = np.ascontiguousarray(np.concatenate([c, d1, d2], axis=1))
        self.knots = sig.knots_s.tolist()
        self.last = len(self.knots) - 2
        self.ch = sig.channels
        self.powers = j.astype(float)

    def __call__(self, t: float):
        k = min(max(bisect.bisect_right(self.knots, t) - 1, 0), self.last)
        out = self.table[k] @ ((t - self.knots[k]) ** self.powers)
        ch = self.ch
        return out[:ch], out[ch:2 * ch], out[2 * ch:]


class PyController:
    """The compiled loop's control law in Python: the actuated torques at (t, q, qd).

    Trees: PD tau = Kp e + Kd e' + g(q)_a; CT tau = ID(q, qd, qdd_r + Kd e' + Kp e)_a. Closed
    chains: PD adds the closed-chain inverse dynamics at rest; CT completes the passive
    accelerations from Phi_p qdd_p = gamma - Phi_a v (Phi_q and gamma may be passed in when
    the caller has them already), then the closed-chain inverse dynamics."""

    def __init__(self, robot, ctl, ref):
        lib = robot.library.functions
        self.n, self.m = robot.n, robot.n_constraints
        self.act = list(robot.actuated)
        self.pas = [i for i in range(self.n) if i not in self.act]
        self.kp, self.kd = np.array(ctl.kp), np.array(ctl.kd)
        self.is_pd = ctl.kind == "pd"
        self.ref = RefEval(ref)
        self.qdd = np.zeros(self.n)
        self.zero = np.zeros(self.n)
        if self.m:
            self.cid = SingleCall(lib["closed_inverse_dynamics"], robot.p)
            self.jac = SingleCall(lib["constraint_jacobian"], robot.p)
            self.bias = SingleCall(lib["constraint_bias"], robot.p)
        else:
            self.grav = SingleCall(lib["gravity"], robot.p)
            self.inv = SingleCall(lib["inverse_dynamics"], robot.p)

    def __call__(self, t, q, qd, jac=None, gamma=None) -> np.ndarray:
        act = self.act
        qr, qdr, qddr = self.ref(t)
        qa, qda = q[act], qd[act]
        if self.is_pd:
            fb = self.kp * (qr - qa) + self.kd * (qdr - qda)
            if self.m:
                return fb + self.cid(q, self.zero, self.zero)[0]
            return fb + self.grav(q)[0][act]
        v = qddr + self.kd * (qdr - qda) + self.kp * (qr - qa)
        qdd = self.qdd
        qdd[act] = v
        if not self.m:
            return self.inv(q, qd, qdd)[0][act]
        if jac is None:  # CasADi's column-major (m x n)
            jac = self.jac(q)[0].reshape(self.n, self.m).T
            gamma = self.bias(q, qd)[0]
        qdd[self.pas] = np.linalg.solve(jac[:, self.pas], gamma - jac[:, act] @ v)
        return self.cid(q, qd, qdd)[0].copy()


# -- (a) SciPy -----------------------------------------------------------------------------------

def _segment_s() -> float:
    """How often the compiled loop re-projects a closed chain (s)."""
    from planar_sym.dynamics.segments import SEGMENT_S

    return SEGMENT_S


def scipy_run(p: Problem, ctl, rtol: float = RTOL, atol: float = ATOL):
    """SciPy DOP853 with the controller in Python: (states (N, 2n + 2), RHS calls, max |Phi|)."""
    from scipy.integrate import solve_ivp

    from planar_sym.dynamics.forward_closed import project

    robot = p.robot
    n, m, act = robot.n, robot.n_constraints, list(robot.actuated)
    lib = robot.library.functions
    law = PyController(robot, ctl, p.ref)
    count = [0]
    y0 = np.concatenate([p.q0, p.qd0, [0.0, 0.0]])  # + actuator work, friction loss (none)

    def solve(t0, t1, y, t_eval):
        sol = solve_ivp(rhs, (t0, t1), y, method="DOP853", t_eval=t_eval, rtol=rtol, atol=atol)
        if not sol.success:
            raise RuntimeError(f"{p.label}: SciPy baseline failed: {sol.message}")
        return sol.y.T

    if not m:
        fd = SingleCall(lib["forward_dynamics"], robot.p)
        full = np.zeros(n)

        def rhs(t, y):
            count[0] += 1
            q, qd = y[:n], y[n:2 * n]
            tau = law(t, q, qd)
            full[act] = tau
            (qdd,) = fd(q, qd, full)
            return np.concatenate([qd, qdd, (tau @ qd[act], 0.0)])

        return solve(p.t[0], p.t[-1], y0, p.t), count[0], 0.0

    terms = SingleCall(lib["constrained_terms"], robot.p)
    kkt, b = np.zeros((n + m, n + m)), np.zeros(n + m)

    def rhs(t, y):
        count[0] += 1
        q, qd = y[:n], y[n:2 * n]
        mass, h, jac, gamma = terms(q, qd)
        jac = jac.reshape(n, m).T
        tau = law(t, q, qd, jac, gamma)  # plant = model here: its Phi_q and gamma serve both
        kkt[:n, :n] = mass.reshape(n, n)
        kkt[:n, n:] = -jac.T
        kkt[n:, :n] = jac
        b[:n] = -h
        b[act] += tau
        b[n:] = gamma
        qdd = np.linalg.solve(kkt, b)[:n]
        return np.concatenate([qd, qdd, (tau @ qd[act], 0.0)])

    t, rows, drift, k, y = p.t, [y0], 0.0, 0, y0
    segment_s = _segment_s()
    while k < len(t) - 1:  # as the compiled loop: segments, projected at each end
        end = min(max(int(np.searchsorted(t, t[k] + segment_s, side="right")) - 1, k + 1),
                  len(t) - 1)
        ys = solve(t[k], t[end], y, t[k:end + 1])
        rows += list(ys[1:])
        drift = max(drift, float(np.max(np.abs(robot.constraint(ys[1:, :n])))))
        qp, qdp = project(robot, ys[-1, :n], ys[-1, n:2 * n])
        y = np.concatenate([qp, qdp, ys[-1, 2 * n:]])
        k = end
    return np.array(rows), count[0], drift


# -- (b) MuJoCo ----------------------------------------------------------------------------------

class MujocoPlant:
    def __init__(self, p: Problem):
        from planar_sym.model import description

        from .baselines import mujoco_model

        closed = p.robot.is_closed_chain
        self.model, self.data = mujoco_model.build(
            description.load(p.robot.name), loops=closed, solimp=MJ_SOLIMP if closed else None)
        n = p.robot.n
        self.mass = np.zeros((n, n))
        self.fill_mass = mujoco_model.mass_matrix_filler(self.model, self.data, self.mass)

    def check(self, p: Problem, q: np.ndarray, qd: np.ndarray) -> list[Check]:
        """MuJoCo's tree mass matrix and bias forces against planar_sym's at states (q, qd);
        a closed chain's connect residual at the start."""
        import mujoco

        mm, md, robot, n = self.model, self.data, p.robot, p.robot.n
        got = np.empty((len(q), n * n + n))
        for k in range(len(q)):
            md.qpos[:], md.qvel[:] = q[k], qd[k]
            mujoco.mj_forward(mm, md)
            self.fill_mass()
            got[k, :n * n], got[k, n * n:] = self.mass.ravel(), md.qfrc_bias
        want = np.hstack([robot.mass_matrix(q).reshape(len(q), n * n), robot.bias(q, qd)])
        out = [Check(f"{p.label}: MuJoCo mass matrix and qfrc_bias vs planar_sym's M and h "
                     f"({len(q)} states along the run)", rel_err(got, want), GATE_MODEL)]
        if mm.neq:
            md.qpos[:], md.qvel[:] = p.q0, p.qd0
            mujoco.mj_forward(mm, md)
            res = float(np.max(np.abs(md.efc_pos[:md.ne]))) if md.ne else math.inf
            out.append(Check(f"{p.label}: MuJoCo connect sites of the cut joint coincide at the "
                             "start (|residual| m, absolute)", res, GATE_MODEL))
        return out


def mujoco_run(plant: MujocoPlant, p: Problem, ctl, law: PyController, dt: float,
               callback: bool):
    """MuJoCo RK4 over the run in equal steps near ``dt``; q at the output times."""
    import mujoco

    mm, md = plant.model, plant.data
    robot = p.robot
    n, act = robot.n, list(robot.actuated)
    steps = max(1, round(p.t_end / dt))
    h = p.t_end / steps
    every = round(OUT_DT / h)
    assert abs(every * h - OUT_DT) < 1e-9 * OUT_DT, (dt, OUT_DT)
    mm.opt.timestep = h
    mm.opt.integrator = int(mujoco.mjtIntegrator.mjINT_RK4)
    if mm.neq:  # the stiffest loop MuJoCo's default safety allows: time constant 2 steps
        mm.eq_solref[:, 0] = 2.0 * h
        mm.eq_solref[:, 1] = 1.0
    mujoco.mj_resetData(mm, md)
    md.qpos[:], md.qvel[:] = p.q0, p.qd0
    out = np.empty((len(p.t), n))
    out[0] = p.q0
    qpos, qvel, frc = md.qpos, md.qvel, md.qfrc_applied
    full = np.zeros(n)
    if not robot.is_closed_chain and ctl.kind == "computed_torque":  # MuJoCo's own M, bias
        kp, kd, ref, mass, fill, bias = (np.array(ctl.kp), np.array(ctl.kd), law.ref,
                                         plant.mass, plant.fill_mass, md.qfrc_bias)

        def control(t):
            qr, qdr, qddr = ref(t)
            fill()
            frc[:] = mass @ (qddr + kd * (qdr - qvel) + kp * (qr - qpos)) + bias
    else:
        def control(t):
            full[act] = law(t, qpos, qvel)
            frc[:] = full
    step = mujoco.mj_step
    k = 1
    if callback:
        mujoco.set_mjcb_control(lambda m_, d_: control(d_.time))
        try:
            for i in range(1, steps + 1):
                step(mm, md)
                if i % every == 0:
                    out[k] = qpos
                    k += 1
        finally:
            mujoco.set_mjcb_control(None)
    elif ctl.kind == "computed_torque" and not robot.is_closed_chain:
        # M and bias need a forward pass at the step's start; then only the acceleration
        # stage again (the applied force changed) and the RK4 stages: mj_step minus its
        # repeated position and velocity stages
        fwd, skip, rk4 = mujoco.mj_forward, mujoco.mj_forwardSkip, mujoco.mj_RungeKutta
        vel = int(mujoco.mjtStage.mjSTAGE_VEL)
        for i in range(1, steps + 1):
            fwd(mm, md)
            control(md.time)
            skip(mm, md, vel, 0)
            rk4(mm, md, 4)
            if i % every == 0:
                out[k] = qpos
                k += 1
    else:
        for i in range(1, steps + 1):
            control(md.time)
            step(mm, md)
            if i % every == 0:
                out[k] = qpos
                k += 1
    assert k == len(p.t)
    return out, steps, h
