"""A MuJoCo model of a description's spanning tree, for mj_inverse and RK4.

The MJCF text comes from the package's writer, ``planar_sym.outputs.export_mjcf.mjcf`` (the
one ``planar-sym export --format mjcf`` uses), fed the description's own values and without the
user file's header comment, visual geoms and motors. Construction (detailed there), generic
over the description (the spanning tree; with ``loops=True`` each revolute loop joint becomes
a ``connect`` equality constraint between two sites, see below):

* every description body becomes an MJCF body whose frame *is* that body's frame, so MuJoCo's
  ``qpos`` equals planar_sym's ``q`` (child frame angle minus parent frame angle);
* a revolute joint: child body at ``parent_point - child_point`` in the parent's frame (the
  drawn configuration, where q = 0 means "aligned with the parent"), ``hinge`` at the child
  point, axis z; a prismatic joint a ``slide`` along its axis; a weld: a joint-less child
  body, rotated by the drawn relative angle;
* ``inertial``: mass, ``pos`` = centre of gravity, ``diaginertia = izz/2, izz/2, izz``. MuJoCo
  demands ``ixx + iyy >= izz`` (triangle inequality), so tiny ixx/iyy are refused; a thin
  lamina's ``izz/2`` each satisfy it and never enter the dynamics (every angular velocity is
  along z);
* gravity ``[gx, gy, 0]``; no geoms; joint damping, armature, stiffness and friction loss are
  zero (MuJoCo's defaults), and ``opt.disableflags`` turns off contacts, constraints, limits,
  equality, friction loss and passive forces so nothing but the rigid-body dynamics acts.

Closed chains (``loops=True``): a site at each loop joint's point on its parent body and one
on its child body, and ``<equality><connect site1=... site2=.../>`` holding the two together.
MuJoCo's equality constraints are soft (``solref``, ``solimp``: a spring-damper towards the
constraint, solved with the other constraint forces at every evaluation), so the loop closes
only approximately; the constraint and equality flags stay enabled in that model. A
``connect`` holds x, y and z; in a planar model its z row is identically satisfied.
"""

from __future__ import annotations

import numpy as np

from planar_sym.model.description import Description
from planar_sym.outputs import export_mjcf
from planar_sym.outputs.export_model import from_description


def mjcf(desc: Description, *, timestep: float = 1e-3, loops: bool = False,
         solref: tuple[float, float] | None = None,
         solimp: tuple[float, ...] | None = None) -> str:
    """The MJCF text of the description's spanning tree; with ``loops``, its loop joints as
    ``connect`` equality constraints (``solref``/``solimp``: MuJoCo's softness, default
    MuJoCo's own). Written by the package's MJCF writer (``planar_sym.outputs.export_mjcf``)
    from the description's own values, without the user file's header, geoms and motors."""
    return export_mjcf.mjcf(from_description(desc), timestep=timestep, loops=loops,
                            solref=solref, solimp=solimp)


def build(desc: Description, *, timestep: float = 1e-3, loops: bool = False,
          solref: tuple[float, float] | None = None, solimp: tuple[float, ...] | None = None):
    """(mujoco.MjModel, mujoco.MjData) with everything but rigid-body dynamics disabled; with
    ``loops``, the loop joints' equality constraints stay on (see ``mjcf``)."""
    import mujoco

    closed = loops and bool(desc.loop_joints)
    model = mujoco.MjModel.from_xml_string(mjcf(desc, timestep=timestep, loops=closed,
                                                solref=solref, solimp=solimp))
    off = mujoco.mjtDisableBit
    flags = ["mjDSBL_CONTACT", "mjDSBL_LIMIT", "mjDSBL_FRICTIONLOSS", "mjDSBL_PASSIVE",
             "mjDSBL_SPRING", "mjDSBL_DAMPER"]
    if not closed:
        flags += ["mjDSBL_CONSTRAINT", "mjDSBL_EQUALITY"]
    for flag in flags:
        if hasattr(off, flag):  # PASSIVE was split into SPRING and DAMPER in MuJoCo 3.x
            model.opt.disableflags |= int(getattr(off, flag))
    assert model.nq == model.nv == len(desc.coordinates)
    # qpos follows the description's coordinates (depth-first order of the tree joints)
    names = [model.joint(k).name for k in range(model.njnt)]
    assert names == list(desc.coordinates), (names, desc.coordinates)
    assert not model.dof_damping.any() and not model.dof_armature.any()
    assert model.neq == (len(desc.loop_joints) if closed else 0)
    return model, mujoco.MjData(model)


def mass_matrix_filler(model, data, out: np.ndarray):
    """A function of no arguments writing MuJoCo's dense mass matrix (of the last forward pass,
    or of the RK4 stage being evaluated) into ``out`` (n, n): ``mj_fullM`` takes (m, d, dst)
    since MuJoCo 3.3 and (m, dst, d.qM) before; which one is found once, here."""
    import mujoco

    full = mujoco.mj_fullM
    try:
        full(model, data, out)
        return lambda: full(model, data, out)
    except TypeError:
        qm = data.qM
        full(model, out, qm)
        return lambda: full(model, out, qm)


def inverse_loop(model, data, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """``mj_inverse`` sample by sample in a Python loop (views bound once); (N, n) in and out."""
    import mujoco

    out = np.empty_like(q)
    qpos, qvel, qacc, frc = data.qpos, data.qvel, data.qacc, data.qfrc_inverse
    inverse = mujoco.mj_inverse
    for k in range(len(q)):
        qpos[:] = q[k]
        qvel[:] = qd[k]
        qacc[:] = qdd[k]
        inverse(model, data)
        out[k] = frc
    return out


def simulate_rk4(model, data, q0, qd0, t_end: float, dt: float, n_out: int = 101):
    """MuJoCo's RK4 from (q0, qd0), zero control, over [0, t_end] in ``round(t_end / dt)``
    equal steps (the step is adjusted so the last step lands exactly on ``t_end``).

    Returns (t, q, qd) at ``n_out`` steps spread over the run (the first at t = 0, the last at
    t_end), and the step actually used.
    """
    import mujoco

    steps = max(1, round(t_end / dt))
    model.opt.timestep = t_end / steps
    model.opt.integrator = int(mujoco.mjtIntegrator.mjINT_RK4)
    mujoco.mj_resetData(model, data)
    data.qpos[:] = q0
    data.qvel[:] = qd0
    marks = np.unique(np.round(np.linspace(0, steps, n_out)).astype(int))
    q = np.empty((len(marks), model.nq))
    qd = np.empty((len(marks), model.nv))
    q[0], qd[0] = data.qpos, data.qvel
    step = mujoco.mj_step
    qpos, qvel = data.qpos, data.qvel
    k = 1
    for i in range(1, steps + 1):
        step(model, data)
        if i == marks[k]:
            q[k], qd[k] = qpos, qvel
            k += 1
    return marks * model.opt.timestep, q, qd, model.opt.timestep
