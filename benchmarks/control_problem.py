"""Section 5's settings and problems, and the compiled loop's runs of them.

What every part of the control benchmark shares: the studies, laws, tolerances, gates and
method names; the run ``Settings`` (full or ``--quick``); a ``Problem`` (robot, reference,
start, output grid) loaded from a study; the controller of a law; and ``ours``, the timed
``simulate_controlled`` call. Apart from ``control.py`` (the timing rounds and the report
section) and ``control_peers.py`` (the SciPy and MuJoCo baselines), which both import it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import Config

STUDIES = (("S3", "serial_2dof_cartesian_move"), ("S5", "five_bar_type1_move_x"))
LAWS = ("pd", "computed_torque")
LAW_NAME = {"pd": "PD + gravity", "computed_torque": "computed torque"}
BANDWIDTH_HZ = 5.0
RTOL, ATOL = 1e-10, 1e-12
REF_RTOL, REF_ATOL = 1e-13, 1e-14
OUT_DT = 0.01  # s between output samples
FIXED_S = 1e-3  # a run this short costs what a call costs besides its steps
TARGET_SCIPY = 30.0  # (a): the compiled loop at least this many times faster
TARGET_FREE = 1.5  # (c): a controlled run at most this many times the free run (issue 28)
LOOSE = 1e-5  # rad: the second accuracy level of (b)
GATE_STATE = 1e-7  # SciPy's final state against the compiled loop's
GATE_REF = 1e-9  # SciPy's whole run against the rtol-1e-13 reference
GATE_TORQUE = 1e-9  # the Python controller's torques against the compiled controller's
GATE_MODEL = 1e-9  # MuJoCo's dynamics against planar_sym's
MJ_SOLIMP = (0.9999, 0.9999, 0.001)
OURS = "planar_sym `simulate_controlled` (C loop)"
SCIPY = "SciPy DOP853 + Python controller"
LOOP = "MuJoCo RK4, controller in a Python loop around `mj_step`"
CALLBACK = "MuJoCo RK4, controller as `mjcb_control` (every RK4 stage)"


@dataclass(frozen=True)
class Settings:
    t_end: float
    repeats: int  # interleaved rounds of (a) and (c)
    mj_repeats: int  # rounds of the work-precision runs of (b)
    ours_rtols: tuple[float, ...]
    loop_dts: dict[str, tuple[float, ...]]
    cb_dts: dict[str, tuple[float, ...]]
    min_block_s: float


def settings(cfg: Config) -> Settings:
    if cfg.quick:
        return Settings(1.0, 1, 1, (1e-6, RTOL), {"S3": (1e-3,), "S5": (1e-3,)},
                        {"S3": (1e-3,), "S5": (1e-3,)}, cfg.min_block_s)
    return Settings(5.0, cfg.sim_repeats, min(cfg.sim_repeats, 3), (1e-6, 1e-8, RTOL),
                    {"S3": (1e-3, 5e-4, 2e-4), "S5": (1e-3, 5e-4)},
                    {"S3": (2e-3, 1e-3, 5e-4, 4e-4), "S5": (1e-3, 5e-4)}, cfg.min_block_s)


# -- the problem ---------------------------------------------------------------------------------

@dataclass
class Problem:
    label: str
    study: str
    robot: object
    ref: object  # control.signals.Signal over the actuated coordinates
    q0: np.ndarray
    qd0: np.ndarray
    t: np.ndarray
    motion_s: float
    build_reference: object  # () -> Signal: what from_motion costs (timed in (c)'s rounds)

    @property
    def t_end(self) -> float:
        return float(self.t[-1])


def load_problem(label: str, study: str, t_end: float) -> Problem:
    from planar_sym.dynamics.events import actuator_events
    from planar_sym.motion.signals import from_motion
    from planar_sym.study.motion import joint_motion
    from planar_sym.study.run import load_study, robot_of

    st = load_study(study)
    robot = robot_of(st)
    # what the Python baselines model of the compiled controller: no friction, no saturation
    assert not robot.has_friction and np.all(np.isinf(actuator_events(robot, "continue")[1]))
    jt, _ = joint_motion(st, robot)
    act = list(robot.actuated)

    def build():
        return from_motion(jt.t_s, jt.q[:, act], jt.qd[:, act], jt.qdd[:, act])

    ref = build().hold_until(t_end)
    t = np.linspace(0.0, t_end, round(t_end / OUT_DT) + 1)
    return Problem(label, study, robot, ref, jt.q[0].copy(), jt.qd[0].copy(), t,
                   float(jt.t_s[-1]), build)


def make_controller(p: Problem, law: str):
    from planar_sym.control import controller
    from planar_sym.control.laws import effective_inertia

    w = 2.0 * np.pi * BANDWIDTH_HZ
    na = len(p.robot.actuated)
    if law == "pd":
        inertia = effective_inertia(p.robot, p.q0)
        return controller("pd", w * w * inertia, 2.0 * w * inertia, width=na)
    return controller("computed_torque", w * w, 2.0 * w, width=na)


def short_run(p: Problem, ctl):
    """The same call over FIXED_S with two outputs: what a call costs besides its steps."""
    from planar_sym.control import simulate_controlled

    return simulate_controlled(p.robot, ctl, (0.0, FIXED_S), reference=p.ref, q0=p.q0,
                               qd0=p.qd0, t_eval=[0.0, FIXED_S], rtol=RTOL, atol=ATOL)


def ours(p: Problem, ctl, rtol: float = RTOL, atol: float = ATOL):
    from planar_sym.control import simulate_controlled

    return simulate_controlled(p.robot, ctl, (0.0, p.t_end), reference=p.ref, q0=p.q0,
                               qd0=p.qd0, t_eval=p.t, rtol=rtol, atol=atol)
