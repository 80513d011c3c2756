"""Every output of every generated function against the SymPy model it was generated from.

The SymPy expressions of ``derive.model.build(desc)`` are evaluated with ``sympy.lambdify``
(numpy) at random states; the compiled functions are called through the runtime (``Robot``
methods, and the raw batch function where the runtime has no method). Tolerance 1e-12 on
``rel_err`` (conftest: per-sample normwise relative error).

Besides the built-in robots, two test robots of tests/robots are derived into a tmp folder:
bent_arm (rotated weld, tilted gravity) and horizontal_2dof (no gravity, so some generated
outputs are structurally sparse). The 1-DOF pendulum has its own analytic tests.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from conftest import ALL_ROBOTS, TEST_ROBOTS, random_states, record, rel_err

from derive.model import build
from derive.tracking import TRACKING_MAX_N
from planar_sym.model import description
from planar_sym.model.locate import load

TOL = 1e-12
N_SAMPLES = 20
EXTRA = ("bent_arm", "horizontal_2dof")
CASES = ALL_ROBOTS + EXTRA



class SympyReference:
    """The model's expressions as numpy functions of (q, qd, qdd, tau, p), one sample at a time."""

    def __init__(self, robot):
        self.desc = description.load(robot)
        self.model = build(self.desc)
        s = self.model.sym
        self.args = [*s.q, *s.qd, *s.qdd, *s.tau, *s.p]
        self.n = len(s.q)
        lag, con = self.model.lagrangian, self.model.constraints
        M, h = lag.mass_matrix, lag.bias
        qdd = sp.Matrix(s.qdd)
        self.exprs = {
            "M": M, "h": h, "g": lag.gravity, "tau": M * qdd + h,
            "kinetic": sp.Matrix([lag.kinetic]), "potential": sp.Matrix([lag.potential]),
            "x": self.model.task, "J": self.model.task_jacobian,
            "jdot_qd": self.model.task_jdot_qd, "frames": self.model.frames,
        }
        if con.count:
            self.exprs.update(phi=con.phi, phi_q=con.jacobian, gamma=con.accel_bias)
        else:
            # qdd = M^-1 (tau - h); d qdd/dq_k = M^-1 (-dM/dq_k qdd - dh/dq_k),
            # d qdd/dqd = -M^-1 dh/dqd: the derivatives of M and h taken symbolically
            self.exprs.update(
                dM=sp.Matrix.hstack(*[M.diff(qk) for qk in s.q]),
                dh_dq=h.jacobian(s.q), dh_dqd=h.jacobian(s.qd))
        self.fns = {k: sp.lambdify(self.args, e, modules="numpy") for k, e in self.exprs.items()}

    def __call__(self, key: str, p, q, qd=None, qdd=None, tau=None) -> np.ndarray:
        z = np.zeros_like(q)
        qd, qdd, tau = (z if a is None else a for a in (qd, qdd, tau))
        out = []
        for k in range(q.shape[0]):
            v = np.array(self.fns[key](*q[k], *qd[k], *qdd[k], *tau[k], *p), dtype=float)
            out.append(v)
        return np.array(out)

    def forward(self, p, q, qd, tau):
        """qdd and its Jacobians from the SymPy M, h and their derivatives."""
        n = self.n
        qdd, dq, dqd = [], [], []
        for k in range(q.shape[0]):
            a = (*q[k], *qd[k], *np.zeros(n), *tau[k], *p)
            M = np.array(self.fns["M"](*a), dtype=float)
            h = np.array(self.fns["h"](*a), dtype=float).ravel()
            acc = np.linalg.solve(M, tau[k] - h)
            dM = np.array(self.fns["dM"](*a), dtype=float)
            dh_dq = np.array(self.fns["dh_dq"](*a), dtype=float)
            dh_dqd = np.array(self.fns["dh_dqd"](*a), dtype=float)
            rhs = -np.column_stack([dM[:, i * n:(i + 1) * n] @ acc for i in range(n)]) - dh_dq
            qdd.append(acc)
            dq.append(np.linalg.solve(M, rhs))
            dqd.append(-np.linalg.solve(M, dh_dqd))
        return np.array(qdd), np.array(dq), np.array(dqd)


@pytest.fixture(scope="module")
def references():
    return {}


@pytest.fixture(scope="module", params=CASES)
def case(request, references, derived):
    name = request.param
    path = TEST_ROBOTS / f"{name}.toml" if name in EXTRA else name
    if name not in references:
        references[name] = SympyReference(path)
    ref = references[name]
    robot = derived(path)[1] if name in EXTRA else load(name)
    rng = np.random.default_rng(100 + CASES.index(name))
    q, qd, qdd = random_states(rng, N_SAMPLES, robot.n)
    tau = rng.uniform(-0.5, 0.5, (N_SAMPLES, robot.n))
    return name, ref, robot, q, qd, qdd, tau


def _check(worst, key, actual, reference):
    err = record(worst, key, rel_err(actual, reference))
    assert err < TOL, f"{key}: worst relative error {err:.3e} >= {TOL:g}"


def test_parameter_vector_is_the_description_order(case):
    """The runtime's p and the SymPy symbol order agree (else every comparison is moot)."""
    _, ref, robot, *_ = case
    assert [str(s) for s in ref.model.sym.p] == [par.name for par in robot.parameter_list]
    assert list(robot.p) == ref.desc.parameter_values()


def test_dynamics_outputs(case, worst_errors):
    name, ref, robot, q, qd, qdd, _ = case
    p = robot.p
    _check(worst_errors, f"sympy M {name}", robot.mass_matrix(q), ref("M", p, q))
    _check(worst_errors, f"sympy h {name}", robot.bias(q, qd), ref("h", p, q, qd)[..., 0])
    _check(worst_errors, f"sympy g {name}", robot.gravity(q), ref("g", p, q)[..., 0])
    _check(worst_errors, f"sympy tau {name}", robot.tree_inverse_dynamics(q, qd, qdd),
           ref("tau", p, q, qd, qdd)[..., 0])


def test_energy(case, worst_errors):
    name, ref, robot, q, qd, *_ = case
    T, V = robot.energy(q, qd)
    _check(worst_errors, f"sympy kinetic {name}", T, ref("kinetic", robot.p, q, qd)[:, 0, 0])
    _check(worst_errors, f"sympy potential {name}", V, ref("potential", robot.p, q)[:, 0, 0])


def test_task_and_frames(case, worst_errors):
    name, ref, robot, q, qd, *_ = case
    p = robot.p
    x, J, jdq = robot.task(q, qd)
    _check(worst_errors, f"sympy task x {name}", x, ref("x", p, q)[..., 0])
    _check(worst_errors, f"sympy task J {name}", J, ref("J", p, q))
    _check(worst_errors, f"sympy task Jdot qd {name}", jdq, ref("jdot_qd", p, q, qd)[..., 0])
    _check(worst_errors, f"sympy frames {name}", robot.frames(q), ref("frames", p, q))


def test_newton_terms(case, worst_errors):
    """ik_terms: F = [Phi; x] and dF/dq = [Phi_q; J] in one call, against SymPy's."""
    name, ref, robot, q, *_ = case
    p = robot.p
    raw = robot.library.functions["ik_terms"](len(q), {"q": q, "p": p})
    x, J = ref("x", p, q)[..., 0], ref("J", p, q)
    if robot.is_closed_chain:
        x = np.concatenate([ref("phi", p, q)[..., 0], x], axis=1)
        J = np.concatenate([ref("phi_q", p, q), J], axis=1)
    _check(worst_errors, f"sympy ik_terms F {name}", raw["F"], x)
    _check(worst_errors, f"sympy ik_terms dF/dq {name}", raw["dF_dq"], J)


def test_closed_chain_outputs(case, worst_errors):
    name, ref, robot, q, qd, *_ = case
    if not robot.is_closed_chain:
        pytest.skip("tree robot: no constraint functions")
    p = robot.p
    _check(worst_errors, f"sympy phi {name}", robot.constraint(q), ref("phi", p, q)[..., 0])
    _check(worst_errors, f"sympy phi_q {name}", robot.constraint_jacobian(q), ref("phi_q", p, q))
    _check(worst_errors, f"sympy gamma {name}", robot.constraint_bias(q, qd),
           ref("gamma", p, q, qd)[..., 0])
    if "constrained_terms" in robot.library.functions:  # M, h, Phi_q, gamma in one call
        raw = robot.library.functions["constrained_terms"](len(q), {"q": q, "qd": qd, "p": p})
        assert set(raw) == {"M", "h", "phi_q", "gamma"}
        _check(worst_errors, f"sympy KKT M {name}", raw["M"], ref("M", p, q))
        _check(worst_errors, f"sympy KKT h {name}", raw["h"], ref("h", p, q, qd)[..., 0])
        _check(worst_errors, f"sympy KKT phi_q {name}", raw["phi_q"], ref("phi_q", p, q))
        _check(worst_errors, f"sympy KKT gamma {name}", raw["gamma"],
               ref("gamma", p, q, qd)[..., 0])
    # fused torques, cut-joint forces and condition number, against a numpy solve of the
    # SymPy M qdd + h and Phi_q: [S^T Phi_q^T][tau; lambda] = M qdd + h
    qdd = np.random.default_rng(5).uniform(-3, 3, q.shape)
    raw = robot.library.functions["closed_inverse_dynamics"](
        len(q), {"q": q, "qd": qd, "qdd": qdd, "p": p})
    M, h, jac = ref("M", p, q), ref("h", p, q, qd)[..., 0], ref("phi_q", p, q)
    act = list(robot.actuated)
    pas = [i for i in range(robot.n) if i not in act]
    a = np.zeros((len(q), robot.n, robot.n))
    a[:, act, np.arange(len(act))] = 1.0
    a[:, :, len(act):] = jac.transpose(0, 2, 1)
    sol = np.linalg.solve(a, ((M @ qdd[..., None])[..., 0] + h)[..., None])[..., 0]
    _check(worst_errors, f"sympy closed tau {name}", raw["tau"], sol[:, :len(act)])
    _check(worst_errors, f"sympy closed lambda {name}", raw["lambda"], sol[:, len(act):])
    cond = np.linalg.cond(jac[:, :, pas].transpose(0, 2, 1), 1)
    _check(worst_errors, f"sympy closed cond {name}", raw["cond"], cond)


def test_tree_forward_dynamics(case, worst_errors):
    name, ref, robot, q, qd, _, tau = case
    if robot.is_closed_chain:
        pytest.skip("closed chain: no forward_dynamics function")
    qdd_ref, dq_ref, dqd_ref = ref.forward(robot.p, q, qd, tau)
    _check(worst_errors, f"sympy forward {name}", robot.forward_dynamics(q, qd, tau), qdd_ref)
    # horizontal_2dof has structurally zero Jacobian columns: caught a sparse-output bug once
    raw = robot.library.functions["forward_dynamics_jacobian"](
        len(q), {"q": q, "qd": qd, "tau": tau, "p": robot.p})
    _check(worst_errors, f"sympy dqdd/dq {name}", raw["dqdd_dq"], dq_ref)
    _check(worst_errors, f"sympy dqdd/dqd {name}", raw["dqdd_dqd"], dqd_ref)


def test_tracking_functions(case, worst_errors):
    """The fused controller and plant (derive/tracking.py) against the SymPy model: tau_cmd
    from the SymPy g or M qdd + h at the nominal parameters (the robot's, scaled: a model
    error), clipped where the limits bind (lo, hi drawn so about half the torques clip), then
    the SymPy forward dynamics at the plant's own parameters."""
    name, ref, robot, q, qd, _, _ = case
    if "tracking_pd" not in robot.library.manifest["functions"]:
        pytest.skip("no fused tracking function (a closed chain, or past TRACKING_MAX_N)")
    act, n_s = list(robot.actuated), len(q)
    rng = np.random.default_rng(11)
    p, p_nom = robot.p, robot.p * rng.uniform(0.8, 1.2, robot.p.shape)
    qr, qdr, qddr, tau_in = (rng.uniform(-1, 1, (n_s, len(act))) for _ in range(4))
    kp, kd = rng.uniform(1, 50, (n_s, len(act))), rng.uniform(0.1, 5, (n_s, len(act)))
    lo, hi = -rng.uniform(0, 2, (n_s, len(act))), rng.uniform(0, 2, (n_s, len(act)))
    e = kp * (qr - q[:, act]) + kd * (qdr - qd[:, act])
    v = np.zeros_like(q)
    v[:, act] = qddr + kd * (qdr - qd[:, act]) + kp * (qr - q[:, act])
    laws = {"tracking_pd": (tau_in + e + ref("g", p_nom, q)[..., 0][:, act], {}),
            "tracking_ct": (tau_in + ref("tau", p_nom, q, qd, v)[..., 0][:, act],
                            {"qdd_ref": qddr})}
    clipped = 0
    for fn, (tau_cmd, extra) in laws.items():
        args = {"q": q, "qd": qd, "q_ref": qr, "qd_ref": qdr, **extra, "kp": kp, "kd": kd,
                "tau_in": tau_in, "lo": lo, "hi": hi, "p": p, "p_nom": np.tile(p_nom, (n_s, 1))}
        raw = robot.library.functions[fn](n_s, args)
        tau_app = np.clip(tau_cmd, lo, hi)
        full = np.zeros_like(q)
        full[:, act] = tau_app
        _check(worst_errors, f"sympy {fn} tau_cmd {name}", raw["tau_cmd"], tau_cmd)
        _check(worst_errors, f"sympy {fn} tau_app {name}", raw["tau_app"], tau_app)
        _check(worst_errors, f"sympy {fn} qdd {name}", raw["qdd"], ref.forward(p, q, qd, full)[0])
        clipped += int(np.sum(tau_app != tau_cmd))
    assert clipped > n_s // 2  # the limits bind on many samples: the clip is exercised


def test_every_generated_function_is_covered(case):
    """A function added to the code generator must get a comparison here."""
    _, _, robot, *_ = case
    covered = {"mass_matrix", "bias", "gravity", "inverse_dynamics", "energy", "task", "frames",
               "body_motion"}  # body_motion: against SymPy in tests/test_reactions.py
    covered |= ({"constraint", "constraint_jacobian", "constraint_bias", "constrained_terms",
                 "closed_inverse_dynamics", "closed_regressor"}
                if robot.is_closed_chain else {"forward_dynamics", "forward_dynamics_jacobian"})
    if not robot.is_closed_chain and robot.actuated and robot.n <= TRACKING_MAX_N:
        covered |= {"tracking_pd", "tracking_ct"}  # test_tracking_functions
    covered |= {"regressor"}  # below, and in tests/test_identify.py
    covered |= {"ik_terms"} if robot.task_names else set()
    assert set(robot.library.manifest["functions"]) == covered


def test_parameters_are_live_inputs(case, worst_errors):
    """Changed parameters reach the compiled code the same way they reach SymPy."""
    name, ref, robot, q, qd, qdd, _ = case
    rng = np.random.default_rng(5)
    p2 = robot.p * rng.uniform(0.5, 1.5, robot.p.shape)
    changed = robot.with_parameters(**{par.name: v for par, v in zip(robot.parameter_list, p2)})
    np.testing.assert_array_equal(changed.p, p2)
    tau = changed.tree_inverse_dynamics(q, qd, qdd)
    _check(worst_errors, f"sympy tau (other p) {name}", tau, ref("tau", p2, q, qd, qdd)[..., 0])
    assert rel_err(robot.tree_inverse_dynamics(q, qd, qdd), tau) > 1e-3


def test_regressors_against_sympy(case, worst_errors):
    """Y (derived from the energies in the standard parameters) times the robot's standard
    parameters is SymPy's tau = M qdd + h (derived in the description's parameters); a closed
    chain's Y and Y_lambda, through the same projection, are the fused closed-chain function's
    torques and cut-joint forces at the same states."""
    from planar_sym.identify.standard import standard_parameters

    name, ref, robot, q, qd, qdd, _ = case
    pi = standard_parameters(robot).values
    args = {"q": q, "qd": qd, "qdd": qdd, "p": robot.p}
    y = robot.library.functions["regressor"](len(q), args)["Y"]
    _check(worst_errors, f"sympy regressor {name}", y @ pi, ref("tau", robot.p, q, qd, qdd)[..., 0])
    if robot.is_closed_chain:
        closed = robot.library.functions["closed_regressor"](len(q), args)
        fused = robot.library.functions["closed_inverse_dynamics"](len(q), args)
        _check(worst_errors, f"closed regressor tau {name}", closed["Y"] @ pi, fused["tau"])
        _check(worst_errors, f"closed regressor lambda {name}", closed["Y_lambda"] @ pi,
               fused["lambda"])
