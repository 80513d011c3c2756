"""Section 1b: inverse kinematics, the generic solver against the textbook's closed forms.

Measured: ``inverse_kinematics(robot, traj, solver=...)`` exactly as a user calls it (positions,
then the exact rates and accelerations from ``[Phi_q; J]``, with the condition-number checks;
for Newton also the branch check), per sample over N samples, for the generic solver
(``"newton"``: Newton continued sample to sample in C, ``planar_sym/motion/_newton.c``) and the
baseline ``"seed"`` (the seed's closed form, vectorised numpy). The positions alone are timed
too (``motion.newton.solve`` against the closed-form function), since the rates cost the same
for both. Motions: the seed scenarios S3 (2-DOF arm, Newton from the elbow-down pose q =
(0.5, 1.0) rad, as the arm is drawn stretched out), S5 and S7 (from the drawn configuration),
their built-in study files' cubic moves sampled at N evenly spaced times. Before timing, the
Newton positions are checked against the closed form to 1e-12. The issue's target: at most 3x
the closed form's time.
"""

from __future__ import annotations

import numpy as np

from . import Config
from .inverse import rel_err
from .report import Check, Section, Table
from .timing import interleaved, ratio

GATE = 1e-12
SCENARIOS = {"S3": "serial_2dof_cartesian_move", "S5": "five_bar_type1_move_x",
             "S7": "parallel_3rrr_move_x"}
START = {"serial_2dof": (0.5, 1.0)}
LABELS = {"seed": "`inverse_kinematics(solver=\"seed\")`, closed form (reference)",
          "newton": "`inverse_kinematics(solver=\"newton\")`, generic",
          "seed positions": "closed-form positions only (reference for the next row)",
          "newton positions": "Newton positions only (`motion.newton.solve`)"}


def _fmt_n(n: int) -> str:
    return f"1e{int(np.log10(n))}" if n >= 1000 and 10 ** int(np.log10(n)) == n else str(n)


def _case(key: str, size: int):
    from planar_sym import load
    from planar_sym.study.motion import profile_at
    from planar_sym.study.run import load_study

    st = load_study(SCENARIOS[key])
    robot = load(st.robot)
    traj = profile_at(st, robot, np.linspace(0.0, st.motion.duration_s, size))
    return robot, traj, START.get(robot.name)


def run(cfg: Config) -> Section:
    from planar_sym.motion import newton
    from planar_sym.motion.ik import inverse_kinematics
    from planar_sym.motion.seed_ik import SEED_SOLVERS

    sec = Section("ik", "1b. Inverse kinematics: generic Newton vs the closed forms",
                  __doc__.split("\n\n", 1)[1])
    sizes = (201,) if cfg.quick else (201, 10_000)
    table = Table("Time per sample; ratio = method time / closed-form time in the same rounds "
                  "(positions only: to the closed-form positions)",
                  ["scenario", "N", "method", "time per sample", "ratio to the closed form"])
    headline = {}
    for key in SCENARIOS:
        for size in sizes:
            robot, traj, q0 = _case(key, size)
            t, x, seed_fn = traj.t_s, traj.x, SEED_SOLVERS[robot.name]
            solved = newton.solve(robot, t, x, q0)
            sec.checks.append(Check(f"{key} ({robot.name}), N = {_fmt_n(size)}: Newton positions "
                                    "vs the closed form", rel_err(solved.q, seed_fn(robot, t, x)),
                                    GATE))
            if not sec.checks[-1].ok:
                continue
            fns = {"seed": lambda r=robot, tr=traj: inverse_kinematics(r, tr, solver="seed"),
                   "newton": lambda r=robot, tr=traj, q0=q0: inverse_kinematics(
                       r, tr, solver="newton", q_start=q0),
                   "seed positions": lambda r=robot, t=t, x=x, f=seed_fn: f(r, t, x),
                   "newton positions": lambda r=robot, t=t, x=x, q0=q0: newton.solve(r, t, x, q0)}
            st = interleaved(fns, repeats=cfg.repeats, per=size, min_block_s=cfg.min_block_s)
            for k, v in st.items():
                base = k.replace("newton", "seed")
                table.add(f"{key} {robot.name}", _fmt_n(size), LABELS[k], v,
                          ratio(v, st[base]) if k != base else "1")
            sec.notes.append(f"{key}, N = {_fmt_n(size)}: Newton made "
                             f"{solved.iterations / size:.2f} corrections and "
                             f"{solved.evaluations / size:.2f} evaluations per sample, "
                             f"{solved.halvings} step halvings")
            headline[(key, size)] = (ratio(st["newton"], st["seed"]),
                                     ratio(st["newton positions"], st["seed positions"]))
    sec.tables.append(table)
    n = max(sizes)
    parts = [f"{k} **{a.median:.3g}x** [{a.min:.3g}-{a.max:.3g}]"
             for (k, size), (a, _) in headline.items() if size == n]
    pos = [f"{k} {b.median:.3g}x" for (k, size), (_, b) in headline.items() if size == n]
    if parts:
        sec.headlines["ik"] = (f"Generic inverse kinematics (Newton in C), N = {_fmt_n(n)}: "
                               + ", ".join(parts) + " the time per sample of the seed's closed "
                               "form, rates included (positions alone: " + ", ".join(pos)
                               + "; the issue's target: at most 3x)")
    return sec
