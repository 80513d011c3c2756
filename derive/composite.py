"""The mass matrix by composite bodies (Featherstone's CRBA, planar): the numeric route's M.

Differentiating the momentum (``M = dp/dqd``) costs about three times the operations of
summing each joint's subtree once and reading every entry off it. Per moving joint k, the
bodies beyond it form one composite: its mass ``M_k``, first moment ``h_k`` and inertia ``J_k``
about a reference point ``r_k`` (the joint's point for a revolute joint). Each composite is its
body plus its children's composites shifted to ``r_k``, so the sums cost O(n) for the tree, and
every entry one dot product (z x v is the vector v turned by +90 degrees):

.. code:: text

    J_k = sum (Izz_b + m_b |c_b - r_k|^2),  h_k = sum m_b (c_b - r_k),  M_k = sum m_b
    M_kk = J_k (revolute), M_k (prismatic);  for i a moving joint above k:
    M_ik = J_k + (r_k - p_i) . h_k           (revolute i, revolute k)
         = (z x (h_k + M_k (r_k - p_i))) . u_k  (revolute i, prismatic k, axis u_k)
         = u_i . (z x h_k)                  (prismatic i, revolute k)
         = M_k u_i . u_k                    (prismatic i, prismatic k)

Shifted to the joints rather than summed about the world origin, the terms stay of the robot's
size wherever it stands (no large |c|^2 cancelling). Three things keep the operations down:

* a distance within one body is the same in its own frame, so ``|c_b - r_k|^2`` and a rigid
  child's ``|r_child - r_k|^2`` are sums of parameters (gcc reads them once per block of
  samples, outside the loop), and ``c_b - r_k``, ``r_child - r_k`` one rotation each;
* a revolute-revolute entry is ``B_k - P_i . h_k`` with ``B_k = J_k + R_k . h_k``, the points
  ``R_k``, ``P_i`` taken from the chain's root joint ``o`` (``R_k = r_k - o``): four operations
  an entry instead of six, of the robot's size still, for ``|r - o|`` is within its reach.
  At 20 links the matrix costs 40 % fewer operations than summing ``J_k + (r_k - p_i) . h_k``. A rotor turns at w_stator + N qd_k, its
stator on the joint's parent body, so it adds ``J_m v v^T`` with v = 1 on every revolute joint
above that body and N on its own: the ones-part is the stator body spinning a little heavier
(``J_m`` added to its composite's inertia), the rest ``N J_m`` beside the revolute joints above
and ``N^2 J_m`` on the diagonal.
``tests/test_composite_mass_matrix.py`` checks it against ``dp/dqd`` to 1e-13.
"""

from __future__ import annotations

import casadi as ca

from planar_sym.model.description import GROUND, Description

from .recursion import Tree, cross_z


def mass_matrix(desc: Description, tree: Tree) -> ca.SX:
    """M(q) (n x n, SX in ``tree.sym``) of the tree, rotors included."""
    s = tree.sym
    joint_of = {j.child: j for j in desc.tree_joints}
    children: dict[str, list[str]] = {}
    for j in desc.tree_joints:
        children.setdefault(j.parent, []).append(j.child)
    moving = [j for j in desc.tree_joints if j.moves]
    index = {j.name: k for k, j in enumerate(moving)}
    rotors = {j.name: (s.param(f"jm_{j.name}"), s.param(f"gear_{j.name}", 1.0))
              for j in moving if j.actuator is not None and s.has(f"jm_{j.name}")}
    stators: dict[str, ca.SX] = {}  # body -> the rotor inertia its stators carry
    for j in moving:
        if j.name in rotors:
            stators[j.parent] = stators.get(j.parent, ca.SX(0.0)) + rotors[j.name][0]

    # each joint's point and slide axis built once: SX repeats an expression built twice
    point = {j.name: tree.at(j.parent, j.parent_point) for j in desc.tree_joints}
    axis = {j.name: tree.slide_axis(j) for j in moving if j.type == "prismatic"}

    def reference(body: str) -> ca.SX:
        """Where a body's composite is summed: its joint's point (on the slider's block for a
        prismatic joint, which moves with it)."""
        j = joint_of[body]
        return tree.at(j.child, j.child_point) if j.type == "prismatic" else point[j.name]

    def local(body: str, point_name: str | None, ref: tuple) -> tuple:
        """A body point (the cg for None) less the body's reference point, in its own frame:
        parameters only."""
        x, y = tree.body_vec(body, point_name)
        return (x - ref[0], y - ref[1])

    composite: dict[str, tuple[ca.SX, ca.SX, ca.SX, ca.SX]] = {}
    for j in reversed(desc.tree_joints):  # children before parents
        body, r = j.child, reference(j.child)
        frame, ref = tree.frames[body], tree.body_vec(body, j.child_point)
        m = s.param(f"m_{body}")
        c = local(body, None, ref)
        inertia = s.param(f"izz_{body}") + m * (c[0] * c[0] + c[1] * c[1]) + stators.get(body, 0.0)
        mass, moment = m, m * frame.rotate(c)
        for child in children.get(body, []):
            mc, hc, ic, rc = composite[child]
            if joint_of[child].type == "prismatic":  # the block slides: its reference moves on this body
                d = rc - r
                dd = ca.dot(d, d)
            else:  # the child's joint is a point of this body
                dl = local(body, joint_of[child].parent_point, ref)
                d, dd = frame.rotate(dl), dl[0] * dl[0] + dl[1] * dl[1]
            mass, moment = mass + mc, moment + hc + mc * d
            inertia = inertia + ic + 2 * ca.dot(d, hc) + mc * dd
        composite[body] = (mass, moment, inertia, r)

    def moving_above(body: str) -> list:
        """The moving joints between the ground and ``body``, nearest first."""
        out, j = [], joint_of.get(body)
        while j is not None:
            if j.moves:
                out.append(j)
            j = joint_of.get(j.parent)
        return out

    def root(j) -> ca.SX:
        """The point of the joint that carries ``j``'s chain from the ground."""
        while j.parent != GROUND:
            j = joint_of[j.parent]
        return point[j.name]

    # revolute-revolute entries as B_k - P_i . h_k, points from the chain's root joint
    from_root = {j.name: point[j.name] - root(j) for j in moving if j.type == "revolute"}
    shifted = {}
    for j in moving:
        mk, hk, jk, rk = composite[j.child]
        if j.type == "revolute":
            shifted[j.name] = jk + ca.dot(rk - root(j), hk)

    n = len(moving)
    M = ca.SX(n, n)
    for k, j in enumerate(moving):
        mk, hk, jk, rk = composite[j.child]
        u_k = axis.get(j.name)
        M[k, k] = jk if u_k is None else mk
        for a in moving_above(j.parent):
            i = index[a.name]
            if a.type == "revolute" and u_k is None:
                v = shifted[j.name] - ca.dot(from_root[a.name], hk)
            elif a.type == "revolute":
                v = ca.dot(cross_z(hk + mk * (rk - point[a.name])), u_k)
            else:
                u_i = axis[a.name]
                v = ca.dot(u_i, cross_z(hk)) if u_k is None else mk * ca.dot(u_i, u_k)
            if a.type == "revolute" and j.name in rotors:  # the rotor's N J_m beside
                v = v + rotors[j.name][0] * rotors[j.name][1]
            M[i, k] = v
            M[k, i] = v
        if j.name in rotors:
            jm, gear = rotors[j.name]
            M[k, k] = M[k, k] + jm * gear * gear
    return M
