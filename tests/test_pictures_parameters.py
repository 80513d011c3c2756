"""Pictures of a robot whose parameters were changed show the machine the dynamics sees.

A user trial: ``with_parameters(px_link1_CS2=0.15)`` (a study's ``[parameters]``, a control
study's plant, a sweep's design) moved joint 2 to 0.15 m while the drawing kept the
description's 0.1 m upper arm, so the links came apart in every picture. Every picture now takes
its points from ``model.described`` (the description with the robot's values). Checked by the
geometry: each joint's two points coincide in world coordinates, and the drawn tool equals the
robot's own forward kinematics and a1 cos q1 + a2 cos(q1 + q2) by hand.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.model.described import described
from planar_sym.model.description import load as load_description
from planar_sym.outputs.animation import scene_figure
from planar_sym.outputs.drawing import geometry
from planar_sym.study.run import motion_and_reference

ROOT = Path(__file__).resolve().parent.parent
Q = np.random.default_rng(7).uniform(-3.0, 3.0, (9, 2))


def joint_gaps(robot, desc, q) -> float:
    """The largest distance (m) between the two points a joint holds together, over ``q``."""
    geo = geometry(desc, robot.body_names, robot.frames(q))
    return max(float(np.max(np.hypot(*(geo.points[(j.parent, j.parent_point)]
                                       - geo.points[(j.child, j.child_point)]).T)))
               for j in desc.tree_joints if j.type != "prismatic")


@pytest.mark.parametrize("changes", [{"px_link1_CS2": 0.15},
                                     {"px_link1_CS2": 0.07, "px_link2_CS2": 0.21,
                                      "cgx_link2": 0.12}])
def test_a_changed_robot_is_drawn_with_its_own_values(changes):
    robot = ps.load("serial_2dof").with_parameters(**changes)
    desc = described(robot)
    assert joint_gaps(robot, desc, Q) < 1e-15
    geo = geometry(desc, robot.body_names, robot.frames(Q))
    x, y = robot.task(Q)[0].T[:2]
    tool = geo.points[("link2", "CS2")]
    np.testing.assert_allclose(tool, np.column_stack([x, y]), rtol=0, atol=1e-15)
    a1, a2 = robot.parameters["px_link1_CS2"], robot.parameters["px_link2_CS2"]
    by_hand = np.column_stack([a1 * np.cos(Q[:, 0]) + a2 * np.cos(Q.sum(axis=1)),
                               a1 * np.sin(Q[:, 0]) + a2 * np.sin(Q.sum(axis=1))])
    np.testing.assert_allclose(tool, by_hand, rtol=0, atol=1e-15)
    c2 = robot.parameters["cgx_link2"]
    by_hand_cg = np.column_stack([a1 * np.cos(Q[:, 0]) + c2 * np.cos(Q.sum(axis=1)),
                                  a1 * np.sin(Q[:, 0]) + c2 * np.sin(Q.sum(axis=1))])
    np.testing.assert_allclose(geo.cgs["link2"], by_hand_cg, rtol=0, atol=1e-15)
    # the description's own values (the bug): the upper arm's end is off joint 2 by the change
    gap = joint_gaps(robot, load_description(robot.description_file), Q)
    assert gap == pytest.approx(abs(changes["px_link1_CS2"] - 0.1), abs=1e-12)


def test_exports_and_pictures_share_the_values():
    """The MJCF and URDF exports took the same values by a routine of their own (now this one):
    their bodies equal the drawing's."""
    from planar_sym.outputs.export_model import from_robot

    robot = ps.load("serial_2dof").with_parameters(px_link1_CS2=0.15, m_link2=0.2)
    model, desc = from_robot(robot), described(robot)
    assert model.bodies == desc.bodies
    assert desc.bodies["link1"].points_m["CS2"] == (0.15, 0.0)
    assert desc.bodies["link2"].mass_kg == 0.2


def test_a_control_studys_animation_draws_the_plant_and_the_models_reference(tmp_path):
    """The plant's upper arm is 0.11 m, the controller's model's 0.1 m: the animation moves the
    plant (its tool where its geometry puts it, as the CSV's x, y) and draws the reference as
    the model's plan."""
    text = (ROOT / "planar_sym" / "studies" / "serial_2dof_cartesian_track.toml").read_text()
    path = tmp_path / "long_arm.toml"
    path.write_text(text.replace("m_link2 = 0.09              # kg (the controller assumes "
                                 "0.075)", "px_link1_CS2 = 0.11").split("[outputs]")[0])
    robot, t, q, (model, q_ref) = motion_and_reference(path, 7)
    assert robot.parameters["px_link1_CS2"] == 0.11
    assert model.parameters["px_link1_CS2"] == 0.1
    fig, _ = scene_figure(robot, t, q, "plant", reference=(model, q_ref))
    (ax,) = fig.axes
    path_line = next(ln for ln in ax.lines if ln.get_linestyle() == ":")  # the tool's whole path
    scale = 1.0  # serial_2dof is typed in m: drawn in m
    a1, a2 = 0.11, 0.1
    np.testing.assert_allclose(np.column_stack(path_line.get_data()) / scale,
                               np.column_stack([a1 * np.cos(q[:, 0]) + a2 * np.cos(q.sum(1)),
                                                a1 * np.sin(q[:, 0]) + a2 * np.sin(q.sum(1))]),
                               rtol=0, atol=1e-12)
    # the upper arm ends at joint 2 in both drawings: the plant's 0.11 m, the ghost's 0.1 m
    vertices = np.concatenate([np.column_stack(ln.get_data()) for ln in ax.lines
                               if len(ln.get_xdata()) and ln.get_linestyle() != ":"]) / scale

    def drawn(xy) -> bool:
        return bool(np.min(np.hypot(*(vertices - xy).T)) < 1e-12)

    assert drawn(0.11 * np.array([np.cos(q[0, 0]), np.sin(q[0, 0])]))
    assert drawn(0.1 * np.array([np.cos(q_ref[0, 0]), np.sin(q_ref[0, 0])]))
    assert not drawn(0.1 * np.array([np.cos(q[0, 0]), np.sin(q[0, 0])]))
    import matplotlib.pyplot as plt

    plt.close(fig)
