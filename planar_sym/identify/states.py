"""Random states a robot can be in: what the base parameters are found from (any generic set of
states has the same regressor rank; a closed chain's must be on its loops)."""

from __future__ import annotations

import numpy as np

from ..errors import WorkspaceError
from ..model.robot import Robot
from ..motion.closure import complete_rates, solve_passive

#: a closed chain's actuated joints wander this far from the drawn pose (rad; a slider the same
#: fraction of its drawn travel, at least SLIDE_M): far enough for generic poses, near enough to
#: stay in the drawn assembly mode
SWING_RAD = 0.4
SLIDE_M = 0.05
#: halvings of the swing tried before a closed chain's random motion is given up
TRIES = 6


def random_states(robot: Robot, samples: int, seed: int = 0
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q, qd, qdd), each (samples, n) in SI: a tree's anywhere (angles in [-pi, pi), sliders
    within their drawn travel), a closed chain's along a random smooth path of its actuated
    joints from the drawn pose, on the loops, in the drawn assembly mode."""
    rng = np.random.default_rng(seed)
    n, slide = robot.n, np.array([u == "m" for u in robot.coordinate_units])
    drawn = np.asarray(robot.q_drawn, dtype=float)
    reach = np.where(slide, np.maximum(np.abs(drawn), SLIDE_M), 1.0)
    qd = rng.normal(size=(samples, n)) * reach
    qdd = rng.normal(size=(samples, n)) * reach
    if not robot.is_closed_chain:
        q = np.where(slide, drawn + rng.uniform(-0.5, 0.5, (samples, n)) * reach,
                     rng.uniform(-np.pi, np.pi, (samples, n)))
        return q, qd, qdd
    act = list(robot.actuated)
    t = np.linspace(0.0, 1.0, samples)
    # a few incommensurate sines per joint: a smooth path through varied poses
    freq = rng.uniform(1.0, 5.0, (3, len(act)))
    phase = rng.uniform(0, 2 * np.pi, (3, len(act)))
    path = np.sum(np.sin(2 * np.pi * freq[None] * t[:, None, None] + phase[None])
                  - np.sin(phase[None]), axis=1) / 3  # starts at 0
    swing = SWING_RAD * reach[act]
    for _ in range(TRIES):
        try:
            q = solve_passive(robot, drawn[act] + swing * path, t=t)
            break
        except WorkspaceError:
            swing = swing / 2
    else:
        raise WorkspaceError(f"{robot.name}: no random motion near the drawn pose stays on the "
                             f"loops (swing down to {swing.max():.3g}): is the drawn pose "
                             "near a singular one?")
    qd, qdd = complete_rates(robot, q, qd[:, act], qdd[:, act])
    return q, qd, qdd
