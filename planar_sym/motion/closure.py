"""Closed chains at the motion layer: passive joints from the loop constraints (Newton,
continued sample to sample so the assembly mode is kept) and their exact rates.

The loop-closure equations are ``Phi(q) = 0`` with ``Phi = r(parent point) - r(child point)``
at every cut joint; rates follow exactly from ``Phi_q qd = 0`` and ``Phi_q qdd = gamma``.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError, WorkspaceError, warn_caller
from ..model.arrays import as_sample_set, as_samples, as_times, as_vector, when
from ..model.library import SingleCall
from ..model.loops import COND_LIMIT, refuse_singular_matrices, warn_between_samples
from ..model.robot import Robot
from .profiles import JointTrajectory

#: Newton on Phi(q) = 0 stops below this residual (m); far under the 1e-9 m the tests demand.
NEWTON_TOL_M = 1e-13
NEWTON_MAX_ITER = 30
#: a residual Newton stalls at below this (m) is named as near the workspace's edge
NEAR_EDGE_M = 1e-6


def partition(robot: Robot) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the actuated and passive coordinates; checks the chain is fully actuated.

    Returns two integer arrays, shapes (actuated,) and (n - actuated,); InputError unless the
    actuated joints and the loop equations together fix every coordinate.
    """
    act, pas = np.array(robot.actuated, dtype=int), np.array(robot.passive, dtype=int)
    if len(act) + robot.n_constraints != robot.n:
        raise InputError(f"{robot.name}: {len(act)} actuated joints and {robot.n_constraints} "
                         f"loop equations for {robot.n} coordinates: the chain is not exactly "
                         "actuated, so torques are not unique")
    return act, pas


def solve_passive(robot: Robot, q_act, q_guess=None, t=None) -> np.ndarray:
    """Full coordinates from actuated ones, Newton on Phi(q) = 0 for the passive joints.

    The first sample is reached from the drawn configuration along the loops (as the others
    from it), so it is in the drawn assembly mode wherever it lies, or from ``q_guess`` by
    Newton, which then picks the mode; the others follow it along the motion, whatever the
    sampling (``_follow``): from each solved pose to the next sample's actuated coordinates in
    steps of at most ``MAX_STEP`` in any coordinate (and shorter near a singular pose), each
    predicted along the loops' tangent and corrected by Newton; refused where the motion meets a
    singular pose (Phi_p's 1-norm condition number above COND_LIMIT), where the sign of det
    Phi_p changes (one crossed between two steps: another assembly mode), or where Newton cannot
    close the loops.

    ``q_act`` (N, actuated) holds the actuated coordinates (rad; m at a slider), ``q_guess``
    (n,) a start pose, ``t`` (N,) the times (s) to name in an error (checked here: finite, one
    per sample). Returns every coordinate,
    shape (N, n), in rad (m). Raises WorkspaceError where the loops cannot be closed or the
    motion would leave its assembly mode.
    """
    act, pas = partition(robot)
    loops = _Loops(robot, act, pas)
    if t is not None:  # the times an error names: checked here, with the samples
        t = as_times(t, len(np.atleast_2d(q_act)), "q_act")
    q_act = as_samples("q_act", q_act, len(act), times=t)
    if q_guess is not None:  # checked here, once: _first is also entered again without one
        q_guess = as_vector("q_guess", q_guess, robot.n)
    pose = _first(loops, q_act[0], q_guess, t)
    out = np.empty((len(q_act), robot.n))
    out[0] = pose.q
    cond, passed = np.empty(len(q_act)), np.empty(len(q_act))
    cond[0] = passed[0] = pose.cond
    for k in range(1, len(q_act)):
        pose = _follow(loops, pose, q_act[k], t, k)
        out[k], cond[k], passed[k] = pose.q, pose.cond, pose.passed
    warn_between_samples(robot.name, cond, passed, t)
    return out


def _first(loops: _Loops, qa: np.ndarray, q_guess, t) -> _Pose:
    """The first sample's pose: continued from the drawn pose, whose assembly mode it keeps,
    or from ``q_guess`` by Newton, which then picks the mode. Newton from the drawn passive
    angles straight at a crank 240 degrees away closed the slider-crank in its other mode (the
    slider on the far side of the pivot, 7% off in torque) without a word, so a guess whose
    passive coordinates are the drawn ones (``simulate(project=True)`` from ``q_drawn`` with
    the crank turned) is no guess. A drawn pose that is itself singular is left to Newton.
    ``q_guess`` (n,) is checked already (``solve_passive``)."""
    robot, act, pas = loops.robot, loops.act, loops.pas
    if q_guess is not None and np.array_equal(q_guess[pas], robot.q_drawn[pas]):
        q_guess = None
    if q_guess is not None:
        return _guessed(loops, qa, np.array(q_guess, dtype=float), t)
    q = np.array(robot.q_drawn, dtype=float)
    drawn, residual = loops.newton(q)
    pose = _Pose(loops, drawn) if residual < NEWTON_TOL_M else None
    if pose is not None and pose.cond <= COND_LIMIT:
        try:
            return _follow(loops, pose, qa, t, 0, origin="the drawn pose")
        except WorkspaceError:
            # a target the loops close at in no mode is outside, whatever lies between
            q[act] = qa
            residual = loops.newton(q)[1]
            if residual < NEWTON_TOL_M:
                raise
            loops.refuse_outside(qa, residual, t, 0)  # (not a second Newton, in close)
    q[act] = qa
    return _Pose(loops, loops.close(q, qa, t, 0))


#: a guess whose passive coordinates Newton moves by more than this (rad; m at a slider) was
#: far from the loops: the pose it closes is compared with the drawn mode's, and a difference
#: is said
FAR_GUESS = 0.5


def _guessed(loops: _Loops, qa: np.ndarray, guess: np.ndarray, t) -> _Pose:
    """Newton from ``guess`` with the actuated coordinates ``qa``; its passive angles in the
    turn nearest the guess (Newton from far away wandered to q2 = 493 rad on a four-bar).
    Where Newton cannot close the loops from the guess the drawn mode is continued there; where
    a far guess closes another pose than the drawn mode's, a warning names both."""
    robot, pas = loops.robot, loops.pas
    q = guess.copy()
    q[loops.act] = qa
    closed, residual = loops.newton(q)
    if not residual < NEWTON_TOL_M:
        try:
            return _first(loops, qa, None, t)
        except WorkspaceError:
            loops.refuse_outside(qa, residual, t, 0)
    turns = np.array([robot.coordinate_units[i] == "rad" for i in pas])
    shift = np.where(turns, 2 * np.pi * np.round((closed[pas] - guess[pas]) / (2 * np.pi)), 0)
    closed[pas] -= shift
    if np.max(np.abs(closed[pas] - guess[pas])) > FAR_GUESS:
        try:
            drawn = _first(loops, qa, None, t).q
        except WorkspaceError:
            drawn = None
        if drawn is not None and not _same_pose(drawn, closed, pas, turns):
            warn_caller(
                f"{robot.name}: the start's passive coordinates {_listed(guess, pas)} are far "
                f"from the loops; Newton from them closes them at {_listed(closed, pas)}, "
                f"another pose than the drawn assembly mode's {_listed(drawn, pas)} at these "
                "actuated coordinates; the first was taken: give a start on the loops "
                "(planar_sym.from_actuated) to choose")
    return _Pose(loops, closed)


def _same_pose(a: np.ndarray, b: np.ndarray, pas: np.ndarray, turns: np.ndarray) -> bool:
    d = a[pas] - b[pas]
    d = np.where(turns, (d + np.pi) % (2 * np.pi) - np.pi, d)
    return bool(np.max(np.abs(d)) < 1e-6)


def _listed(q: np.ndarray, idx: np.ndarray) -> list[float]:
    return np.round(q[idx], 4).tolist()


#: continuation: the largest change of any coordinate (rad; m at a slider) in one step from
#: a solved pose to the next; a larger move between two samples is taken in several steps
MAX_STEP = 0.05
#: a step whose Newton correction fails (or leaves the predicted neighbourhood) is halved,
#: at most this many times, before the motion is refused
MAX_HALVINGS = 20


class _Loops:
    """The loops' residual and Jacobian at a pose, and Newton on the passive joints."""

    def __init__(self, robot: Robot, act: np.ndarray, pas: np.ndarray):
        self.robot, self.act, self.pas = robot, act, pas
        self.phi = SingleCall(robot.library.functions["constraint"], robot.p)
        self.jac = SingleCall(robot.library.functions["constraint_jacobian"], robot.p)
        self.n, self.m = robot.n, robot.n_constraints

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        (jac,) = self.jac(q)
        return jac.reshape(self.n, self.m).T

    def newton(self, q: np.ndarray) -> tuple[np.ndarray, float]:
        """Newton on the passive joints from ``q``: the pose and its largest |Phi| (m)."""
        q = q.copy()
        for _ in range(NEWTON_MAX_ITER):
            (phi,) = self.phi(q)
            if np.max(np.abs(phi)) < NEWTON_TOL_M:
                break
            jp = self.jacobian(q)[:, self.pas]
            try:
                q[self.pas] -= np.linalg.solve(jp, phi)
            except np.linalg.LinAlgError:  # exactly singular (a five-bar's cranks at 0, 0)
                q[self.pas] -= np.linalg.lstsq(jp, phi, rcond=None)[0]
        return q, float(np.max(np.abs(phi)))

    def close(self, q: np.ndarray, qa: np.ndarray, t, k: int) -> np.ndarray:
        """Newton from ``q``, or WorkspaceError naming sample ``k``."""
        q, residual = self.newton(q)
        if not residual < NEWTON_TOL_M:
            self.refuse_outside(qa, residual, t, k)
        return q

    def refuse_outside(self, qa, residual: float, t, k: int, closed_far: bool = False):
        """WorkspaceError: the loops cannot be closed at ``qa`` (sample ``k``); ``closed_far``:
        Newton closed them only away from where the motion goes on (another solution)."""
        robot = self.robot
        why = (f"Newton closes them (|Phi| = {residual:.3g} m) only at a pose away from where "
               "the motion goes on: another solution, not this motion's" if closed_far
               else f"|Phi| = {residual:.3g} m" if residual >= NEAR_EDGE_M
               # a small residual read as closed in a user trial: say what closed means
               else f"|Phi| = {residual:.3g} m, not below the {NEWTON_TOL_M:g} m of closed loops: "
               "at or just past the edge of the workspace")
        raise WorkspaceError(f"{robot.name}: the loops cannot be closed at {when(t, k)} "
                             f"for actuated coordinates {np.round(qa, 9).tolist()} "
                             f"({', '.join(robot.coordinate_units[i] for i in self.act)}"
                             f"{self.degrees(qa)}) ({why}): outside the workspace")

    def degrees(self, qa) -> str:
        """``; name = D deg`` per revolute actuated coordinate of ``qa`` (rad): a study in
        degrees reads its own numbers (a trial: "[3.141592654] (rad)" for a crank at 180)."""
        said = [f"{self.robot.coordinates[i]} = {math.degrees(v):.6g} deg"
                for i, v in zip(self.act, qa) if self.robot.coordinate_units[i] == "rad"]
        return "; " + ", ".join(said) if said else ""

    def refuse_singular(self, cond: float, at_sample: bool, t, k: int,
                        origin: str | None = None, qa=None) -> None:
        """WorkspaceError for a pose whose Phi_p has 1-norm condition number ``cond`` above
        COND_LIMIT: sample ``k`` itself, or on the way from ``origin`` (default the sample
        before), where the actuated coordinates are ``qa`` (rad; m at a slider)."""
        where = (when(t, k) if at_sample
                 else f"between {origin or when(t, k - 1)} and {when(t, k)}")
        units = ", ".join(self.robot.coordinate_units[i] for i in self.act)
        there = ("" if qa is None else f" (actuated coordinates there: "
                 f"{np.round(qa, 9).tolist()} ({units}{self.degrees(qa)}))")
        raise WorkspaceError(f"{self.robot.name}: singular pose {'at ' if at_sample else ''}"
                             f"{where}: the passive-joint constraint Jacobian Phi_p has "
                             f"1-norm condition number {cond:.3g} > {COND_LIMIT:g}{there}: the "
                             "actuated joints cannot drive the loops through this pose (a dead "
                             "point or limit position, as where a four-bar's crank that is not "
                             "its shortest link stops turning); end the motion short of it, "
                             "or drive another joint")


class _Pose:
    """A solved pose ``q`` and what the next step needs of Phi_p there: its inverse (the
    tangent), its 1-norm condition number and the sign of its determinant (the mode)."""

    def __init__(self, loops: _Loops, q: np.ndarray, jac: np.ndarray | None = None):
        self.q = q
        self.jac = loops.jacobian(q) if jac is None else jac
        jp = self.jac[:, loops.pas]
        self.sign = float(np.sign(np.linalg.det(jp)))
        try:
            self.inv = np.linalg.inv(jp)
            self.cond = float(np.abs(jp).sum(axis=0).max() * np.abs(self.inv).sum(axis=0).max())
        except np.linalg.LinAlgError:  # exactly singular
            self.inv, self.cond = None, np.inf
        self.passed = self.cond  # the largest condition number on the way here (_follow)


def _follow(loops: _Loops, pose: _Pose, qa_to: np.ndarray, t, k: int,
            origin: str | None = None) -> _Pose:
    """From the solved ``pose`` to the actuated coordinates ``qa_to`` of sample ``k``, in the
    assembly mode of ``pose`` (see ``solve_passive``); ``origin`` names where ``pose`` is in
    an error (default the sample before)."""
    act, pas = loops.act, loops.pas
    origin = origin or when(t, k - 1)
    if not pose.cond <= COND_LIMIT:
        loops.refuse_singular(pose.cond, False, t, k, origin, pose.q[act])
    qa_from, sign = pose.q[act].copy(), pose.sign
    span = qa_to - qa_from
    s, ds = 0.0, 1.0 / max(1, int(np.ceil(np.max(np.abs(span)) / MAX_STEP)))
    halvings, residual, passed = 0, 0.0, pose.cond
    while s < 1.0:
        ds = min(ds, 1.0 - s)
        target = qa_from + (s + ds) * span if s + ds < 1.0 else qa_to
        step = target - pose.q[act]
        # the loops' tangent: Phi_p dq_p = -Phi_a dq_a
        dp = -pose.inv @ (pose.jac[:, act] @ step)
        # near a singular pose (condition number ~ 1 / its distance) a step may not reach it:
        # the steps shrink as the pose nears it, so it is met (and refused), never jumped over
        # onto another branch that meets this one there
        too_far = np.max(np.abs(dp)) > MAX_STEP or np.max(np.abs(step)) * pose.cond > 1.0
        if too_far and halvings < MAX_HALVINGS:
            ds, halvings = ds / 2, halvings + 1
            continue
        guess = pose.q.copy()
        guess[act], guess[pas] = target, pose.q[pas] + dp
        trial, residual = loops.newton(guess)
        # accepted: closed, near the prediction (no jump to another solution), same mode
        near = np.max(np.abs(trial[pas] - guess[pas])) <= 0.5 * max(np.max(np.abs(dp)), 1e-6)
        if residual < NEWTON_TOL_M and near:
            new = _Pose(loops, trial)
            if not new.cond <= COND_LIMIT:
                loops.refuse_singular(new.cond, s + ds >= 1.0, t, k, origin, new.q[act])
            if new.sign == sign:
                pose, s, passed = new, s + ds, max(passed, new.cond)
                if halvings:  # the step grows back once the hard part is passed
                    ds, halvings = ds * 2, halvings - 1
                continue
        if halvings >= MAX_HALVINGS:
            break
        ds, halvings = ds / 2, halvings + 1
    else:
        pose.passed = passed
        return pose
    last = _Pose(loops, trial) if residual < NEWTON_TOL_M else None
    if last is not None and not last.cond <= COND_LIMIT:  # Newton closed it there: singular
        loops.refuse_singular(last.cond, s + ds >= 1.0, t, k, origin, last.q[act])
    if last is not None and last.sign != sign:
        robot = loops.robot
        hint = ("; to start in another assembly mode, give a start pose in it (start_pose, "
                "q_guess)") if k == 0 else ""
        raise WorkspaceError(f"{robot.name}: between {origin} and {when(t, k)} the "
                             "passive joints pass a singular pose (det Phi_p changes sign): "
                             "the loops would go on in another assembly mode, so the motion "
                             f"leaves the workspace of the mode it started in{hint}")
    loops.refuse_outside(qa_to, residual, t, k, closed_far=residual < NEWTON_TOL_M)


def complete_rates(robot: Robot, q, qd_act, qdd_act, t=None) -> tuple[np.ndarray, np.ndarray]:
    """Passive rates from the constraints, batched.

    .. code:: text

        Phi_p qd_p = -Phi_a qd_a,    Phi_p qdd_p = gamma - Phi_a qdd_a

    ``q`` (N, n) is on the loops (rad); ``qd_act``, ``qdd_act`` (N, actuated) are the actuated
    rates (rad/s) and accelerations (rad/s^2); ``t`` (N,) times (s) to name in an error.
    Returns ``qd``, ``qdd``, each (N, n), every coordinate. Raises WorkspaceError at a pose
    where Phi_p is singular.
    """
    act, pas = partition(robot)
    q, qd_act, qdd_act = as_sample_set({"q": robot.n, "qd_act": len(act), "qdd_act": len(act)},
                                       {"q": q, "qd_act": qd_act, "qdd_act": qdd_act}, times=t)
    jac = robot.constraint_jacobian(q)
    jac = jac if jac.ndim == 3 else jac[None]
    refuse_singular_matrices(robot.name, jac[:, :, pas],
                             "passive-joint constraint Jacobian Phi_p", t)
    qd = np.zeros_like(q)
    qd[:, act] = qd_act
    qd[:, pas] = np.linalg.solve(jac[:, :, pas], -(jac[:, :, act] @ qd[:, act, None]))[..., 0]
    gamma = robot.constraint_bias(q, qd).reshape(len(q), -1)
    qdd = np.zeros_like(q)
    qdd[:, act] = qdd_act
    qdd[:, pas] = np.linalg.solve(jac[:, :, pas],
                                  (gamma - (jac[:, :, act] @ qdd[:, act, None])[..., 0])[..., None]
                                  )[..., 0]
    return qd, qdd


def from_actuated(robot: Robot, t, q_act, qd_act, qdd_act, q_guess=None) -> JointTrajectory:
    """Full joint motion of a closed chain from its actuated joints' motion (of a fully
    actuated tree: the motion given, as a ``JointTrajectory``).

    Parameters
    ----------
    t : ndarray, shape (N,)
        Times (s), one per sample.
    q_act, qd_act, qdd_act : ndarray, shape (N, actuated)
        The actuated joints' angles (rad), rates (rad/s) and accelerations (rad/s^2).
    q_guess : ndarray, shape (n,), optional
        Where the first sample's Newton starts (default the drawn configuration): its assembly
        mode is kept.
    """
    if t is None:  # (None is solve_passive's "no times")
        raise InputError("t must be the samples' times (s), one per sample of q_act: got None")
    if robot.is_closed_chain:
        q = solve_passive(robot, q_act, q_guess, t)  # t checked there, with q_act
        t = np.asarray(t, dtype=float).reshape(-1)
        qd, qdd = complete_rates(robot, q, qd_act, qdd_act, t)
        return JointTrajectory(t, q, qd, qdd)
    t = as_times(t, len(np.atleast_2d(q_act)), "q_act")
    # a tree (a KeyError on the loop functions a tree has not, before)
    passive = [robot.coordinates[i] for i in range(robot.n) if i not in robot.actuated]
    if passive:
        raise InputError(f"{robot.name}: {', '.join(passive)} passive in a tree: a tree's "
                         "passive joints follow from its dynamics, not from the actuated "
                         "joints' motion (simulate it under their torques)")
    act = list(robot.actuated)
    full = [np.zeros((len(t), robot.n)) for _ in range(3)]
    for f, (k, a) in zip(full, (("q_act", q_act), ("qd_act", qd_act), ("qdd_act", qdd_act))):
        f[:, act] = as_samples(k, a, len(act), times=t)
    return JointTrajectory(t, *full)


def complete_state(robot: Robot, q_act, qd_act, q_guess=None) -> tuple[np.ndarray, np.ndarray]:
    """One state of a closed chain from its actuated joints: every coordinate (n,) on the loops
    (Newton from ``q_guess``, default the drawn configuration) and every rate (n,) from
    ``Phi_q qd = 0``; ``q_act``, ``qd_act`` (actuated,) in rad, rad/s (m, m/s at a slider)."""
    n_act = len(robot.actuated)
    jt = from_actuated(robot, np.zeros(1), np.reshape(q_act, (1, -1)),
                       np.reshape(qd_act, (1, -1)), np.zeros((1, n_act)), q_guess)
    return jt.q[0], jt.qd[0]
