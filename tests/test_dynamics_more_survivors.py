"""Survivors of mutation testing (issue 30) in ``dynamics/integrate.py`` and
``dynamics/linearize.py``: two refusals, each checked word for word against the rule it states.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.dynamics.integrate import torque_function
from planar_sym.errors import InputError


def test_a_long_torque_of_the_wrong_shape_is_shown_summarised():
    """Catches integrate.torque_function's ``np.array2string(arr, threshold=8)`` given another
    threshold: a refused constant torque of 9 numbers (for a robot of 2 actuated joints) is
    shown as numpy summarises an array longer than 8, its first and last three numbers,
    and one of 8 in full (numpy's rule: summarise when the size exceeds the threshold)."""
    rule = ("torque must be None, 2 numbers (N*m; N at a slider), one for every actuated "
            "joint, or a function of time")
    with pytest.raises(InputError) as info:
        torque_function(np.arange(1.0, 10.0), 2)
    assert str(info.value) == f"{rule} (got shape (9,): [1. 2. 3. ... 7. 8. 9.])"
    with pytest.raises(InputError) as info:
        torque_function(np.arange(1.0, 9.0), 2)
    assert str(info.value) == f"{rule} (got shape (8,): [1. 2. 3. 4. 5. 6. 7. 8.])"


def test_linearize_refuses_a_closed_chain_with_more_passive_coordinates_than_loop_equations():
    """Catches linearize._closed's refusal emptied (``InputError(None)``) or reworded: a closed
    chain must have as many passive coordinates as loop equations (its actuated coordinates
    then fix the rest); a stand-in with 3 passive coordinates and 2 loop equations (one
    actuated of 4) is refused before anything is computed, by name and with both counts."""
    loop = SimpleNamespace(name="stand_in", n=4, actuated=(0,), passive=(1, 2, 3),
                           coordinates=("a", "b", "c", "d"), is_closed_chain=True,
                           n_constraints=2)
    with pytest.raises(InputError) as info:
        ps.linearize(loop, np.zeros(4))
    assert str(info.value) == ("stand_in: linearize needs as many passive coordinates as loop "
                               "equations (3 against 2)")
