"""The run-time parameter rules (``model.parameters``) pinned: one message per mistake, the
slider's units in its messages, gravity's wording at its bounds, every body checked after a
bad one, a body's reach computed by hand (its own points only, not a longer-named body's), the
doubts' one warning per slip, and the sweep's column-wise rules (``failing``) row for row equal
to the scalar ones on random designs of a robot with a slider (issue 30: the survivors of the
first mutation run of parameters.py showed which of these were unpinned)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import TEST_ROBOTS

import planar_sym as ps
from planar_sym.model import parameters as P


@pytest.fixture(scope="module")
def rpr():
    return ps.load(TEST_ROBOTS / "rpr_geared.toml")


def test_one_message_per_mistake_and_every_body_checked():
    bodies = ("a", "b")
    values = {"m_a": -1.0, "izz_a": 0.1, "m_b": 0.0, "izz_b": -2.0, "cgx_a": 0.0}
    assert P.problems(values, bodies) == ["parameter m_a must be > 0 kg (got -1)",
                                          "parameter m_b must be > 0 kg (got 0)"]
    values = {"m_a": 1.0, "izz_a": -0.5, "m_b": 1.0, "izz_b": -2.0}
    assert P.problems(values, bodies) == ["parameter izz_a must be >= 0 kg*m^2 (got -0.5)",
                                          "parameter izz_b must be >= 0 kg*m^2 (got -2)"]
    assert P.problems({"m_a": 1.0, "izz_a": 0.0}, ("a",)) == []  # a point mass: no extent


def test_a_slider_s_rules_speak_its_units():
    units = {"fc_s": "N", "fv_s": "N*s/m", "vs_s": "m/s", "gear_s": "rad/m", "fc_r": "N*m"}
    values = {"fc_s": -1.0, "fv_s": -2.0, "vs_s": 0.0, "gear_s": -3.0, "fc_r": -4.0}
    assert P.problems(values, (), units) == [
        "parameter fc_s (Coulomb friction) must be >= 0 N (got -1)",
        "parameter fv_s (viscous friction) must be >= 0 N*s/m (got -2)",
        "parameter vs_s (Coulomb smoothing speed) must be > 0 m/s (got 0)",
        "parameter gear_s (gear ratio) must be > 0 rad/m (got -3)",
        "parameter fc_r (Coulomb friction) must be >= 0 N*m (got -4)"]


def test_gravity_at_its_bounds():
    assert P.problems({"g": 0.0}, ()) == [] and P.problems({"g": 300.0}, ()) == []
    assert P.problems({"g": -1.0}, ()) == [
        "parameter g (gravity magnitude) must be from 0 to 300 m/s^2 (got -1)"]
    assert P.problems({"g": 300.5}, ()) == [
        "parameter g (gravity magnitude) must be from 0 to 300 m/s^2 (got 300.5); a unit slip?"]
    assert P.problems({"g": math.nan}, ()) == ["parameter g must be finite (got nan)"]


def test_a_body_s_reach_is_its_own_points_from_its_cg():
    values = {"cgx_link": 0.04168, "px_link_B": 0.1, "py_link_B": 0.0,
              "px_link_2_C": 5.0, "cgx_link_2": 0.0}
    bodies = ("link", "link_2")
    # link: origin (0, 0) and B (0.1, 0) from its cg at 0.04168: 0.05832 m; link_2's C is not
    # link's although its name starts with "link_"
    assert P._extent(values, "link", bodies) == pytest.approx(0.1 - 0.04168, abs=1e-15)
    assert P._extent(values, "link_2", bodies) == pytest.approx(5.0, abs=1e-15)
    values["cgy_link"] = 0.03
    assert P._extent(values, "link", bodies) == pytest.approx(math.hypot(0.05832, 0.03), 1e-14)
    cols = {k: np.array([v, v]) for k, v in values.items()}
    assert np.allclose(P._extent_columns(cols, "link", bodies, 2),
                       math.hypot(0.05832, 0.03), rtol=1e-14, atol=0)
    assert np.allclose(P._extent_columns(cols, "link_2", bodies, 2), 5.0, rtol=1e-14, atol=0)


def test_gyration_against_the_reach():
    bodies = ("a",)
    base = {"m_a": 1.0, "px_a_B": 0.1}
    assert P.problems({**base, "izz_a": 0.3 ** 2}, bodies) == []  # radius 0.3 = 3 x reach
    said = P.problems({**base, "izz_a": 0.31 ** 2}, bodies)
    assert said == [("parameter izz_a = 0.0961 kg*m^2 with m_a = 1 kg gives a radius of gyration "
                    "of 310 mm for a body whose points reach 100 mm from its centre of gravity "
                    "(more than 3 times); a unit or decimal-point slip?")]
    assert P.problems({**base, "izz_a": 0.0}, bodies) == [
        ("parameter izz_a must be > 0 for a body with extent (its points reach 100 mm from its "
        "centre of gravity)")]


def test_one_warning_per_slip(rpr):
    own = {p.name: p.value for p in rpr.parameter_list}
    units = {p.name: p.unit for p in rpr.parameter_list}
    # 2000 kg: heavier than osmium filling the 250 mm ball (1479 kg), which wins over the
    # relative rule (one message, not two)
    said = P.doubts(["m_boom"], {**own, "m_boom": 2000.0}, units, own, rpr.body_names)
    assert said == [('parameter m_boom = 2000 kg (read in kg) is more than osmium filling the '
                    'ball its points reach from its centre of gravity (250 mm) would weigh '
                    '(1479 kg); a slip? In "g" it would be 2 kg')]
    # 1200 kg fits that ball: 1000 times the boom's 1.2 kg, and in g it would be 1.2 kg
    said = P.doubts(["m_boom"], {**own, "m_boom": 1200.0}, units, own, rpr.body_names)
    assert said == [("parameter m_boom = 1200 kg (read in kg) is 1000 times the robot's own "
                    '1.2 kg; a slip? In "g" it would be 1.2 kg')]
    # a slider's friction has no N*mm reading: 1000 times its own is quiet until implausible
    assert P.doubts(["fc_extend"], {**own, "fc_extend": 3000.0}, units, own,
                    rpr.body_names) == []
    assert P.doubts(["fc_extend"], {**own, "fc_extend": 3e6}, units, own, rpr.body_names) == [
        ("parameter fc_extend = 3e+06 N (read in N) is above the plausible 1e+06 N for a Coulomb "
        "friction; a unit or decimal-point slip?")]
    assert P.doubts(["m_boom"], own, units, own, rpr.body_names) == []
    # the typed value and unit are what the warning quotes
    said = P.doubts(["m_boom"], {**own, "m_boom": 2000.0}, units, own, rpr.body_names,
                    {"m_boom": (2e6, "g")})
    assert len(said) == 1 and said[0].startswith("parameter m_boom = 2e+06 g (read in g, 2000 kg)")


def test_the_column_rules_equal_the_scalar_ones_row_for_row(rpr):
    """``failing`` (a sweep's designs, column-wise) against ``problems`` on 400 random designs
    of the geared RPR boom: every kind of parameter perturbed, a quarter of them made bad."""
    rng = np.random.default_rng(30)
    names = [p.name for p in rpr.parameter_list]
    units = {p.name: p.unit for p in rpr.parameter_list}
    base = np.array([p.value for p in rpr.parameter_list])
    P_ = np.tile(base, (400, 1)) * rng.uniform(0.5, 2.0, (400, len(base)))
    for k in range(400):
        if k % 4 == 0:
            j = rng.integers(len(base))
            P_[k, j] = rng.choice([-1.0, 0.0, 1e3, 400.0, math.inf]) * abs(base[j] or 1.0)
    bad = P.failing(names, P_, rpr.body_names, units)
    assert 30 < bad.sum() < 200
    for k in range(400):
        assert bad[k] == bool(P.problems(dict(zip(names, P_[k])), rpr.body_names, units)), k


def test_the_column_rules_at_their_edges():
    """The sweep's rules on hand-made designs: a massless point body, a zero inertia with
    extent, a radius of gyration exactly at 3 times the reach, gravity exactly at 300, and a
    robot whose only body has no inertia entry (a point mass) after one that has; no numpy
    warning from a zero mass (the column rule divides by it)."""
    import warnings

    names = ["m_a", "izz_a", "px_a_B", "m_p", "izz_p", "g"]
    bodies = ("a", "p")  # a: a 0.1 m link; p: a point mass (no points beyond its origin)
    ok = [1.0, 0.003, 0.1, 0.5, 0.0, 9.81]

    def row(**change):
        return [change.get(n, v) for n, v in zip(names, ok)]

    rows = [ok, row(m_p=0.0), row(izz_a=0.0), row(izz_a=(3 * 0.1) ** 2), row(g=300.0),
            row(g=math.nextafter(300.0, 400.0)), row(izz_a=1.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        bad = P.failing(names, np.array(rows), bodies)
    assert bad.tolist() == [False, True, True, False, False, True, True]
    for r, b in zip(rows, bad):
        assert b == bool(P.problems(dict(zip(names, r)), bodies))
    # only the second body has both entries: the first's missing inertia skips it, not the rest
    bad = P.failing(["m_a", "m_p", "izz_p"], np.array([[1.0, 0.0, 0.0]]), bodies)
    assert bad.tolist() == [True]


def test_every_body_is_checked_whatever_the_one_before_lacks():
    # a body with no inertia entry (a point mass) before a bad one
    assert P.problems({"m_a": 1.0, "m_b": -1.0, "izz_b": 0.1}, ("a", "b")) == [
        "parameter m_b must be > 0 kg (got -1)"]
    assert P.problems({"m_a": 1.0}, ("a",)) == []  # a mass alone: nothing else to judge
    # the column rule divides by the mass: a massless point body with inertia, no warning
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        bad = P.failing(["m_p", "izz_p"], np.array([[0.0, 0.1], [1.0, 0.1]]), ("p",))
    assert bad.tolist() == [True, False]


def test_reach_from_points_given_in_any_order_and_by_one_coordinate():
    bodies = ("a",)
    # the farther point first, then a nearer one; a point given by its y alone
    values = {"px_a_B": 0.5, "px_a_C": 0.1, "py_a_D": 0.2}
    assert P._extent(values, "a", bodies) == pytest.approx(0.5, abs=1e-15)
    assert P._extent({"py_a_D": 0.2}, "a", bodies) == pytest.approx(0.2, abs=1e-15)
    cols = {"py_a_D": np.array([0.2]), "cgy_a": np.array([-0.1]), "px_a_B": np.array([0.5]),
            "px_a_C": np.array([0.1])}
    reach = max(math.hypot(0.0, 0.2 + 0.1), math.hypot(0.5, 0.1), math.hypot(0.1, 0.1))
    assert P._extent_columns(cols, "a", bodies, 1) == pytest.approx([reach], abs=1e-15)
    assert P._extent({k: float(v[0]) for k, v in cols.items()}, "a", bodies) == \
        pytest.approx(reach, abs=1e-15)


def test_doubts_skip_a_point_body_and_quote_what_was_typed():
    bodies = ("p", "a")  # p: a point mass first
    own = {"m_p": 0.3, "izz_p": 0.0, "m_a": 0.075, "izz_a": 1e-4, "px_a_B": 0.1, "cgx_a": 0.04}
    said = P.doubts(["m_p", "m_a"], {**own, "m_a": 75.0}, {}, own, bodies)
    assert said == [("parameter m_a = 75 kg (read in kg) is more than osmium filling the ball "
                    "its points reach from its centre of gravity (60 mm) would weigh (20.44 kg); "
                    'a slip? In "g" it would be 0.075 kg')]
    # an inertia typed in kg*m^2 where kg*mm^2 is read: its gyration and its distance from
    # the robot's own value both say so; one message, quoting what was typed
    said = P.doubts(["izz_a"], {**own, "izz_a": 1e-10}, {}, own, bodies,
                    {"izz_a": (1e-4, "kg*mm^2")})
    assert len(said) == 1
    assert said[0].startswith("parameter izz_a = 0.0001 kg*mm^2 (read in kg*mm^2, 1e-10 "
                              "kg*m^2) gives a radius of gyration")
    said = P.doubts(["cgy_a"], {**own, "cgy_a": 150.0}, {"cgy_a": "m"}, own, bodies,
                    {"cgy_a": (150000.0, "mm")})
    assert said == [("parameter cgy_a = 150000 mm (read in mm, 150 m) is above the plausible "
                    "100 m for a coordinate of a point or centre of gravity; a unit or "
                    "decimal-point slip?")]


def test_a_negligible_own_offset_is_no_slip_reference():
    """The seed's 5-bar draws its links' centres of gravity 5e-8 m off their axes (the table's
    rounding): an identified 0.1 mm is 2000 times that but no slip, and is not called one; a
    first-moment offset comparable to the body's reach still is: 10 times the link's own
    (0.53 m, 4.3 times the link's size outside it) warned, 1000 times refused, as the
    description's centre-of-gravity rule does."""
    import warnings

    import planar_sym as ps
    from planar_sym.errors import InputError

    robot = ps.load("five_bar_type1")
    assert abs(robot.parameters["cgy_L_Link1"]) < 1e-7
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        robot.with_parameters(cgy_L_Link1=1e-4)
    own = robot.parameters["cgx_L_Link1"]
    with pytest.warns(RuntimeWarning, match=r"parameter cgx_L_Link1 puts the centre of gravity "
                                             r".* outside the outline"):
        robot.with_parameters(cgx_L_Link1=own * 10)
    with pytest.raises(InputError, match=r"parameter cgx_L_Link1 puts the centre of gravity "
                                         r"5\.3\d*e\+04 mm outside .* 530 times the body's size"):
        robot.with_parameters(cgx_L_Link1=own * 1000)
