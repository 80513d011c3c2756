"""Shared helpers of the test suite.

Error measure used everywhere (``rel_err``): for each sample k, the largest absolute difference
over all entries of that sample divided by the largest absolute entry of the reference at that
sample, ``max_k ||a_k - b_k||_inf / ||b_k||_inf`` (a ``floor`` keeps an all-zero reference from
dividing by zero; it then becomes an absolute error).
"""

from __future__ import annotations

import shutil
import signal
from pathlib import Path

import numpy as np
import pytest

# A job started in the background of a non-interactive shell (a CI step, `make test &`) inherits
# SIGINT ignored, and every Python process under it keeps ignoring it: the tests that interrupt a
# command (Ctrl-C) would see it run to the end. Handled here, SIGINT is reset to its default in
# every child at exec, so a child interrupts as at a terminal.
if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"
ROBOTS_DIR = ROOT / "planar_sym" / "robots"
TEST_ROBOTS = Path(__file__).resolve().parent / "robots"

TREES = ("serial_2dof", "serial_3dof")
CLOSED = ("five_bar_type1", "five_bar_type2", "parallel_3rrr")
ALL_ROBOTS = TREES + CLOSED
#: built-in robots with prismatic joints (issue 11): checked in tests/test_prismatic_robots.py
#: (their pose = "joints" files and missing tasks do not fit every seed-robot test above)
PRISMATIC_ROBOTS = ("parallel_3rpr", "serial_rpr", "slider_crank", "slider_crank_slider_driven")
#: built-in robots with a passive joint in a tree (issue 27): checked in tests/test_tvlqr.py and
#: tests/test_optimal_study.py
UNDERACTUATED_ROBOTS = ("cart_pole",)
BUILTIN_ROBOTS = ALL_ROBOTS + PRISMATIC_ROBOTS + UNDERACTUATED_ROBOTS


#: run a module as `python -m` does, with SIGINT at Python's default handler whatever the test
#: process's disposition is by then: under pytest-xdist a worker runs many tests, and one that
#: leaves SIGINT ignored would make an interrupted child run to its end (seen once: a 60 s
#: timeout). Not preexec_fn, which is unsafe with threads.
_INTERRUPTIBLE = ("import runpy, signal, sys; signal.signal(signal.SIGINT, "
                  "signal.default_int_handler); sys.argv = sys.argv[1:]; "
                  "runpy.run_module(sys.argv[0], run_name='__main__', alter_sys=True)")


def interruptible(module: str, *args: str) -> list[str]:
    """The command line of ``python -m module args...`` that Ctrl-C (SIGINT) interrupts."""
    import sys

    return [sys.executable, "-c", _INTERRUPTIBLE, module, *args]


def rel_err(actual, reference, floor: float = 1e-300) -> float:
    """Worst per-sample normwise relative error; arrays shaped (N, ...) or (N,)."""
    a = np.asarray(actual, dtype=float)
    b = np.asarray(reference, dtype=float)
    assert a.shape == b.shape, f"shape {a.shape} != reference shape {b.shape}"
    a = a.reshape(a.shape[0], -1)
    b = b.reshape(b.shape[0], -1)
    diff = np.max(np.abs(a - b), axis=1)
    scale = np.maximum(np.max(np.abs(b), axis=1), floor)
    return float(np.max(diff / scale))


def random_states(rng: np.random.Generator, n_samples: int, n: int):
    """q uniform in [-pi, pi], qd and qdd (or tau) uniform in [-3, 3]."""
    q = rng.uniform(-np.pi, np.pi, (n_samples, n))
    qd = rng.uniform(-3, 3, (n_samples, n))
    qdd = rng.uniform(-3, 3, (n_samples, n))
    return q, qd, qdd


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20240611)


@pytest.fixture(scope="session")
def worst_errors():
    """Records the worst relative error per comparison; printed at the end with -s."""
    table: dict[str, float] = {}
    yield table
    if table:
        width = max(map(len, table))
        print("\nworst relative errors:")
        for k, v in sorted(table.items()):
            print(f"  {k:<{width}}  {v:.3e}")


def record(table: dict[str, float], key: str, value: float) -> float:
    table[key] = max(table.get(key, 0.0), value)
    return value


def copy_builtin(tmp_path: Path, robot: str, name: str | None = None) -> Path:
    """A copy of a built-in description in tmp_path (to be edited by a test)."""
    dst = tmp_path / f"{name or robot}.toml"
    shutil.copyfile(ROBOTS_DIR / f"{robot}.toml", dst)
    return dst


@pytest.fixture(scope="session")
def derived(tmp_path_factory):
    """``derived(toml_path) -> (folder, Robot)``: derive a test robot into a tmp folder and load
    it, compiled into a session tmp cache (test robots stay out of the user's cache)."""
    from derive.__main__ import main as derive_main  # needs SymPy: only for tests that use it
    from planar_sym.model.library import Library
    from planar_sym.model.robot import Robot

    out = tmp_path_factory.mktemp("derived")
    cache = tmp_path_factory.mktemp("cache")
    done: dict[Path, tuple[Path, object]] = {}

    def get(toml: Path):
        toml = Path(toml)
        if toml not in done:
            assert derive_main([str(toml), "--out", str(out), "--quiet"]) == 0
            name = toml.stem
            with pytest.MonkeyPatch.context() as mp:
                mp.setenv("PLANAR_SYM_CACHE", str(cache))
                robot = Robot(name, Library(name, folder=out / name))
            done[toml] = (out / name, robot)
        return done[toml]

    return get


def serial_2dof_in_cm(folder: Path) -> Path:
    """The seed's 2-DOF arm typed again in cm (``serial_2dof.toml`` with every length x 100
    and ``length = "cm"``): the same robot, another unit. Returns its path."""
    text = (ROBOTS_DIR / "serial_2dof.toml").read_text()
    for a, b in (('length = "m"', 'length = "cm"'), ("[0.0373, 0.0]", "[3.73, 0.0]"),
                 ("[0.04168, 0.0]", "[4.168, 0.0]"), ("[0.1, 0.0]", "[10.0, 0.0]"),
                 ("[0.2, 0.0]", "[20.0, 0.0]")):
        assert a in text
        text = text.replace(a, b)
    path = Path(folder) / "serial_2dof.toml"
    path.write_text(text)
    return path


def seed_studies() -> dict:
    """The built-in studies (the seed's scenarios), by name."""
    from planar_sym.study.builtin import names
    from planar_sym.study.run import load_study

    return {n: load_study(n) for n in names()}


def study_motion(name: str, t=None):
    """(robot, task trajectory, joint trajectory) of a built-in inverse-dynamics study at times
    ``t`` (default 201 evenly spaced samples), exactly as the study runs it."""
    from planar_sym.study.motion import joint_motion, profile_at
    from planar_sym.study.run import load_study, robot_of

    st = load_study(name)
    robot = robot_of(st)
    t = np.linspace(0.0, st.motion.duration_s, 201) if t is None else np.asarray(t, float)
    jt, _ = joint_motion(st, robot, t=t)
    return robot, profile_at(st, robot, t), jt
