"""The torque envelope along an inverse-dynamics study's path (not at rest): at each sample's
q, qd the torques are affine in the task acceleration,

.. code:: text

    K qdd = [gamma; xdd - Jdot qd]   =>   tau(xdd) = b + A xdd,    envelope_k = |b_k| + a ||A_k||

over task accelerations of size ``a`` in the x-y plane (``pose_measures.envelope``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..model.robot import Robot
from .pose_measures import envelope, stacked


@dataclass(frozen=True, eq=False)
class EnvelopeAlong:
    """Torques along an inverse-dynamics study, each sample's ``tau = b + A xdd``.

    ``b`` (N, na) is the torque with task acceleration 0 at the path's own q, qd; ``A``
    (N, na, nt) maps the task acceleration (m/s^2, rad/s^2 for phi); ``q`` (N, n) is the path's
    pose, ``x`` (N, nt) its task coordinates (m, rad) and ``xdd`` (N, nt) its acceleration, the
    study's own, so ``tau_study = b + A xdd``. The envelope is the largest |tau_k| over task
    accelerations of size ``accel_m_s2`` in the x-y plane, ``angle_rad`` its direction.
    """

    study: str
    robot: str
    t_s: np.ndarray
    q: np.ndarray
    x: np.ndarray
    xdd: np.ndarray
    tau_study: np.ndarray
    b: np.ndarray
    A: np.ndarray
    envelope: np.ndarray
    angle_rad: np.ndarray
    accel_m_s2: float
    actuated: tuple[int, ...]
    actuator_units: tuple[str, ...]
    task_names: tuple[str, ...]

    def table(self) -> tuple[list[str], np.ndarray]:
        """Columns with units (t_s, x_mm, y_mm[, phi_rad], per actuator tau, b, envelope)."""
        names, cols = ["t_s"], [self.t_s]
        for k, t in enumerate(self.task_names):
            names.append("phi_rad" if t == "phi" else f"{t}_mm")
            cols.append(self.x[:, k] * (1.0 if t == "phi" else 1e3))
        for k, (i, u) in enumerate(zip(self.actuated, self.actuator_units)):
            s = "n_m" if u == "N*m" else "n"
            names += [f"tau{i + 1}_{s}", f"tau_b{i + 1}_{s}", f"tau_env{i + 1}_{s}",
                      f"env_angle{i + 1}_deg"]
            cols += [self.tau_study[:, k], self.b[:, k], self.envelope[:, k],
                     np.degrees(self.angle_rad[:, k])]
        return names, np.column_stack(cols)


def envelope_along(study, accel_m_s2: float = 1.0, samples: int | None = None) -> EnvelopeAlong:
    """The torque envelope along an inverse-dynamics study's path.

    .. code:: text

        K qdd = [gamma; xdd - Jdot qd]   =>   tau(xdd) = b + A xdd

    at each sample's q, qd (``b``: xdd = 0; ``A``: one column per task coordinate), and the
    envelope ``|b_k| + a ||A_k[:, x, y]||`` over task accelerations of size ``a`` in the x-y
    plane.

    Parameters
    ----------
    study : str, Path or Study
        A built-in study name or a study file, of kind "inverse".
    accel_m_s2 : float
        Size of the task acceleration (m/s^2).
    samples : int, optional
        Evenly spaced samples (default the study's).
    """
    from ..motion.newton import check_square
    from ..study.motion import joint_motion
    from ..study.run import load_study, robot_of

    st = load_study(study)
    if st.kind != "inverse":
        raise InputError(f"{st.name}: the torque envelope follows an inverse-dynamics study's "
                         f"path (kind = \"inverse\"); this one is kind = \"{st.kind}\"")
    if not (np.ndim(accel_m_s2) == 0 and np.isfinite(accel_m_s2) and accel_m_s2 >= 0):
        raise InputError(f"accel_m_s2 must be a finite acceleration >= 0 in m/s^2 "
                         f"(got {accel_m_s2!r})")
    robot = robot_of(st)
    if not robot.task_names:
        raise InputError(f"{robot.name} has no task point: no task acceleration to size")
    check_square(robot)
    jt, _ = joint_motion(st, robot, samples)
    q, qd, N, m, nt = jt.q, jt.qd, len(jt.q), robot.n_constraints, len(robot.task_names)
    K, x, _, jdq = stacked(robot, q, qd)
    gamma = (np.reshape(robot.constraint_bias(q, qd), (N, m)) if m else np.zeros((N, 0)))
    rhs = [np.concatenate([gamma, -jdq], axis=1)]
    rhs += [np.concatenate([np.zeros((N, m)), np.tile(e, (N, 1))], axis=1) for e in np.eye(nt)]
    qdd = [np.linalg.solve(K, r[..., None])[..., 0] for r in rhs]
    qdd = [qdd[0]] + [qdd[0] + d for d in qdd[1:]] + [jt.qdd]
    tau = _torques(robot, np.tile(q, (len(qdd), 1)), np.tile(qd, (len(qdd), 1)),
                   np.concatenate(qdd)).reshape(len(qdd), N, -1)
    b, study_tau = tau[0], tau[-1]
    A = np.stack([t - b for t in tau[1:-1]], axis=-1)
    J = K[:, m:]
    xdd = (J @ jt.qdd[..., None])[..., 0] + jdq
    trans = [k for k, t in enumerate(robot.task_names) if t in ("x", "y")]
    env = envelope(b, A[..., trans], float(accel_m_s2))
    return EnvelopeAlong(st.name, robot.name, jt.t_s, q, x, xdd, study_tau, b, A, env["envelope"],
                         env["envelope_angle_rad"], float(accel_m_s2), robot.actuated,
                         tuple(a["unit"] for a in robot.actuators), robot.task_names)


def _torques(robot: Robot, q, qd, qdd) -> np.ndarray:
    """Actuated torques (N, na), refusing a singular pose (the study's own path)."""
    if robot.is_closed_chain:
        return robot.closed_chain_inverse_dynamics(q, qd, qdd)[0]
    return robot.inverse_dynamics(q, qd, qdd)
