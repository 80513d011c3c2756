"""Degrees of freedom of a closed chain, counted and measured, and the actuation checked against
them (issue 10). numpy only, like the rest of the description stage.

Counted (Gruebler/Kutzbach for planar chains, every body moving in the plane)::

    F = 3 N - 2 R - 3 W  =  n - 2 c

with N moving bodies, R revolute and prismatic joints (cuts included: one degree of freedom
each), W welds; equivalently n coordinates (revolute and prismatic tree joints) minus 2 per cut
joint c, since each body is the child of one tree joint.
Measured: the rank r of the loop-constraint Jacobian Phi_q (2c x n) at the drawn pose, the
mobility there being n - r. The count equals the mobility exactly when r = 2c.

The rules (each refusal names the joints and the counts):

* r < 2c, the loop equations are dependent: either a constraint is redundant (it stays so as the
  mechanism moves: a parallelogram with an extra parallel link, which Gruebler counts as a
  structure) or the drawn pose is singular (links aligned; a small motion away restores the
  rank). Both are errors: the generated closed-chain functions invert the passive block Phi_p
  and project with (Phi_q Phi_q^T)^-1, which a redundant constraint makes singular everywhere;
  and the drawn pose is where every Newton solve and simulation starts by default.
* F <= 0 with r = 2c: a structure, not a mechanism (nothing moves): error.
* a closed chain with a != F actuated joints: error. More (over-actuated): the motors fight and
  the closed-chain torques are not unique. Fewer, none included (under-actuated, free release):
  the actuated joints do not determine the motion, so there is no closed-chain inverse dynamics
  along their trajectory; and the compiled closed-chain functions are built on the split into
  F actuated and 2c passive coordinates (Phi_p square): such a chain never derived (CasADi
  stopped on a non-square solve), so refusing it here costs nothing that worked.
* a tree (no loop) with passive joints is legitimate: it derives, simulates, and only its
  inverse dynamics refuses at run time, naming the passive joint.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .assembly import ASSEMBLY_TOL_M, close_loops, gap_jacobian, moved_by, tree_angles
from .types import CLOSURE_TOLERANCE_M, GROUND, Body, Joint

#: A singular value of Phi_q (m: a lever arm) below this relative size counts as zero; the same
#: 1e6 condition number at which the runtime refuses a singular pose.
RANK_RTOL = 1e-6
#: How far (rad) the redundancy test moves the mechanism along a null direction of Phi_q.
PROBE_RAD = 0.02


@dataclass(frozen=True)
class Mobility:
    """The degrees of freedom of a described robot (see the module docstring)."""

    coordinates: tuple[str, ...]  # revolute and prismatic tree joints
    cuts: tuple[str, ...]
    welds: int
    moving_bodies: int
    actuated: tuple[str, ...]
    rank: int  # of Phi_q at the drawn pose (0 for a tree)
    singular_values: tuple[float, ...]
    slides: int = 0  # prismatic joints among the coordinates

    @property
    def gruebler(self) -> int:
        """F = 3 N - 2 R - 3 W = n - 2 c."""
        return len(self.coordinates) - 2 * len(self.cuts)

    @property
    def dof(self) -> int:
        """The mobility at the drawn pose, n - rank(Phi_q)."""
        return len(self.coordinates) - self.rank

    def count(self) -> str:
        """The Gruebler count, spelled out for a message: ``F = 3 x 3 moving bodies - 2 x 4
        revolute joints = 3 coordinates - 2 x 1 cut joint (B) = 1``."""
        n, c = len(self.coordinates), len(self.cuts)
        welds = f" - 3 x {self.welds} weld{_s(self.welds)}" if self.welds else ""
        kinds = "revolute and prismatic joints" if self.slides else "revolute joints"
        return (f"F = 3 x {self.moving_bodies} moving bodies - 2 x {n + c} {kinds}"
                f"{welds} = {n} coordinate{_s(n)} - 2 x {c} cut joint{_s(c)} "
                f"({', '.join(self.cuts)}) = {self.gruebler}")


def _s(k: int) -> str:
    return "" if k == 1 else "s"


def _rank(jac: np.ndarray) -> tuple[int, np.ndarray]:
    sv = np.linalg.svd(jac, compute_uv=False) if jac.size else np.zeros(0)
    if not len(sv):
        return 0, sv
    # the typed pose is good to CLOSURE_TOLERANCE_M, so are the lever arms in Phi_q
    tol = max(RANK_RTOL * sv[0], CLOSURE_TOLERANCE_M * math.sqrt(jac.size))
    return int(np.sum(sv > tol)), sv


def phi_q(bodies: dict[str, Body], tree, loops) -> np.ndarray:
    """Phi_q = d gaps / d coordinates at the bodies' placement (2c x n, m)."""
    coords = [j.name for j in tree if j.moves]
    return gap_jacobian(bodies, list(tree), list(loops), moved_by(list(tree)), coords)


def mobility(bodies: dict[str, Body], tree, loops) -> Mobility:
    """The counts and the rank of Phi_q with the bodies as placed (the drawn pose)."""
    coords = tuple(j.name for j in tree if j.moves)
    rank, sv = _rank(phi_q(bodies, tree, loops)) if loops else (0, np.zeros(0))
    return Mobility(coords, tuple(j.name for j in loops), sum(j.type == "weld" for j in tree),
                    len([b for b in bodies if b != GROUND]),
                    tuple(j.name for j in tree if j.moves and j.actuated),
                    rank, tuple(float(s) for s in sv),
                    sum(j.type == "prismatic" for j in tree))


def of(desc) -> Mobility:
    """The Mobility of a validated Description."""
    return mobility(desc.bodies, desc.tree_joints, desc.loop_joints)


def _redundant(bodies, tree, loops, m: Mobility) -> bool:
    """Whether the rank deficiency persists after moving along a null direction of Phi_q and
    closing the loops again (a redundant constraint), rather than vanishing (a singular pose)."""
    jac = phi_q(bodies, tree, loops)
    null = np.linalg.svd(jac)[2][m.rank:]
    start = tree_angles(bodies, tree)
    for v in null:
        for sign in (1, -1):
            trial = dict(start)
            for name, dv in zip(m.coordinates, v / np.max(np.abs(v))):
                trial[name] += sign * PROBE_RAD * dv
            angles, placed, gap, _ = close_loops(bodies, tree, loops, trial, list(m.coordinates))
            moved = max(abs(angles[c] - start[c]) for c in m.coordinates)
            if (np.max(np.abs(gap)) < ASSEMBLY_TOL_M and moved > PROBE_RAD / 4
                    and _rank(phi_q(placed, tree, loops))[0] == m.rank):
                return True
    return False


def _involved(bodies, tree, loops, rank: int) -> list[str]:
    """Cut joints with an equation that the others already imply (removing it keeps the rank)."""
    jac = phi_q(bodies, tree, loops)
    return [cut.name for k, cut in enumerate(loops)
            if any(_rank(np.delete(jac, 2 * k + i, axis=0))[0] == rank for i in (0, 1))]


def problems(bodies: dict[str, Body], tree: list[Joint], loops: list[Joint],
             placed: bool = True) -> list[str]:
    """What is wrong with the degrees of freedom of a robot placed in its drawn pose: [] for a
    tree, or for a closed chain whose loops are independent there and whose F >= 1 joints are
    exactly the actuated ones. Each problem is one line (the field is ``joints``). Not
    ``placed`` (the loops could not be closed): only what the count shows (F <= 0, or more
    actuated joints than F, which is why an assembly holding them fixed fails)."""
    if not loops:
        return []
    if placed and (len(tree) < len(bodies) - 1 or not any(j.moves for j in tree)):
        return []  # bodies off the tree, or no coordinate: the tree stage says so, no count
    m = mobility(bodies, tree, loops) if placed else mobility({}, tree, [])
    if not placed:
        m = Mobility(m.coordinates, tuple(j.name for j in loops), m.welds,
                     len(tree), m.actuated, 2 * len(loops), (), m.slides)
        if m.gruebler > 0 and len(m.actuated) <= m.gruebler:
            return []
    n, c = len(m.coordinates), len(m.cuts)
    if m.rank < 2 * c:
        names = _involved(bodies, tree, loops, m.rank) or list(m.cuts)
        figures = (f"the {2 * c} loop-closure equations of loop{_s(len(names))} "
                   f"{', '.join(names)} have rank {m.rank} at the drawn pose (Phi_q {2 * c} x "
                   f"{n}, smallest singular value {m.singular_values[-1]:.3g} m of "
                   f"{m.singular_values[0]:.3g} m)")
        if _redundant(bodies, tree, loops, m):
            return [(f"redundant constraint: {figures} and keep it as the mechanism moves: it "
                    f"moves with {m.dof} degree{_s(m.dof)} of freedom where {m.count()} (an "
                    "extra link parallel to a parallelogram's, say); remove the redundant link "
                    "or joint: the loop equations must be independent")]
        return [(f"singular drawn pose: {figures}: {m.dof} degrees of freedom there where "
                f"the count gives {m.count()}; links are aligned (a dead-centre or change point): "
                "draw the robot away from it, every Newton solve and simulation starts there")]
    if m.gruebler <= 0:
        rank = (f"Phi_q has full rank {m.rank} at the drawn pose" if placed else
                "the loops cannot be closed either")
        return [(f"a structure, not a mechanism: {m.count()} degrees of freedom and {rank}, so "
                "nothing moves; remove a link, or split one with a joint")]
    a, f = len(m.actuated), m.gruebler
    passive = ", ".join(x for x in m.coordinates if x not in m.actuated)
    dof = f"{m.count()} degree{_s(f)} of freedom"
    if a > f:
        return [(f"over-actuated: {a} actuated joints ({', '.join(m.actuated)}) for {dof}: the "
                "motors fight each other and the closed-chain torques are not unique"
                + ("" if placed else " (and the loops cannot close with them all held at their "
                   "given angles)") + f"; mark {a - f} of them actuated = false")]
    if a == 0:
        return [(f"no actuated joint for {dof}: a free-release closed chain is not supported "
                "(its compiled functions split the coordinates into F actuated and 2 per cut "
                f"passive ones); mark {f} of {passive} actuated = true")]
    if a < f:
        return [(f"under-actuated: {a} actuated joint{_s(a)} ({', '.join(m.actuated)}) for "
                f"{dof}: the actuated joints do not determine the motion, so there is no "
                "closed-chain inverse dynamics along their trajectory (a closed chain needs "
                f"exactly F actuated joints); mark {f - a} of {passive} actuated = true")]
    return []
