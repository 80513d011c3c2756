"""Every scenario of SCENARIOS.md (S1-S7), as a built-in study, runs; its CSV columns are as specified; its start and
end values match SCENARIOS.md; the joint and task columns agree through forward kinematics
computed by hand from the seed's geometry; S2's first torque matches a hand calculation from
Table 1.
"""

from __future__ import annotations

import io

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.model import description
from planar_sym.study.builtin import names
from planar_sym.study.run import load_study, run

#: the seed's S1-S7; the other built-in studies (robots with prismatic joints) are checked in
#: tests/test_prismatic_robots.py
SEED = {"serial_2dof_free_swing", "serial_2dof_joint_move", "serial_2dof_cartesian_move",
        "serial_3dof_cartesian_move", "five_bar_type1_move_x", "five_bar_type1_move_y",
        "five_bar_type2_move_x", "five_bar_type2_move_y", "parallel_3rrr_move_x",
        "parallel_3rrr_move_y"}
SCENARIOS = [n for n in names() if n in SEED]

SAMPLES = 21

TASK_XY = ["x_mm", "y_mm"]
TASK_XYPHI = ["x_mm", "y_mm", "phi_rad"]


def expected_columns(name: str) -> list[str]:
    st = load_study(name)
    n = {"serial_2dof": 2, "serial_3dof": 3, "five_bar_type1": 4, "five_bar_type2": 4,
         "parallel_3rrr": 7}[st.robot]
    q = [f"q{k}_rad" for k in range(1, n + 1)]
    qd = [f"qd{k}_rad_s" for k in range(1, n + 1)]
    qdd = [f"qdd{k}_rad_s2" for k in range(1, n + 1)]
    task = TASK_XYPHI if st.robot in ("serial_3dof", "parallel_3rrr") else TASK_XY
    if st.kind == "forward":
        return ["t_s", *task, *q, *qd, "energy_j"]
    # then every joint's load (parent on child: force, bearing load, a weld's couple), in the
    # manifest's joint order, and the power of each actuator
    joints = [(j["name"], j["type"]) for j in ps.load(st.robot).library.manifest["joints"]]
    loads = [c for name, kind in joints for c in (
        f"jfx_{name}_n", f"jfy_{name}_n", f"jload_{name}_n",
        *([f"jm_{name}_n_m"] if kind == "weld" else []))]
    if st.robot.startswith("serial"):
        return ["t_s", *task, *q, *qd, *qdd, *[f"tau{k}_n_m" for k in range(1, n + 1)], *loads,
                *[f"p{k}_w" for k in range(1, n + 1)]]
    if st.robot.startswith("five_bar"):  # actuated A = q1, E = q3
        return ["t_s", *task, *q, *qd, *qdd, "tau1_n_m", "tau3_n_m", "fx_C_n", "fy_C_n", *loads,
                "p1_w", "p3_w"]
    assert st.robot == "parallel_3rrr"  # actuated A1 = q1, A2 = q4, A3 = q6
    return ["t_s", *task, *q, *qd, *qdd, "tau1_n_m", "tau4_n_m", "tau6_n_m",
            "fx_B2_n", "fy_B2_n", "fx_B3_n", "fy_B3_n", *loads, "p1_w", "p4_w", "p6_w"]


_RESULTS: dict = {}


def result(name):
    if name not in _RESULTS:
        _RESULTS[name] = run(name, SAMPLES)
    return _RESULTS[name]


def test_scenario_list_is_the_seed_s1_to_s7():
    assert set(SCENARIOS) == SEED


@pytest.mark.parametrize("name", list(SCENARIOS))
def test_runs_with_specified_columns(name):
    res = result(name)
    cols = expected_columns(name)
    assert list(res.columns) == cols
    text = res.csv_text()
    header, _, body = text.partition("\n")
    assert header.split(",") == cols
    table = np.loadtxt(io.StringIO(body), delimiter=",", ndmin=2)
    assert table.shape == (SAMPLES, len(cols))
    for i, c in enumerate(cols):
        assert np.all(np.isfinite(res.columns[c])), c
        assert np.array_equal(table[:, i], res.columns[c]), f"{c}: CSV round trip not exact"
    st = load_study(name)
    duration = (st.motion or st.simulation).duration_s
    assert np.array_equal(res.columns["t_s"], np.linspace(0.0, duration, SAMPLES))
    if st.motion is not None and st.motion.space == "task":
        x = np.column_stack([res.columns[c] for c in ("x_mm", "y_mm", "phi_rad")
                             if c in res.columns])
        assert np.allclose(x[0], st.motion.start, rtol=0, atol=1e-9)
        assert np.allclose(x[-1], np.add(st.motion.start, st.motion.by), rtol=0, atol=1e-9)
    tau = [c for c in cols if c.startswith("tau")]
    if tau:  # inverse dynamics: torques are not all zero
        assert max(np.max(np.abs(res.columns[c])) for c in tau) > 1e-3


def _q(name, k=None):
    """The actuated joints' angles (every joint of a tree), rad."""
    res = result(name)
    q = np.column_stack(list(res.angles().values()))[:, list(res.actuated)]
    return q if k is None else q[k]


def test_start_and_end_poses():
    deg = np.radians
    assert np.allclose(_q("serial_2dof_cartesian_move", 0), deg([0.0, 90.0]), atol=1e-12)
    assert np.allclose(_q("serial_2dof_cartesian_move", -1), deg([90.0, 90.0]), atol=1e-12)
    assert np.allclose(_q("serial_3dof_cartesian_move", 0), deg([0.0, 90.0, 0.0]), atol=1e-12)
    assert np.allclose(_q("serial_2dof_joint_move", 0), [0.0, 0.0], atol=1e-15)
    assert np.allclose(_q("serial_2dof_joint_move", -1), deg([90.0, 0.0]), atol=1e-14)
    assert np.allclose(_q("serial_2dof_free_swing", 0), deg([-60.0, 0.0]), atol=1e-15)
    for axis in "xy":
        assert np.allclose(_q(f"five_bar_type1_move_{axis}", 0), [2.07359, 1.06801], atol=1e-5)
        assert np.allclose(_q(f"five_bar_type2_move_{axis}", 0), [0.0, np.pi / 2], atol=1e-12)
        assert np.allclose(np.degrees(_q(f"parallel_3rrr_move_{axis}", 0)),
                           [-144.9004, -24.9004, 95.0996], atol=1e-3)


def test_s1_forward_columns():
    c = result("serial_2dof_free_swing").columns
    assert np.allclose([c["qd1_rad_s"][0], c["qd2_rad_s"][0]], 0.0, atol=0)
    # released from rest below the horizontal: link 1 first falls (q1 decreases)
    assert c["q1_rad"][1] < c["q1_rad"][0]
    assert np.ptp(c["energy_j"]) < 1e-9 * np.max(np.abs(c["energy_j"]))


# -- forward kinematics by hand --------------------------------------------------------------

def test_serial_task_columns_by_hand():
    for name, (a1, a2, a3) in [("serial_2dof_joint_move", (0.1, 0.1, 0.0)),
                               ("serial_2dof_cartesian_move", (0.1, 0.1, 0.0)),
                               ("serial_3dof_cartesian_move", (0.1, 0.07, 0.05))]:
        c = result(name).columns
        q = _q(name)
        s1 = q[:, 0]
        s12 = s1 + q[:, 1]
        s123 = s12 + (q[:, 2] if q.shape[1] == 3 else 0.0)
        x = a1 * np.cos(s1) + a2 * np.cos(s12) + a3 * np.cos(s123)
        y = a1 * np.sin(s1) + a2 * np.sin(s12) + a3 * np.sin(s123)
        assert np.max(np.abs(c["x_mm"] - 1e3 * x)) < 1e-9, name
        assert np.max(np.abs(c["y_mm"] - 1e3 * y)) < 1e-9, name
        if "phi_rad" in c:
            assert np.max(np.abs(c["phi_rad"] - s123)) < 1e-12


def _circle_intersections(b, rb, d, rd):
    """Both intersections of the circles (b, rb) and (d, rd), points (N, 2)."""
    v = d - b
    L = np.linalg.norm(v, axis=1)
    a = (rb**2 - rd**2 + L**2) / (2 * L)
    h = np.sqrt(rb**2 - a**2)
    u = v / L[:, None]
    n = np.column_stack([-u[:, 1], u[:, 0]])
    base = b + a[:, None] * u
    return base + h[:, None] * n, base - h[:, None] * n


@pytest.mark.parametrize("name", [n for n in SCENARIOS if n.startswith("five_bar")])
def test_five_bar_task_columns_by_hand(name):
    """From the actuated angles alone: B = A + l2 (cos q1, sin q1), D = E + l5 (cos q2, sin q2),
    C on the circles |BC| = l3 and |DC| = l4 (the branch of the drawn pose), P rigid with B-C (on
    the extension of BC); lengths from the description's drawn points (SCENARIOS.md)."""
    desc = description.load(load_study(name).robot)
    b = desc.bodies
    world = {}
    for body, point, label in [("ground", "A", "A"), ("ground", "E", "E"),
                               ("L_Link1", "CS2", "B"), ("L_Link2", "CS2", "C"),
                               ("L_Link2", "CS3", "P"), ("R_Link1", "CS2", "D")]:
        bd = b[body]
        x, y = bd.points_m[point]
        c, s = np.cos(bd.drawn_angle_rad), np.sin(bd.drawn_angle_rad)
        o = np.array(bd.drawn_origin_m)
        world[label] = o + np.array([c * x - s * y, s * x + c * y])
    A, E, B0, C0, P0, D0 = (world[k] for k in "AEBCPD")
    l2, l5 = np.linalg.norm(B0 - A), np.linalg.norm(D0 - E)
    l3, l4, lbp = np.linalg.norm(C0 - B0), np.linalg.norm(C0 - D0), np.linalg.norm(P0 - B0)
    q = _q(name)
    B = A + l2 * np.column_stack([np.cos(q[:, 0]), np.sin(q[:, 0])])
    D = E + l5 * np.column_stack([np.cos(q[:, 1]), np.sin(q[:, 1])])
    c1, c2 = _circle_intersections(B, l3, D, l4)
    ref = _circle_intersections(B0[None], l3, D0[None], l4)
    branch1 = np.linalg.norm(ref[0][0] - C0) < np.linalg.norm(ref[1][0] - C0)
    C = c1 if branch1 else c2
    # P rigid with B and C: its drawn coordinates along and across BC (P is on the line BC only
    # to the table's rounding, 4e-8 m off it in S5)
    u0 = (C0 - B0) / l3
    along, across = (P0 - B0) @ u0, (P0 - B0) @ np.array([-u0[1], u0[0]])
    assert abs(along - lbp) < 1e-7
    u = (C - B) / l3
    P = B + along * u + across * np.column_stack([-u[:, 1], u[:, 0]])
    c = result(name).columns
    err = max(np.max(np.abs(c["x_mm"] - 1e3 * P[:, 0])), np.max(np.abs(c["y_mm"] - 1e3 * P[:, 1])))
    assert err < 1e-8, f"{name}: P from the actuated angles differs by {err:.3g} mm"


@pytest.mark.parametrize("name", ["parallel_3rrr_move_x", "parallel_3rrr_move_y"])
def test_parallel_3rrr_angles_by_the_seed_formula(name):
    """th_i = 2 atan((-e1 - sqrt(e1^2 + e2^2 - e3^2)) / (e3 - e2)) of SCENARIOS.md S7, with
    d = p + R(phi) B_i - A_i and the description's points (mod 2 pi)."""
    desc = description.load("parallel_3rrr")
    g, plat = desc.bodies["ground"], desc.bodies["platform"]
    c = result(name).columns
    px, py, phi = c["x_mm"] * 1e-3, c["y_mm"] * 1e-3, c["phi_rad"]
    for i in (1, 2, 3):
        a = np.array(g.points_m[f"A{i}"])
        bi = np.array(plat.points_m[f"CS{i}"]) - np.array(plat.points_m["P"])
        l1 = np.linalg.norm(np.array(desc.bodies[f"Link{i}_1"].points_m["CS2"]))
        l2 = np.linalg.norm(np.array(desc.bodies[f"Link{i}_2"].points_m["CS2"]))
        dx = px + np.cos(phi) * bi[0] - np.sin(phi) * bi[1] - a[0]
        dy = py + np.sin(phi) * bi[0] + np.cos(phi) * bi[1] - a[1]
        e1, e2, e3 = -2 * l1 * dy, -2 * l1 * dx, dx**2 + dy**2 + l1**2 - l2**2
        th = 2 * np.arctan((-e1 - np.sqrt(e1**2 + e2**2 - e3**2)) / (e3 - e2))
        coordinate = (1, 4, 6)[i - 1]  # A1, A2, A3
        diff = (c[f"q{coordinate}_rad"] - th + np.pi) % (2 * np.pi) - np.pi
        assert np.max(np.abs(diff)) < 1e-9, f"leg {i}"


# -- S2: torque at t = 0 by hand from Table 1 ------------------------------------------------------

def test_s2_initial_torque_by_hand():
    """q = 0 (both links along +x), qd = 0, qdd = [6 dq / T^2, 0] (the cubic starts with
    acceleration 2 c2 = 6 dq / T^2):

        tau1 = M11 qdd1 + g (m1 lc1 + (mM + m2) a1 + m2 lc2)
        tau2 = M21 qdd1 + g m2 lc2
        M11 = I1 + m1 lc1^2 + mM a1^2 + I2 + m2 (a1 + lc2)^2,  M21 = I2 + m2 (lc2^2 + a1 lc2)
    """
    m1, i1, lc1, a1 = 0.071, 89.395e-6, 0.0373, 0.1
    mm = 0.292
    m2, i2, lc2 = 0.075, 109.864e-6, 0.04168
    g = 9.81
    qdd1 = 6 * np.radians(90.0) / 10.0**2
    m11 = i1 + m1 * lc1**2 + mm * a1**2 + i2 + m2 * (a1 + lc2) ** 2
    m21 = i2 + m2 * (lc2**2 + a1 * lc2)
    static = np.array([g * (m1 * lc1 + (mm + m2) * a1 + m2 * lc2), g * m2 * lc2])
    tau0 = static + np.array([m11, m21]) * qdd1
    c = result("serial_2dof_joint_move").columns
    got = np.array([c["tau1_n_m"][0], c["tau2_n_m"][0]])
    assert got == pytest.approx(tau0, rel=1e-12)
    # the inertial part is large enough to matter: the static torque alone is off
    assert abs(got[0] - static[0]) > 1e-3 * abs(static[0])
    # at t = T: qdd = -6 dq / T^2 at q = [90, 0] deg (arm straight up: no gravity torque)
    got_end = np.array([c["tau1_n_m"][-1], c["tau2_n_m"][-1]])
    assert got_end == pytest.approx(-np.array([m11, m21]) * qdd1, rel=1e-9, abs=1e-15)
