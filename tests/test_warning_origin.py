"""Where the exporters' warnings point (``outputs/export_model.from_robot``'s ``stacklevel=3``):
at the line of the caller of ``to_mjcf`` / ``to_urdf``, the user's code, not inside the package.

Not listed in ``mutation/targets.toml``: under mutmut every call of a mutated module goes
through two frames of its trampoline, so the original's stacklevel names one of mutmut's frames
there and this test would fail on the original (see the judgments in
``mutation/equivalent/outputs.toml``). In a plain run it pins the attribution a user sees.
"""

from __future__ import annotations

import warnings

import planar_sym as ps
from planar_sym.outputs.export_mjcf import to_mjcf


def _robot():
    from conftest import TEST_ROBOTS

    return ps.load(TEST_ROBOTS / "rpr_geared.toml")


def _origin(call):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        call()
    assert len(rec) == 1 and rec[0].category is RuntimeWarning
    return rec[0].filename, rec[0].lineno


def test_the_drive_trains_warning_names_the_callers_line():
    """Catches ``stacklevel=3`` dropped or turned into 4 for the drive train's warning
    (rpr_geared: Coulomb friction exported as MuJoCo's frictionloss): the warning is filed
    under this file at the line of the call, found by ``_origin``'s own frame."""
    robot = _robot()
    call = lambda: to_mjcf(robot)  # the warning must point at this line
    assert _origin(call) == (__file__, call.__code__.co_firstlineno)


def test_the_ideal_machines_warning_names_the_callers_line():
    """Catches ``stacklevel=3`` dropped or turned into 4 for the ideal machine's warning (the
    actuator figures left out of the file)."""
    robot = _robot()
    call = lambda: to_mjcf(robot, ideal=True)  # the warning must point here
    assert _origin(call) == (__file__, call.__code__.co_firstlineno)
