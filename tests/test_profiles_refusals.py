"""motion/profiles.py's refusals by value: the seed's cubic (``coeff_3rd``) and ``cubic`` name
the input that is wrong (start, start velocity, end, end velocity, displacement, times,
duration) and what it was, one message each; and a valid call's coefficients against the
closed form of a rest-to-rest cubic, 3 dx / T^2 and -2 dx / T^3."""

from __future__ import annotations

import numpy as np
import pytest

from planar_sym.errors import InputError
from planar_sym.motion.profiles import coeff_3rd, cubic


def _message(fn, *args) -> str:
    with pytest.raises(InputError) as info:
        fn(*args)
    return str(info.value)


@pytest.mark.parametrize("k, name", [(0, "start"), (1, "start velocity"), (2, "end"),
                                     (3, "end velocity")])
def test_coeff_3rd_names_the_wrong_input(k, name):
    good = [[0.0], [0.0], [1.0], [0.0]]
    bad = list(good)
    bad[k] = ["a"]
    assert _message(coeff_3rd, *bad, 2.0).startswith(f"trajectory {name} must be numbers "
                                                     "(got ['a']: ")
    bad[k] = [np.nan]
    assert _message(coeff_3rd, *bad, 2.0) == f"trajectory {name} must be finite (got [nan])"


@pytest.mark.parametrize("duration", [0.0, -1.0, np.inf, np.nan, True, "2", None])
def test_coeff_3rd_refuses_a_duration_that_is_not_a_positive_number(duration):
    assert _message(coeff_3rd, [0.0], [0.0], [1.0], [0.0], duration) == (
        f"trajectory duration must be a positive number of seconds (got {duration!r})")


def test_coeff_3rd_is_the_rest_to_rest_closed_form():
    c = coeff_3rd([0.5, -1.0], [0.0, 0.0], [0.9, 2.0], [0.0, 0.0], 2)  # an int duration too
    dx, T = np.array([0.4, 3.0]), 2.0
    assert np.allclose(c, np.column_stack([[0.5, -1.0], [0.0, 0.0], 3 * dx / T**2,
                                           -2 * dx / T**3]), rtol=1e-15, atol=0)


def test_cubic_names_the_wrong_input():
    t = np.linspace(0.0, 1.0, 3)
    assert _message(cubic, [0.0, 0.0], [1.0], 1.0, t) == (
        "x0 and dx must have the same length (got 2 and 1)")
    assert _message(cubic, [0.0], [1.0], 1.0, np.zeros((2, 2))) == (
        "trajectory times must be a 1-D array (got shape (2, 2))")
    assert _message(cubic, [0.0], [1.0], 1.0, [0.0, np.nan]) == "trajectory times must be finite"
    assert _message(cubic, [0.0], [1.0], 1.0, [0.0, 0.5, 1.5]) == (
        "time t = 1.5 s (sample 2) is outside the trajectory [0, 1.0] s")
    assert _message(cubic, [0.0], [1.0], 1.0, [-0.1]) == (
        "time t = -0.1 s (sample 0) is outside the trajectory [0, 1.0] s")
    assert _message(cubic, [0.0], ["x"], 1.0, t).startswith(
        "trajectory displacement must be numbers (got ['x']: ")
    tr = cubic([0.0], [1.0], 1.0, [0.0, 1.0])  # the ends themselves are inside
    assert tr.x[:, 0].tolist() == [0.0, 1.0] and np.all(tr.xd == 0.0)
