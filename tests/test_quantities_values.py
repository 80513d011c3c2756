"""The table of quantities (``model.description.quantities``) at its edges: each threshold at
its exact value (in or out, as documented), each reading's arithmetic against a hand
computation, and the numbers its messages print. The routes are in test_quantity_routes.py;
these pin the rules themselves (the mutation survivors of issue 30 showed which were loose).
"""

from __future__ import annotations

import math

import pytest

from planar_sym.model.description.quantities import (
    FAR,
    NEAR,
    QUANTITIES,
    doubt,
    inertia_doubt,
    mass_doubt,
    of_parameter,
)
from planar_sym.model.description.types import DENSITY_MAX, G_LIMIT, GYRATION_LIMIT, GYRATION_LOW

Q = QUANTITIES


def test_physical_ranges_at_their_edges():
    assert Q["gravity"].error(0.0) is None and Q["gravity"].error(G_LIMIT) is None
    assert Q["gravity"].error(-1e-300) == "must be from 0 to 300 m/s^2 (got -1e-300)"
    assert Q["gravity"].error(math.nextafter(G_LIMIT, math.inf)) is not None
    assert Q["mass"].error(0.0) == "must be > 0 kg (got 0)"
    assert Q["mass"].error(5e-324) is None
    assert Q["viscous"].error(0.0) is None
    assert Q["viscous"].error(-5e-324) == "must be >= 0 N*m*s/rad (got -4.94066e-324)"
    assert Q["gear_ratio"].error(0.0) == "must be > 0 (got 0)"  # a pure number: no unit
    assert Q["inertia"].error(-1.0, "kg*mm^2") == "must be >= 0 kg*mm^2 (got -1)"
    assert Q["length"].error(-1e9) is None and Q["length"].error(math.nan) == \
        "must be finite (got nan)"


def test_plausible_ranges_at_their_edges():
    lo, hi = Q["mass"].plausible
    assert doubt(Q["mass"], lo) is None and doubt(Q["mass"], hi) is None
    assert "below the plausible 0.0001 kg" in doubt(Q["mass"], math.nextafter(lo, 0))
    assert "above the plausible 10000 kg" in doubt(Q["mass"], math.nextafter(hi, math.inf))
    assert doubt(Q["gravity"], 0.0) is None  # a horizontal robot
    assert doubt(Q["gravity"], 0.00981) == (  # no reading makes it plausible
        "0.00981 m/s^2 (read in m/s^2) is below the plausible 0.1 m/s^2 for a gravity "
        "magnitude; a unit or decimal-point slip?")
    assert doubt(Q["viscous"], 0.0) is None  # a frictionless joint
    assert doubt(Q["length"], 0.0) is None and doubt(Q["length"], -100.0) is None
    assert "above the plausible 100 m" in doubt(Q["length"], -101.0)  # its magnitude
    assert doubt(Q["gear_ratio"], 0.0) is not None  # an error first; a doubt does not crash
    assert doubt(Q["gear_ratio_slider"], 0.0) is not None


def test_far_from_the_robot_s_own_value_at_the_thresholds():
    # exactly FAR times off, a reading within NEAR: the relative rule speaks (the absolute one
    # would say "above the plausible" instead)
    own = 0.5
    msg = doubt(Q["smoothing"], FAR * own, reference=own)
    assert "is 30 times the robot's own 0.5 rad/s" in msg
    assert "In deg/s it would be 0.261799 rad/s" in msg
    low = doubt(Q["viscous"], 0.1, reference=3.0)  # 0.1 / 3 == 1 / FAR exactly
    assert "is 0.03333 times the robot's own 3 N*m*s/rad" in low
    assert "Per deg/s it would be 5.72958 N*m*s/rad" in low
    # a reading landing exactly NEAR times off, either side, still counts
    assert "times the robot's own 1 kg" in doubt(Q["mass"], 3000.0, reference=1.0)
    assert "times the robot's own 3 kg" in doubt(Q["mass"], 1000.0, reference=3.0)
    # just beyond NEAR: no reading explains it, and 3000.1 kg is plausible on its own
    assert doubt(Q["mass"], 3000.1, reference=1.0) is None
    assert doubt(Q["mass"], 999.9, reference=3.0) is None
    # a reading that lands near, for a value that is not far: the relative rule stays silent
    # (1 m/s^2 against the robot's 9.81 is 0.1 times; in g it would be 9.81) and 1 m/s^2 is a
    # plausible gravity
    assert doubt(Q["gravity"], 1.0, reference=9.81) is None
    assert doubt(Q["gravity"], 0.5, reference=9.81) is None  # 0.051 times: still not 1 / 30
    assert (FAR, NEAR) == (30.0, 3.0)


def test_readings_and_their_arithmetic():
    # a value typed in mm/s^2 read as such: 50 mm/s^2 = 0.05 m/s^2; in g it would be 0.49
    msg = doubt(Q["gravity"], 50.0, "mm/s^2")
    assert msg.startswith("50 mm/s^2 (read in mm/s^2, 0.05 m/s^2) is below the plausible 0.1")
    assert "In g (standard gravities) it would be 0.490333 m/s^2" in msg
    assert '"m/s^2"' not in msg  # 50 m/s^2 is not plausible either
    # a slider's gear ratio typed as a screw lead in mm: 2 pi / 0.5e-3 m
    msg = doubt(Q["gear_ratio_slider"], 0.5)
    assert f"As a screw lead in mm it would be {2 * math.pi / 0.5e-3:.6g} rad/m" in msg
    # upside down
    assert "Upside down (joint turns per motor turn) it would be 40" in doubt(Q["gear_ratio"],
                                                                            0.025)
    # the speed readings, each by its own factor
    msg = doubt(Q["motor_speed_rpm"], 2.0)
    assert "In rad/s it would be 19.0986 rpm" in msg
    assert "in thousands of rpm it would be 2000 rpm" in msg
    assert "in rev/s it would be 120 rpm" in msg


def test_parameters_find_their_rows():
    assert of_parameter("g") is Q["gravity"]
    assert of_parameter("m_link1") is Q["mass"] and of_parameter("izz_a") is Q["inertia"]
    assert of_parameter("px_link1_B") is Q["length"] and of_parameter("cgy_a") is Q["length"]
    assert of_parameter("gear_j") is Q["gear_ratio"]
    assert of_parameter("gear_j", "rad/m") is Q["gear_ratio_slider"]
    assert of_parameter("fv_j", "N*s/m") is Q["viscous_slider"]
    assert of_parameter("fc_j", "N") is Q["coulomb_slider"]
    assert of_parameter("vs_j", "m/s") is Q["smoothing_slider"]
    assert of_parameter("fc_j", "N*m") is Q["coulomb"]
    assert of_parameter("s0_slide") is None


def test_a_mass_against_osmium_filling_its_reach():
    most = DENSITY_MAX * 4.0 / 3.0 * math.pi * 0.05 ** 3  # 11.828 kg
    assert mass_doubt(most, "kg", 0.05) is None
    msg = mass_doubt(12.0, "kg", 0.05)
    assert msg == ('12 kg (read in kg) is more than osmium filling the ball its points reach from '
                   'its centre of gravity (50 mm) would weigh (11.83 kg); a slip? In "g" it '
                   'would be 0.012 kg')
    assert mass_doubt(11000.0, "g", 0.05) is None  # 11 kg, read in g
    assert "(read in g, 12000 kg)" in mass_doubt(12e6, "g", 0.05)
    assert mass_doubt(1e9, "kg", 0.0) is None  # a point: no ball
    assert mass_doubt(1e9, "kg", 0.05).endswith("would weigh (11.83 kg); a unit or decimal slip?")


def test_an_inertia_against_its_reach():
    m, reach = 0.075, 0.05
    edge = (GYRATION_LOW * reach) ** 2 * m  # a radius of gyration of exactly 1% of the reach
    assert inertia_doubt(edge, "kg*m^2", m, reach) is None
    msg = inertia_doubt(edge / 4, "kg*m^2", m, reach)
    assert msg.startswith("4.6875e-09 kg*m^2 (read in kg*m^2) gives a radius of gyration of "
                          "0.25 mm, less than 0.01 times the 50 mm its points reach")
    assert msg.endswith("; a unit or decimal slip?")  # every other unit makes it smaller still
    # typed in kg*m^2 where kg*mm^2 is read: the reading in kg*m^2 brings it inside
    msg = inertia_doubt(1e-4, "kg*mm^2", m, reach)
    assert msg.startswith("0.0001 kg*mm^2 (read in kg*mm^2, 1e-10 kg*m^2) gives a radius of "
                          "gyration of 0.03651 mm")
    assert 'In "kg*m^2" it would be 0.0001 kg*m^2' in msg
    assert "kg*cm^2" not in msg  # 1e-8 kg*m^2: a radius of 0.37 mm, still under 0.5 mm
    # a light, short body: the kg*m^2 reading (a radius of 100 mm) is beyond 3 times its 20 mm
    # reach, the kg*cm^2 one (1 mm) inside
    msg = inertia_doubt(1e-4, "kg*mm^2", 0.01, 0.02)
    assert 'In "kg*cm^2" it would be 1e-08 kg*m^2' in msg and '"kg*m^2"' not in msg
    assert inertia_doubt(1e-12, "kg*m^2", 0.0, reach) is None  # no mass: nothing to judge
    assert inertia_doubt(0.0, "kg*m^2", m, reach) is None  # zero inertia: the error's case
    assert inertia_doubt(1e-12, "kg*m^2", m, 0.0) is None  # a point mass
    big = (GYRATION_LIMIT * reach) ** 2 * m
    assert inertia_doubt(big, "kg*m^2", m, reach) is None


@pytest.mark.parametrize("name", sorted(QUANTITIES))
def test_every_row_is_consistent(name):
    q = QUANTITIES[name]
    lo, hi = q.plausible
    assert 0.0 <= lo < hi and (q.signed or q.low <= lo)
    inside = hi if math.isfinite(hi) else lo * 10 or 1.0
    assert q.error(inside) is None and doubt(q, inside) is None
