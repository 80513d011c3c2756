"""The sign of a prismatic joint's normal force (``JointLoads.normal``), against values found
without the load computation.

Convention (``planar_sym.dynamics.reactions``): ``F_j`` is the force the parent exerts on the
child; its normal part is ``F_j . (k x u)``, ``k x u`` the slide axis ``u`` turned +90 deg. On a
level rail along +x, ``k x u`` is +y: a rail that holds a load up pushes with a POSITIVE normal
force. ``hypot(axial, normal) == |F|`` (tests/test_reactions.py) cannot see this sign; these
tests can:

1. the cart-pole on a level rail (tests/robots/cart_pole.toml), in closed form at random
   states: the rail carries the cart and the pole, so
   ``normal = (M + m) g + m l (c2 qdd2 - s2 qd2^2)`` (the vertical momentum balance; cart mass
   M, pole mass m at l from the hinge) and ``axial = f1`` of tests/test_sliders.py;
2. at rest, the weight of what the slider carries: ``normal = W . (k x u)`` with
   ``W = (0, +m_subtree g)``: ``(M + m) g cos 20deg`` on the cart-pole's 20 deg rail,
   ``(m_boom + m_wrist) g cos q1`` on the RPR arm's sleeve at shoulder angle q1 (negative past
   90 deg: the sign follows the axis), the same on tests/robots/rotated_slider.toml, whose
   carriage is turned 30 deg to its rail; on the slider-crank (a closed chain, passive slider,
   rod cg at mid-length) the rod hangs half its weight on the slider pin, so
   ``normal = (m_slider + m_rod cgx_rod / l_rod) g`` at every pose;
3. a free body by hand at random states: the force on the slider's subtree is
   ``sum m (a_cg - g)``, the cg accelerations by Richardson-extrapolated second differences of
   the generated frames (not ``body_motion``), the axis ``u`` from how the child's frame moves
   with its coordinate; then ``normal = F . (k x u)`` and ``axial = F . u``.

Measured: the closed forms agree to 6e-16 of the largest force, the finite-difference free body
to 5e-11 (asserted 1e-12 and 1e-9). A flipped sign errs by twice the normal force: 1.7 to 2 of
the largest force.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import TEST_ROBOTS

import planar_sym as ps
from planar_sym.dynamics.reactions import joint_loads

G = 9.81
M_CART, M_POLE, L_CG = 2.0, 0.5, 0.25  # tests/robots/cart_pole.toml: kg, kg, m
CLOSED_FORM_TOL = 1e-12  # relative to the largest force
FREE_BODY_TOL = 1e-9  # finite differences: measured 5e-11
#: robot -> (its prismatic joint, the bodies that joint carries: the child's subtree)
SLIDERS = {"cart_pole": ("slide", ("cart", "pole")),
           "cart_pole_incline": ("rail", ("cart", "pole")),
           "serial_rpr": ("extend", ("boom", "wrist")),
           "rotated_slider": ("slide", ("carriage", "tip"))}
DERIVED = ("cart_pole", "cart_pole_incline", "rotated_slider")


@pytest.fixture(scope="module")
def robots(derived):
    out = {name: derived(TEST_ROBOTS / f"{name}.toml")[1] for name in DERIVED}
    out["serial_rpr"] = ps.load("serial_rpr")
    for robot in out.values():  # every one is drawn with gravity 9.81 m/s^2 along -y
        assert robot.parameters["g"] == G
        assert tuple(robot.library.manifest["gravity_direction"]) == (0.0, -1.0)
    return out


def _k_cross(u):
    """k x u: u (N, 2) turned +90 deg."""
    return np.column_stack([-u[:, 1], u[:, 0]])


def _cg_world(robot, q, body):
    """The cg of ``body`` in world axes (N, 2) from the generated frames and its cg parameters."""
    fr = robot.frames(q)[:, list(robot.body_names).index(body)]
    cx, cy = robot.parameters.get(f"cgx_{body}", 0.0), robot.parameters.get(f"cgy_{body}", 0.0)
    c, s = np.cos(fr[:, 2]), np.sin(fr[:, 2])
    return np.column_stack([fr[:, 0] + c * cx - s * cy, fr[:, 1] + s * cx + c * cy])


def _slide_axis(robot, q, joint, child):
    """u in world axes (N, 2): how the child's frame origin moves per metre of the joint's
    coordinate (it moves exactly along u, so a forward difference is exact to rounding)."""
    i, b = robot.coordinates.index(joint), list(robot.body_names).index(child)
    step = np.zeros(robot.n)
    step[i] = 1e-3
    du = (robot.frames(q + step)[:, b, :2] - robot.frames(q)[:, b, :2]) / 1e-3
    return du / np.linalg.norm(du, axis=1, keepdims=True)


def _subtree_force(robot, q, qd, qdd, bodies):
    """sum m (a_cg - g) over ``bodies`` (N, 2): the force the slider's parent must exert on
    them, the accelerations by second differences along q + qd t + qdd t^2 / 2 at t = 0
    (h = 2e-3 and 1e-3 s, Richardson extrapolated: O(h^4))."""
    def second_difference(body, h):
        def at(t):
            return _cg_world(robot, q + qd * t + qdd * t * t / 2, body)
        return (at(h) - 2 * at(0.0) + at(-h)) / h**2

    total = np.zeros((len(q), 2))
    for body in bodies:
        acc = (4 * second_difference(body, 1e-3) - second_difference(body, 2e-3)) / 3
        total += robot.parameters[f"m_{body}"] * (acc - np.array([0.0, -G]))
    return total


def _random_states(rng, robot, n_s=30):
    q = robot.q_drawn + rng.uniform(-1.5, 1.5, (n_s, robot.n))
    return q, rng.uniform(-3, 3, (n_s, robot.n)), rng.uniform(-3, 3, (n_s, robot.n))


def test_cart_pole_on_a_level_rail_in_closed_form(robots, rng):
    """Reference: the cart-pole's momentum balance by hand (its numbers from its description):
    the rail pushes up with (M + m) g plus what the pole's cg accelerates upward, and along x
    with f1 = (M + m) ddd1 - m l (s2 qdd2 + c2 qd2^2)."""
    robot = robots["cart_pole"]
    q, qd, qdd = _random_states(rng, robot, 50)
    loads = joint_loads(robot, q, qd, qdd)
    s2, c2 = np.sin(q[:, 1]), np.cos(q[:, 1])
    normal = (M_CART + M_POLE) * G + M_POLE * L_CG * (c2 * qdd[:, 1] - s2 * qd[:, 1] ** 2)
    scale = np.abs(loads.force).max()
    assert normal.min() > 0.5  # the rail holds the cart up at every sample: the sign matters
    assert np.abs(loads.normal["slide"] - normal).max() < CLOSED_FORM_TOL * scale
    axial = (M_CART + M_POLE) * qdd[:, 0] - M_POLE * L_CG * (s2 * qdd[:, 1] + c2 * qd[:, 1] ** 2)
    assert np.abs(loads.axial["slide"] - axial).max() < CLOSED_FORM_TOL * scale


@pytest.mark.parametrize("name", sorted(SLIDERS))
def test_at_rest_the_rail_carries_the_weight_of_the_slider_and_what_it_holds(name, robots, rng):
    """Reference: the weight W = (0, m_subtree g) of the slider's subtree, turned onto k x u
    with u the rail's direction written out by hand: 20 deg (the incline), the shoulder
    angle q1 (the RPR's sleeve and the rotated slider's arm, both along the parent's x)."""
    robot = robots[name]
    joint, bodies = SLIDERS[name]
    q = robot.q_drawn + rng.uniform(-2.5, 2.5, (40, robot.n))
    zero = np.zeros_like(q)
    loads = joint_loads(robot, q, zero, zero)
    weight = G * math.fsum(robot.parameters[f"m_{b}"] for b in bodies)
    angle = {"cart_pole": np.zeros(len(q)), "cart_pole_incline": np.full(len(q), np.radians(20)),
             "serial_rpr": q[:, 0], "rotated_slider": q[:, 0]}[name]
    normal = weight * np.cos(angle)  # W . (k x u) = W u_x for W = (0, W)
    axial = weight * np.sin(angle)  # W . u: the actuator holds the load up the rail
    if name in ("serial_rpr", "rotated_slider"):  # the rail points left at some samples
        assert normal.min() < -0.2 * weight and normal.max() > 0.2 * weight
    assert np.abs(loads.normal[joint] - normal).max() < CLOSED_FORM_TOL * weight
    assert np.abs(loads.axial[joint] - axial).max() < CLOSED_FORM_TOL * weight


def test_slider_crank_at_rest_the_slider_carries_half_the_rod():
    """Reference: statics by hand. The slider is passive and frictionless, so the rod's pin
    force on it is vertical; the rod's moment about its crank pin A then gives that force as
    m_rod g (x_cg - x_A) / (x_B - x_A) = m_rod g cgx_rod / l_rod for a rod with its cg on AB
    (cgy_rod = 0), at every pose: normal = (m_slider + m_rod cgx_rod / l_rod) g."""
    robot = ps.load("slider_crank")
    par = robot.parameters
    assert par.get("cgy_rod", 0.0) == 0.0 and par.get("py_rod_B", 0.0) == 0.0
    crank = np.radians([20.0, 60.0, 95.0, 140.0, 165.0])
    zero = np.zeros((len(crank), 1))
    jt = ps.from_actuated(robot, np.arange(len(crank), dtype=float), crank[:, None], zero, zero)
    assert np.max(np.abs(robot.constraint(jt.q))) < 1e-12
    loads = joint_loads(robot, jt.q, jt.qd, jt.qdd)
    normal = (par["m_slider"] + par["m_rod"] * par["cgx_rod"] / par["px_rod_B"]) * G
    assert normal > 0.5  # N
    assert np.abs(loads.normal["slide"] - normal).max() < CLOSED_FORM_TOL * normal
    assert np.abs(loads.axial["slide"]).max() < CLOSED_FORM_TOL * normal  # passive


@pytest.mark.parametrize("name", sorted(SLIDERS))
def test_in_motion_against_a_free_body_by_hand(name, robots, rng):
    """Reference: sum m (a_cg - g) over the slider's subtree, the accelerations by finite
    differences of the generated frames, the axis from the frames; normal = F . (k x u)."""
    robot = robots[name]
    joint, bodies = SLIDERS[name]
    child = bodies[0]
    q, qd, qdd = _random_states(rng, robot)
    loads = joint_loads(robot, q, qd, qdd)
    force = _subtree_force(robot, q, qd, qdd, bodies)
    u = _slide_axis(robot, q, joint, child)
    normal = np.sum(force * _k_cross(u), axis=1)
    axial = np.sum(force * u, axis=1)
    scale = np.abs(force).max()
    assert np.abs(normal).max() > 0.2 * scale  # a normal force worth its sign
    i = loads.index(joint)
    assert np.abs(loads.force[:, i] - force).max() < FREE_BODY_TOL * scale
    assert np.abs(loads.normal[joint] - normal).max() < FREE_BODY_TOL * scale
    assert np.abs(loads.axial[joint] - axial).max() < FREE_BODY_TOL * scale
