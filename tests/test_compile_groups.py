"""Compile groups (``derive/groups.py``, issue 28): past ``GROUP_PAST_OPS`` operations each
generated function compiles into libraries of its own, the first time it is called.

The five-bar (a closed chain: loop functions, closed-chain inverse dynamics) is derived here
with the bound at 0, so every function is a group, and its libraries are built on an empty
cache. Checked: making the library compiles nothing; a call compiles its own group and no
other; each group's libraries hold that group's functions and no other's (the bound on what a
compiler process holds); and every quantity, the simulations on dopri5, Radau (the Jacobian's
group) and CVODES (CasADi externals per group) agree with the built-in five-bar, whose same
code is compiled as one whole file.
"""

from __future__ import annotations

import ctypes
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from derive import codegen, groups, simd
from derive.__main__ import write_atomically
from planar_sym.model.description import load as load_description
from planar_sym.model.library import Library
from planar_sym.model.robot import Robot
from planar_sym.motion.closure import from_actuated

ROOT = Path(__file__).resolve().parent.parent
ROBOT = "five_bar_type1"


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """The five-bar derived with every function its own group."""
    out = tmp_path_factory.mktemp("grouped")
    desc = load_description(ROBOT)
    write_atomically(codegen.render(desc, group_past=0), out / ROBOT)
    return out / ROBOT


@pytest.fixture
def cache(tmp_path, monkeypatch):
    path = tmp_path / "cache"
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(path))
    monkeypatch.setenv("PLANAR_SYM_PREBUILT", "0")
    return path


def _robot(folder) -> tuple[Robot, Library]:
    lib = Library(ROBOT, folder)
    return Robot(ROBOT, lib, parameters=ps.load(ROBOT).p), lib


def _pose():
    """A crank revolution's states on the loops, from the built-in robot."""
    ref = ps.load(ROBOT)
    t = np.linspace(0, 0.5, 7)
    start = np.array(ref.q_drawn)[list(ref.actuated)]
    qa = start + np.outer(t, [0.3, -0.2])
    jt = from_actuated(ref, t, qa, np.tile([0.6, -0.4], (7, 1)), np.tile([1.0, 2.0], (7, 1)))
    return ref, jt


def test_every_function_is_a_group_with_its_own_units(folder):
    manifest = json.loads((folder / "manifest.json").read_text())
    assert [g["functions"] for g in manifest["groups"]] == [[q] for q in manifest["functions"]]
    seen = [u for g in manifest["groups"] for u in g["units"]]
    assert seen == list(range(len(manifest["compile_units"]["simd"]))), "a unit in two groups"
    looped = [q for q in manifest["functions"] if "loop" in manifest["functions"][q]]
    assert [g["functions"][0] for g in manifest["groups"] if g["units"]] == looped


def test_a_call_compiles_its_own_group_and_no_other(folder, cache):
    robot, lib = _robot(folder)  # (the built-in's parameters compile the built-in: no -g)
    assert not lib._built and not list(cache.glob("*-g*.so")), "compiled before any call"
    assert type(robot.__dict__["mass_matrix"]).__name__ == "_OnFirstCall"
    ref, jt = _pose()
    np.testing.assert_allclose(robot.mass_matrix(jt.q), ref.mass_matrix(jt.q), rtol=0,
                               atol=1e-14)
    assert sorted(lib._built) == [lib._group_of["mass_matrix"]]
    names = sorted(p.name for p in cache.glob("*-g*.so"))
    g = lib._group_of["mass_matrix"]
    assert len(names) == 2 and all(f"-g{g}" in n for n in names), names
    assert type(robot.__dict__["mass_matrix"]).__name__ != "_OnFirstCall", "not rebound"


class _Terminal:
    """Standard error as a terminal (progress lines are shown on one only)."""

    def __init__(self):
        self.text = ""

    def write(self, s):
        self.text += s

    def flush(self):
        pass

    def isatty(self):
        return True


def test_a_first_compile_says_so_once_on_a_terminal(folder, cache, monkeypatch):
    """A big robot's function can take seconds to compile on its first call: a terminal hears
    which and how big before the wait, once; a cached one, or --quiet, says nothing."""
    from planar_sym import progress

    q = _pose()[1].q  # (the built-in robot compiled first: its one group says so too)
    err = _Terminal()
    monkeypatch.setattr(sys, "stderr", err)
    robot, lib = _robot(folder)
    robot.mass_matrix(q)
    robot.mass_matrix(q)
    ops = lib.manifest["functions"]["mass_matrix"]["operations"]
    assert err.text == (f"{ROBOT}: compiling mass_matrix ({ops:,} operations), once: kept in "
                        "the cache ...\n")
    err.text = ""
    _robot(folder)[0].mass_matrix(q)  # a new library, the group cached: nothing to say
    monkeypatch.setattr(progress, "QUIET", True)
    _robot(folder)[0].gravity(q)
    assert err.text == ""


def test_each_group_holds_its_functions_only(folder, cache):
    _, lib = _robot(folder)
    lib.build_all()
    manifest = lib.manifest
    for k, (path, exact, loops) in sorted(lib._built.items()):
        for q, spec in manifest["functions"].items():
            mine = lib._group_of[q] == k
            assert hasattr(exact, spec["symbol"] + "_batch") == mine, (k, q)
            if loops is not None and "loop" in spec:
                assert hasattr(loops, spec["loop"]) == mine, (k, q)
        get = exact[f"{ROBOT}_input_hash"]
        get.restype = ctypes.c_char_p
        assert get().decode() == manifest["input_hash"]
        assert (loops is None) == (not lib.groups[k]["units"])


def test_grouped_robot_computes_what_the_whole_build_does(folder, cache):
    robot, _ = _robot(folder)
    ref, jt = _pose()
    tau, cut = ref.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)
    got_tau, got_cut = robot.closed_chain_inverse_dynamics(jt.q, jt.qd, jt.qdd)
    for got, want in (
            (got_tau, tau), (got_cut, cut),
            (robot.tree_inverse_dynamics(jt.q, jt.qd, jt.qdd),
             ref.tree_inverse_dynamics(jt.q, jt.qd, jt.qdd)),
            (robot.bias(jt.q, jt.qd), ref.bias(jt.q, jt.qd)),
            (robot.constraint_jacobian(jt.q), ref.constraint_jacobian(jt.q)),
            (robot.task(jt.q)[0], ref.task(jt.q)[0]),
            (robot.energy(jt.q, jt.qd)[0], ref.energy(jt.q, jt.qd)[0])):
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)
    for method in ("dopri5", "Radau", "cvodes"):
        a = ps.simulate(robot, jt.q[0], jt.qd[0], (0, 0.2), method=method)
        b = ps.simulate(ref, jt.q[0], jt.qd[0], (0, 0.2), method=method)
        np.testing.assert_allclose(a.q, b.q, rtol=0, atol=1e-12, err_msg=method)


def test_units_never_hold_two_groups():
    assert simd.units([10, 10, 10, 10], 100, [0, 0, 1, 1]) == [0, 0, 1, 1]
    assert simd.units([10, 10, 10], 100) == [0, 0, 0]
    assert simd.units([60, 60, 10], 100, [0, 0, 0]) == [0, 1, 1]
    assert groups.assign({"a": 5, "b": 5}, 10) == [["a", "b"]]
    assert groups.assign({"a": 5, "b": 6}, 10) == [["a"], ["b"]]


def test_a_sweep_sees_the_loops_of_a_group_not_yet_built(folder, cache):
    """A sweep asks ``hasattr(robot.tree_inverse_dynamics, "designs")`` to choose its fast
    route: before the first call that must compile the group and answer yes (not fall back to
    a run per design), and the designs' torques are each design's own."""
    robot, lib = _robot(folder)
    ref, jt = _pose()
    assert type(robot.__dict__["tree_inverse_dynamics"]).__name__ == "_OnFirstCall"
    assert hasattr(robot.tree_inverse_dynamics, "designs")
    assert lib.is_built("inverse_dynamics")
    P = np.stack([ref.p, ref.p * 1.1])
    tau = robot.tree_inverse_dynamics.designs(P, jt.q, jt.qd, jt.qdd)
    other = ref.with_parameters(**{par.name: 1.1 * v for par, v in zip(ref.parameter_list,
                                                                         ref.p)})
    np.testing.assert_allclose(tau[0], ref.tree_inverse_dynamics(jt.q, jt.qd, jt.qdd),
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(tau[1], other.tree_inverse_dynamics(jt.q, jt.qd, jt.qdd),
                               rtol=1e-12, atol=1e-12)


def test_the_command_line_on_a_robot_past_the_bound(tmp_path):
    """`planar-sym derive` of a 6-link chain (5,104 operations, past the bound) says its
    functions compile when first called, and compiles nothing (it used to print "not compiled
    (no C compiler ...)" from the library's empty path); `planar-sym build` then compiles every
    group: an exact library per function and a loops library per function that has a loop."""
    from benchmarks.chains import write_chain

    toml = write_chain(6, tmp_path)
    env = {**os.environ, "PLANAR_SYM_CACHE": str(tmp_path / "cache"), "PLANAR_SYM_PREBUILT": "0",
           "PYTHONPATH": str(ROOT)}
    out = tmp_path / "out"

    def cli(*args):
        proc = subprocess.run([sys.executable, "-m", "planar_sym", *args], env=env,
                              capture_output=True, text=True, timeout=600, check=False)
        assert proc.returncode == 0, proc.stderr
        return proc.stdout

    said = cli("derive", str(toml), "--out", str(out))
    # 14: the 12 of a tree with a task, and the fused tracking laws (derive/tracking.py)
    assert (f"chain_6: wrote {out / 'chain_6'}/; its 14 functions compile each when first "
            f"called (all of them now: `planar-sym build {out / 'chain_6'}`)") in said
    assert not list((tmp_path / "cache").glob("*.so"))
    said = cli("build", str(out / "chain_6"))
    assert f"chain_6: 14 libraries, one per function, in {tmp_path / 'cache'}" in said
    assert len(list((tmp_path / "cache").glob("chain_6-*-g*.so"))) == 14 + 8  # exact + loops
