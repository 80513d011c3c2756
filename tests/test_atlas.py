"""The atlas (analysis.atlas, outputs.atlas_plots, ``planar-sym atlas``) against independent
routes: the 5-bars' singular loci and workspaces in closed form (written out below from the
link lengths), the seed's closed-form inverse kinematics and Newton along a straight line, a
map value against a direct single-pose computation (finite differences through the loop
closure, a brute-force envelope over 3600 directions), the 2-link arm's condition number in
closed form, and the envelope along study S5 against the study's own torques.

5-bar geometry (planar_sym/robots/five_bar_type*.toml, SCENARIOS.md S5, S6): ground pivots A
and E, left leg A -> B (l2 = |AB|), one link B -> C -> P (l3 = |BC|, l36 = |BP|, P on BC
extended), right leg E -> D (l5), D -> C (l4). Coordinates (A, B, E, D): A and E absolute angles
of AB and ED, B the angle of BP relative to AB, D the angle of DC relative to ED.

.. code:: text

    Type I  (det [Phi_q; J] = 0):  (B - A) x (P - B) = 0  or  (D - E) x (C - D) = 0
                                   i.e. |AP| = l2 +- l36  or  |EC| = l5 +- l4
    Type II (det Phi_p = 0):       (C - B) x (D - C) = 0   (B, C, D collinear)
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import TEST_ROBOTS

import planar_sym as ps
from planar_sym.analysis.atlas import atlas, envelope_along, pose_measures, rest_torques
from planar_sym.errors import InputError, LibraryError, WorkspaceError

FIVE_BARS = ("five_bar_type1", "five_bar_type2")
POINTS = 100
L = 0.1  # m: serial_2dof's two links (planar_sym/robots/serial_2dof.toml)


def cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def unit(angle):
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def rotate(angle, v):
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]], axis=-1)


def geometry(name):
    """The link lengths (m) as the description gives them: the Type I's points are typed to
    6 decimals, so its links are 0.1 m and 0.128 m to within 4e-7 m, and C lies 4e-8 m off
    the line BP (``l3y``)."""
    p = ps.load(name).parameters
    return {"E": np.array([p["px_ground_E"], 0.0]), "l2": p["px_L_Link1_CS2"],
            "l3": np.array([p["px_L_Link2_CS2"], p.get("py_L_Link2_CS2", 0.0)]),
            "l36": p["px_L_Link2_CS3"], "l5": p["px_R_Link1_CS2"], "l4": p["px_R_Link2_CS2"]}


def five_bar_points(q, g):
    """B, C, P from the left leg and D, C' from the right leg (m), closed form."""
    A = np.zeros(2)
    B = A + g["l2"] * unit(q[..., 0])
    P = B + g["l36"] * unit(q[..., 0] + q[..., 1])
    C = B + rotate(q[..., 0] + q[..., 1], g["l3"])
    D = g["E"] + g["l5"] * unit(q[..., 2])
    C_right = D + g["l4"] * unit(q[..., 2] + q[..., 3])
    return A, B, C, D, P, C_right


def wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def inner(mask):
    """Cells whose 4 neighbours (inside the grid) share the cell's value True."""
    out = mask.copy()
    out[1:] &= mask[:-1]
    out[:-1] &= mask[1:]
    out[:, 1:] &= mask[:, :-1]
    out[:, :-1] &= mask[:, 1:]
    return out


@pytest.fixture(scope="module")
def bars():
    return {name: atlas(name, points=POINTS) for name in FIVE_BARS}


@pytest.fixture(scope="module")
def arm():
    return atlas("serial_2dof", points=101, q_start=[0.0, np.radians(60.0)])


# -- 1. singular loci against their closed forms ---------------------------------------------


@pytest.mark.parametrize("name", FIVE_BARS)
def test_singular_loci_of_the_five_bars_in_closed_form(bars, name):
    a, g = bars[name], geometry(name)
    E = g["E"]
    r = a.reachable[0]
    A, B, C, D, P, C_right = five_bar_points(a.q[0], g)
    X, Y = np.meshgrid(a.x_m, a.y_m)
    # the closed-form forward kinematics is the robot's: the loop closes, P is the target
    assert np.nanmax(np.abs(C - C_right)) < 1e-12
    assert np.nanmax(np.abs(P - np.stack([X, Y], -1))[r]) < 1e-12
    # Type I: det of the scaled [Phi_q; J] is a fixed multiple of the two legs' determinants,
    # so its zero set is theirs: one sign over the whole working mode, zero only at the edge
    legs = cross(B - A, P - B) * cross(D - E, C - D)
    ratio = a.det_type1[0][r] / legs[r]
    assert np.ptp(ratio) <= 1e-9 * np.abs(ratio).mean(), ratio
    assert len(np.unique(np.sign(a.det_type1[0][r]))) == 1
    # Type II: det of the scaled Phi_p is a fixed multiple of (C - B) x (D - C)
    bcd = cross(C - B, D - C)
    ratio2 = a.det_type2[0][r] / bcd[r]
    assert np.ptp(ratio2) <= 1e-6 * np.abs(ratio2).mean()
    # ... and changes sign between exactly the neighbouring reachable cells where it does
    crossings = 0
    for axis in (0, 1):
        both = np.diff(r.astype(int), axis=axis) == 0
        both &= r.take(range(1, r.shape[axis]), axis=axis)
        closed = np.diff(np.sign(bcd), axis=axis) != 0
        mapped = np.diff(np.sign(a.det_type2[0]), axis=axis) != 0
        assert np.array_equal(closed & both, mapped & both)
        crossings += int((closed & both).sum())
    assert crossings > 10, "a Type II locus crosses the working mode of either 5-bar"
    print(f"\n{name}: det_type1 / (leg determinants) spread {np.ptp(ratio) / abs(ratio.mean()):.1e},"
          f" det_type2 / ((C - B) x (D - C)) spread {np.ptp(ratio2) / abs(ratio2.mean()):.1e}, "
          f"{crossings} Type II crossings between neighbouring cells, all matched")
    # the workspace edge is the Type I locus: edge cells are within a cell of a leg's limit
    edge = r & ~inner(r)
    edge[[0, -1]] = edge[:, [0, -1]] = False
    ap = np.hypot(*P[edge].T)
    ec = np.hypot(*(C[edge] - E).T)
    l2, l36, l5, l4 = g["l2"], g["l36"], g["l5"], g["l4"]
    gap = np.min(np.abs(np.stack([ap - (l2 + l36), ap - abs(l36 - l2), ec - (l5 + l4),
                                  ec - abs(l5 - l4)])), axis=0)
    step = a.x_m[1] - a.x_m[0]
    assert gap.max() < 2 * step, gap.max() / step
    print(f"  workspace edge within {gap.max() / step:.2f} grid steps of a closed-form Type I "
          "locus")


@pytest.mark.parametrize("name", FIVE_BARS)
def test_a_pose_on_the_type2_locus_in_closed_form(name):
    """B, C, D collinear (the distal links stretched along one line): type2 and dexterity
    vanish there while K stays regular (no Type I)."""
    robot, g = ps.load(name), geometry(name)
    E, l3 = g["E"], np.hypot(*g["l3"])
    worst = 0.0
    for qa in np.radians([75.0, 90.0, 110.0, 140.0]):  # where |BE| >= |BD| - |DE|
        B = g["l2"] * unit(qa)
        # D on the circle |D - E| = l5 and on |D - B| = |BC| + l4 (C between B and D)
        d = E - B
        r = np.hypot(*d)
        along = ((l3 + g["l4"]) ** 2 - g["l5"] ** 2 + r**2) / (2 * r)
        h = np.sqrt((l3 + g["l4"]) ** 2 - along**2)
        D = B + along * d / r + h * np.array([-d[1], d[0]]) / r
        w = (D - B) / (l3 + g["l4"])
        C = B + l3 * w
        theta = np.arctan2(w[1], w[0]) - np.arctan2(g["l3"][1], g["l3"][0])  # angle of BP
        P = B + g["l36"] * unit(theta)
        q = np.array([qa, theta - qa, np.arctan2(*(D - E)[::-1]),
                      np.arctan2(*(C - D)[::-1]) - np.arctan2(*(D - E)[::-1])])
        assert np.max(np.abs(robot.constraint(q))) < 1e-15
        assert np.max(np.abs(np.reshape(robot.task(q)[0], -1) - P)) < 1e-15
        m = pose_measures(robot, q[None], 0.2)
        assert m["type2"][0] < 1e-8 and m["dexterity"][0] < 1e-8
        assert m["type1"][0] > 1e-3
        worst = max(worst, float(m["type2"][0]))
    print(f"\n{name}: type2 on the closed-form Type II locus <= {worst:.2e}")


# -- 2. reachability against the inverse kinematics ------------------------------------------


def test_serial_arm_reaches_its_annulus(arm):
    r = np.hypot(*np.meshgrid(arm.x_m, arm.y_m))
    step = arm.x_m[1] - arm.x_m[0]
    clear = (np.abs(r - 2 * L) > step) & (r > step)  # away from the two edges
    assert np.array_equal(arm.reachable[0][clear], (r < 2 * L)[clear])
    assert arm.start_note == ""


@pytest.mark.parametrize("name", FIVE_BARS)
def test_five_bar_reaches_its_closed_form_workspace(bars, name):
    """Left leg: |AP| in [l36 - l2, l2 + l36] with the start's elbow; then C = B + l3 (P - B) /
    l36 and the right leg: |EC| in [|l5 - l4|, l5 + l4]."""
    a, g = bars[name], geometry(name)
    l2, l36, l5, l4 = g["l2"], g["l36"], g["l5"], g["l4"]
    _, B0, _, _, P0, _ = five_bar_points(a.start_pose, g)
    s1 = np.sign(cross(B0, P0 - B0))
    P = np.stack(np.meshgrid(a.x_m, a.y_m), axis=-1)
    dist = np.hypot(*np.moveaxis(P, -1, 0))
    along = (l2**2 - l36**2 + dist**2) / (2 * dist)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(l2**2 - along**2)
    n = np.stack([-P[..., 1], P[..., 0]], -1) / dist[..., None]
    B = along[..., None] * P / dist[..., None] - (s1 * h)[..., None] * n  # B x P = -h |P|
    assert np.all(np.sign(cross(B, P - B))[np.isfinite(h)] == s1)
    BP = P - B
    C = B + rotate(np.arctan2(BP[..., 1], BP[..., 0]), g["l3"])
    ec = np.hypot(*np.moveaxis(C - g["E"], -1, 0))
    closed = np.isfinite(h) & (ec <= l5 + l4) & (ec >= abs(l5 - l4))
    assert np.array_equal(a.reachable[0][inner(closed)], np.ones(inner(closed).sum(), bool))
    assert not a.reachable[0][inner(~closed)].any()
    print(f"\n{name}: reachable {a.reachable.sum()} cells, closed form {closed.sum()}, "
          f"differing {(a.reachable[0] != closed).sum()}")


@pytest.mark.parametrize("name", FIVE_BARS)
def test_atlas_poses_are_the_seeds_closed_form(bars, name):
    from planar_sym.motion.seed_ik import SEED_SOLVERS

    a, robot = bars[name], ps.load(name)
    r = a.reachable[0]
    X, Y = np.meshgrid(a.x_m, a.y_m)
    x = np.column_stack([X[r], Y[r]])
    q = SEED_SOLVERS[name](robot, np.arange(len(x), dtype=float), x)
    worst = float(np.max(np.abs(wrap(q - a.q[0][r]))))
    print(f"\n{name}: worst |q_atlas - q_seed| = {worst:.2e} rad over {len(x)} cells")
    assert worst < 1e-9


def test_atlas_poses_are_newtons_along_a_line(bars):
    from planar_sym.motion import newton

    a, robot = bars["five_bar_type1"], ps.load("five_bar_type1")
    x0 = np.reshape(robot.task(a.start_pose)[0], -1)
    rng = np.random.default_rng(7)
    cells = np.argwhere(a.reachable[0])
    done = 0
    for j, i in cells[rng.choice(len(cells), 12, replace=False)]:
        target = np.array([a.x_m[i], a.y_m[j]])
        run = newton.solve(robot, np.linspace(0, 1, 40), np.linspace(x0, target, 40),
                           a.start_pose)
        if run.failed is not None:  # the straight line leaves the workspace
            continue
        assert np.max(np.abs(wrap(run.q[-1] - a.q[0, j, i]))) < 1e-9
        done += 1
    assert done >= 5


# -- 3. map values against a direct single-pose computation ----------------------------------


def _fk_actuated(robot, q_guess, qa):
    from planar_sym.motion.closure import solve_passive

    q = solve_passive(robot, np.atleast_2d(qa), q_guess)
    return np.reshape(robot.task(q)[0], (len(q), -1))


def test_a_cell_against_a_direct_computation(bars):
    a, robot = bars["five_bar_type1"], ps.load("five_bar_type1")
    score = np.where(a.reachable[0], np.minimum(a.type2[0], a.dexterity[0]), -1)
    j, i = np.unravel_index(np.argmax(score), score.shape)
    q = a.q[0, j, i]
    zero = np.zeros_like(q)
    # gravity torque: the public closed-chain inverse dynamics at rest
    tau_g, _ = robot.closed_chain_inverse_dynamics(q[None], zero[None], zero[None])
    assert np.max(np.abs(tau_g[0] - a.gravity[0, j, i])) <= 1e-12 * np.max(np.abs(tau_g))
    # dexterity: J_x = dx/dq_a by 4th-order central differences through the loop closure
    act, h = list(robot.actuated), 1e-4
    Jx = np.zeros((2, 2))
    for k, c in enumerate(act):
        f = {s: _fk_actuated(robot, q, q[act] + s * h * np.eye(2)[k])[0] for s in (-2, -1, 1, 2)}
        Jx[:, k] = (f[-2] - 8 * f[-1] + 8 * f[1] - f[2]) / (12 * h)
    s = np.linalg.svd(Jx, compute_uv=False)
    dex = a.dexterity[0, j, i]
    assert abs(s[-1] / s[0] - dex) < 1e-8
    # envelope: brute force over 3600 directions of a 1 m/s^2 task acceleration
    K = np.vstack([np.reshape(robot.constraint_jacobian(q), (2, 4)),
                   np.reshape(robot.task(q)[1], (2, 4))])
    ang = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
    rhs = np.column_stack([np.zeros((3600, 2)), a.accel_m_s2 * unit(ang)])
    qdd = np.linalg.solve(K, rhs.T).T
    tau, _ = robot.closed_chain_inverse_dynamics(np.tile(q, (3600, 1)), np.zeros((3600, 4)), qdd)
    brute = np.max(np.abs(tau), axis=0)
    rel = np.max(np.abs(brute - a.envelope[0, j, i]) / a.envelope[0, j, i])
    print(f"\ncell ({a.x_m[i] * 1e3:.1f}, {a.y_m[j] * 1e3:.1f}) mm: dexterity "
          f"{a.dexterity[0, j, i]:.9f}, by differences |diff| {abs(s[-1] / s[0] - dex):.1e}; "
          f"envelope vs brute force {rel:.1e} relative")
    assert rel < 1e-6
    assert np.all(brute <= a.envelope[0, j, i] * (1 + 1e-12))
    worst_dir = ang[np.argmax(np.abs(tau), axis=0)]
    assert np.all(np.abs(wrap(worst_dir - a.envelope_angle_rad[0, j, i])) < 2 * np.pi / 3600)


def test_rest_torques_of_a_tree_are_its_inverse_dynamics(arm):
    robot = ps.load("serial_2dof")
    q = arm.q[0][arm.reachable[0]][::97]
    found = rest_torques(robot, q, 2.0)
    assert np.allclose(found["gravity"], robot.inverse_dynamics(q, 0 * q, 0 * q), rtol=0,
                       atol=1e-15)
    J = robot.task(q)[1]
    qdd = np.linalg.solve(J, np.tile([[0.0], [1.0]], (len(q), 1, 1)))[..., 0]
    ay = robot.inverse_dynamics(q, 0 * q, qdd) - found["gravity"]
    assert np.allclose(found["A"][..., 1], ay, rtol=1e-12, atol=1e-15)


# -- 4. the 2-link arm's dexterity in closed form --------------------------------------------


def test_two_link_dexterity_in_closed_form(arm):
    """Equal links l: J = l [[-s1 - s12, -s12], [c1 + c12, c12]], so sigma1^2 + sigma2^2 =
    ||J||_F^2 = l^2 (3 + 2 c2) = l^2 S and sigma1 sigma2 = |det J| = l^2 |s2|:

    .. code:: text

        1 / cond = sqrt((S - sqrt(S^2 - 4 s2^2)) / (S + sqrt(S^2 - 4 s2^2)))

    with cos q2 = (r^2 - 2 l^2) / (2 l^2) from the target's distance r."""
    r = np.hypot(*np.meshgrid(arm.x_m, arm.y_m))
    cells = arm.reachable[0]
    c2 = (r**2 - 2 * L**2) / (2 * L**2)
    S, s2sq = 3 + 2 * c2, 1 - c2**2
    with np.errstate(invalid="ignore"):  # NaN beyond reach (|cos q2| > 1)
        root = np.sqrt(np.maximum(S**2 - 4 * s2sq, 0))
        closed = np.sqrt((S - root) / (S + root))
    worst = float(np.max(np.abs(arm.dexterity[0][cells] - closed[cells])))
    print(f"\nserial_2dof: worst |dexterity - closed form| = {worst:.1e} over {cells.sum()} cells")
    assert worst < 1e-10
    assert np.max(np.abs(arm.type1[0][cells] - closed[cells])) < 1e-10  # K = J for a tree
    assert np.all(arm.type2[0][cells] == 1.0) and arm.same_assembly[0][cells].all()


# -- 5. along a study's path -----------------------------------------------------------------


def test_envelope_along_study_s5():
    study = "five_bar_type1_move_x"
    along = envelope_along(study, accel_m_s2=1.0)
    res = ps.run_study(study)
    tau = np.column_stack([res.columns["tau1_n_m"], res.columns["tau3_n_m"]])
    peak = np.max(np.abs(tau))
    assert np.max(np.abs(along.tau_study - tau)) <= 1e-12 * peak
    rebuilt = along.b + np.einsum("nkj,nj->nk", along.A, along.xdd)
    assert np.max(np.abs(rebuilt - tau)) <= 1e-9 * peak
    # with the study's own peak task acceleration as the size, the envelope bounds its torques
    a_study = float(np.max(np.hypot(along.xdd[:, 0], along.xdd[:, 1])))
    tight = envelope_along(study, accel_m_s2=a_study)
    assert np.all(tight.envelope >= np.abs(tau) - 1e-12 * peak)
    assert np.all(along.envelope >= np.abs(tau))  # 1 m/s^2 >> the study's 0.075 m/s^2
    # at t = 0 the path is at rest: b is the gravity torque and the envelope the atlas's
    rest = rest_torques(ps.load("five_bar_type1"), along.q[:1], 1.0)
    assert np.max(np.abs(rest["envelope"][0] - along.envelope[0])) <= 1e-12 * peak
    print(f"\nS5: |b + A xdd - tau| / peak = {np.max(np.abs(rebuilt - tau)) / peak:.1e}, "
          f"study acceleration {a_study:.3g} m/s^2")


# -- 6. bad input and the command line -------------------------------------------------------


@pytest.mark.parametrize("kwargs, pattern", [
    ({"x_range": (0.1, -0.1)}, r"x_range = \(0\.1, -0\.1\) m: the minimum must be below"),
    ({"y_range": (0.0, np.inf)}, r"y_range = \(0, inf\) m: both ends must be finite"),
    ({"step": -0.001}, r"step must be a positive length in m \(got -0\.001\)"),
    ({"points": 1}, r"points must be an integer >= 2 per axis"),
    ({"step": 0.001, "points": 50}, r"give a step or a number of points, not both"),
    ({"x_range": (1.0, 2.0), "y_range": (1.0, 2.0)}, r"lies outside the robot's reach"),
    ({"orientations": [0.0]}, r"orientations: five_bar_type1 has no orientation"),
    ({"accel_m_s2": -1.0}, r"accel_m_s2 must be a finite acceleration >= 0"),
    ({"length_scale": 0.0}, r"length_scale must be a positive length in m \(got 0\.0\)"),
    ({"q_start": [2.0736, -1.4223, 1.0680, 1.5223]},
     r"five_bar_type1: q_start does not close the loops \(\|Phi\| = 8\.2\d* mm, limit 1 mm\)"),
])
def test_bad_input_is_named(kwargs, pattern):
    with pytest.raises(InputError, match=pattern):
        atlas("five_bar_type1", **kwargs)


def test_a_grid_too_large_for_memory_is_refused_with_its_size():
    with pytest.raises(InputError, match=r"five_bar_type1: a grid of 193,818,240,000 points "
                       r"\(404800 x 478800\) would take 8\.68e\+04 GB of memory \(limit 2 GB\)"):
        atlas("five_bar_type1", step=1e-6)


def test_robots_an_atlas_cannot_map(tmp_path, monkeypatch):
    with pytest.raises(LibraryError, match="unknown robot 'no_such_robot'"):
        atlas("no_such_robot")
    with pytest.raises(InputError, match="slider_crank has no task point"):
        atlas("slider_crank")
    with pytest.raises(InputError, match=r"serial_rpr: a slider on every leg .* give the "
                       r"region \(x_range and y_range"):
        atlas("serial_rpr")
    with pytest.raises(WorkspaceError, match=r"serial_2dof: the start pose .* is singular"):
        atlas("serial_2dof", q_start=[0.0, 0.0])
    with pytest.raises(InputError, match=r"serial_2dof_free_swing: .*\(kind = \"inverse\"\); "
                       r"this one is kind = \"forward\""):
        envelope_along("serial_2dof_free_swing")
    from derive.__main__ import main as derive_main
    from planar_sym.model.library import Library
    from planar_sym.model.robot import Robot

    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    assert derive_main([str(TEST_ROBOTS / "pendulum.toml"), "--out", str(tmp_path), "--quiet"]) == 0
    pendulum = Robot("pendulum", Library("pendulum", folder=tmp_path / "pendulum"), exact=True)
    with pytest.raises(WorkspaceError, match="pendulum: no inverse kinematics in task space"):
        atlas(pendulum)


def test_sliders_and_orientations_map_with_a_given_region(tmp_path):
    a = atlas("serial_rpr", x_range=(-0.6, 0.9), y_range=(-0.6, 0.9), points=30,
              orientations=[1.2, 1.5708])
    assert a.q.shape == (2, 30, 30, 3) and a.reachable.all()
    assert a.actuator_units == ("N*m", "N", "N*m")
    names, values = a.table()
    assert "phi_deg" in names and "tau_g2_n" in names and "q2_m" in names
    assert values.shape == (2 * 30 * 30, len(names))
    a.to_npz(tmp_path / "rpr.npz")
    a.to_csv(tmp_path / "rpr.csv")
    with np.load(tmp_path / "rpr.npz") as npz:
        assert np.array_equal(npz["envelope"], a.envelope)
        assert list(npz["actuator_units"]) == ["N*m", "N", "N*m"]
    back = np.loadtxt(tmp_path / "rpr.csv", delimiter=",", skiprows=1)
    assert np.allclose(back, values, rtol=1e-9, atol=0, equal_nan=True)


def test_cli_writes_pictures_and_arrays_with_units(tmp_path, capsys):
    from planar_sym.cli import main

    out = tmp_path / "atlas"
    assert main(["atlas", "five_bar_type2", "--out", str(out), "--points", "40"]) == 0
    printed = capsys.readouterr().out
    for f in ("atlas.png", "atlas_torque.png", "atlas.npz", "atlas.csv"):
        assert (out / f).stat().st_size > 0 and f"wrote {out / f}" in printed
    assert "Type II singularity inside the workspace: yes" in printed
    header = (out / "atlas.csv").read_text().splitlines()[0].split(",")
    assert header[:4] == ["x_mm", "y_mm", "reachable", "same_assembly"]
    assert {"q1_rad", "type1", "type2", "dexterity", "tau_g1_n_m", "tau_env3_n_m",
            "env_angle1_deg"} <= set(header)
    table = np.loadtxt(out / "atlas.csv", delimiter=",", skiprows=1)
    assert table.shape == (1600, len(header))
    ref = atlas("five_bar_type2", points=40)
    with np.load(out / "atlas.npz") as npz:
        for key in ("x_m", "y_m", "reachable", "same_assembly", "q", "type1", "type2",
                    "dexterity", "gravity", "envelope"):
            assert np.array_equal(npz[key], getattr(ref, key), equal_nan=key not in (
                "reachable", "same_assembly")), key
        assert str(npz["robot"]) == "five_bar_type2"
    col = header.index("tau_g1_n_m")
    assert np.allclose(table[:, col], ref.gravity[..., 0].reshape(-1), equal_nan=True,
                       rtol=1e-9, atol=0)
    # a bad range on the command line: exit code 2, the message names it
    assert main(["atlas", "five_bar_type2", "--out", str(out), "--x", "100", "-100"]) == 2
    assert "--x 100 -100: give MIN MAX in mm, finite, MIN below MAX" in capsys.readouterr().err
    assert main(["atlas", "five_bar_type2", "--out", str(out), "--step", "0"]) == 2
    assert "--step must be a positive length in mm (got 0)" in capsys.readouterr().err
    assert main(["atlas", "five_bar_type2", "--out", str(out), "--phi", "10"]) == 2
    assert "orientations: five_bar_type2 has no orientation" in capsys.readouterr().err


def test_cli_with_a_study_writes_the_envelope_along_its_path(tmp_path, capsys):
    from planar_sym.cli import main

    out = tmp_path / "s5"
    assert main(["atlas", "five_bar_type1", "--out", str(out), "--points", "30", "--study",
                 "five_bar_type1_move_x", "--quiet"]) == 0
    assert capsys.readouterr().out == ""
    header = (out / "envelope_along.csv").read_text().splitlines()[0].split(",")
    assert header[:3] == ["t_s", "x_mm", "y_mm"] and "tau_env1_n_m" in header
    assert (out / "envelope_along.png").stat().st_size > 0


def test_cli_several_robots_side_by_side(tmp_path, capsys):
    """Two robots: each atlas in its own folder, compare.png over both; the printed areas are
    the atlases' own (the Type I design reaches further than the Type II one)."""
    from planar_sym.cli import main

    rc = main(["atlas", "five_bar_type1", "five_bar_type2", "--out", str(tmp_path),
               "--points", "40", "--x", "-160", "240", "--y", "-240", "240"])
    assert rc == 0
    out = capsys.readouterr().out
    for name in ("five_bar_type1", "five_bar_type2"):
        assert (tmp_path / name / "atlas.npz").is_file()
    assert (tmp_path / "compare.png").stat().st_size > 2e4
    areas = [float(line.split("reachable area ")[1].split(" cm^2")[0])
             for line in out.splitlines() if "reachable area" in line]
    assert len(areas) == 2 and areas[0] > 1.5 * areas[1]
    assert main(["atlas", "five_bar_type1", "five_bar_type2", "--study",
                 "five_bar_type1_move_x", "--out", str(tmp_path)]) == 2
    assert "--study and --q-start are for one robot" in capsys.readouterr().err
