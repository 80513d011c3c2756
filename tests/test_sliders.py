"""Prismatic joints, point masses and optional [task] against analytic equations.

Cart-pole (tests/robots/cart_pole.toml): cart mass M on a prismatic joint along x (coordinate
d1, m, measured from the drawn pose), pole of mass m, inertia I about its cg at distance l from
the hinge, hinge angle q2 (0: pole along +x), gravity -y::

    x_cg = s0 + d1 + l cos q2,  y_cg = l sin q2
    f1   = (M + m) ddd1 - m l s2 qdd2 - m l c2 qd2^2
    tau2 = -m l s2 ddd1 + (I + m l^2) qdd2 + m g l c2

Point-mass pendulum (tests/robots/point_pendulum.toml, ``mass_at``): tau = m L^2 qdd + m g L cos q.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import TEST_ROBOTS, rel_err

from planar_sym.errors import DescriptionError
from planar_sym.model import description

M_CART, M_POLE, I_POLE, L_CG, G = 2.0, 0.5, 0.004, 0.25, 9.81


def cart_pole_tau(q, qd, qdd):
    s2, c2 = np.sin(q[:, 1]), np.cos(q[:, 1])
    f1 = (M_CART + M_POLE) * qdd[:, 0] - M_POLE * L_CG * s2 * qdd[:, 1] \
        - M_POLE * L_CG * c2 * qd[:, 1] ** 2
    tau2 = -M_POLE * L_CG * s2 * qdd[:, 0] + (I_POLE + M_POLE * L_CG**2) * qdd[:, 1] \
        + M_POLE * G * L_CG * c2
    return np.column_stack([f1, tau2])


@pytest.fixture(scope="module")
def cart_pole(derived):
    return derived(TEST_ROBOTS / "cart_pole.toml")[1]


def test_cart_pole_description():
    d = description.load(TEST_ROBOTS / "cart_pole.toml")
    assert d.coordinates == ("slide", "hinge")
    assert d.coordinate_units == ("m", "rad")
    assert d.q_drawn() == (0.0, 0.0)  # a slide is measured from the drawn pose
    assert d.task_point is None and d.task_names == ()
    params = {p.name: p.value for p in d.parameters()}
    assert params["s0_slide"] == pytest.approx(0.5, abs=1e-15)  # rail at -0.2, cart at 0.3
    assert d.tree_joints[0].axis == (1.0, 0.0)


def test_cart_pole_dynamics_analytic(cart_pole, rng):
    n = 50
    q = rng.uniform(-2, 2, (n, 2))
    qd, qdd = rng.uniform(-3, 3, (n, 2)), rng.uniform(-5, 5, (n, 2))
    assert rel_err(cart_pole.tree_inverse_dynamics(q, qd, qdd), cart_pole_tau(q, qd, qdd)) < 1e-12
    # forward of inverse: the generated M^-1 (tau - h) returns qdd
    tau = cart_pole_tau(q, qd, qdd)
    assert rel_err(cart_pole.tree_forward_dynamics(q, qd, tau), qdd) < 1e-11
    # the body frames: the cart's origin slides by d1 from x = 0.3
    fr = cart_pole.frames(q)
    assert np.max(np.abs(fr[:, 0, 0] - (0.3 + q[:, 0]))) < 1e-15
    assert np.max(np.abs(fr[:, 1, 2] - q[:, 1])) < 1e-15


def test_cart_pole_energy_is_conserved_in_free_motion(cart_pole):
    from planar_sym.dynamics.forward import simulate

    sim = simulate(cart_pole, [0.0, 0.3], [0.0, 0.0], (0.0, 2.0),
                   t_eval=np.linspace(0.0, 2.0, 201))
    assert sim.energy_drift < 1e-9
    # momentum along x: no horizontal force, so (M + m) d1' - m l s2 q2' stays 0
    p_x = (M_CART + M_POLE) * sim.qd[:, 0] - M_POLE * L_CG * np.sin(sim.q[:, 1]) * sim.qd[:, 1]
    assert np.max(np.abs(p_x)) < 1e-9


def test_cart_pole_study_columns_are_in_m_and_n(derived, tmp_path):
    """Both joints driven (a cart-pole's hinge has no motor: no inverse dynamics there)."""
    from planar_sym.study import spec
    from planar_sym.study.run import run

    driven = tmp_path / "cart_pole_driven.toml"
    driven.write_text((TEST_ROBOTS / "cart_pole.toml").read_text().replace(
        'name = "cart_pole"', 'name = "cart_pole_driven"').replace(
        "actuated = false", "actuated = true"))
    folder = derived(driven)[0]
    st = tmp_path / "move.toml"
    st.write_text(f'title = "cart move"\nrobot = "{folder}"\nkind = "inverse"\n'
                  '[units]\nlength = "mm"\nangle = "deg"\n'
                  '[motion]\nspace = "joint"\nprofile = "cubic"\nstart = [0.0, 10.0]\n'
                  'by = [200.0, 30.0]\nduration = 1.0\nsamples = 51\n')
    r = run(spec.load(st))
    for name in ("q1_m", "qd1_m_s", "qdd1_m_s2", "tau1_n", "q2_rad", "tau2_n_m"):
        assert name in r.columns, name
    assert r.columns["q1_m"][-1] == pytest.approx(0.2, abs=1e-12)  # 200 mm
    q = np.column_stack([r.columns["q1_m"], r.columns["q2_rad"]])
    qd = np.column_stack([r.columns["qd1_m_s"], r.columns["qd2_rad_s"]])
    qdd = np.column_stack([r.columns["qdd1_m_s2"], r.columns["qdd2_rad_s2"]])
    ref = cart_pole_tau(q, qd, qdd)
    assert rel_err(np.column_stack([r.columns["tau1_n"], r.columns["tau2_n_m"]]), ref) < 1e-12


def test_cart_pole_equations_print_d(cart_pole):
    text = (cart_pole.library.folder / "equations.txt").read_text()
    assert "d1 = slide" in text and "f1 = " in text
    assert "Coordinates (rad; d: m)" in text


def test_cart_pole_drawing_has_a_slider(cart_pole):
    import matplotlib

    matplotlib.use("Agg")
    from planar_sym.outputs.drawing import drawing_figure

    fig = drawing_figure(TEST_ROBOTS / "cart_pole.toml")
    gids = {a.get_gid() for a in fig.axes[0].get_children()}
    assert {"rail:slide", "joint:slide", "joint:hinge"} <= gids
    assert "task" not in gids  # no [task]: no task star
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_point_mass_pendulum(derived, rng):
    d = description.load(TEST_ROBOTS / "point_pendulum.toml")
    assert "izz_rod" not in {p.name for p in d.parameters()}  # structural zero, not a 1e-12
    robot = derived(TEST_ROBOTS / "point_pendulum.toml")[1]
    m, length = 1.5, 0.6
    q, qd, qdd = (rng.uniform(-3, 3, (30, 1)) for _ in range(3))
    ref = m * length**2 * qdd + m * G * length * np.cos(q)
    assert rel_err(robot.inverse_dynamics(q, qd, qdd), ref) < 1e-12
    assert robot.task_names == ()
    with pytest.raises(Exception, match="has no task point"):
        robot.task(q)


def _write(tmp_path, text: str):
    p = tmp_path / "bad.toml"
    p.write_text(text)
    return p


def _cart(**joint) -> str:
    src = (TEST_ROBOTS / "cart_pole.toml").read_text()
    for old, new in joint.items():
        assert old in src
        src = src.replace(old, new)
    return src


@pytest.mark.parametrize("old,new,field,message", [
    ("axis = [1.0, 0.0]", "axis = [0.0, 0.0]", "joints[0] (slide).axis", "zero length"),
    ("axis = [1.0, 0.0]", "axis = [1.0, 0.1]", "joints (slide)",
     "prismatic joint's axis does not pass both its points: cart.C is 49.75"),
    ("axis = [1.0, 0.0]\n", "", "joints[0] (slide).axis", "missing"),
    ('actuated = false\n', 'actuated = false\naxis = [1.0, 0.0]\n',
     "joints[1] (hinge).axis", "only a prismatic joint has an axis"),
    ('actuated = true\n', 'actuated = true\ndisplacement = 0.1\n',
     "joints[0] (slide).displacement", "only with pose = 'joints'"),
    # a student's typos: one mistake, one message (no 'axis' or 'displacement' on top)
    ('type = "prismatic"', 'type = "Prismatic"', "joints[0] (slide).type",
     "must be 'revolute', 'prismatic' or 'weld' (got 'Prismatic')"),
    ("actuated = true\n", "", "joints[0] (slide).actuated",
     "missing: true where a motor drives the joint, false where it is passive"),
])
def test_bad_prismatic_joints(tmp_path, old, new, field, message):
    with pytest.raises(DescriptionError) as info:
        description.load(_write(tmp_path, _cart(**{old: new})))
    problems = info.value.problems
    assert len(problems) == 1, problems
    assert f": {field}: " in problems[0] and message in problems[0], problems[0]


def test_a_loop_cut_at_a_prismatic_joint_is_refused(tmp_path):
    src = (TEST_ROBOTS / "cart_pole.toml").read_text().replace(
        'child = "cart.C"\nactuated = true', 'child = "cart.C"\nactuated = false\n'
        'closes_loop = true')
    with pytest.raises(DescriptionError) as info:
        description.load(_write(tmp_path, src))
    assert any("a loop cannot be cut at a prismatic joint" in p and "cut the loop at one of its "
               "revolute joints" in p for p in info.value.problems), info.value.problems


def test_pose_joints_places_a_slider(tmp_path):
    """pose = "joints": the displacement puts the child point along the parent's axis."""
    src = '''name = "slider_joints"
gravity = [0.0, -9.81]
pose = "joints"
[units]
length = "m"
mass = "kg"
inertia = "kg*m^2"
angle = "deg"
acceleration = "m/s^2"
[ground]
points = { O = [0.0, 0.0] }
[[bodies]]
name = "arm"
mass = 1.0
izz = 0.01
cg = [0.1, 0.0]
points = { O = [0.0, 0.0], E = [0.2, 0.0] }
[[bodies]]
name = "slider"
mass = 0.5
izz = 0.001
cg = [0.0, 0.0]
points = { S = [0.0, 0.0] }
[[joints]]
name = "turn"
type = "revolute"
parent = "ground.O"
child = "arm.O"
actuated = true
angle = 30.0
[[joints]]
name = "slide"
type = "prismatic"
axis = [1.0, 0.0]
parent = "arm.O"
child = "slider.S"
actuated = true
displacement = 0.15
angle = 90.0
'''
    d = description.load(_write(tmp_path, src))
    s = d.bodies["slider"]
    assert s.drawn_origin_m == pytest.approx((0.15 * math.cos(math.pi / 6),
                                              0.15 * math.sin(math.pi / 6)), abs=1e-15)
    assert s.drawn_angle_rad == pytest.approx(math.radians(120.0), abs=1e-15)
    assert {p.name: p.value for p in d.parameters()}["s0_slide"] == pytest.approx(0.15)


def test_unused_units_are_not_required(tmp_path):
    src = (TEST_ROBOTS / "point_pendulum.toml").read_text()
    d = description.load(_write(tmp_path, src))  # no inertia, no angle: none is used
    assert d.bodies["rod"].izz_kg_m2 == 0.0 and d.bodies["rod"].point_mass
    with pytest.raises(DescriptionError, match=r"units\.inertia: missing"):
        description.load(_write(tmp_path, src.replace('mass_at = "bob"\n',
                                                      'izz = 0.01\ncg = [0.6, 0.0]\n'
                                                      'cg_from = "world"\n')))


def test_mass_at_refuses_izz_and_cg(tmp_path):
    src = (TEST_ROBOTS / "point_pendulum.toml").read_text().replace(
        'mass_at = "bob"\n', 'mass_at = "bob"\ncg = [0.1, 0.0]\n')
    with pytest.raises(DescriptionError) as info:
        description.load(_write(tmp_path, src))
    assert len(info.value.problems) == 1
    assert "bodies[0] (rod).cg: not with mass_at" in info.value.problems[0]
