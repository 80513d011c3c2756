"""An interrupted ``python -m derive`` leaves every robot folder complete: the old version or the
new one, never a mix.

Each run works on a copy of ``generated/`` whose folders are first made distinguishable from
what derive writes (a marker line appended to ``equations.txt``, the manifest's hash updated, so
the old version is itself consistent). Then derive is interrupted, and every robot folder must

* be consistent: exactly the manifest's files, each with the manifest's sha256;
* be byte for byte the old version, or a new one (consistent, without the marker);
* load (``Library(robot, folder)`` checks the manifest again), with hidden ``.<robot>.*``
  leftovers of a killed run ignored by the loader (and removed by the next derive of that
  robot: ``test_leftovers_of_a_killed_run_are_ignored_then_cleaned``).

Moments on the real command (every built-in robot): SIGKILL and SIGINT right after the first
"wrote" line on stderr (between two folder swaps, possibly in the middle of writing the next).
Moments before any folder is written, by a driver that runs the same command (``runpy`` on
``derive``, every built-in robot) and signals itself from inside it at a named stage, not
after a time (a loaded machine would move those): SIGKILL while importing derive (when
``derive.__main__`` imports ``derive.codegen``, before anything is derived), and SIGKILL and
SIGINT while deriving in memory (when ``codegen.render`` is called for the second robot: the
first one is derived, nothing is written). Further deterministic moments, by the same driver on
two robots: SIGKILL/SIGINT in the middle of writing the second robot's temporary folder. (The
driver's modes "swapped", right after a folder was swapped in, and "between", between the two
renames of the fallback swap, are used by no test here.)
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from conftest import interruptible

from planar_sym.model.library import Library

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"
ROBOTS = sorted(p.name for p in GENERATED.iterdir() if (p / "manifest.json").is_file())
MARKER = "\n(old version, made by tests/test_interrupted_derive.py)\n"


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    return env


def old_copy(tmp_path: Path) -> Path:
    """generated/ copied, every robot folder marked as the old version (and consistent)."""
    gen = tmp_path / "gen"
    shutil.copytree(GENERATED, gen, ignore=shutil.ignore_patterns("__pycache__"))
    for robot in ROBOTS:
        folder = gen / robot
        eq = folder / "equations.txt"
        eq.write_bytes(eq.read_bytes() + MARKER.encode())
        manifest = json.loads((folder / "manifest.json").read_text())
        manifest["files"]["equations.txt"] = hashlib.sha256(eq.read_bytes()).hexdigest()
        (folder / "manifest.json").write_text(json.dumps(manifest, indent=2) + "\n")
    shutil.copytree(gen, tmp_path / "old")
    return gen


def folder_problems(folder: Path) -> list[str]:
    try:
        manifest = json.loads((folder / "manifest.json").read_text())
    except (OSError, ValueError) as exc:
        return [f"{folder.name}: no readable manifest ({exc})"]
    problems = []
    present = {p.name for p in folder.iterdir()}
    if present != set(manifest["files"]) | {"manifest.json"}:
        problems.append(f"{folder.name}: files {sorted(present)} != the manifest's")
    for name, digest in manifest["files"].items():
        path = folder / name
        if path.is_file() and hashlib.sha256(path.read_bytes()).hexdigest() != digest:
            problems.append(f"{folder.name}/{name}: sha256 differs from the manifest")
    return problems


def _same_tree(a: Path, b: Path) -> bool:
    names = sorted(p.name for p in a.iterdir())
    return names == sorted(p.name for p in b.iterdir()) and all(
        (a / n).read_bytes() == (b / n).read_bytes() for n in names)


def check_folders(gen: Path, old: Path) -> dict[str, str]:
    """Every robot folder old or new and loadable; returns robot -> "old" | "new"."""
    states = {}
    for robot in ROBOTS:
        folder = gen / robot
        assert folder.is_dir(), f"{robot}: folder missing after the interrupt"
        assert folder_problems(folder) == [], folder_problems(folder)
        if _same_tree(folder, old / robot):
            states[robot] = "old"
        else:
            assert MARKER.encode() not in (folder / "equations.txt").read_bytes(), (
                f"{robot}: a mix of old and new files")
            states[robot] = "new"
        Library(robot, folder=folder)  # the runtime's own check: manifest hashes, library
    names = {p.name for p in gen.iterdir()}
    allowed = set(ROBOTS) | {"__init__.py"}
    for name in names - allowed:
        assert re.match(rf"^\.({'|'.join(ROBOTS)})\.", name), f"stray entry {name!r} in {gen}"
    return states


def _hidden(gen: Path) -> list[str]:
    """Hidden leftovers; a robot's ``.<robot>.lock`` file is the derive lock, not litter."""
    return sorted(p.name for p in gen.iterdir()
                  if p.name.startswith(".") and not p.name.endswith(".lock"))


# -- the real command, interrupted after its first folder ------------------------------------------

@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGINT],
                         ids=["kill-after-first-folder", "int-after-first-folder"])
def test_interrupted_after_the_first_folder(tmp_path, sig):
    gen = old_copy(tmp_path)
    proc = subprocess.Popen(interruptible("derive", "--out", str(gen)), cwd=ROOT,
                            env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            text=True)
    for line in proc.stderr:  # "wrote <folder>/ (...)" after each folder swap
        if line.startswith("wrote "):
            proc.send_signal(sig)
            break
    else:
        pytest.fail(f"derive wrote no folder (exit code {proc.wait()})")
    proc.communicate(timeout=60)
    states = check_folders(gen, tmp_path / "old")
    assert "new" in states.values(), states


# -- deterministic moments: derive signals itself from inside ----------------------------------------

DRIVER = textwrap.dedent("""
    import importlib.abc, os, pathlib, runpy, signal, sys

    mode, sig, out = sys.argv[1], getattr(signal, sys.argv[2]), sys.argv[3]
    robots = sys.argv[4:]
    writes = [0]
    real_write, real_replace = pathlib.Path.write_bytes, os.replace

    def write_bytes(self, data):
        n = real_write(self, data)
        if self.parent.name.startswith(f".{robots[1]}."):  # the second robot's temporary folder
            writes[0] += 1
            if mode == "writing" and writes[0] == 3:  # its third file
                os.kill(os.getpid(), sig)
        return n

    def replace(src, dst):
        real_replace(src, dst)
        name = os.path.basename(os.fspath(dst))
        if mode == "between" and ".old." in name:  # committed folder moved away
            os.kill(os.getpid(), sig)
        if mode == "swapped" and not name.startswith("."):  # new folder in place
            os.kill(os.getpid(), sig)

    pathlib.Path.write_bytes, os.replace = write_bytes, replace
    if mode == "importing":  # derive.__main__ importing its code generator (SymPy, CasADi)
        class Importing(importlib.abc.MetaPathFinder):
            def find_spec(self, name, path=None, target=None):
                if name == "derive.codegen":
                    print("driver: signal while importing", file=sys.stderr, flush=True)
                    os.kill(os.getpid(), sig)
                return None

        sys.meta_path.insert(0, Importing())
    if mode == "deriving":  # the second robot's derivation starts: the first is in memory
        import derive.codegen as codegen

        real_render, renders = codegen.render, [0]

        def render(*args, **kwargs):
            renders[0] += 1
            if renders[0] == 2:
                print("driver: signal while deriving", file=sys.stderr, flush=True)
                os.kill(os.getpid(), sig)
            return real_render(*args, **kwargs)

        codegen.render = render
    sys.argv = ["derive", *robots, "--out", out, "--quiet"]
    runpy.run_module("derive", run_name="__main__")
    sys.exit(3)  # not interrupted: the driver missed its moment
""")
PAIR = ["serial_2dof", "five_bar_type1"]  # written in this order


def _drive(tmp_path: Path, mode: str, sig: str,
           robots: list[str] = PAIR) -> tuple[Path, subprocess.CompletedProcess]:
    gen = old_copy(tmp_path)
    script = tmp_path / "driver.py"
    script.write_text(DRIVER)
    res = subprocess.run([sys.executable, str(script), mode, sig, str(gen), *robots], cwd=ROOT,
                         env=_env(), capture_output=True, text=True, timeout=60, check=False)
    expected = -signal.SIGKILL if sig == "SIGKILL" else -signal.SIGINT
    assert res.returncode in (expected, 1, 130), (res.returncode, res.stderr[-2000:])
    assert res.returncode != 3, "the interrupt never happened"
    return gen, res


@pytest.mark.parametrize("sig, stage", [("SIGKILL", "importing"), ("SIGKILL", "deriving"),
                                        ("SIGINT", "deriving")],
                         ids=["kill-importing", "kill-deriving", "int-deriving"])
def test_interrupted_before_any_folder_is_written(tmp_path, sig, stage):
    """Every built-in robot (those ``python -m derive`` derives when given no names):
    interrupted while importing or while deriving in memory, nothing is swapped: every folder
    is the old one, nonzero exit, and nothing is left beside them."""
    from planar_sym.model.description import builtin_robots

    assert sorted(builtin_robots()) == ROBOTS
    gen, res = _drive(tmp_path, stage, sig, robots=ROBOTS)
    assert res.returncode != 0 and f"driver: signal while {stage}\n" in res.stderr, res.stderr
    states = check_folders(gen, tmp_path / "old")
    assert set(states.values()) == {"old"}, states
    assert _hidden(gen) == []


@pytest.mark.parametrize("sig", ["SIGKILL", "SIGINT"])
def test_interrupted_while_writing_a_folder(tmp_path, sig):
    gen, _ = _drive(tmp_path, "writing", sig)
    states = check_folders(gen, tmp_path / "old")
    assert states["serial_2dof"] == "new" and states["five_bar_type1"] == "old", states
    hidden = _hidden(gen)
    if sig == "SIGINT":  # the finally clause removes the half-written temporary folder
        assert hidden == [], hidden
    else:
        assert len(hidden) == 1 and hidden[0].startswith(".five_bar_type1."), hidden


def test_leftovers_of_a_killed_run_are_ignored_then_cleaned(tmp_path):
    """Killed while writing five_bar_type1's new folder: its temporary folder is left as a
    hidden ``.five_bar_type1.<random>``; the loader ignores it, and the next derive of that
    robot removes it (under the lock) before writing."""
    gen, _ = _drive(tmp_path, "writing", "SIGKILL")
    hidden = _hidden(gen)
    assert len(hidden) == 1 and hidden[0].startswith(".five_bar_type1."), hidden
    env = dict(_env(), PLANAR_SYM_GENERATED=str(gen))
    code = "import planar_sym as ps; print(ps.load('five_bar_type1').library.folder)"
    res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=60, check=False)
    assert res.returncode == 0 and res.stdout.strip() == str(gen / "five_bar_type1"), res
    res = subprocess.run([sys.executable, "-m", "derive", "five_bar_type1", "--out", str(gen),
                          "--quiet"], cwd=ROOT, env=_env(), capture_output=True, text=True,
                         timeout=120, check=False)
    assert res.returncode == 0, res.stderr
    assert _hidden(gen) == []
    assert folder_problems(gen / "five_bar_type1") == []
