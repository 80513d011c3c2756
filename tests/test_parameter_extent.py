"""A body's extent for the inertial rules is measured from all its points on every route:
the run-time parameter checks (``with_parameters``, a study's ``[parameters]``, sweeps) used
only the points that are parameters, so a carriage whose corners only show its size was
accepted by the description and then refused on any change of any parameter as "a unit or
decimal-point slip" (found in a user trial). The reference is the description's own check on
the same values, typed into the file: the run-time rule must refuse exactly what it refuses.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.errors import DescriptionError, InputError
from planar_sym.model import description

FILE = Path(__file__).resolve().parent / "robots" / "carriage_arm.toml"
TEXT = FILE.read_text()


@pytest.fixture(scope="module")
def arm():
    return ps.load(str(FILE))


def test_the_fixed_corners_count_in_the_extent(arm):
    assert {"px_carriage_c1", "py_carriage_c2"} <= set(arm.parameters.fixed)
    assert arm.parameters.fixed["px_carriage_c1"] == pytest.approx(-0.12, abs=1e-15)
    moved = arm.with_parameters(m_upper=1.6)  # any change checks every body again
    assert moved.parameters["m_upper"] == 1.6


@pytest.mark.parametrize("izz_kg_cm2", [150.0, 1500.0, 4000.0, 6000.0])
def test_the_run_time_rule_is_the_description_rule(arm, tmp_path, izz_kg_cm2):
    """The same inertia refused (or not) by the description and by with_parameters."""
    path = tmp_path / "carriage_arm.toml"
    path.write_text(TEXT.replace("izz = 150.0", f"izz = {izz_kg_cm2}", 1))
    try:
        description.load(path)
        by_file = False
    except DescriptionError as exc:
        by_file = any("carriage" in p and "izz" in p for p in exc.problems)
    try:
        arm.with_parameters(izz_carriage=izz_kg_cm2 * 1e-4)
        at_run_time = False
    except InputError:
        at_run_time = True
    assert at_run_time == by_file, (izz_kg_cm2, by_file)


def test_a_sweep_checks_with_the_corners_too(arm):
    from planar_sym.analysis.designs import _check_physical

    names = ["izz_carriage"]
    values = np.array([[0.015], [0.6]])  # kg*m^2: 70.7 mm (plausible), 447 mm (refused)
    P = np.tile(arm.parameters.vector, (2, 1))
    k = [p.name for p in arm.parameter_list].index("izz_carriage")
    P[:, k] = values[:, 0]
    with pytest.raises(InputError, match=r"design 1 \(izz_carriage = 0.6\) is not physical"):
        _check_physical(arm, names, values, P)
    _check_physical(arm, names, values[:1], P[:1])
