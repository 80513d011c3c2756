"""The actuator power columns ``p<k>_w`` of an inverse-dynamics result, by value, on closed
chains whose actuated coordinates are not simply the first ones (the 5-bar's A and E are
coordinates 1 and 3 of 4, the 3-RRR's 1, 4 and 6 of 7, the 3-RPR's sliders 2, 5 and 7 of 7), so
the actuator's index k among the torques and its coordinate i differ:

1. in the written CSV, ``p<i>_w`` equals ``tau<i> * qd<i>`` (the torque column and the rate
   column of the same coordinate, read back from the file) to 1e-14 of the largest power, and
   there is one power column per actuated coordinate and no other;
2. power balance: the actuators are the only forces that work on a frictionless closed chain
   (the loop forces do none), so ``sum_k p_k = d/dt (T + V)`` along the motion; the rate of
   the robot's energy comes from ``robot.energy`` at times shifted by +-h, +-2h (h = 0.25 ms,
   fourth-order central difference; the motion recomputed at each shifted time as the study
   makes it), at interior samples (the cubic profile's acceleration jumps at its ends).
   Measured 3e-11 (3-RRR), 5e-11 (5-bar), 7e-10 (3-RPR) of the largest power (5 to 12 mW);
   asserted 1e-8.

The power of actuator k taken with the rate of coordinate k instead of its own coordinate
breaks both (by about 1 relative).
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import study_motion

import planar_sym as ps
from planar_sym.study.result import coordinate_column
from planar_sym.study.run import run

STUDIES = ("five_bar_type1_move_x", "parallel_3rrr_move_x", "parallel_3rpr_move_x")
SAMPLES = 41
H = 2.5e-4  # s
BALANCE_TOL = 1e-8  # relative to the largest power; measured 3e-11 to 7e-10
COLUMN_TOL = 1e-14


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    """Each study run at SAMPLES samples, written as CSV and read back: name -> (result,
    structured array of the CSV's columns)."""
    out = {}
    folder = tmp_path_factory.mktemp("power")
    for name in STUDIES:
        result = run(name, SAMPLES)
        (path,) = ps.write_result(result, folder, plot=False)
        out[name] = result, np.genfromtxt(path, delimiter=",", names=True)
    return out


@pytest.mark.parametrize("name", STUDIES)
def test_each_power_column_is_its_own_coordinates_torque_times_rate(name, written):
    """Reference: tau<i> and qd<i> of the same CSV, multiplied here."""
    result, data = written[name]
    robot = ps.load(result.robot)
    units = robot.coordinate_units
    assert list(robot.actuated) != list(range(len(robot.actuated)))  # k and i differ
    powers = {c for c in data.dtype.names if c.startswith("p") and c.endswith("_w")}
    assert powers == {f"p{i + 1}_w" for i in robot.actuated}
    scale = max(np.abs(data[c]).max() for c in powers)
    assert scale > 1e-3  # W: the actuators do work in these moves
    for i in robot.actuated:
        tau = data[coordinate_column("tau", i, units[i])]
        rate = data[coordinate_column("qd", i, units[i])]
        err = np.abs(data[f"p{i + 1}_w"] - tau * rate).max()
        assert err <= COLUMN_TOL * scale, (f"p{i + 1}_w", err / scale)


@pytest.mark.parametrize("name", STUDIES)
def test_the_actuators_power_is_the_rate_of_the_robots_energy(name, written):
    """Reference: d/dt (T + V) from robot.energy along the study's own motion."""
    _, data = written[name]
    t = data["t_s"][2:-2]  # interior: the cubic's acceleration jumps at t = 0 and T
    robot = study_motion(name, t)[0]  # with the study's parameters, if it sets any

    def energy(shift):
        _, _, jt = study_motion(name, t + shift)
        kinetic, potential = robot.energy(jt.q, jt.qd)
        return kinetic + potential

    de_dt = (energy(-2 * H) - 8 * energy(-H) + 8 * energy(H) - energy(2 * H)) / (12 * H)
    power = sum(data[f"p{i + 1}_w"][2:-2] for i in robot.actuated)
    scale = np.abs(power).max()
    assert scale > 1e-3  # W
    err = np.abs(power - de_dt).max() / scale
    assert err < BALANCE_TOL, err
