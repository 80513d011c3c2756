"""Validation row (a): every compiled function against the SymPy model derived again from the
robot's description (needs SymPy; imported by ``analysis.validate`` only when the row runs)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..model.robot import Robot
from .validate_rows import TOL_SYMBOLIC, Row, random_states, rel_err, row, worst_key


# -- (a) SymPy ----------------------------------------------------------------------------------
def find_description(robot: Robot, given: Path | None = None) -> Path | None:
    """The description: the one given (which must exist), else the robot's own (a built-in's,
    or the copy ``planar-sym derive`` writes); never another robot's of the same name."""
    from ..errors import InputError

    if given is not None:
        if not Path(given).is_file():
            raise InputError(f"--description {given}: no such file")
        return Path(given)
    own = robot.description_file
    if own is not None:
        return own
    # a copied generated folder: the manifest names the repo file it was derived from (a
    # repo-relative path; a bare file name means a file outside the repo, not to be guessed)
    source = robot.library.manifest.get("input", "")
    path = Path(__file__).resolve().parents[2] / source
    return path if "/" in source and path.is_file() else None


def check_symbolic(robot: Robot, description: Path | None = None, samples: int = 20,
                   seed: int = 1) -> Row:
    """(a) Every output of every compiled function (and of the fast loops) against the SymPy
    model derived again from the description, at ``samples`` random states; skipped without
    SymPy or without a description file."""
    name = f"(a) compiled vs SymPy, {samples} random states"
    try:
        import sympy  # noqa: F401  (explicitly: derive may already be imported)
    except ImportError:
        return Row(name, None, TOL_SYMBOLIC, "skipped", "skipped: needs SymPy")
    if robot.library.manifest.get("equations") == "structure":
        return Row(name, None, TOL_SYMBOLIC, "skipped",
                   "skipped: past the closed-form size (the report shows why); the expanded "
                   "forms would take minutes, the other rows still check the compiled code")
    path = find_description(robot, description)
    if path is None:
        return Row(name, None, TOL_SYMBOLIC, "skipped",
                   "skipped: no description file found (pass --description)")
    from ..model import description as descriptions
    from ..model.deriving import symbolic_model

    model = symbolic_model(descriptions.load(path))
    if [str(s) for s in model.sym.p] != [p.name for p in robot.parameter_list]:
        return Row(name, math.inf, TOL_SYMBOLIC, "FAIL", f"{path}: parameter vector differs")
    states = dict(zip(("q", "qd", "qdd", "tau"), random_states(robot, samples, seed)))
    refs = _sympy_reference(model, robot.p, states)
    extra, tracked = (_tracking_reference(robot, refs, states, seed)
                      if "tracking_pd" in robot.library.functions else ({}, {}))

    def ref_for(quantity: str, out: str) -> np.ndarray:
        if quantity.startswith("tracking_"):  # the fused controller and plant
            return tracked[f"{quantity}.{out}"]
        # the fused closed-chain solve returns the actuated torques only
        if quantity in ("closed_inverse_dynamics", "closed_regressor") and out in ("tau", "Y"):
            return refs["closed.tau"]
        return refs[{"Y": "tau", "Y_lambda": "lambda"}.get(out, out)]

    pi = None
    if "regressor" in robot.library.functions:  # Y times the robot's standard parameters
        from ..identify.standard import standard_parameters

        pi = standard_parameters(robot).values

    def compared(out: str, value: np.ndarray) -> np.ndarray:
        return value @ pi if out in ("Y", "Y_lambda") else value

    errs = {f"{quantity}.{out}": rel_err(compared(out, value), ref_for(quantity, out))
            for quantity, fn in robot.library.functions.items()
            for out, value in fn(samples, {k: (robot.p if k == "p" else {**states, **extra}[k])
                                           for k, _ in fn.spec.inputs}).items()}
    if not robot.exact:  # the vectorised loops the robot's methods call, too
        q, qd, qdd, tau = (states[k] for k in ("q", "qd", "qdd", "tau"))
        fast = {"mass_matrix.M": robot.mass_matrix(q), "gravity.g": robot.gravity(q),
                "bias.h": robot.bias(q, qd),
                "inverse_dynamics.tau": robot.tree_inverse_dynamics(q, qd, qdd),
                "energy.kinetic": robot.energy(q, qd)[0]}
        if not robot.is_closed_chain:
            fast["forward_dynamics.qdd"] = robot.tree_forward_dynamics(q, qd, tau)
        errs.update({f"fast {k}": rel_err(v, refs[k.split(".")[1]]) for k, v in fast.items()})
    where = worst_key(errs)
    return row(name, errs[where], TOL_SYMBOLIC, f"worst: {where}; from {path}")


def _sympy_reference(model, p, states) -> dict[str, np.ndarray]:
    """Every output name evaluated from the SymPy expressions, sample by sample."""
    import sympy as sp

    s, lag, con = model.sym, model.lagrangian, model.constraints
    M, h = lag.mass_matrix, lag.bias
    exprs = {"M": M, "h": h, "g": lag.gravity, "tau": M * sp.Matrix(s.qdd) + h,
             "kinetic": sp.Matrix([lag.kinetic]), "potential": sp.Matrix([lag.potential]),
             "x": model.task, "J": model.task_jacobian, "jdot_qd": model.task_jdot_qd,
             "frames": model.frames, "phi": con.phi, "phi_q": con.jacobian,
             "gamma": con.accel_bias, "dh_dq": h.jacobian(s.q), "dh_dqd": h.jacobian(s.qd),
             "dM": sp.Matrix.hstack(*[M.diff(qk) for qk in s.q]),
             # body_motion's outputs: one component per row, one body (or point) per column
             "accelerations": model.body_accelerations.T, "cg": model.cg_positions.T,
             "joint_points": model.joint_points.T}
    keys = list(exprs)
    fn = sp.lambdify([*s.q, *s.qd, *s.qdd, *s.tau, *s.p], [exprs[k] for k in keys], "numpy")
    out: dict[str, list] = {k: [] for k in [*keys, "qdd", "dqdd_dq", "dqdd_dqd"]}
    n = len(s.q)
    for k in range(len(states["q"])):
        vals = fn(*(v for key in ("q", "qd", "qdd", "tau") for v in states[key][k]), *p)
        r = {key: np.array(v, dtype=float) for key, v in zip(keys, vals)}
        acc = np.linalg.solve(r["M"], states["tau"][k] - r["h"].ravel())
        dm = np.column_stack([r["dM"][:, i * n:(i + 1) * n] @ acc for i in range(n)])
        r.update(qdd=acc, dqdd_dq=np.linalg.solve(r["M"], -dm - r["dh_dq"]),
                 dqdd_dqd=-np.linalg.solve(r["M"], r["dh_dqd"]))
        for key, v in r.items():
            out[key].append(v)
    refs = {k: np.array(v) for k, v in out.items() if v}
    if model.task.shape[0]:  # ik_terms: Newton's F = [Phi; x] and dF/dq = [Phi_q; J]
        refs["F"] = np.concatenate([refs["phi"].reshape(len(refs["x"]), -1, 1),
                                    refs["x"].reshape(len(refs["x"]), -1, 1)], axis=1)
        refs["dF_dq"] = np.concatenate([refs["phi_q"].reshape(len(refs["J"]), -1, n),
                                        refs["J"]], axis=1)
    if con.phi.shape[0]:  # closed chains: the fused solve, by numpy from the SymPy M, h, Phi_q
        refs.update(_closed_reference(model, refs, states["qd"], states["qdd"]))
    return refs


def _closed_reference(model, refs: dict, qd: np.ndarray, qdd: np.ndarray
                      ) -> dict[str, np.ndarray]:
    """tau (actuated), lambda and cond of closed_inverse_dynamics from [S^T Phi_q^T] solved,
    and its loop residuals Phi_q qd, Phi_q qdd - gamma."""
    act = list(model.desc.actuated)
    n = len(model.sym.q)
    pas = [i for i in range(n) if i not in act]
    jac = refs["phi_q"]
    a = np.zeros((len(jac), n, n))
    a[:, act, np.arange(len(act))] = 1.0
    a[:, :, len(act):] = jac.transpose(0, 2, 1)
    sol = np.linalg.solve(a, refs["tau"].reshape(len(jac), n, 1))[..., 0]
    return {"closed.tau": sol[:, :len(act)], "lambda": sol[:, len(act):],
            "cond": np.linalg.cond(jac[:, :, pas].transpose(0, 2, 1), 1),
            "phi_v": np.einsum("kij,kj->ki", jac, qd),
            "phi_a": np.einsum("kij,kj->ki", jac, qdd) - refs["gamma"].reshape(len(jac), -1)}


def _tracking_reference(robot: Robot, refs: dict, states: dict, seed: int
                        ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Inputs drawn for the fused tracking functions (derive/tracking.py; the nominal
    parameters the robot's own, limits that clip about half the torques) and their outputs
    from the SymPy M, h and g: tau_cmd, tau_app (clipped) and the plant's qdd."""
    act, q, qd = list(robot.actuated), states["q"], states["qd"]
    ns, na = len(q), len(act)
    rng = np.random.default_rng(seed)
    ins = {k: rng.uniform(-1.0, 1.0, (ns, na)) for k in ("q_ref", "qd_ref", "qdd_ref", "tau_in")}
    ins.update(kp=rng.uniform(1.0, 50.0, (ns, na)), kd=rng.uniform(0.1, 5.0, (ns, na)),
               lo=-rng.uniform(0.0, 2.0, (ns, na)), hi=rng.uniform(0.0, 2.0, (ns, na)),
               p_nom=np.tile(robot.p, (ns, 1)))
    m, h, g = refs["M"], refs["h"].reshape(ns, -1), refs["g"].reshape(ns, -1)
    error = ins["kp"] * (ins["q_ref"] - q[:, act]) + ins["kd"] * (ins["qd_ref"] - qd[:, act])
    v = np.zeros_like(q)
    v[:, act] = ins["qdd_ref"] + ins["kd"] * (ins["qd_ref"] - qd[:, act]) \
        + ins["kp"] * (ins["q_ref"] - q[:, act])
    laws = {"tracking_pd": ins["tau_in"] + error + g[:, act],
            "tracking_ct": ins["tau_in"] + (np.einsum("kij,kj->ki", m, v) + h)[:, act]}
    out = {}
    for fn, cmd in laws.items():
        app = np.clip(cmd, ins["lo"], ins["hi"])
        full = np.zeros_like(q)
        full[:, act] = app
        out.update({f"{fn}.tau_cmd": cmd, f"{fn}.tau_app": app,
                    f"{fn}.qdd": np.linalg.solve(m, (full - h)[..., None])[..., 0]})
    return ins, out

