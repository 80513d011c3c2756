"""Survivors of mutation testing (issue 30) in ``dynamics/integrate.py`` and
``dynamics/linearize.py``: two refusals, each checked word for word against the rule it states,
and the clock a free run reports while its compiled loop runs.
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


def test_a_free_runs_progress_hears_its_clock_up_to_its_own_end():
    """Catches integrate._dopri5's watcher given no clock, another end time (the grid's
    second or last-but-one time, or none) or no callback: ps.simulate of serial_2dof from
    0.2 to 0.7 s with a progress callback hears at least once, every time with the run's end
    0.7 s (t_eval's last time, not 0.25 or 0.6 s), clock readings between 0.2 and 0.7 s that
    never go back, the last one the end itself; and the run is the one made without it."""
    robot = ps.load("serial_2dof")
    heard = []
    t = np.array([0.2, 0.25, 0.4, 0.6, 0.7])
    run = ps.simulate(robot, [0.3, 0.2], [0.0, 0.0], (0.2, 0.7), t_eval=t,
                      progress=lambda done, total: heard.append((done, total)))
    assert heard and all(total == 0.7 for _, total in heard)
    clock = [done for done, _ in heard]
    assert clock == sorted(clock) and 0.2 <= clock[0] and clock[-1] == 0.7
    plain = ps.simulate(robot, [0.3, 0.2], [0.0, 0.0], (0.2, 0.7), t_eval=t)
    assert np.array_equal(run.q, plain.q) and np.array_equal(run.t_s, t)
