"""The atlas's measures on robots with prismatic joints and an orientation in the task, where the
scaling to dimensionless matrices matters, against an independent computation.

On an all-revolute robot with an x-y task every column of K = [Phi_q; J] is scaled by the same
1 / L_c and every row by 1, so 1 / cond does not see the scaling (tests/test_atlas.py); here
it does. The reference rebuilds the matrices without the robot's generated Jacobians and
without ``pose_measures.scales``:

* serial_rpr: J in closed form from its description (planar_sym/robots/serial_rpr.toml: the
  wrist pivot W at s0 + l2 + d2 = 0.3 + 0.5 + d2 m from the shoulder along the sleeve, the tool
  l3 = 0.2 m beyond it, phi = q1 + q3), its x(q) checked against the robot's forward kinematics;
* parallel_3rpr: Phi_q and J by central differences of the robot's own ``constraint`` and
  ``task`` (functions of q only, not their generated Jacobians);

then scaled as the module docstring of planar_sym/analysis/pose_measures.py defines it, with
the coordinate kinds read from the descriptions (revolute or prismatic), not from the runtime:

.. code:: text

    rows: loop equations and x, y  x 1;  phi  x L_c
    cols: revolute coordinates  x 1 / L_c;  prismatic ones  x 1
    type1 = 1 / cond_2(K_s),  type2 = 1 / cond_2(K_s[loops, passive]),
    dexterity = 1 / cond_2((K_s^-1)[actuated, task rows])

and compared with numpy.linalg.cond to 1e-6 relative at every reachable cell of a small atlas
and at the drawn pose for two other lengths L_c.
"""

from __future__ import annotations

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.analysis.atlas import atlas, pose_measures

#: coordinates of the prismatic joints, from the descriptions' [[joints]] (in their order):
#: serial_rpr shoulder (R), extend (P), wrist (R); parallel_3rpr A1, leg1 (P), B1, A2,
#: leg2 (P), A3, leg3 (P); the loop joints B2, B3 are cut (no coordinate)
PRISMATIC = {"serial_rpr": [1], "parallel_3rpr": [1, 4, 6]}
ACTUATED = {"serial_rpr": [0, 1, 2], "parallel_3rpr": [1, 4, 6]}
#: serial_rpr's lengths (m) from its description: s0 (boom's rear end in the drawn pose),
#: l2 (boom R -> W), l3 (wrist W -> T)
S0, L2, L3 = 0.3, 0.5, 0.2
REL = 1e-6
#: atlases: region (m), points per axis, orientations (rad), L_c (m)
ATLASES = {
    "serial_rpr": {"x_range": (-0.6, 0.9), "y_range": (-0.6, 0.9), "points": 9,
                       "orientations": [1.2, 1.5708], "length_scale": 0.5},
    "parallel_3rpr": {"x_range": (-0.1, 0.1), "y_range": (-0.1, 0.1), "points": 7,
                          "orientations": [-0.2, 0.0, 0.25], "length_scale": 0.4},
}


def rpr_closed_form(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """serial_rpr's x = (x, y, phi) and J = dx/dq, (N, 3) and (N, 3, 3), by hand."""
    q1, d, q3 = q.T
    r, a = S0 + L2 + d, q1 + q3
    x = np.column_stack([r * np.cos(q1) + L3 * np.cos(a), r * np.sin(q1) + L3 * np.sin(a), a])
    J = np.zeros((len(q), 3, 3))
    J[:, 0] = np.column_stack([-r * np.sin(q1) - L3 * np.sin(a), np.cos(q1), -L3 * np.sin(a)])
    J[:, 1] = np.column_stack([r * np.cos(q1) + L3 * np.cos(a), np.sin(q1), L3 * np.cos(a)])
    J[:, 2] = [1.0, 0.0, 1.0]
    return x, J


def by_differences(f, q: np.ndarray, h: float = 1e-5) -> np.ndarray:
    """d f / d q (N, rows, n) by 4th-order central differences of f: (N, n) -> (N, rows)."""
    N, n = q.shape
    cols = []
    for j in range(n):
        e = np.zeros(n)
        e[j] = h
        f2, f1, b1, b2 = (np.reshape(f(q + s * e), (N, -1)) for s in (2, 1, -1, -2))
        cols.append((-f2 + 8 * f1 - 8 * b1 + b2) / (12 * h))
    return np.stack(cols, axis=-1)


def reference_K(robot, q: np.ndarray) -> np.ndarray:
    """[Phi_q; J] (N, n, n) without the robot's generated Jacobians."""
    if robot.name == "serial_rpr":
        x, J = rpr_closed_form(q)
        assert np.max(np.abs(x - np.reshape(robot.task(q)[0], x.shape))) < 1e-14
        return J
    task = by_differences(lambda z: robot.task(z)[0], q)
    return np.concatenate([by_differences(robot.constraint, q), task], axis=1)


def reference_measures(robot, q: np.ndarray, L: float) -> dict[str, np.ndarray]:
    """type1, type2, dexterity per the documented definition, with numpy.linalg.cond."""
    n, m = robot.n, robot.n_constraints
    rows = np.ones(n)
    rows[m + list(robot.task_names).index("phi")] = L
    cols = np.full(n, 1.0 / L)
    cols[PRISMATIC[robot.name]] = 1.0
    Ks = reference_K(robot, q) * rows[:, None] * cols
    act = ACTUATED[robot.name]
    passive = [j for j in range(n) if j not in act]
    out = {"type1": 1 / np.linalg.cond(Ks),
           "type2": 1 / np.linalg.cond(Ks[:, :m][:, :, passive]) if m else np.ones(len(q)),
           "dexterity": 1 / np.linalg.cond(np.linalg.inv(Ks)[:, act][:, :, m:])}
    return out


@pytest.fixture(scope="module", params=list(ATLASES))
def mapped(request):
    name = request.param
    robot = ps.load(name)
    # the hard-coded kinds are the descriptions': the runtime's units say the same
    assert [j for j, u in enumerate(robot.coordinate_units) if u == "m"] == PRISMATIC[name]
    assert list(robot.actuated) == ACTUATED[name] and "phi" in robot.task_names
    return robot, atlas(name, **ATLASES[name])


def test_measures_at_every_cell_against_numpy(mapped):
    """Every reachable cell of a 2- or 3-orientation atlas: type1, type2 and dexterity equal
    the reference's 1 / cond to 1e-6 relative."""
    robot, a = mapped
    cells = a.reachable
    assert cells.sum() >= 40, cells.sum()
    q = a.q[cells]
    ref = reference_measures(robot, q, a.length_scale_m)
    worst = {}
    for key, values in ref.items():
        got = getattr(a, key)[cells]
        worst[key] = float(np.max(np.abs(got - values) / values))
        assert worst[key] < REL, (key, worst[key])
    print(f"\n{robot.name} (L_c = {a.length_scale_m} m, {cells.sum()} cells): type1 in "
          f"[{ref['type1'].min():.3f}, {ref['type1'].max():.3f}], type2 in "
          f"[{ref['type2'].min():.3f}, {ref['type2'].max():.3f}]; worst relative difference "
          + ", ".join(f"{k} {v:.1e}" for k, v in worst.items()))


@pytest.mark.parametrize("name, L, type1", [
    # the drawn pose (serial_rpr: shoulder 30 deg, boom 0.8 m, wrist 60 deg; parallel_3rpr:
    # platform centred, phi = 0), the reference's figure to 3 digits
    ("serial_rpr", 0.5, 0.315), ("serial_rpr", 2.0, 0.187),
    ("parallel_3rpr", 0.5, 0.186), ("parallel_3rpr", 2.0, 0.067)])
def test_drawn_pose_at_other_length_scales(name, L, type1):
    """The measures depend on L_c only through the scaling: at the drawn pose, for L_c = 0.5 m
    and 2 m, they equal the reference's (whose type1 differs between the two: 0.315 and 0.187,
    0.186 and 0.067; on an all-revolute x-y robot it would not)."""
    robot = ps.load(name)
    q = robot.q_drawn[None]
    ref = reference_measures(robot, q, L)
    got = pose_measures(robot, q, L)
    for key, values in ref.items():
        assert got[key][0] == pytest.approx(values[0], rel=REL), key
    assert ref["type1"][0] == pytest.approx(type1, abs=5e-4)
