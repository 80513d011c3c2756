"""The seed's scenarios as study files: the same numbers as the code they replaced, bit for bit,
and each file runnable on its own when copied elsewhere.

Reference: tests/data/seed_results_before_studies.npz, written by the scenario code (a Python
list in planar_sym/scenarios.py) just before it was replaced by study files; its columns had
no units in their names and, for closed chains, numbered only the actuated joints.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.study import builtin
from planar_sym.study.run import run

REFERENCE = Path(__file__).resolve().parent / "data" / "seed_results_before_studies.npz"
SEED_STUDIES = ("serial_2dof_free_swing", "serial_2dof_joint_move", "serial_2dof_cartesian_move",
                "serial_3dof_cartesian_move", "five_bar_type1_move_x", "five_bar_type1_move_y",
                "five_bar_type2_move_x", "five_bar_type2_move_y", "parallel_3rrr_move_x",
                "parallel_3rrr_move_y")
#: the built-in studies of robots with prismatic joints (issue 11), checked in
#: tests/test_prismatic_robots.py
PRISMATIC_STUDIES = ("slider_crank_turn", "slider_crank_slider_driven_stroke",
                     "serial_rpr_tool_move", "parallel_3rpr_move_x")
#: the built-in control studies (issue 12), checked in tests/test_control.py
CONTROL_STUDIES = ("serial_2dof_cartesian_track", "serial_2dof_cartesian_track_pd",
                   "five_bar_type1_track_x")
#: the built-in time-optimal studies (issue 27), checked in tests/test_time_optimal.py
FASTEST_STUDIES = ("serial_2dof_cartesian_fastest", "five_bar_type1_move_x_fastest")
#: the built-in optimal-move studies (issue 27), checked in tests/test_optimal_study.py
OPTIMAL_STUDIES = ("cart_pole_swing_up",)


def old_name(new: str, actuated: tuple[int, ...], closed: bool) -> str | None:
    """The reference's column for a new column name (None where the old CSV had none)."""
    if new == "t_s":
        return "t"
    if m := re.fullmatch(r"(q|qd|tau)(\d+)_(rad|rad_s|n_m)", new):
        kind, k = m.group(1), int(m.group(2)) - 1
        if closed:  # the old CSV numbered the actuated joints only
            if k not in actuated:
                return None
            k = actuated.index(k)
        return f"{kind}{k + 1}"
    if new.startswith("qdd"):
        return None
    return new  # x_mm, y_mm, phi_rad, fx_C_n, energy_j unchanged


def test_the_built_in_studies_are_the_seed_scenarios():
    assert tuple(builtin.names()) == tuple(sorted(SEED_STUDIES + PRISMATIC_STUDIES
                                                       + CONTROL_STUDIES + FASTEST_STUDIES
                                                       + OPTIMAL_STUDIES))


@pytest.mark.parametrize("name", SEED_STUDIES)
def test_study_gives_the_scenario_numbers_exactly(name):
    ref = np.load(REFERENCE)
    result = run(name)
    robot = ps.load(result.robot)
    compared = set()
    for new, values in result.columns.items():
        old = old_name(new, robot.actuated, robot.is_closed_chain)
        if old is None or f"{name}/{old}" not in ref.files:
            continue  # a column the old CSV did not have (task columns of a forward run)
        reference = ref[f"{name}/{old}"]
        scale = max(np.max(np.abs(reference)), 1e-300)
        # 0 when the scenario code was replaced (commit "Studies as data"); later changes to
        # the generated code (the fused closed-chain function gained its loop residuals)
        # reorder rounding by an ulp or two, and another CPU's vector libm (numpy 2.4 on an
        # AVX-512 machine) moves the 3-RRR's cut forces by up to 1.7e-14 of their peak
        assert np.max(np.abs(values - reference)) / scale <= 5e-14, (new, old)
        compared.add(old)
    expected = {k.split("/", 1)[1] for k in ref.files if k.startswith(f"{name}/")
                and "/split_" not in k}
    assert compared == expected  # every old column is still there
    # the split terms are measured against the largest of them: a term that is nearly zero
    # (the velocity term of a slow move) carries the rounding of the others (5e-13 of its own
    # peak on one machine, 1.5e-16 of the largest term)
    archived = [part for part in result.split if f"{name}/split_{part}" in ref.files]
    assert set(archived) == {"inertial", "velocity", "gravity"}
    peak = max([np.max(np.abs(ref[f"{name}/split_{part}"])) for part in archived] + [1e-300])
    for part, values in result.split.items():
        if part not in archived:  # the drive train's parts: the seed's robots have no drives
            assert part in ("friction", "rotor") and not np.any(values), part
            continue
        reference = ref[f"{name}/split_{part}"]
        assert np.max(np.abs(values - reference)) <= 1e-14 * peak, part


def test_a_study_file_copied_elsewhere_runs_on_its_own(tmp_path):
    copy = tmp_path / "mine.toml"
    shutil.copy(builtin.find("five_bar_type1_move_x"), copy)
    a, b = run(copy), run("five_bar_type1_move_x")
    assert a.name == "mine"
    for k in b.columns:
        np.testing.assert_array_equal(a.columns[k], b.columns[k])


def test_inverse_csv_holds_rates_and_accelerations_with_units():
    result = run("five_bar_type1_move_x")
    header = result.csv_text().splitlines()[0].split(",")
    assert header[:3] == ["t_s", "x_mm", "y_mm"]
    for k in range(1, 5):
        assert {f"q{k}_rad", f"qd{k}_rad_s", f"qdd{k}_rad_s2"} <= set(header)
    assert [h for h in header if h.startswith("tau")] == ["tau1_n_m", "tau3_n_m"]  # A and E
    cut = header.index("fx_C_n")  # the cut force, then every joint's load, then the power
    assert header[cut:cut + 2] == ["fx_C_n", "fy_C_n"]
    assert header[-2:] == ["p1_w", "p3_w"]
    # rates and accelerations are consistent with the positions: the corrected trapezoid rule
    # q(k+1) - q(k) = h (qd(k) + qd(k+1)) / 2 + h^2 (qdd(k) - qdd(k+1)) / 12 + O(h^5)
    t = result.columns["t_s"]
    h = np.diff(t)
    for k in range(1, 5):  # passive joints too
        q, qd, qdd = (result.columns[f"{p}{k}_{u}"] for p, u in
                      (("q", "rad"), ("qd", "rad_s"), ("qdd", "rad_s2")))
        step = h * (qd[1:] + qd[:-1]) / 2 + h**2 * (qdd[:-1] - qdd[1:]) / 12
        assert np.max(np.abs(np.diff(q) - step)) < 1e-9, k
