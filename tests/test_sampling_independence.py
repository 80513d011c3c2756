"""A closed chain driven at its actuated joints gives the same motion whatever the sampling
(issue 25, class 5): the passive joints follow the loops from sample to sample in steps of at
most ``continuation.MAX_STEP``, predicted along the loops' tangent, corrected by Newton, and kept in
the assembly mode they started in (the sign of det Phi_p). Before, Newton took one full step
per sample: ``examples/jansen_turn.toml`` at 61 samples folded the leg over (peak 49.6 N*m
against 19.4 N*m, the foot 782 mm off at the same times).

For every inverse study shipped (the closed-chain examples and every built-in one, joint or
task space), every series at 5 samples and at coarser grids that share the fine grid's times
equals the study's own fine-grid result at those times (to 1e-9, relative to max(1, |value|)).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from planar_sym.errors import WorkspaceError
from planar_sym.motion import closure
from planar_sym.motion.profiles import cubic
from planar_sym.study.builtin import names as studies
from planar_sym.study.run import load_study, run

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = [str(ROOT / "examples" / f"{name}.toml")
            for name in ("jansen_turn", "six_bar_turn", "four_bar_turn")]
#: every inverse study shipped: the closed chains driven at their joints (the loops give the
#: passive joints), and in task space (Newton in C, continued from sample to sample) as well;
#: not the [optimise] ones: their timing is a discretised optimum on the study's samples, so it
#: changes with the grid (test_time_optimal_converges_with_the_grid below)
STUDIES = EXAMPLES + [s for s in studies() if load_study(s).kind == "inverse"
                      and load_study(s).optimise is None]


def _coarse_counts(n_fine: int) -> list[int]:
    """Sample counts from 5 up whose times are fine-grid times (n - 1 divides n_fine - 1)."""
    return [n for n in range(5, n_fine) if (n_fine - 1) % (n - 1) == 0][:3]


@pytest.mark.parametrize("study", STUDIES, ids=lambda s: Path(s).stem)
def test_any_sampling_gives_the_fine_grid_motion(study):
    st = load_study(study)
    fine = run(st)
    n_fine = len(fine.get("t").values)
    counts = _coarse_counts(n_fine)
    assert counts and counts[0] == 5, counts
    columns = list(fine.columns)
    reference = np.column_stack([s.values for s in fine.data])
    for n in counts:
        coarse = run(st, samples=n)
        assert list(coarse.columns) == columns
        rows = np.arange(n) * ((n_fine - 1) // (n - 1))
        values = np.column_stack([s.values for s in coarse.data])
        error = np.abs(values - reference[rows]) / np.maximum(1.0, np.abs(reference[rows]))
        k, c = np.unravel_index(np.argmax(error), error.shape)
        assert error[k, c] < 1e-9, (n, columns[c], k, values[k, c], reference[rows][k, c])


def test_a_motion_past_the_workspace_edge_is_refused_at_its_first_sample_beyond():
    """five_bar_type2 driven from (0, 90) to (120, 90) deg: at (90, 90) deg the distal links
    are stretched in one line (|BD| = l3 + l4, Phi_p singular), the edge of the actuated
    workspace; beyond it the loops cannot close. At any sampling the refusal names the first
    sample past the edge, whose crank angle is over 90 deg; the samples before it are solved."""
    from planar_sym import load

    robot = load("five_bar_type2")
    for n in (5, 9, 17, 33):
        t = np.linspace(0.0, 1.0, n)
        tr = cubic([0.0, np.pi / 2], [2 * np.pi / 3, 0.0], 1.0, t)
        first_past = int(np.argmax(tr.x[:, 0] > np.pi / 2))
        with pytest.raises(WorkspaceError) as exc:
            closure.from_actuated(robot, t, tr.x, tr.xd, tr.xdd)
        assert f"(sample {first_past})" in str(exc.value), (n, str(exc.value))
        assert "outside the workspace" in str(exc.value) or "singular" in str(exc.value)
        closure.from_actuated(robot, t[:first_past], tr.x[:first_past], tr.xd[:first_past],
                              tr.xdd[:first_past])


@pytest.mark.parametrize("study", [s for s in studies() if load_study(s).optimise is not None])
def test_time_optimal_converges_with_the_grid(study):
    """A time-optimal study's time reached is a discretised optimum on its samples: finer
    grids change it less and less (first order: the differences about halve per doubling)."""
    st = load_study(study)
    times = [run(st, samples=n).get("t").values[-1] for n in (51, 101, 201, 401)]
    steps = np.abs(np.diff(times))
    assert steps[-1] < 1e-3 * times[-1]  # seen: a few 1e-5 relative
    assert steps[1] < steps[0] / 1.5 and steps[2] < steps[1] / 1.5
