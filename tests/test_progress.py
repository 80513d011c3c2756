"""Progress lines: shown on a terminal, never into a pipe or a file, never under --quiet; used by
``planar-sym build``, ``derive``, ``validate`` and ``python -m derive``."""

from __future__ import annotations

import io

from conftest import ROOT

from planar_sym.cli import main
from planar_sym.progress import Progress, track, wanted


class FakeTTY(io.StringIO):
    """A stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def test_not_a_terminal_prints_nothing():
    stream = io.StringIO()
    progress = Progress(2, stream=stream)
    progress.step("deriving a")
    progress.note("detail")
    progress.done()
    assert list(track(["x", "y"], "compiling", stream=stream)) == ["x", "y"]
    assert stream.getvalue() == ""
    assert not wanted(stream) and not wanted(object())  # no isatty at all: not a terminal


def test_a_terminal_gets_one_line_per_step():
    stream = FakeTTY()
    assert list(track(["a", "b"], "compiling", stream=stream)) == ["a", "b"]
    lines = stream.getvalue().splitlines()
    assert lines[:2] == ["[1/2] compiling a ...", "[2/2] compiling b ..."]
    assert lines[2].startswith("done: 2 in ")


def test_quiet_silences_a_terminal():
    stream = FakeTTY()
    progress = Progress(1, quiet=True, stream=stream)
    progress.step("deriving a")
    progress.done()
    assert list(track(["a"], "x", quiet=True, stream=stream)) == ["a"]
    assert stream.getvalue() == "" and not wanted(stream, quiet=True)


def tty_stderr(monkeypatch) -> FakeTTY:
    """Standard error replaced by a fake terminal. Call it in the test body: pytest's output
    capture re-installs its own sys.stderr between a fixture's set-up and the test."""
    stream = FakeTTY()
    monkeypatch.setattr("sys.stderr", stream)
    return stream


def test_build_shows_progress_on_a_terminal_only(monkeypatch, capsys):
    tty = tty_stderr(monkeypatch)
    assert main(["build", "serial_2dof", "five_bar_type1"]) == 0
    assert "[1/2] compiling serial_2dof ..." in tty.getvalue()
    assert "[2/2] compiling five_bar_type1 ..." in tty.getvalue()
    tty.truncate(0)
    assert main(["--quiet", "build", "serial_2dof"]) == 0
    assert main(["build", "serial_2dof", "--quiet"]) == 0
    assert tty.getvalue() == ""
    lines = capsys.readouterr().out.splitlines()  # --quiet runs add no result line either
    assert [line.split(":")[0] for line in lines] == ["serial_2dof", "five_bar_type1"]


def test_validate_shows_each_check(monkeypatch):
    tty = tty_stderr(monkeypatch)
    assert main(["validate", "serial_2dof"]) == 0
    assert "[1/4] serial_2dof: (a) compiled vs SymPy ..." in tty.getvalue()
    assert "[4/4] serial_2dof: (d) power balance ..." in tty.getvalue()


def test_derive_shows_progress_per_robot(tmp_path, monkeypatch):
    tty = tty_stderr(monkeypatch)
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    toml = ROOT / "examples" / "heavy_motor_2dof.toml"
    assert main(["derive", str(toml), "--out", str(tmp_path / "cli")]) == 0
    err = tty.getvalue()
    assert f"[1/2] deriving heavy_motor_2dof ({toml}) ..." in err
    # each stage as it starts (a big robot's closed forms take minutes), then compiling
    stages = [line.strip() for line in err.splitlines() if line.startswith("      the ")]
    assert stages == ["the dynamics by algorithmic differentiation ...",
                      "the closed forms (SymPy: Lagrangian, simplification) ...",
                      "the equation report ...", "the regressor (identification) ...",
                      "the C code ..."], err
    assert err.index("the C code ...") < err.index("[2/2] compiling heavy_motor_2dof ...")

    from derive.__main__ import main as derive_main

    tty.truncate(0)
    tty.seek(0)
    assert derive_main([str(toml), "--out", str(tmp_path / "module")]) == 0
    assert f"[1/1] deriving {toml} ..." in tty.getvalue()
    tty.truncate(0)
    tty.seek(0)
    assert derive_main([str(toml), "--out", str(tmp_path / "module"), "--quiet"]) == 0
    assert tty.getvalue() == ""


def test_meter_rewrites_one_line_and_ends_it(monkeypatch):
    """A long job counted in units: '\\r'-rewritten, throttled, ended with count and time."""
    import itertools
    from types import SimpleNamespace

    import planar_sym.progress as progress_module
    from planar_sym.progress import Meter

    clock = itertools.chain([0.0, 0.1, 0.2, 0.9, 1.0, 1.1], itertools.count(2.0))
    monkeypatch.setattr(progress_module, "time", SimpleNamespace(perf_counter=lambda: next(clock)))
    stream = FakeTTY()
    meter = Meter(4, "drawing s.gif", stream=stream)
    for k in (1, 2, 3, 4):  # at 0.1 s shown; 0.2 s too soon; 0.9 s shown; the last always
        meter(k)
    meter.close()
    assert stream.getvalue() == ("\rdrawing s.gif: 1/4 (25 %)\rdrawing s.gif: 3/4 (75 %)"
                                 "\rdrawing s.gif: 4/4 (100 %)\rdrawing s.gif: 4/4 in 1.1 s\n")
    quiet, pipe = FakeTTY(), io.StringIO()
    for m in (Meter(4, "x", quiet=True, stream=quiet), Meter(4, "x", stream=pipe)):
        m(4)
        m.close()
    assert quiet.getvalue() == pipe.getvalue() == ""


def test_animation_and_sweep_count_their_units_on_a_terminal(tmp_path, monkeypatch):
    tty = tty_stderr(monkeypatch)
    assert main(["animate", "serial_2dof_joint_move", "--frames", "6", "--out",
                 str(tmp_path / "a.gif")]) == 0
    assert "serial_2dof_joint_move: drawing a.gif: 6/6 in " in tty.getvalue()
    tty.truncate(0)
    tty.seek(0)
    assert main(["sweep", "serial_2dof_cartesian_move", "--vary", "m_motor2=0.2:0.4:5",
                 "--out", str(tmp_path)]) == 0
    assert "serial_2dof_cartesian_move: designs: 5/5 in " in tty.getvalue()
    tty.truncate(0)
    tty.seek(0)
    assert main(["--quiet", "animate", "serial_2dof_joint_move", "--frames", "6", "--out",
                 str(tmp_path / "b.gif")]) == 0
    assert tty.getvalue() == ""


def test_an_atlas_counts_its_cells_and_its_numbers_do_not_change(tmp_path, monkeypatch):
    """The atlas's progress: the flood fill's solved cells (never fewer than before), ending at
    the grid's size, then the reachable cells measured, ending at their count; the atlas is the
    same with and without it. On a terminal the command shows both stages."""
    import numpy as np

    import planar_sym as ps

    heard = []
    seen = ps.atlas("five_bar_type1", points=41, progress=lambda *a: heard.append(a))
    plain = ps.atlas("five_bar_type1", points=41)
    poses = [(d, t) for s, d, t in heard if s == "poses"]
    measures = [(d, t) for s, d, t in heard if s == "measures"]
    assert [d for d, _ in poses] == sorted(d for d, _ in poses) and poses[-1] == (41 * 41,) * 2
    reachable = int(np.sum(plain.reachable))
    assert measures[-1] == (reachable, reachable) and heard.index(("measures", *measures[0])) > \
        heard.index(("poses", *poses[-1]))
    assert np.array_equal(seen.q, plain.q, equal_nan=True)
    assert np.array_equal(seen.envelope, plain.envelope, equal_nan=True)
    tty = tty_stderr(monkeypatch)
    assert main(["atlas", "five_bar_type1", "--points", "31", "--out", str(tmp_path)]) == 0
    text = tty.getvalue()
    assert "five_bar_type1: solving poses (grid cells): 961/961 in " in text
    assert "five_bar_type1: measuring poses: " in text


def _heard_run(progress=None, **kw):
    """A free swing of the 3-DOF arm long enough for several clock reads (0.1 s apart): about
    0.7 s on a quiet machine, several seconds on a loaded one."""
    import numpy as np

    import planar_sym as ps

    r = ps.load("serial_3dof")
    return ps.simulate(r, [0.1, 0.2, 0.3], [0, 0, 0], (0.0, 400.0), t_eval=np.linspace(0, 400, 401),
                       rtol=1e-12, atol=1e-13, progress=progress, **kw)


def test_a_long_simulation_reports_its_clock_and_its_numbers_do_not_change():
    """simulate(progress=...) hears the time the C loop has reached, increasing, ending at the
    end time; the run is bit for bit the one without a clock (the loop never reads it)."""
    import numpy as np

    heard = []
    seen = _heard_run(lambda t, end: heard.append((t, end)))
    plain = _heard_run()
    assert np.array_equal(seen.q, plain.q) and np.array_equal(seen.qd, plain.qd)
    times = [t for t, _ in heard]
    assert {end for _, end in heard} == {400.0} and heard[-1] == (400.0, 400.0)
    assert times == sorted(times)
    # read while the loop runs (not only at its end): the C loop writes the time reached
    assert len(heard) >= 2 and any(0.0 < t < 400.0 for t in times), heard


def test_a_controlled_run_reports_its_clock_through_the_engine():
    import numpy as np

    import planar_sym as ps
    from planar_sym.control import controller

    r = ps.load("serial_2dof")
    heard = []
    run = ps.simulate_controlled(r, controller("none"), (0.0, 2.0), q0=[0.3, 0.2],
                                 qd0=[0.0, 0.0], t_eval=np.linspace(0, 2, 21),
                                 progress=lambda t, end: heard.append((t, end)))
    free = ps.simulate(r, [0.3, 0.2], [0.0, 0.0], (0.0, 2.0), t_eval=np.linspace(0, 2, 21),
                       rtol=1e-10, atol=1e-12)
    assert heard and heard[-1] == (2.0, 2.0)
    assert np.max(np.abs(run.q - free.q)) < 1e-8  # the same free swing by the other route


def test_the_clock_line_waits_a_second_then_rewrites_itself(monkeypatch):
    """Clock: nothing in the first DELAY_S (quick runs stay silent), then one line rewritten
    at most every INTERVAL_S, ended by close; nothing into a pipe or under --quiet."""
    import itertools
    from types import SimpleNamespace

    import planar_sym.progress as progress_module
    from planar_sym.progress import Clock, ambient, watching

    clock = itertools.chain([0.0, 0.5, 1.2, 1.3, 1.8, 2.5], itertools.count(3.0))
    monkeypatch.setattr(progress_module, "time", SimpleNamespace(perf_counter=lambda: next(clock)))
    stream = FakeTTY()
    c = Clock("S1: simulating", stream=stream)
    with watching(c) as w:
        assert ambient() is w is c
        for t in (1.0, 3.0, 4.0, 7.5):  # at 0.5 s too early; 1.2 s shown; 1.3 s too soon
            c(t, 10.0)
    assert ambient() is None
    assert stream.getvalue() == ("\rS1: simulating, t = 3 of 10 s (30 %)"
                                 "\rS1: simulating, t = 7.5 of 10 s (75 %)"
                                 "\rS1: simulating: done in 2.5 s" + " " * 20 + "\n")
    quiet, pipe = FakeTTY(), io.StringIO()
    for k in (Clock("x", quiet=True, stream=quiet), Clock("x", stream=pipe)):
        k(1.0, 2.0)
        k.close()
    assert quiet.getvalue() == pipe.getvalue() == ""


def test_run_shows_the_simulation_clock_on_a_terminal_only(tmp_path, monkeypatch):
    """``planar-sym run`` of a forward study: the clock line on a terminal (its delay set to
    0 here, as the free swing takes milliseconds), ended with the time taken; nothing with
    --quiet or into a pipe, and the CSV is the same either way."""
    import planar_sym.progress as progress_module

    monkeypatch.setattr(progress_module, "DELAY_S", 0.0)
    tty = tty_stderr(monkeypatch)
    assert main(["run", "serial_2dof_free_swing", "--out", str(tmp_path / "a")]) == 0
    text = tty.getvalue()
    assert "\rserial_2dof_free_swing: simulating, t = 1 of 1 s (100 %)" in text, text
    assert "serial_2dof_free_swing: simulating: done in " in text
    tty.truncate(0)
    tty.seek(0)
    assert main(["--quiet", "run", "serial_2dof_free_swing", "--out", str(tmp_path / "b")]) == 0
    assert tty.getvalue() == ""
    name = "serial_2dof_free_swing.csv"
    assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()


def test_a_watched_call_returns_its_value_and_raises_its_error_in_the_caller():
    """call_watched as the C loop's caller sees it: the call's return code comes back, an
    error raised in the worker is raised again in the caller (not lost in the thread), and the
    worker is a daemon thread named for thread dumps, so Ctrl-C ends the program at once."""
    import ctypes
    import threading

    import pytest

    from planar_sym.dynamics.watched import call_watched

    clock, heard = ctypes.c_double(2.5), []
    seen = {}

    def call():
        me = threading.current_thread()
        seen.update(daemon=me.daemon, name=me.name, main=me is threading.main_thread())
        return 7

    assert call_watched(call, clock, 10.0, lambda t, end: heard.append((t, end))) == 7
    assert seen == {"daemon": True, "name": "planar-sym integrator", "main": False}
    assert heard and heard[-1] == (2.5, 10.0)
    assert call_watched(lambda: 3, clock, 10.0, None) == 3  # no clock: called directly

    def fails():
        raise ZeroDivisionError("in the C loop's caller")

    with pytest.raises(ZeroDivisionError, match="in the C loop's caller"):
        call_watched(fails, clock, 10.0, lambda t, end: None)
