"""assemble = true: a closed chain typed with approximate world points has its loops closed
numerically (the passive joints move, the actuated ones keep their angles), checked against
the four-bar's closed-form position solution; an impossible one is refused naming the loop."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import DescriptionError
from planar_sym.model.description import load

FOUR_BAR = Path(__file__).resolve().parent.parent / "examples" / "four_bar.toml"
EXACT_B = "B = [133.880965996, 72.471236661]"


def approximate(tmp_path: Path, coupler_b: str, rocker_b: str, assemble: bool = True) -> Path:
    """The example four-bar with its B points typed roughly (mm)."""
    text = FOUR_BAR.read_text()
    assert text.count(EXACT_B) == 2
    text = text.replace(EXACT_B, f"B = [{coupler_b}]", 1).replace(EXACT_B, f"B = [{rocker_b}]", 1)
    if assemble:
        text = text.replace('name = "four_bar"', 'name = "four_bar"\nassemble = true')
    path = tmp_path / "four_bar_rough.toml"
    path.write_text(text)
    return path


def world(body, point) -> np.ndarray:
    x, y = body.points_m[point]
    c, s = math.cos(body.drawn_angle_rad), math.sin(body.drawn_angle_rad)
    return np.array(body.drawn_origin_m) + [c * x - s * y, s * x + c * y]


def test_rough_points_assemble_to_the_closed_form_pose(tmp_path):
    desc = load(approximate(tmp_path, "135.0, 71.0", "132.5, 73.5"))
    b = desc.bodies
    gap = world(b["coupler"], "B") - world(b["rocker"], "B")
    assert np.max(np.abs(gap)) < 1e-12
    # the crank (actuated) keeps its angle; B is where the circles about A and O4 meet
    exact = load(FOUR_BAR)
    assert b["crank"].drawn_angle_rad == exact.bodies["crank"].drawn_angle_rad
    A, O4 = world(b["crank"], "A"), np.array(b["ground"].points_m["O4"])
    rb = np.hypot(*b["coupler"].points_m["B"])  # the coupler's A-B length as typed
    rc = np.hypot(*b["rocker"].points_m["B"])
    d = np.linalg.norm(O4 - A)
    along = (rb**2 - rc**2 + d**2) / (2 * d)
    u = (O4 - A) / d
    n = np.array([-u[1], u[0]])
    h = math.sqrt(rb**2 - along**2)
    candidates = [A + along * u + h * n, A + along * u - h * n]
    near = min(candidates, key=lambda p: np.linalg.norm(p - world(exact.bodies["rocker"], "B")))
    assert np.max(np.abs(world(b["rocker"], "B") - near)) < 1e-10
    report = desc.assembly.report()
    assert "loop B: gap" in report and "point rocker.B moved" in report


def test_the_assembled_robot_derives_and_runs(tmp_path):
    robot = ps.load(approximate(tmp_path, "135.0, 71.0", "132.5, 73.5"))
    assert np.max(np.abs(robot.constraint(robot.q_drawn))) < 1e-12
    motion = ps.from_actuated(robot, [0.0, 0.1], robot.q_drawn[[0]] + np.array([[0.0], [0.1]]),
                              np.zeros((2, 1)), np.zeros((2, 1)))
    tau, _ = robot.closed_chain_inverse_dynamics(motion.q, motion.qd, motion.qdd)
    assert np.all(np.isfinite(tau))


def test_without_assemble_the_gap_is_an_error_with_a_hint(tmp_path):
    with pytest.raises(DescriptionError, match="set assemble = true to let planar-sym close it"):
        load(approximate(tmp_path, "135.0, 71.0", "132.5, 73.5", assemble=False))


def test_a_loop_that_cannot_close_is_refused_naming_it(tmp_path):
    """A coupler 2.4 mm long cannot reach from A to the rocker: refused, with the gap."""
    with pytest.raises(DescriptionError, match=r"joints \(B\): loop B cannot be closed from the "
                                               r"given pose: its points stay [0-9.]+ mm apart"):
        load(approximate(tmp_path, "22.0, 36.0", "132.5, 73.5"))
