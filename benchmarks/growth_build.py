"""Section 3c's builds: deriving and first-compiling each robot, and measuring its generated code.

``Robot`` holds one robot's measurements (filled here, then by the run timing of
``growth.py``); ``_build_rounds`` derives and compiles it in fresh subprocesses (wall times,
peak compiler memory), ``_code`` reads the generated folder's sizes, operations and routes,
``_robot`` loads round 0's library and ``_export_urdf`` writes the URDF the Pinocchio baseline
reads. Apart from ``growth.py`` (run timing against Pinocchio, fits, tables and the section)
because building is subprocesses and files, not in-process timing.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from .timing import Stats

ROOT = Path(__file__).resolve().parent.parent
ROUTES = {"closed form": "CF", "algorithmic differentiation": "AD"}

#: run in the compile subprocess: "first" is a user's first use of the derived folder (the
#: robot, then the torques of the tree at the drawn pose: what compiles on first use), "all"
#: compiles every other group too (``planar-sym build``); then what its compilers took
COMPILE = """
import json, resource, sys, time
from pathlib import Path
t0 = time.perf_counter()
import numpy as np
from planar_sym.model.library import Library
from planar_sym.model.robot import Robot
lib = Library(sys.argv[1], Path(sys.argv[2]))
robot = Robot(sys.argv[1], lib)
if sys.argv[3] == "first":
    z = np.zeros((1, robot.n))
    robot.tree_inverse_dynamics(robot.q_drawn[None], z, z)
else:
    lib.build_all()
print(json.dumps({"library_s": time.perf_counter() - t0, "simd": lib.simd is not None
                  or len(lib.groups) > 1, "groups": len(lib.groups),
                  "maxrss_kib": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss}))
"""


@dataclass
class Robot:
    """One robot's measurements (lists: one value per round)."""

    label: str
    n: int  # links (chains) or coordinates (Jansen)
    chain: bool
    derive_wall: list[float] = field(default_factory=list)
    derive_own: list[float] = field(default_factory=list)
    imports: list[float] = field(default_factory=list)
    compile_wall: list[float] = field(default_factory=list)
    compile_lib: list[float] = field(default_factory=list)
    rest_wall: list[float] = field(default_factory=list)  # the groups first use left out
    groups: int = 1
    warm_wall: list[float] = field(default_factory=list)
    maxrss_kib: list[int] = field(default_factory=list)
    simd_built: bool = True
    code: dict = field(default_factory=dict)
    run: dict[str, Stats] = field(default_factory=dict)
    pin: Stats | None = None
    pin_ratio: Stats | None = None
    pin_rnea: Stats | None = None  # rnea alone, inputs packed beforehand
    pin_crba: Stats | None = None  # crba on the same packed inputs
    pin_crba_stored: Stats | None = None  # the same, every matrix written out as ours is
    crba_stored_ratio: Stats | None = None  # Pinocchio crba + store over our mass matrix
    pin_aba: Stats | None = None  # aba on them, fed rnea's torques
    crba_ratio: Stats | None = None  # Pinocchio crba over our mass matrix, per round
    aba_ratio: Stats | None = None  # Pinocchio aba over our forward dynamics, per round
    pin_note: str = ""


def _timed(cmd: list[str], env: dict | None = None, cwd: Path = ROOT):
    """(wall time, finished process) of one subprocess; raises if it failed."""
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, check=False)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(map(str, cmd))} failed ({proc.returncode}):\n"
                           f"{proc.stderr[-3000:]}")
    return wall, proc


def _env(cache: Path) -> dict:
    env = {**os.environ, "PLANAR_SYM_CACHE": str(cache), "PLANAR_SYM_PREBUILT": "0"}
    env.pop("PLANAR_SYM_EXACT", None)
    return env


def _build_rounds(r: Robot, toml: Path, work: Path, repeats: int) -> tuple[Path, Path]:
    """Derive and first-compile ``repeats`` times; returns round 0's folder and its cache."""
    keep = None
    for k in range(repeats):
        out, cache = work / f"derived{k}", work / f"cache{k}"
        imports = [sys.executable, "-c", "import sympy, casadi, derive.model, derive.codegen"]
        # the baseline before the candidate in even rounds, after it in odd ones
        if k % 2 == 0:
            r.imports.append(_timed(imports)[0])
        wall, proc = _timed([sys.executable, "-m", "derive", str(toml), "--out", str(out)])
        if k % 2 == 1:
            r.imports.append(_timed(imports)[0])
        found = re.findall(r"derived (\S+) in ([0-9.]+) s", proc.stderr)
        if len(found) != 1:
            raise RuntimeError(f"no 'derived NAME in X s' line from derive:\n{proc.stderr}")
        name = found[0][0]
        r.derive_wall.append(wall)
        r.derive_own.append(float(found[0][1]))
        folder = out / name
        cmd = [sys.executable, "-W", "ignore", "-c", COMPILE, name, str(folder), "first"]
        wall, proc = _timed(cmd, _env(cache))
        info = json.loads(proc.stdout.strip().splitlines()[-1])
        r.compile_wall.append(wall)
        r.compile_lib.append(info["library_s"])
        r.simd_built = r.simd_built and info["simd"]
        r.groups = info["groups"]
        r.warm_wall.append(_timed(cmd, _env(cache))[0])
        rest, proc = _timed([*cmd[:-1], "all"], _env(cache))
        r.rest_wall.append(rest)
        r.maxrss_kib.append(max(int(info["maxrss_kib"]), int(json.loads(
            proc.stdout.strip().splitlines()[-1])["maxrss_kib"])))
        if keep is None:
            keep = (folder, cache)
        else:
            shutil.rmtree(out, ignore_errors=True)
            shutil.rmtree(cache, ignore_errors=True)
    return keep


def _code(folder: Path) -> dict:
    from planar_sym.model.folders import read_manifest

    m = read_manifest(folder)
    name = m["robot"]
    fns = m["functions"]
    routes = [f.get("route", "?") for f in fns.values()]
    eq = (folder / "equations.txt").read_text()
    main = ("closed_inverse_dynamics" if m["constraints"] else "inverse_dynamics", "mass_matrix",
            "forward_dynamics")
    return {
        "c": (folder / f"{name}.c").stat().st_size,
        "simd": (folder / f"{name}_simd.c").stat().st_size
        if (folder / f"{name}_simd.c").exists() else 0,
        "ops": sum(f.get("operations", 0) for f in fns.values()),
        "units": len(m.get("compile_units", {}).get("simd", [0])),
        "flag": _flags(m),
        "cf": routes.count("closed form"), "ad": routes.count("algorithmic differentiation"),
        "main": ", ".join(_route(fns[q].get("route", "")) if q in fns else "-" for q in main),
        "eq": len(eq.encode()),
        "eq_kind": "structure" if "structure" in eq else "closed forms",
    }


def _flags(manifest: dict) -> str:
    """The exact libraries' optimisation flag, per compile group where they differ: "-O3",
    or "-O3; -O1 for 1 of 12 groups" (the forward dynamics' Jacobian past 20,000
    operations)."""
    from planar_sym.model.compile import exact_flags, groups

    flags = [exact_flags(manifest, k)[0] for k in range(len(groups(manifest)))]
    first = max(set(flags), key=flags.count)
    other = [f for f in flags if f != first]
    return first + (f"; {other[0]} for {len(other)} of {len(flags)} groups" if other else "")


def _route(route: str) -> str:
    """CF or AD, and +ABA where M^-1 is the articulated-body recursion."""
    short = next((v for k, v in ROUTES.items() if route.startswith(k)), "?")
    return short + ("+ABA" if "articulated" in route else "")


@contextmanager
def _cache(path: Path):
    old = os.environ.get("PLANAR_SYM_CACHE")
    os.environ["PLANAR_SYM_CACHE"] = str(path)
    try:
        yield
    finally:
        if old is None:
            del os.environ["PLANAR_SYM_CACHE"]
        else:
            os.environ["PLANAR_SYM_CACHE"] = old


def _robot(name: str, folder: Path, cache: Path):
    from planar_sym.model.library import Library
    from planar_sym.model.robot import Robot as PsRobot

    with _cache(cache):  # round 0's libraries: loaded, not compiled again
        return PsRobot(name, Library(name, folder))


def _export_urdf(toml: Path, folder: Path, cache: Path, work: Path) -> Path:
    shutil.copyfile(toml, folder / "description.toml")  # what export reads the bodies from
    urdf = work / f"{folder.name}.urdf"
    _timed([sys.executable, "-m", "planar_sym", "export", str(folder), "--format", "urdf",
            "--out", str(urdf), "--quiet"], _env(cache))
    return urdf
