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
