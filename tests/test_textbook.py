"""The 2-DOF arm against its textbook closed form, with the seed's Table 1 numbers typed in.

Tolerance 1e-12 on ``rel_err`` (conftest: per-sample normwise relative error).
"""

from __future__ import annotations

import numpy as np
from conftest import GENERATED, random_states, record, rel_err

from planar_sym.model.locate import load

TOL = 1e-12

# seed Table 1, SI (inertias given in kg*mm^2 in the table)
m1, I1, lc1 = 0.071, 89.395e-6, 0.0373
mM = 0.292  # motor point mass welded at the elbow, a1 from the shoulder
m2, I2, lc2 = 0.075, 109.864e-6, 0.04168
a1, a2 = 0.1, 0.1
g0 = 9.81


def textbook(q, qd):
    """M(q), C(q, qd) qd and g(q) of the two-link arm with an elbow motor mass."""
    q1, q2 = q[:, 0], q[:, 1]
    qd1, qd2 = qd[:, 0], qd[:, 1]
    c2, s2 = np.cos(q2), np.sin(q2)
    M11 = I1 + m1 * lc1**2 + I2 + m2 * (a1**2 + lc2**2 + 2 * a1 * lc2 * c2) + mM * a1**2
    M12 = I2 + m2 * (lc2**2 + a1 * lc2 * c2)
    M22 = np.full_like(q1, I2 + m2 * lc2**2)
    M = np.stack([np.stack([M11, M12], -1), np.stack([M12, M22], -1)], -2)
    hh = m2 * a1 * lc2 * s2
    C = np.stack([-hh * (2 * qd1 * qd2 + qd2**2), hh * qd1**2], -1)
    G = np.stack([(m1 * lc1 + (m2 + mM) * a1) * g0 * np.cos(q1) + m2 * lc2 * g0 * np.cos(q1 + q2),
                  m2 * lc2 * g0 * np.cos(q1 + q2)], -1)
    return M, C, G


def test_mass_matrix_coriolis_gravity(rng, worst_errors):
    robot = load("serial_2dof")
    q, qd, qdd = random_states(rng, 100, 2)
    M, C, G = textbook(q, qd)
    for key, have, want in [
        ("M", robot.mass_matrix(q), M),
        ("g", robot.gravity(q), G),
        ("h", robot.bias(q, qd), C + G),
        # C qd alone: gravity switched off (h - g would lose digits to cancellation)
        ("C qd", robot.with_parameters(g=0.0).bias(q, qd), C),
        ("tau", robot.inverse_dynamics(q, qd, qdd), np.einsum("kij,kj->ki", M, qdd) + C + G),
    ]:
        err = record(worst_errors, f"textbook {key}", rel_err(have, want))
        assert err < TOL, f"{key}: {err:.3e}"


def test_task_is_the_forward_kinematics(rng, worst_errors):
    robot = load("serial_2dof")
    q, qd, _ = random_states(rng, 50, 2)
    x, J, _ = robot.task(q, qd)
    q1, q12 = q[:, 0], q[:, 0] + q[:, 1]
    want = np.stack([a1 * np.cos(q1) + a2 * np.cos(q12), a1 * np.sin(q1) + a2 * np.sin(q12)], -1)
    jac = np.stack([np.stack([-a1 * np.sin(q1) - a2 * np.sin(q12), -a2 * np.sin(q12)], -1),
                    np.stack([a1 * np.cos(q1) + a2 * np.cos(q12), a2 * np.cos(q12)], -1)], -2)
    assert record(worst_errors, "textbook task x", rel_err(x, want)) < TOL
    assert record(worst_errors, "textbook task J", rel_err(J, jac)) < TOL


def test_parameters_are_table_1():
    p = load("serial_2dof").parameters
    want = {"g": g0, "m_link1": m1, "izz_link1": I1, "cgx_link1": lc1, "m_motor2": mM,
            "izz_motor2": 0.0, "m_link2": m2, "izz_link2": I2, "cgx_link2": lc2,
            "px_link1_CS2": a1, "px_link2_CS2": a2}
    assert set(p) == set(want)
    for k, v in want.items():
        assert abs(p[k] - v) <= 1e-15 * abs(v), (k, p[k], v)


def _section(text: str, title: str) -> list[str]:
    """The indented lines under a heading of equations.txt."""
    lines = text.splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(title))
    out = []
    for line in lines[start + 1:]:
        if not line.startswith("  "):
            break
        out.append(line)
    return out


def test_printed_equations_are_compact():
    text = (GENERATED / "serial_2dof" / "equations.txt").read_text()
    words = " ".join(text.split())
    assert "c2 = cos(q2)" in words and "c12 = cos(q1 + q2)" in words  # the notation line
    assert "M22 = I_2 + m_2*l_c2**2" in text
    mass = _section(text, "Mass matrix M(q)")
    assert [line.split("=")[0].strip() for line in mass] == ["M11", "M12", "M22"]
    for line in mass:
        assert len(line) <= 120, f"mass-matrix line of {len(line)} characters: {line}"
        # the compact form has no products of trigonometric functions of q1
        assert "q1" not in line and "cos(" not in line, line
    assert "m_2*(a_1**2 + l_c2**2 + 2*a_1*l_c2*c2)" in text
    assert "M12 = I_2 + m_2*(l_c2**2 + a_1*l_c2*c2)" in text
    gravity = _section(text, "Gravity terms g(q)")
    assert all("c12" in line for line in gravity[:2])

