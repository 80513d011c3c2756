"""``planar_sym.dynamics.segments.run_segments``, the driver both integrators of a controlled run
share, called directly with a plant whose loop is worked out by hand and a segment function
whose states are written down in closed form, so every figure it returns is known beforehand:

* the plant has two coordinates and one loop, Phi(q) = q0 - q1 (m), Phi_q = [1, -1]: its
  projection (``forward_closed.project``) is the mean of the two coordinates, and the same for
  the two rates; the work and loss columns pass through unchanged;
* the segment glides: q(t) = q(t0) + qd(t0) (t - t0), with a known opening ``rate * (t - t0)``
  added to q0, so |Phi| at a row is ``rate * (t - t0)`` and the largest is known per segment;
* where the run is cut: a sample exactly SEGMENT_S = 0.1 s after a segment's start closes it
  (0.1 + 0.1 == 0.2 in binary, so the grid below has those ties), a step longer than 0.1 s is a
  segment of its own, and a tree (no loop) is one segment over the whole grid, even of two
  samples; the segment always gets contiguous float64 times (the C loop reads them as doubles);
* the loops' events: a singular constraint matrix at the time the segment reports, with the rows
  filled so far, the RHS count and the drift of the segments before; a drift above
  DRIFT_LIMIT_M = 1e-6 m at the segment's start, with the message naming the drift and the
  segment's end; a drift of exactly 1e-6 m is still accepted; a segment that adds no row adds
  no drift.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from planar_sym.dynamics import segments
from planar_sym.dynamics.segments import DRIFT_LIMIT_M, SEGMENT_S, run_segments


class LinePlant:
    """Two coordinates on one loop Phi(q) = q0 - q1 (m); ``m = 0``: the same without the loop."""

    def __init__(self, m: int = 1):
        self.n, self.n_constraints = 2, m

    def constraint(self, q):
        assert self.n_constraints, "a tree has no loop to evaluate"
        q = np.asarray(q, dtype=float)
        return q[..., 0:1] - q[..., 1:2]

    def constraint_jacobian(self, q):
        q = np.asarray(q, dtype=float)
        return np.broadcast_to(np.array([[1.0, -1.0]]), q.shape[:-1] + (1, 2)).copy()


class Glide:
    """segment(tt, y): the closed-form glide q(t) = q(t0) + qd(t0) (t - t0), q0 opened by
    ``rate * (t - t0)`` (``rate`` a number, or a list: one per call), work and loss growing by
    2 (t - t0) and 3 (t - t0). Records each call; ``fail`` = {call index: (rows filled,
    failure time)}, None where it does not fail; ``got`` = {call index: rows filled}."""

    def __init__(self, count, rate=0.0, fail=None, got=None, rhs_per_call=7, setup=None,
                 stop_after=None):
        self.count, self.rate, self.calls = count, rate, []
        self.fail, self.got = fail or {}, got or {}
        self.rhs, self.setup, self.stop_after = rhs_per_call, setup, stop_after

    def __call__(self, tt, y):
        assert len(tt) >= 2, f"a segment of one sample at t = {tt[0]} (the run would not advance)"
        assert len(self.calls) < 100, "the run does not end"
        i = len(self.calls)
        self.calls.append((tt.copy(), y.copy(), tt.dtype, tt.flags["C_CONTIGUOUS"]))
        s = tt - tt[0]
        rate = self.rate[i] if isinstance(self.rate, list) else self.rate
        out = np.empty((len(tt), 6))
        out[:, 0] = y[0] + y[2] * s + rate * s
        out[:, 1] = y[1] + y[3] * s
        out[:, 2:4] = y[2:4]
        out[:, 4] = y[4] + 2.0 * s
        out[:, 5] = y[5] + 3.0 * s
        self.count[0] += self.rhs
        if self.stop_after == i:
            self.setup.c.stopped = True
        if i in self.fail:
            got, at = self.fail[i]
            return out, got, at
        return out, self.got.get(i, len(tt)), None  # None: no failure


def _setup():
    return SimpleNamespace(c=SimpleNamespace(stopped=False, t_stop=0.0), y_stop=None)


Y0 = np.array([0.3, 0.3, 0.5, 0.5, 0.0, 0.0])


def test_the_constants():
    assert SEGMENT_S == 0.1
    assert DRIFT_LIMIT_M == 1e-6


def test_friction_is_the_drive_trains_three_columns():
    dt = SimpleNamespace(viscous=np.array([0.1, 0.2]), coulomb=np.array([0.3, 0.0]),
                         smoothing=np.array([0.01, 0.02]))
    b, c, v = segments.friction(SimpleNamespace(drive_train=dt))
    assert b is dt.viscous and c is dt.coulomb and v is dt.smoothing


def test_closed_chain_cut_every_segment_s_with_ties_inclusive():
    t = np.array([0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3])
    count = [0]
    seg = Glide(count)
    ys, ts, n_rhs, drift, event = run_segments(LinePlant(), _setup(), Y0.copy(), t, seg, count)
    got = [c[0].tolist() for c in seg.calls]
    assert got == [[0.0, 0.05, 0.1], [0.1, 0.15, 0.2], [0.2, 0.25, 0.3]]
    assert event is None
    assert n_rhs == 21
    assert drift == 0.0
    assert ts.tolist() == t.tolist()
    # on the loop the glide is exact: q = 0.3 + 0.5 t on both coordinates
    assert np.allclose(ys[:, 0], 0.3 + 0.5 * t, rtol=0, atol=1e-15)
    assert np.allclose(ys[:, 1], 0.3 + 0.5 * t, rtol=0, atol=1e-15)
    assert np.allclose(ys[:, 4], 2.0 * t, rtol=0, atol=1e-15)
    assert np.allclose(ys[:, 5], 3.0 * t, rtol=0, atol=1e-15)


def test_closed_chain_long_steps_are_segments_of_their_own():
    t = np.array([0.0, 0.25, 0.5, 0.75])
    count = [0]
    seg = Glide(count, rate=1e-6)  # opens 0.25e-6 m over each step
    ys, ts, n_rhs, drift, event = run_segments(LinePlant(), _setup(), Y0.copy(), t, seg, count)
    assert [c[0].tolist() for c in seg.calls] == [[0.0, 0.25], [0.25, 0.5], [0.5, 0.75]]
    assert event is None
    assert n_rhs == 21
    assert ts.tolist() == t.tolist()
    assert ys.shape == (4, 6)
    # each segment's only new row is 0.25e-6 m off the loop; the drift is that largest |Phi|
    assert drift == pytest.approx(0.25e-6, rel=1e-9)
    # each segment starts from the previous end projected: the mean of the two coordinates
    # (the opening split in halves) and the same rates, work and loss carried over
    for j in (1, 2):
        start = seg.calls[j][1]
        end = ys[j]
        assert end[0] - end[1] == pytest.approx(0.25e-6, rel=1e-9)
        assert start[0] == pytest.approx((end[0] + end[1]) / 2, abs=1e-15)
        assert start[1] == pytest.approx((end[0] + end[1]) / 2, abs=1e-15)
        assert start[2:4].tolist() == [0.5, 0.5]
        assert start[4:].tolist() == end[4:].tolist()
    assert ys[3, 4] == pytest.approx(1.5, abs=1e-15)


def test_mixed_grid_fine_then_coarse_then_fine():
    t = np.array([0.0, 0.04, 0.08, 0.12, 0.5, 0.55, 0.6, 0.7])
    count = [0]
    seg = Glide(count)
    run_segments(LinePlant(), _setup(), Y0.copy(), t, seg, count)
    # from 0: 0.1 falls between 0.08 and 0.12 -> [0, 0.08]; from 0.08: 0.18 -> [0.08, 0.12];
    # from 0.12: a long step -> [0.12, 0.5]; from 0.5: 0.6 -> [0.5, 0.6]; then [0.6, 0.7]
    # (0.5 + 0.1 == 0.6 and 0.6 + 0.1 == 0.7 in binary: the ties close their segments)
    assert [c[0].tolist() for c in seg.calls] == [
        [0.0, 0.04, 0.08], [0.08, 0.12], [0.12, 0.5], [0.5, 0.55, 0.6], [0.6, 0.7]]


def test_tree_is_one_segment_over_the_whole_grid():
    t = np.linspace(0.0, 0.35, 8)
    count = [0]
    seg = Glide(count)
    ys, ts, n_rhs, drift, event = run_segments(LinePlant(0), _setup(), Y0.copy(), t, seg, count)
    assert len(seg.calls) == 1
    assert seg.calls[0][0].tolist() == t.tolist()
    assert ts.tolist() == t.tolist() and event is None and drift == 0.0 and n_rhs == 7
    assert np.allclose(ys[:, 0], 0.3 + 0.5 * t, rtol=0, atol=1e-15)


def test_tree_of_two_samples_runs_its_one_step():
    t = np.array([1.0, 1.5])
    count = [0]
    seg = Glide(count)
    ys, ts, n_rhs, drift, event = run_segments(LinePlant(0), _setup(), Y0.copy(), t, seg, count)
    assert len(seg.calls) == 1
    assert ts.tolist() == [1.0, 1.5]
    assert ys.shape == (2, 6)
    assert ys[1].tolist() == pytest.approx([0.55, 0.55, 0.5, 0.5, 1.0, 1.5], abs=1e-15)
    assert n_rhs == 7 and drift == 0.0 and event is None


def test_closed_chain_of_two_samples_and_a_last_short_step():
    t = np.array([0.0, 0.08, 0.11])
    count = [0]
    seg = Glide(count)
    ys, ts, *_ = run_segments(LinePlant(), _setup(), Y0.copy(), t, seg, count)
    assert [c[0].tolist() for c in seg.calls] == [[0.0, 0.08], [0.08, 0.11]]
    assert ts.tolist() == [0.0, 0.08, 0.11]
    assert ys[-1, 0] == pytest.approx(0.3 + 0.5 * 0.11, abs=1e-15)


@pytest.mark.parametrize("m", [0, 1])
@pytest.mark.parametrize("dtype", [np.int64, np.float32])
def test_segment_gets_contiguous_float64_times(m, dtype):
    t = np.array([0, 1, 2, 3], dtype=dtype)
    count = [0]
    seg = Glide(count)
    ys, ts, *_ = run_segments(LinePlant(m), _setup(), Y0.copy(), t, seg, count)
    assert seg.calls, "no segment ran"
    for tt, _, dt, contiguous in seg.calls:
        assert dt == np.float64
        assert contiguous
    assert ts.dtype == np.float64
    assert ts.tolist() == [0.0, 1.0, 2.0, 3.0]
    assert ys[-1, 4] == 6.0  # work 2 t, here computed on float64 times


def test_segment_gets_contiguous_times_from_a_strided_grid():
    t = np.arange(0.0, 1.0, 0.125)[::2]  # 0, 0.25, 0.5, 0.75: a view with stride 2
    count = [0]
    seg = Glide(count)
    run_segments(LinePlant(), _setup(), Y0.copy(), t, seg, count)
    assert all(c[3] for c in seg.calls)
    assert [c[0].tolist() for c in seg.calls] == [[0.0, 0.25], [0.25, 0.5], [0.5, 0.75]]


def test_singular_constraint_matrix_is_an_event_at_the_time_reported():
    t = np.array([0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3])
    count = [0]
    # the first segment opens the loop by 0.4e-6 m (rate 4e-6 m/s over 0.1 s); the second stops
    # after its first new row, at t = 0.13 s
    seg = Glide(count, rate=4e-6, fail={1: (2, 0.13)})
    ys, ts, n_rhs, drift, event = run_segments(LinePlant(), _setup(), Y0.copy(), t, seg, count)
    assert event == (0.13, "singular constraint matrix")
    assert len(seg.calls) == 2
    assert ts.tolist() == [0.0, 0.05, 0.1, 0.15]
    assert isinstance(ys, np.ndarray) and ys.shape == (4, 6)
    assert ys[:, 4] == pytest.approx([0.0, 0.1, 0.2, 0.3], abs=1e-15)
    assert n_rhs == 14
    assert drift == pytest.approx(4e-7, rel=1e-9)  # the first segment's only
    assert isinstance(ts, np.ndarray)


def test_drift_beyond_the_limit_is_an_event_at_the_segments_start():
    t = np.array([0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3])
    count = [0]
    # 2e-5 m/s: 1e-6 m at 0.05 s, 2e-6 m at 0.1 s after a segment's start
    seg = Glide(count, rate=2e-5)
    ys, ts, n_rhs, drift, event = run_segments(LinePlant(), _setup(), Y0.copy(), t, seg, count)
    assert len(seg.calls) == 1
    assert event == (0.0, "|Phi| reached 2e-06 m by t = 0.1 s, above 1e-06 m")
    assert isinstance(event[0], float)
    assert drift == pytest.approx(2e-6, rel=1e-9)
    assert ts.tolist() == [0.0, 0.05, 0.1]  # the rows of the failing segment are returned
    assert isinstance(ys, np.ndarray) and ys.shape == (3, 6)
    assert ys[2, 0] - ys[2, 1] == pytest.approx(2e-6, rel=1e-9)
    assert n_rhs == 7


def test_drift_event_in_a_later_segment_names_its_start_and_end():
    t = np.array([0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3])
    count = [0]
    # 0.5e-6 m in the first segment; the second opens faster: 3e-6 m by its end, 0.2 s
    seg = Glide(count, rate=[5e-6, 3e-5])
    ys, ts, n_rhs, drift, event = run_segments(LinePlant(), _setup(), Y0.copy(), t, seg, count)
    assert event == (0.1, "|Phi| reached 3e-06 m by t = 0.2 s, above 1e-06 m")
    assert drift == pytest.approx(3e-6, rel=1e-9)
    assert ts.tolist() == [0.0, 0.05, 0.1, 0.15, 0.2]
    assert ys.shape == (5, 6)
    assert n_rhs == 14


class Prescribed:
    """segment(tt, y): rows [phi_j, 0, 0, 0, tt_j, 0], so |Phi| of row j is exactly |phi_j|."""

    def __init__(self, count, phis):
        self.count, self.phis, self.calls = count, phis, []

    def __call__(self, tt, y):
        assert len(tt) >= 2 and len(self.calls) < 100
        phi = self.phis[len(self.calls)]
        self.calls.append(tt.copy())
        out = np.zeros((len(tt), 6))
        out[:, 0] = phi[:len(tt)]
        out[:, 4] = tt
        self.count[0] += 1
        return out, len(tt), None


def test_drift_of_exactly_the_limit_is_accepted():
    t = np.array([0.0, 0.05, 0.1, 0.15, 0.2])
    count = [0]
    seg = Prescribed(count, [[0.0, -5e-7, 1e-6], [0.0, 1e-6, -1e-6]])
    ys, ts, n_rhs, drift, event = run_segments(LinePlant(), _setup(), np.zeros(6), t, seg, count)
    assert event is None
    assert drift == 1e-6
    assert ts.tolist() == t.tolist()
    assert ys[:, 0].tolist() == [0.0, -5e-7, 1e-6, 1e-6, -1e-6]
    assert n_rhs == 2


def test_drift_just_above_the_limit_is_refused():
    t = np.array([0.0, 0.05, 0.1, 0.15, 0.2])
    count = [0]
    above = np.nextafter(1e-6, 1.0)
    seg = Prescribed(count, [[0.0, 0.0, 0.0], [0.0, above, 0.0]])
    *_, drift, event = run_segments(LinePlant(), _setup(), np.zeros(6), t, seg, count)
    assert drift == above
    assert event == (0.1, "|Phi| reached 1e-06 m by t = 0.2 s, above 1e-06 m")


def test_drift_is_the_largest_over_the_segments_rows_not_the_first_or_last():
    t = np.array([0.0, 0.05, 0.1, 0.15, 0.2])
    count = [0]
    seg = Prescribed(count, [[9.0, 3e-7, -1e-7], [9.0, -1e-7, 2e-7]])  # row 0 is not looked at
    *_, drift, event = run_segments(LinePlant(), _setup(), np.zeros(6), t, seg, count)
    assert event is None
    assert drift == 3e-7


def test_a_segment_with_no_new_row_adds_no_drift():
    t = np.array([0.0, 0.05, 0.1, 0.15, 0.2])
    count = [0]
    # the first call fills only its starting row (a large |Phi| there is not a new sample)
    seg = Glide(count, rate=0.0, got={0: 1})
    y0 = Y0.copy()
    ys, ts, n_rhs, drift, event = run_segments(LinePlant(), _setup(), y0, t, seg, count)
    assert event is None
    assert drift == 0.0
    # no rows from the first call; the second segment again starts at 0.1 s
    assert [c[0].tolist() for c in seg.calls] == [[0.0, 0.05, 0.1], [0.1, 0.15, 0.2]]
    assert ts.tolist() == [0.0, 0.15, 0.2]
    assert ys.shape == (3, 6) and ys[0].tolist() == Y0.tolist()
    assert n_rhs == 14


def test_a_stop_appends_the_stop_state_and_ends_the_run():
    t = np.array([0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3])
    count = [0]
    setup = _setup()
    setup.y_stop = np.array([1.0, 1.0, 0.0, 0.0, 0.25, 0.5])
    setup.c.t_stop = 0.125
    # the loop opens 1e-4 m in the stopping segment: a stop ends the run before the drift check
    seg = Glide(count, rate=[0.0, 1e-3], setup=setup, stop_after=1)
    ys, ts, n_rhs, drift, event = run_segments(LinePlant(), setup, Y0.copy(), t, seg, count)
    assert len(seg.calls) == 2
    assert event is None and drift == 0.0 and n_rhs == 14
    assert ts.tolist() == [0.0, 0.05, 0.1, 0.15, 0.2, 0.125]
    assert ys[-1].tolist() == [1.0, 1.0, 0.0, 0.0, 0.25, 0.5]
    assert ys[-2, 0] - ys[-2, 1] == pytest.approx(1e-4, rel=1e-9)


def test_a_failure_at_the_first_time_is_a_failure():
    """A segment that fails at its start, t = 0 exactly: an event at 0.0, not "no failure"
    (0.0 was read as false and the run went on over unfilled rows)."""
    count = [0]
    seg = Glide(count, fail={0: (1, 0.0)})
    rows, ts, _, _, event = run_segments(LinePlant(), _setup(), Y0.copy(),
                                         np.linspace(0, 0.3, 7), seg, count)
    assert event == (0.0, "singular constraint matrix")
    assert ts.tolist() == [0.0] and len(rows) == 1
