"""Identification (issue 26): the regressor per sample against Pinocchio's joint-torque
regressor in a native C++ loop, and a whole identification against NumPy's least squares.

* **regressor**: ``planar_sym.identify.regressor`` (compiled batch calls of 1000 samples,
  whose Y stays in the cache, and one call of all N, which writes Y to memory) against ``pinocchio::computeJointTorqueRegressor`` looped in C++ (``baselines/
  pinocchio_native.cpp``, on inputs packed beforehand), on the seed's 2-DOF arm and a 6-link
  chain, ns per sample. Gate: Pinocchio's regressor times its own dynamic parameters equals our
  inverse dynamics on the exported URDF (so both compute the same robot's regressor).
* **identification**: ``identify`` of 10^5 exact samples of the Type I 5-bar (regressor,
  stacking, weighted least squares twice, the SVD and covariance) against
  ``numpy.linalg.lstsq`` alone on the same stacked matrix.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np

from . import Config
from .report import Check, Section, Table
from .timing import Stats, _block, calibrate, fmt_time, interleaved, ratio

GATE = 1e-10
#: samples per call of the cache-resident timing (Y of a 6-link chain: 1.7 MB)
BATCH = 1000


def _states(n: int, size: int, seed: int):
    rng = np.random.default_rng(seed)
    return tuple(np.ascontiguousarray(rng.uniform(-2, 2, (size, n))) for _ in range(3))


def _regressor_rows(cfg: Config, sec: Section, table: Table, work: Path) -> None:
    from planar_sym.identify.regressor import regressor
    from planar_sym.model.locate import load
    from planar_sym.outputs.export import write

    from .baselines import pinocchio_native as pn
    from .chains import write_chain

    if not cfg.growth_pinocchio:  # --quick: no native build (about 45 s, more on a loaded CI)
        sec.notes.append("not run with --quick (no native Pinocchio build): regressor rows "
                         "not timed")
        return
    try:
        exe = pn.build()
    except (RuntimeError, OSError, ImportError) as exc:
        sec.notes.append(f"native Pinocchio could not be built ({str(exc).splitlines()[0]}): "
                         "regressor rows not timed")
        return
    import pinocchio as pin

    n_s = 1_000 if cfg.quick else 100_000
    for label, ref in (("serial_2dof", "serial_2dof"),
                       ("6-link chain", str(write_chain(6, work)))):
        robot = load(ref)
        urdf = work / f"{robot.name}.urdf"
        write(robot, urdf, "urdf")
        q, qd, qdd = _states(robot.n, n_s, seed=3)
        # gate: Pinocchio's regressor times its own parameters is our inverse dynamics
        gravity, joints = pn.urdf_facts(urdf)
        model = pin.buildModelFromUrdf(str(urdf))
        model.gravity.linear = np.array(gravity)
        data = model.createData()
        order = [model.idx_vs[model.getJointId(j)] for j in joints]
        params = np.concatenate([model.inertias[j].toDynamicParameters()
                                 for j in range(1, model.njoints)])
        tau = robot.tree_inverse_dynamics(q[:20], qd[:20], qdd[:20])
        worst = 0.0
        for k in range(20):
            qp = pin.neutral(model)
            for i, j in enumerate(joints):
                jid = model.getJointId(j)
                if model.nqs[jid] == 2:
                    qp[model.idx_qs[jid]:model.idx_qs[jid] + 2] = np.cos(q[k, i]), np.sin(q[k, i])
                else:
                    qp[model.idx_qs[jid]] = q[k, i]
            v, a = np.zeros(model.nv), np.zeros(model.nv)
            v[order], a[order] = qd[k], qdd[k]
            y = pin.computeJointTorqueRegressor(model, data, qp, v, a)
            got = np.atleast_2d(y)[order] @ params
            worst = max(worst, float(np.max(np.abs(got - tau[k])) / max(np.abs(tau[k]).max(),
                                                                        1e-12)))
        check = Check(f"{label}: Pinocchio's regressor x its parameters vs our inverse dynamics",
                      worst, GATE)
        sec.checks.append(check)
        if not check.ok:
            table.add(label, robot.n, "-", "-", "-", "**baseline disagrees: not timed**")
            continue
        # two batch sizes: BATCH samples per call keep Y in the cache, as Pinocchio's loop
        # keeps its one data buffer; all n_s in one call also writes Y to memory (n_s x n x
        # columns doubles, 26 MB for the 2-DOF arm), which Pinocchio's loop never does
        sizes = {f"{BATCH} per call": BATCH, f"{n_s} in one call": n_s}
        ours: dict[str, list] = {k: [] for k in sizes}
        theirs = []
        calls = {k: (lambda m=m, robot=robot, q=q, qd=qd, qdd=qdd:
                     regressor(robot, q[:m], qd[:m], qdd[:m])) for k, m in sizes.items()}
        number = {k: calibrate(f, cfg.min_block_s) for k, f in calls.items()}
        for _ in range(cfg.repeats):  # paired: one of each per round, same load
            for k, f in calls.items():
                ours[k].append(_block(f, number[k]) / number[k] / sizes[k])
            got = pn.run(urdf, q, qd, qdd, 1, exe=exe)
            theirs.append(got["regressor_best_ns"] * 1e-9)
        pins = Stats(tuple(theirs))
        for k in sizes:
            mine = Stats(tuple(ours[k]))
            table.add(label, robot.n, k, fmt_time(mine.median), fmt_time(pins.median),
                      ratio(pins, mine))
            sec.headlines[f"regressor vs native Pinocchio, {label}, {k}"] = \
                f"{ratio(pins, mine).median:.3g}x faster"


def _identification_row(cfg: Config, sec: Section, table: Table) -> None:
    from planar_sym.identify.base import base_parameters
    from planar_sym.identify.data import experiment
    from planar_sym.identify.estimate import identify, stacked
    from planar_sym.model.locate import load
    from planar_sym.motion.closure import from_actuated

    robot = load("five_bar_type1")
    n_s = 2_000 if cfg.quick else 100_000
    t = np.linspace(0.0, 20.0, n_s)
    w = 2 * np.pi / 20.0
    act = np.asarray(robot.q_drawn)[list(robot.actuated)]
    q = act + 0.05 * np.column_stack([np.sin(3 * w * t), np.sin(5 * w * t + 1.0)])
    qd = 0.05 * np.column_stack([3 * w * np.cos(3 * w * t), 5 * w * np.cos(5 * w * t + 1.0)])
    qdd = -0.05 * np.column_stack([(3 * w) ** 2 * np.sin(3 * w * t),
                                   (5 * w) ** 2 * np.sin(5 * w * t + 1.0)])
    jt = from_actuated(robot, t, q, qd, qdd)
    tau, _ = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)
    ex = experiment(robot, t, jt.q, tau, jt.qd, jt.qdd)
    base = base_parameters(robot)
    wmat, tvec, _ = stacked(robot, [ex], base)
    est = identify(robot, ex, base)
    err = float(np.max(np.abs(est.values - base.values())) / np.abs(base.values()).max())
    sec.checks.append(Check("five_bar_type1: identification of exact data recovers the "
                            "description's base parameters", err, 1e-9))
    got = interleaved({"identify": lambda: identify(robot, ex, base),
                       "lstsq": lambda: np.linalg.lstsq(wmat, tvec, rcond=None)},
                      repeats=max(3, cfg.repeats // 2), per={"identify": 1, "lstsq": 1})
    table.add(f"five_bar_type1, {n_s} samples", f"{len(base)} base",
              fmt_time(got["identify"].median), fmt_time(got["lstsq"].median),
              ratio(got["identify"], got["lstsq"]))
    sec.headlines[f"identify {n_s} samples of a 5-bar"] = (
        f"{fmt_time(got['identify'].median)} ({ratio(got['identify'], got['lstsq']).median:.3g}"
        "x NumPy lstsq alone)")


def run(cfg: Config) -> Section:
    sec = Section("identify", "Identification", __doc__.split("\n\n", 1)[1].strip())
    reg = Table("Regressor per sample: planar_sym (batch calls) vs Pinocchio's "
                "computeJointTorqueRegressor in a native C++ loop (one data buffer reused)",
                ["robot", "n", "samples", "planar_sym", "Pinocchio native",
                 "ratio (Pinocchio / ours)"])
    ident = Table("Identification of exact data: identify() vs NumPy lstsq on the same "
                  "stacked matrix", ["data", "parameters", "identify", "lstsq alone",
                                     "ratio (identify / lstsq)"])
    with tempfile.TemporaryDirectory(prefix="bench_identify_") as tmp:
        _regressor_rows(cfg, sec, reg, Path(tmp))
    _identification_row(cfg, sec, ident)
    sec.tables += [reg, ident]
    return sec
