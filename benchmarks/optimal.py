"""Optimal motion (issue 27): the time-optimal timing of a path against toppra on the same
path and grid.

* **five_bar_type1, S5 path** (201 samples, |tau| <= 0.1 N*m): ``planar_sym.time_optimal``
  against toppra 0.6 (``TOPPRA``, seidel solver, collocation) given the same spline and grid
  and our closed-chain torques as its inverse-dynamics callable (one call per grid point, the
  passive joints completed by ``from_actuated``): what a toppra user has to write for a closed
  chain. Gate: the two final times agree (1e-6).
* The S3 path of the 2-DOF arm is not timed here: toppra 0.6 fails on it (a NaN controllable
  set where a torque row vanishes); tests/test_time_optimal.py checks ours there against the
  same discretised problem as one linear program (SciPy's HiGHS).
"""

from __future__ import annotations

import warnings

import numpy as np

from . import Config
from .report import Check, Section, Table
from .timing import fmt_time, interleaved, ratio


def run(cfg: Config) -> Section:
    import planar_sym as ps
    from planar_sym.motion.closure import from_actuated
    from planar_sym.optimal.time_optimal import arc_length_path

    sec = Section("optimal", "Optimal motion", __doc__.split("\n\n", 1)[1].strip())
    table = Table("Time-optimal timing of a path: planar_sym against a peer on the same grid",
                  ["path", "samples", "planar_sym", "peer", "peer time", "ratio (peer / ours)"])
    try:
        import toppra
        from toppra import algorithm, constraint
    except ImportError:
        sec.notes.append("toppra is not installed: pip install toppra")
        return sec
    samples = 51 if cfg.quick else 201
    fb = ps.load("five_bar_type1")
    t = np.linspace(0.0, 2.0, samples)
    path = ps.inverse_kinematics(fb, ps.cubic([0.060852, 0.154665], [0.05, 0.0], 2.0, t))
    lim = np.array([0.1, 0.1])
    s, *_ = arc_length_path(fb, path)
    act = list(fb.actuated)

    def reduced(qa, va, aa):
        jt = from_actuated(fb, np.zeros(1), np.atleast_2d(qa), np.atleast_2d(va),
                           np.atleast_2d(aa), q_guess=path.q[0])
        return fb.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)[0][0]

    def peer():
        torque = constraint.JointTorqueConstraint(
            reduced, np.column_stack([-lim, lim]), np.zeros(2),
            discretization_scheme=constraint.DiscretizationType.Collocation)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return algorithm.TOPPRA([torque], toppra.SplineInterpolator(s, path.q[:, act]),
                                    gridpoints=s, solver_wrapper="seidel").compute_trajectory(0, 0)

    ours = ps.time_optimal(fb, path, lim)
    theirs = peer()
    gap = abs(theirs.duration - ours.duration_s) / theirs.duration if theirs else np.inf
    sec.checks.append(Check("five_bar_type1 S5: final time, ours vs toppra", gap, 1e-6))
    got = interleaved({"ours": lambda: ps.time_optimal(fb, path, lim), "toppra": peer},
                      repeats=max(3, cfg.repeats // 3), per=1.0, min_block_s=0.0)
    table.add("five_bar_type1 S5", samples, fmt_time(got["ours"].median), "toppra 0.6",
              fmt_time(got["toppra"].median), ratio(got["toppra"], got["ours"]))
    sec.headlines["time-optimal S5 vs toppra"] = (
        f"{ratio(got['toppra'], got['ours']).median:.3g}x faster ({ours.duration_s:.6g} s "
        "reached by both)")
    sec.tables.append(table)
    return sec
