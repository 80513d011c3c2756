"""The continuation of a closed chain's passive joints from one solved pose to the next
(``solve_passive`` runs it sample to sample): a tangent predictor along the loops, Newton's
correction, steps that shrink near a singular pose so it is met and refused rather than jumped
over, and what the steps met between the samples.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import WorkspaceError, warn_caller
from ..model.arrays import when
from ..model.library import SingleCall
from ..model.loops import COND_LIMIT, COND_WARN
from ..model.robot import Robot

#: Newton on Phi(q) = 0 stops below this residual (m); far under the 1e-9 m the tests demand.
NEWTON_TOL_M = 1e-13
NEWTON_MAX_ITER = 30
#: a residual Newton stalls at below this (m) is named as near the workspace's edge
NEAR_EDGE_M = 1e-6
#: continuation: the largest change of any coordinate (rad; m at a slider) in one step from
#: a solved pose to the next; a larger move between two samples is taken in several steps
MAX_STEP = 0.05
#: a step whose Newton correction fails (or leaves the predicted neighbourhood) is halved,
#: at most this many times, before the motion is refused
MAX_HALVINGS = 20


class Loops:
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


class Pose:
    """A solved pose ``q`` and what the next step needs of Phi_p there: its inverse (the
    tangent), its 1-norm condition number and the sign of its determinant (the mode)."""

    def __init__(self, loops: Loops, q: np.ndarray, jac: np.ndarray | None = None):
        self.q = q
        self.jac = loops.jacobian(q) if jac is None else jac
        jp = self.jac[:, loops.pas]
        self.sign = float(np.sign(np.linalg.det(jp)))
        try:
            self.inv = np.linalg.inv(jp)
            self.cond = float(np.abs(jp).sum(axis=0).max() * np.abs(self.inv).sum(axis=0).max())
        except np.linalg.LinAlgError:  # exactly singular
            self.inv, self.cond = None, np.inf
        self.passed = self.cond  # the largest condition number on the way here (follow)


def follow(loops: Loops, pose: Pose, qa_to: np.ndarray, t, k: int,
            origin: str | None = None) -> Pose:
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
            new = Pose(loops, trial)
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
    last = Pose(loops, trial) if residual < NEWTON_TOL_M else None
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


def warn_between_samples(name: str, cond: np.ndarray, passed: np.ndarray, t) -> None:
    """Warn where Phi_p's condition number on the way to a sample (``passed``, (N,)) is above
    COND_WARN while every sample's (``cond``) is below: torques and loads, which grow like it,
    peak between the samples (a trial's four-bar near its change point: 0.34 N*m peak at 101
    samples, 137 at 100001, no word). Finer samplings see it at the samples themselves."""
    if len(cond) < 2 or cond.max() > COND_WARN or passed.max() <= COND_WARN:
        return
    k = int(np.argmax(passed))
    warn_caller(f"{name}: between {when(t, k - 1)} and {when(t, k)} the loops pass near a "
                f"singular pose (Phi_p's 1-norm condition number {passed[k]:.3g} there, at "
                f"most {cond.max():.3g} at the samples): torques and joint loads peak between "
                "the samples, so the peaks reported are too low; more samples resolve them")
