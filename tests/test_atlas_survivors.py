"""Survivors of the first mutation runs of the atlas's modules (issue 30): ``atlas_grid``,
``atlas_flood`` and ``atlas``, each figure against a rule worked out by hand in the test."""

from __future__ import annotations

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.analysis.atlas_grid import DEFAULT_POINTS, make_grid


@pytest.fixture(scope="module")
def arm():
    return ps.load("serial_2dof")


# -- atlas_grid.py -----------------------------------------------------------------------------

@pytest.mark.parametrize("x_range, y_range, nx, ny", [
    ((0.02, 0.18), (-0.1, -0.02), 101, 51),  # x the longer side, neither range about 0
    ((-0.1, -0.02), (0.02, 0.18), 51, 101),  # y the longer side
])
def test_the_default_step_puts_101_points_on_the_longer_side(arm, x_range, y_range, nx, ny):
    """Catches make_grid's default step taken from a sum of a range's ends instead of its
    width (``xr[1] + xr[0]``, ``xr[1] - xr[1]``, ``yr[1] + yr[0]``): with neither a step nor
    points, the longer side of the region gets DEFAULT_POINTS = 101 points and the shorter
    one the same step, (longer side) / 100: 0.16 m / 100 = 1.6 mm, so the 0.08 m side has
    0.08 / 0.0016 + 1 = 51 points, starting at the range's low end. L_c stays the arm's
    reach radius, 1.05 x 0.2 m, not a length of the region."""
    assert DEFAULT_POINTS == 101
    g = make_grid(arm, x_range=x_range, y_range=y_range)
    assert (len(g.x_m), len(g.y_m)) == (nx, ny)
    step = 0.16 / 100
    np.testing.assert_allclose(g.x_m, x_range[0] + step * np.arange(nx), rtol=0, atol=1e-15)
    np.testing.assert_allclose(g.y_m, y_range[0] + step * np.arange(ny), rtol=0, atol=1e-15)
    assert g.length_scale_m == pytest.approx(1.05 * 0.2, rel=1e-14)


def test_a_step_that_does_not_divide_the_region_stops_short_of_its_end(arm):
    """Catches make_grid's y axis spread over the whole y range (numpy's linspace to its end)
    when a step is given: a step of 0.1 m on y from -0.1 to 0.05 m gives the points -0.1 and
    0.0 m (0.05 m is not a multiple of the step away from the start), as on x from 0 to
    0.25 m: 0, 0.1, 0.2 m."""
    g = make_grid(arm, x_range=(0.0, 0.25), y_range=(-0.1, 0.05), step=0.1)
    np.testing.assert_allclose(g.x_m, [0.0, 0.1, 0.2], rtol=0, atol=1e-16)
    np.testing.assert_allclose(g.y_m, [-0.1, 0.0], rtol=0, atol=1e-16)


def test_without_a_reach_bound_the_length_scale_is_half_the_longer_side():
    """Catches make_grid's default L_c of a robot with a slider on every leg (serial_rpr: no
    reach bound) taken from a sum of the y range's ends or from x alone: half the longer side
    of the region given, here y from 0.05 to 0.35 m: 0.15 m (x is 0.1 m wide)."""
    g = make_grid(ps.load("serial_rpr"), x_range=(-0.1, 0.0), y_range=(0.05, 0.35), points=3)
    assert g.reach_box_m is None
    assert g.length_scale_m == pytest.approx(0.15, rel=1e-14)


def test_the_task_body_is_the_shortest_chain_of_exactly_the_moving_coordinates():
    """Catches atlas_grid._task_body comparing with a field the best candidate does not have
    (``best[2]``) and returning ``best[0]`` when there is no candidate: on a chain drawn by
    hand, ground -(joint 0, coordinate 0)-> A -(joint 1, coordinate 1)-> B -(weld)-> C, a
    task point moved by coordinates 0 and 1 is on B (C, welded to it, has the same
    coordinates by a longer chain; A lacks coordinate 1), one moved by coordinate 0 only is
    on A, and one moved by coordinate 1 alone is on no body: None."""
    from planar_sym.analysis.atlas_grid import _task_body

    joints = [{"parent": "ground", "child": "A", "coordinate": 0, "closes_loop": False},
              {"parent": "A", "child": "B", "coordinate": 1, "closes_loop": False},
              {"parent": "B", "child": "C", "coordinate": None, "closes_loop": False}]
    assert _task_body(joints, np.array([[0.2, 0.1], [0.05, -0.1]])) == "B"
    assert _task_body(joints, np.array([[0.2, 0.0], [0.05, 0.0]])) == "A"
    assert _task_body(joints, np.array([[0.0, 0.1], [0.0, -0.1]])) is None


# -- atlas_flood.py ----------------------------------------------------------------------------

def _halving_newton(monkeypatch):
    """atlas_flood._Newton on a problem whose iterates are known in closed form: one
    coordinate (rad), the task x(q) = q, no loops, and a K of 2 where the derivative is 1, so
    every Newton step q <- q - (q - x*) / 2 halves the error: e_k = e_0 / 2^k exactly (powers
    of two). det K = 2 > 0 keeps the start's sign."""
    from types import SimpleNamespace

    from planar_sym.analysis import atlas_flood

    def stacked(robot, q):
        n = len(q)
        return np.full((n, 1, 1), 2.0), q.copy(), np.zeros((n, 0)), None

    monkeypatch.setattr(atlas_flood, "stacked", stacked)
    return atlas_flood._Newton(SimpleNamespace(coordinate_units=("rad",)), 1.0, 1.0)


def test_newton_accepts_a_cell_converged_by_its_twelfth_step_and_no_later(monkeypatch):
    """Catches _Newton.solve's loop run for NEWTON_ITER - 1 rounds (11 steps, the last one's
    result never checked): a cell whose error is below NEWTON_TOL (1 + |x*|) = 1e-12 after
    exactly 12 halvings (e_0 = 0.9e-12 x 2^12, e_10 = 3.6e-12) is accepted, at its 12th
    iterate; one that would need a 13th (e_0 = 1.1e-12 x 2^12) is not; one left exactly at
    NEWTON_TOL (e_0 = 1e-12 x 2^12: every halving is exact) is accepted (``<=``)."""
    from planar_sym.analysis.atlas_flood import NEWTON_ITER, NEWTON_TOL

    assert (NEWTON_ITER, NEWTON_TOL) == (12, 1e-12)
    newton = _halving_newton(monkeypatch)
    e0 = np.array([[0.9e-12 * 2**12], [1.1e-12 * 2**12], [1e-12 * 2**12]])
    q, ok = newton.solve(e0, np.zeros((3, 1)))
    assert ok.tolist() == [True, False, True]
    assert q[0, 0] == e0[0, 0] / 2**12 and q[2, 0] == NEWTON_TOL


def test_newtons_tolerance_is_scaled_by_each_cells_own_target(monkeypatch):
    """Catches the tolerance's scale 1 + |x*|_inf taken as 2 + |x*|_inf, or over every cell
    at once (``axis=None``) instead of per cell: after 12 halvings both cells below miss
    their target by 5e-12 (rad); the cell at x* = 9 accepts it (scale 10: 1e-11), the cell
    at x* = 0 does not (scale 1: 1e-12), and at x* = 0 an error of 1.5e-12 is refused too."""
    newton = _halving_newton(monkeypatch)
    target = np.array([[0.0], [9.0], [0.0]])
    e12 = np.array([[5e-12], [5e-12], [1.5e-12]])
    _, ok = newton.solve(target + e12 * 2**12, target)
    assert ok.tolist() == [False, True, False]


def test_newton_stops_at_its_aim_not_before_and_not_after(monkeypatch):
    """Catches the aim |F| <= NEWTON_AIM (1 + |x*|) turned strict or divided by the scale:
    Newton steps a cell until its residual is at or below the aim, then leaves it. With every
    step halving the error: from 8e-14 at x* = 0 the cell stops at exactly 1e-14 = NEWTON_AIM
    (three halvings, all exact); from 1.2e-12 at x* = 9 (aim 1e-13) at 7.5e-14 (four)."""
    from planar_sym.analysis.atlas_flood import NEWTON_AIM

    assert NEWTON_AIM == 1e-14
    newton = _halving_newton(monkeypatch)
    target = np.array([[0.0], [9.0]])
    q, ok = newton.solve(target + [[8e-14], [1.2e-12]], target)
    assert ok.tolist() == [True, True]
    assert q[0, 0] == 1e-14
    assert q[1, 0] - 9.0 == pytest.approx(7.5e-14, abs=5e-15)


def _line_robot(monkeypatch, k):
    """A one-coordinate stand-in for atlas_flood.flood: x(q) = q, no loops, K = k (1: exact
    Newton, one step to the target; 2: every step halves the error)."""
    from types import SimpleNamespace

    from planar_sym.analysis import atlas_flood

    def stacked(robot, q):
        n = len(q)
        return np.full((n, 1, 1), float(k)), q.copy(), np.zeros((n, 0)), None

    monkeypatch.setattr(atlas_flood, "stacked", stacked)
    return SimpleNamespace(n=1, coordinate_units=("rad",))


def test_the_fill_retries_a_far_neighbour_in_substeps_and_counts_its_waves(monkeypatch):
    """Catches the retry of failed cells dropped or given to the cells that succeeded, the
    neighbour at flat index 0 taken for one outside the grid (``nbs > 0``), and the progress
    calls' arguments: a line of three cells 0.8 rad apart, filled from cell 0 with exact
    Newton; one step of 0.8 rad is refused (more than DQ_LIMIT = 0.5 rad), four substeps of
    0.2 rad reach each cell. The fill hears (solved, total) after each wave, then (total,
    total): (2, 3), (3, 3), (3, 3)."""
    from planar_sym.analysis.atlas_flood import DQ_LIMIT, SUBSTEPS, flood

    assert (DQ_LIMIT, SUBSTEPS) == (0.5, 4)
    robot = _line_robot(monkeypatch, 1)
    targets = np.array([[0.0], [0.8], [1.6]])
    heard = []
    q = flood(robot, targets, (1, 1, 3), 0, np.array([0.0]), 1.0,
              lambda done, total: heard.append((done, total)))
    np.testing.assert_allclose(q, targets, rtol=0, atol=1e-15)
    assert heard == [(2, 3), (3, 3), (3, 3)]


def test_a_neighbour_is_first_tried_in_one_step_then_in_four(monkeypatch):
    """Catches the first attempt made in two steps, and the substeps' targets spaced s * steps
    instead of s / steps: with every Newton step halving the error (12 steps), a neighbour
    6e-9 rad away is missed in one step (6e-9 / 2^12 = 1.46e-12 > NEWTON_TOL) and reached in
    four of 1.5e-9, each leaving 1/4096 of its error: the pose is the one this recurrence
    gives, 3.7e-13 short of the target (two steps would leave 7.3e-13)."""
    from planar_sym.analysis.atlas_flood import flood

    robot = _line_robot(monkeypatch, 2)
    targets = np.array([[0.0], [6e-9]])
    q = flood(robot, targets, (1, 1, 2), 0, np.array([0.0]), 1.0)
    want = 0.0
    for s in range(1, 5):
        want += (s / 4 * 6e-9 - want) * (1 - 2.0**-12)
    assert 6e-9 - want == pytest.approx(3.7e-13, rel=0.02)
    assert q[1, 0] == pytest.approx(want, rel=0, abs=1e-21)


def test_newton_gives_up_a_step_beyond_twice_its_limit_and_singular_cells(monkeypatch):
    """Catches the give-up rule of _Newton.solve changed: a step may go up to 2 x DQ_LIMIT
    (1 rad) from the start (``<=``, not ``<``, nor 3 x or 2 / DQ_LIMIT), a step beyond it
    ends the cell (not kept alive at its pose), an exactly singular K ends it (not solved:
    numpy refuses a singular matrix), and the final limit is each cell's own. One coordinate,
    x(q) = q, K = 0.1 for q < 0.05, 4e-13 for 0.29 < q < 0.31, 0 for q < -0.5, else 1:
    from 0 to 0.1 the first step lands exactly 1 rad away, then exact Newton comes back:
    accepted; to 0.12 it lands 1.2 rad away: given up; from 0.3 + 5e-13 to 0.3 (already
    within NEWTON_TOL, above the aim) the step of 1.25 rad is refused: given up; from -1 the
    singular cell is given up; from 2 to 2.3 accepted, to 2.6 not (0.6 rad > DQ_LIMIT), to
    2.5 accepted (exactly DQ_LIMIT away: the limit is inclusive)."""
    from types import SimpleNamespace

    from planar_sym.analysis import atlas_flood

    def stacked(robot, q):
        k = np.where(q < -0.5, 0.0, np.where(q < 0.05, 0.1, np.where(
            np.abs(q - 0.3) < 0.01, 4e-13, 1.0)))
        return k[:, :, None], q.copy(), np.zeros((len(q), 0)), None

    monkeypatch.setattr(atlas_flood, "stacked", stacked)
    newton = atlas_flood._Newton(SimpleNamespace(coordinate_units=("rad",)), 1.0, 1.0)
    q0 = np.array([[0.0], [0.0], [0.3 + 5e-13], [-1.0], [2.0], [2.0], [2.0]])
    target = np.array([[0.1], [0.12], [0.3], [-0.9], [2.3], [2.6], [2.5]])
    q, ok = newton.solve(q0, target)
    assert ok.tolist() == [True, False, False, False, True, False, True]  # 0.5 rad: at most
    np.testing.assert_allclose(q[ok], target[ok], rtol=0, atol=1e-15)


def test_the_start_cell_is_the_one_nearest_the_start_pose():
    """Catches atlas_flood._start_cell's nearest row found for -y or with x's coordinate, and
    its layer always the first: serial_2dof at q = (0.3, 0.5) rad has its tip at
    x = 0.1 (cos 0.3 + cos 0.8), y = 0.1 (sin 0.3 + sin 0.8) = (0.1652, 0.1013) m; on a
    5 x 5 grid over x 0..0.2, y -0.05..0.15 m the nearest point is x = 0.15, y = 0.1 (column
    3, row 3), which the pose returned reaches. serial_3dof at its drawn pose, bent, with
    orientations phi0 - 0.3 and phi0 + 0.05 rad: the start layer is the second."""
    from planar_sym.analysis.atlas_flood import _start_cell

    arm = ps.load("serial_2dof")
    q0 = np.array([0.3, 0.5])
    tip = 0.1 * np.array([np.cos(0.3) + np.cos(0.8), np.sin(0.3) + np.sin(0.8)])
    g = make_grid(arm, x_range=(0.0, 0.2), y_range=(-0.05, 0.15), points=5)
    cell, q = _start_cell(arm, g, g.targets(), q0)
    assert (int(np.argmin(np.abs(g.x_m - tip[0]))), int(np.argmin(np.abs(g.y_m - tip[1])))) \
        == (3, 3)
    assert cell == np.ravel_multi_index((0, 3, 3), g.shape)
    np.testing.assert_allclose(np.reshape(arm.task(q)[0], -1), [0.15, 0.1], rtol=0, atol=1e-12)
    three = ps.load("serial_3dof")
    q0 = np.array([0.2, 0.4, 0.3])
    x0 = np.reshape(three.task(q0)[0], -1)
    assert x0[2] == pytest.approx(0.9, rel=1e-14)  # phi, the angles summed
    g = make_grid(three, x_range=(x0[0] - 0.01, x0[0] + 0.01), y_range=(x0[1] - 0.01,
                  x0[1] + 0.01), points=3, orientations=[0.6, 0.95])
    cell, q = _start_cell(three, g, g.targets(), q0)
    assert cell == np.ravel_multi_index((1, 1, 1), g.shape)
    np.testing.assert_allclose(np.reshape(three.task(q)[0], -1), [x0[0], x0[1], 0.95],
                               rtol=0, atol=1e-12)


def test_an_unreachable_start_cell_is_named_with_its_orientation_in_degrees():
    """Catches the refusal of a start cell the start pose cannot reach naming its orientation
    in mm, or in another angle unit: serial_3dof from q = (0.2, 0.4, 0.3) rad (phi = 0.9 rad)
    on a region 0.15..0.22 m square at the one orientation 0.9 rad; the grid point nearest the
    start pose is (185, 150) mm, out of reach: phi is given as 0.9 rad = 51.57 deg."""
    from planar_sym.analysis.atlas import atlas
    from planar_sym.errors import WorkspaceError

    with pytest.raises(WorkspaceError) as err:
        atlas("serial_3dof", x_range=(0.15, 0.22), y_range=(0.15, 0.22), points=3,
              orientations=[0.9], q_start=[0.2, 0.4, 0.3])
    assert f"{np.degrees(0.9):.4g}" == "51.57"
    assert str(err.value) == ("serial_3dof: the grid point nearest the start pose (x 185 mm, "
                              "y 150 mm, phi 51.57 deg) cannot be reached from it in its "
                              "working mode: choose a region around the start pose or another "
                              "start pose (q_start)")


def test_a_closed_chains_start_off_its_loops():
    """Catches atlas_flood.start's refusal reworded or its gap scaled otherwise than to mm,
    and a q_start near the loops replaced by the drawn pose: five_bar_type1 with passive
    joint 2 moved 0.05 rad off its drawn pose misses the loops by max |Phi| (evaluated here
    by the robot's constraint function, 4.19 mm): refused with that gap; a pose with the first
    actuated joint turned 0.05 rad, assembled, then its passive joint 2 moved 0.3 mrad
    (within the 1 mm allowed) starts at those actuated angles, its passive ones solved; one
    near the other assembly mode starts in that mode (its passive joints solved from it)."""
    from planar_sym.analysis.atlas_flood import start
    from planar_sym.errors import InputError
    from planar_sym.motion.closure import solve_passive

    five = ps.load("five_bar_type1")
    off = five.q_drawn.copy()
    off[1] += 0.05
    gap = float(np.max(np.abs(five.constraint(off))))
    with pytest.raises(InputError) as err:
        start(five, off)
    assert str(err.value) == (f"five_bar_type1: q_start does not close the loops (|Phi| = "
                              f"{gap * 1e3:.4g} mm, limit 1 mm): give an assembled pose")
    assert f"{gap * 1e3:.4g}" == "4.192"
    turned = five.q_drawn.copy()
    turned[0] += 0.05
    turned = solve_passive(five, turned[[0, 2]][None], turned)[0]
    near = turned.copy()
    near[1] += 3e-4
    assert 0 < np.max(np.abs(five.constraint(near))) < 1e-3
    q, note = start(five, near)
    assert note == "" and np.max(np.abs(five.constraint(q))) < 1e-12
    np.testing.assert_array_equal(q[[0, 2]], turned[[0, 2]])
    np.testing.assert_allclose(q, turned, rtol=0, atol=1e-9)
    # the other assembly mode (passive joints about -2.62 and 2.62 rad instead of the drawn
    # -1.52 and 1.52): a q_start near it keeps it, solved from itself, not from the drawing
    guess = five.q_drawn.copy()
    guess[[1, 3]] = [-2.6, 2.6]
    other = solve_passive(five, five.q_drawn[[0, 2]][None], guess)[0]
    assert abs(other[1] - five.q_drawn[1]) > 1.0
    near = other.copy()
    near[1] += 3e-4
    q, _ = start(five, near)
    np.testing.assert_allclose(q, other, rtol=0, atol=1e-9)


def test_a_singular_drawn_tree_is_bent_from_its_drawn_angles(monkeypatch):
    """Catches atlas_flood.start setting the revolute joints after the first to BEND_RAD
    instead of turning them by it, and a note where the drawn pose is fine: a stand-in tree
    drawn folded, (0.3, pi) rad, whose start_pose refuses the drawn configuration (singular)
    and takes any pose given, starts at (0.3, pi + 30 deg); serial_rpr, whose drawn pose is
    regular, starts there with no note."""
    from types import SimpleNamespace

    from planar_sym.analysis.atlas_flood import BEND_RAD, start
    from planar_sym.errors import WorkspaceError
    from planar_sym.motion import newton

    rpr = ps.load("serial_rpr")
    q, note = start(rpr, None)
    assert note == "" and np.array_equal(q, rpr.q_drawn)

    def start_pose(robot, q):
        if q is None:
            raise WorkspaceError("singular")
        return q

    monkeypatch.setattr(newton, "start_pose", start_pose)
    folded = SimpleNamespace(is_closed_chain=False, q_drawn=np.array([0.3, np.pi]),
                             coordinate_units=("rad", "rad"), coordinates=("a", "b"))
    q, note = start(folded, None)
    assert BEND_RAD == np.radians(30.0)
    np.testing.assert_array_equal(q, [0.3, np.pi + np.radians(30.0)])
    assert note.startswith("the drawn configuration is singular: started from it with joints b "
                           "bent by 30 deg")


# -- atlas.py ----------------------------------------------------------------------------------

def _atlas_module():
    import planar_sym.analysis.atlas as atlas_module

    return atlas_module


def test_the_arms_gravity_map_is_its_inverse_dynamics_beside_a_singular_cell():
    """The bug the first run's survivors led to: an odd grid centred on serial_2dof's shoulder
    (the default grid is one, 101 points) reaches the folded pose at the origin, where J is
    singular and the envelope is ~1e14 N*m; the rounding rule compared the largest gravity
    torque (0.39 N*m) with 1e-12 x that largest envelope and mapped both joints' gravity as 0
    everywhere. The gravity map must be the arm's inverse dynamics at rest, tau(q, 0, 0), at
    every reached cell, and the summary's peak its largest |tau|."""
    robot = ps.load("serial_2dof")
    a = _atlas_module().atlas(robot, points=9, q_start=[0.0, np.radians(60.0)])
    r = a.reachable[0]
    assert r[4, 4] and a.x_m[4] == 0.0 and a.y_m[4] == 0.0  # the origin, reached folded
    assert np.min(a.envelope[0, 4, 4]) > 1e10
    q = a.q[0][r]
    tau = robot.inverse_dynamics(q, 0 * q, 0 * q)
    assert np.abs(tau[:, 0]).max() > 0.3 and np.abs(tau[:, 1]).max() > 0.02
    np.testing.assert_allclose(a.gravity[0][r], tau, rtol=0, atol=1e-12)
    assert np.all(np.isnan(a.gravity[0][~r]))
    np.testing.assert_allclose(a.summary()["peak_gravity"], np.abs(tau).max(axis=0), rtol=1e-12)


def test_the_rounding_rule_is_cell_by_cell_and_inclusive(monkeypatch):
    """A joint's gravity is mapped as 0 when at every cell |g| <= ROUNDING |envelope|
    (ROUNDING = 1e-12), and kept as computed otherwise; a stand-in for rest_torques gives three
    reached cells of serial_3dof these torques (N*m) by hand, the fourth row unreached:

    .. code:: text

        joint 1: g (1e-12, -5e-13, 0),  envelope (1, 1, 2)     -> 0 (1e-12 <= 1e-12: at most)
        joint 2: g (2e-13, 0.3, -0.1),  envelope (0.1, 1e14, 1) -> kept (2e-13 > 1e-13 at cell 1,
                 though 0.3 is below 1e-12 x the largest envelope: cell by cell, not peaks)
        joint 3: g (5e-13, 0, 0),       envelope (10, 10, 10)   -> 0 (5e-13 <= 1e-11)"""
    mod = _atlas_module()
    assert mod.ROUNDING == 1e-12
    G = np.array([[1e-12, 2e-13, 5e-13], [-5e-13, 0.3, 0.0], [0.0, -0.1, 0.0]])
    E = np.array([[1.0, 0.1, 10.0], [1.0, 1e14, 10.0], [2.0, 1.0, 10.0]])

    def stand_in(robot, q, accel):
        assert len(q) == 3 and accel == 1.0
        return {"gravity": G.copy(), "envelope": E.copy(), "envelope_angle_rad": np.zeros((3, 3))}

    monkeypatch.setattr(mod, "rest_torques", stand_in)
    robot = ps.load("serial_3dof")
    q = np.array([[0.1, 0.5, 0.5], [0.2, 0.6, 0.4], [0.3, 0.7, 0.3], [np.nan] * 3])
    out = mod._maps(robot, q, 0.2, 1.0, q[0])
    want = np.array([[0.0, 2e-13, 0.0], [0.0, 0.3, 0.0], [0.0, -0.1, 0.0], [np.nan] * 3])
    np.testing.assert_array_equal(out["gravity"], want)
    np.testing.assert_array_equal(out["envelope"][:3], E)
    assert np.all(np.isnan(out["envelope"][3])) and list(out["reachable"]) == [True] * 3 + [False]


def test_an_atlas_carries_its_region_names_start_and_time():
    """serial_2dof (two 0.1 m links) from q = (0, 60 deg): the reach box is 1.05 x 0.2 m about
    the shoulder, the task (x, y), no loop equations and no note (the start is given); the
    start pose as lines: link1 from the origin to (0.1, 0), link2 from there to the tip
    (0.1 + 0.1 cos 60 deg, 0.1 sin 60 deg); the time is the call's own, in seconds."""
    import time

    t0 = time.perf_counter()
    a = _atlas_module().atlas("serial_2dof", points=9, q_start=[0.0, np.radians(60.0)])
    took = time.perf_counter() - t0
    assert a.reach_box_m == pytest.approx((-0.21, 0.21, -0.21, 0.21), rel=1e-14)
    assert a.task_names == ("x", "y") and a.n_constraints == 0 and a.start_note == ""
    assert a.coordinates == ("joint1", "joint2") and a.length_unit == "m"
    tip = [0.1 + 0.1 * np.cos(np.pi / 3), 0.1 * np.sin(np.pi / 3)]
    d = a.start_drawing
    assert sorted(d) == ["bodies", "ground", "joints", "task"] and len(d["bodies"]) == 2
    np.testing.assert_allclose(d["bodies"][0], [[0.0, 0.0], [0.1, 0.0]], rtol=0, atol=1e-16)
    np.testing.assert_allclose(d["bodies"][1], [[0.1, 0.0], tip], rtol=0, atol=1e-16)
    np.testing.assert_array_equal(d["ground"], [[0.0, 0.0]])
    np.testing.assert_allclose(d["task"], tip, rtol=0, atol=1e-16)
    assert 0.0 < a.time_s <= took and a.summary()["time_s"] == a.time_s


def test_a_five_bars_atlas_and_its_assembly_mode_in_closed_form():
    """five_bar_type1 (one loop: 2 loop equations): a reached cell is in the start pose's
    assembly mode when (C - B) x (D - C), a fixed multiple of det Phi_p (tests/test_atlas.py),
    has the start pose's sign; its default 12 x 12 grid reaches cells of both modes."""
    from test_atlas import cross, five_bar_points, geometry

    a = _atlas_module().atlas("five_bar_type1", points=12)
    assert a.n_constraints == 2 and a.task_names == ("x", "y")
    g = geometry("five_bar_type1")
    _, B, C, D, _, _ = five_bar_points(a.q, g)
    _, B0, C0, D0, _, _ = five_bar_points(a.start_pose, g)
    with np.errstate(invalid="ignore"):
        same = a.reachable & (np.sign(cross(C - B, D - C)) == np.sign(cross(C0 - B0, D0 - C0)))
    assert same.sum() > 10 and (a.reachable & ~same).sum() > 3
    np.testing.assert_array_equal(a.same_assembly, same)


def test_the_start_note_and_the_orientation_reach_the_atlas():
    """serial_3dof's drawn pose is stretched (singular): the atlas starts from it with joints 2
    and 3 bent by 30 deg and says so; its one orientation is that pose's, 0 + 30 + 30 deg."""
    a = _atlas_module().atlas("serial_3dof", points=12)
    np.testing.assert_allclose(a.start_pose, np.radians([0.0, 30.0, 30.0]), rtol=1e-15)
    assert a.start_note == ("the drawn configuration is singular: started from it with joints "
                            "joint2, joint3 bent by 30 deg (give q_start for another working "
                            "mode)")
    assert a.task_names == ("x", "y", "phi") and a.n_constraints == 0
    np.testing.assert_allclose(a.phi_rad, [np.radians(60.0)], rtol=1e-15)


def test_an_atlas_of_a_robot_typed_in_cm_says_cm(tmp_path):
    """serial_2dof typed in cm: the same robot, so the same grid in m; its maps' axes in cm."""
    from conftest import serial_2dof_in_cm

    a = _atlas_module().atlas(ps.load(str(serial_2dof_in_cm(tmp_path))), points=9,
                              q_start=[0.0, np.radians(60.0)])
    assert a.length_unit == "cm"
    np.testing.assert_allclose(a.x_m, np.linspace(-0.21, 0.21, 9), rtol=0, atol=1e-15)


@pytest.mark.parametrize("accel", [0.0, 0.5, 2.5])
def test_the_envelope_is_the_worst_direction_of_the_acceleration_given(accel):
    """At each reached cell of serial_2dof the envelope is max over unit u of
    |tau(q, 0, J^-1 a u)|, found here by brute force over 3600 directions from the robot's
    own inverse dynamics (not the atlas's rest_torques); 0 m/s^2 is allowed (then it is
    |gravity|), and 0.5 and 2.5 m/s^2 scale its acceleration part."""
    robot = ps.load("serial_2dof")
    a = _atlas_module().atlas(robot, points=10, q_start=[0.0, np.radians(60.0)],
                              accel_m_s2=accel)
    assert a.accel_m_s2 == accel
    r = a.reachable[0]
    q = a.q[0][r]
    J = robot.task(q)[1]
    g = robot.inverse_dynamics(q, 0 * q, 0 * q)
    qdd = [np.linalg.solve(J, np.tile(e, (len(q), 1))[..., None])[..., 0]
           for e in ([1.0, 0.0], [0.0, 1.0])]  # unit task accelerations along x, along y
    cols = [robot.inverse_dynamics(q, 0 * q, d) - g for d in qdd]
    th = np.linspace(0.0, 2 * np.pi, 3600, endpoint=False)
    tau = g[..., None] + accel * (cols[0][..., None] * np.cos(th)
                                  + cols[1][..., None] * np.sin(th))
    brute = np.abs(tau).max(axis=-1)
    np.testing.assert_allclose(a.envelope[0][r], brute, rtol=1e-6, atol=0)
    assert np.all(a.envelope[0][r] >= brute * (1 - 1e-14))
    if accel == 0.0:
        np.testing.assert_array_equal(a.envelope[0][r], np.abs(a.gravity[0][r]))


def test_the_summarys_thresholds_are_where_the_docs_put_them():
    """Regular cells have type2 >= REGULAR (0.1) and, for the envelope, type1 >= REGULAR_TYPE1
    (0.01); near a Type II singularity is type2 < NEAR_TYPE2 (0.01): a cell exactly on each
    threshold, by hand (the 1 x 2 x 3 atlas of tests/test_analysis_survivors.py, cell (0, 2)
    out of reach):

    .. code:: text

        type2   0.1   0.5   -        type1  0.01  0.005  -      |gravity 1|  9  3  -
                0.01  0.005 0.5             0.5   0.5    0.5                 2  5  0.5

    regular: (0, 0), (0, 1), (1, 2): peak gravity 9 (3 without the cell on 0.1); the
    envelope's (0, 0), (1, 2): peak 20 (1 without the cell on 0.01); near: 0.005 only, 1 of 5."""
    from test_analysis_survivors import hand_atlas

    mod = _atlas_module()
    assert (mod.REGULAR, mod.REGULAR_TYPE1, mod.NEAR_TYPE2) == (0.1, 0.01, 0.01)
    nan = np.nan
    base = hand_atlas()
    grav, env = base.gravity.copy(), base.envelope.copy()
    grav[0, 0, :, 0] = [-9.0, 3.0, nan]
    env[0, 0, :, 0] = [20.0, 6.0, nan]
    s = hand_atlas(type2=np.array([[[0.1, 0.5, nan], [0.01, 0.005, 0.5]]]),
                   type1=np.array([[[0.01, 0.005, nan], [0.5, 0.5, 0.5]]]),
                   gravity=grav, envelope=env).summary()
    assert s["peak_gravity_regular"][0] == 9.0
    assert s["peak_envelope_regular"][0] == 20.0
    assert s["type2_near_fraction"] == pytest.approx(0.2, rel=1e-15)


def test_an_atlas_with_no_reached_cell_summarises_without_warnings():
    """No reached cell: the dexterity figures and the Type II fraction are NaN, said by no
    numpy warning (a median or mean of nothing warns 'Mean of empty slice')."""
    import warnings

    from test_analysis_survivors import hand_atlas

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = hand_atlas(reachable=np.zeros((1, 2, 3), bool)).summary()
    assert np.isnan(s["worst_dexterity"]) and np.isnan(s["median_dexterity"])
    assert np.isnan(s["type2_near_fraction"]) and np.isnan(s["peak_gravity"]).all()


def test_the_table_of_two_orientations_by_hand():
    """Two orientations (0 and 90 deg) of the 1 x 2 x 3 atlas: rows go orientation slowest,
    then y, then x: x (0, 100, 200) mm four times, y (0, 0, 0, 50, 50, 50) mm twice, phi 0 then
    90 deg; the second layer's dexterity is the first's halved."""
    from test_analysis_survivors import hand_atlas

    base = hand_atlas()

    def two(v):
        return np.concatenate([v, v])

    a = hand_atlas(phi_rad=np.array([0.0, np.pi / 2]), q=two(base.q),
                   reachable=two(base.reachable), same_assembly=two(base.same_assembly),
                   det_type1=two(base.det_type1), det_type2=two(base.det_type2),
                   type1=two(base.type1), type2=two(base.type2),
                   dexterity=np.concatenate([base.dexterity, base.dexterity / 2]),
                   gravity=two(base.gravity), envelope=two(base.envelope),
                   envelope_angle_rad=two(base.envelope_angle_rad))
    names, values = a.table()
    assert names[:5] == ["x_mm", "y_mm", "phi_deg", "reachable", "same_assembly"]
    np.testing.assert_allclose(values[:, 0], [0, 100, 200] * 4, rtol=1e-15)
    np.testing.assert_allclose(values[:, 1], [0, 0, 0, 50, 50, 50] * 2, rtol=1e-15)
    np.testing.assert_allclose(values[:, 2], [0.0] * 6 + [90.0] * 6, rtol=1e-15)
    d = [0.4, 0.1, np.nan, 0.3, 0.2, 0.9]
    np.testing.assert_array_equal(values[:, names.index("dexterity")], d + [v / 2 for v in d])


def test_the_csv_text_by_hand(tmp_path):
    """The CSV's numbers as printf's %.10g writes them (lower-case e, nan), the first row of
    the 1 x 2 x 3 atlas by hand, and read back as the table."""
    from test_analysis_survivors import hand_atlas

    from planar_sym.analysis.atlas import write_csv

    dex = hand_atlas().dexterity.copy()
    dex[0, 0, 0] = 1.25e-05
    a = hand_atlas(dexterity=dex)
    write_csv(a, tmp_path / "a.csv")
    lines = (tmp_path / "a.csv").read_text().splitlines()
    assert lines[1] == "0,0,1,1,0,0,0.5,0.5,1.25e-05,1,1,1,2,0,nan,1,0"
    back = np.loadtxt(tmp_path / "a.csv", delimiter=",", skiprows=1)
    np.testing.assert_array_equal(back, a.table()[1])


def test_the_npz_holds_names_as_text_and_joint_indices_as_integers(tmp_path):
    """The NPZ reads back without pickles: the coordinates' names as text, the actuated joints
    as integers, also when there are none (an atlas made without actuators)."""
    from test_analysis_survivors import hand_atlas

    a = hand_atlas()
    a.to_npz(tmp_path / "a.npz")
    with np.load(tmp_path / "a.npz", allow_pickle=False) as npz:
        assert list(npz["coordinates"]) == ["a", "b"]
        assert npz["actuated"].dtype.kind == "i" and list(npz["actuated"]) == [0, 1]
    none = hand_atlas(actuated=(), actuator_units=()).arrays()["actuated"]
    assert none.dtype.kind == "i" and none.shape == (0,)


def test_a_body_off_the_origin_is_drawn_around_its_own_centre():
    """_order on a 0.2 m square centred at (1, 1) m, its corners shuffled: around its centre
    from the corner at -135 deg, closed; a 10 x 1 rectangle (singular values 10 and 1, exactly
    the ratio 0.1 of a thin body) is not thin: also drawn around, closed."""
    from planar_sym.analysis.atlas import _order

    square = np.array([[1.1, 1.1], [0.9, 0.9], [1.1, 0.9], [0.9, 1.1]])
    np.testing.assert_array_equal(_order(square), [[0.9, 0.9], [1.1, 0.9], [1.1, 1.1],
                                                   [0.9, 1.1], [0.9, 0.9]])
    box = np.array([[5.0, 0.5], [-5.0, 0.5], [5.0, -0.5], [-5.0, -0.5]])
    s = np.linalg.svd(box - box.mean(axis=0), compute_uv=False)
    if s[1] != 0.1 * s[0]:
        pytest.skip("this LAPACK does not return the rectangle's singular values exactly")
    np.testing.assert_array_equal(_order(box), [[-5.0, -0.5], [5.0, -0.5], [5.0, 0.5],
                                                [-5.0, 0.5], [-5.0, -0.5]])


def test_a_piston_whose_two_joints_meet_draws_no_line():
    """parallel_3rpr drawn: each piston's prismatic joint and its pivot on the platform are at
    the same point (one point: no line), so no body of the drawing has fewer than two points;
    the ground is the three pivots A1..A3 of the description, each cylinder runs from its pivot
    to the platform's vertex, and the task point is the platform's centre (0, 0)."""
    from planar_sym.analysis.atlas import stick

    robot = ps.load("parallel_3rpr")
    s = stick(robot, robot.q_drawn)
    assert all(len(b) >= 2 for b in s["bodies"])
    A = np.array([[0.0, 0.4], [-0.346410161513775, -0.2], [0.346410161513775, -0.2]])
    B = np.array([[-0.1, 0.0], [0.05, -0.086602540378444], [0.05, 0.086602540378444]])
    np.testing.assert_allclose(s["ground"], A, rtol=0, atol=1e-15)
    for a_k, b_k in zip(A, B):
        assert any(len(b) == 2 and np.allclose(np.sort(b, axis=0), np.sort([a_k, b_k], axis=0),
                                               rtol=0, atol=1e-12) for b in s["bodies"])
    np.testing.assert_allclose(s["task"], [0.0, 0.0], rtol=0, atol=1e-15)
