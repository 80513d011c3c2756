"""What a wheel holds and what an install builds.

* Every runtime package is packaged (the control layer was once missing from a hand-kept list,
  which an editable install hides); ``derive`` ships as ``planar_sym._derive``, never as a
  top-level package.
* setup.py names the robots' libraries it compiles at install exactly as the runtime looks them
  up (``library.library_path``), and the runtime uses them and the installed C helpers.
* A real wheel, built from this checkout: its files, its metadata (licence, classifiers,
  ``py.typed``) and a build log with no warnings.
"""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import zipfile
from email.parser import Parser
from pathlib import Path

import pytest

from planar_sym.model import compile as library
from planar_sym.model.description import builtin_robots
from planar_sym.model.folders import find_generated, read_manifest
from planar_sym.model.library import Library

ROOT = Path(__file__).resolve().parent.parent


def _setup_module():
    spec = importlib.util.spec_from_file_location("planar_sym_setup", ROOT / "setup.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)  # not __main__: setup() does not run
    return module


def test_every_runtime_package_is_packaged():
    packages, data = _setup_module()._packages()
    folders = {".".join(d.relative_to(ROOT).parts) for d in (ROOT / "planar_sym").rglob("*")
               if d.is_dir() and any(d.glob("*.py")) and "__pycache__" not in d.parts}
    assert folders | {"planar_sym", "planar_sym._derive"} <= set(packages)
    assert not any(p == "derive" or p.startswith("derive.") for p in packages)
    robots = {p.rpartition(".")[2] for p in packages if p.startswith("planar_sym.generated.")}
    assert robots == set(builtin_robots())
    assert "*.casadi" in data["planar_sym.generated.serial_2dof"]


@pytest.mark.parametrize("robot", builtin_robots())
def test_install_names_libraries_as_the_runtime_does(robot):
    folder = find_generated(robot)
    manifest = read_manifest(folder)
    from planar_sym.model.compile import _compiler, _is_gcc

    setup = _setup_module()
    names = {name for _, _, name in setup._robot_builds(folder, setup._is_gcc(_compiler()))}
    assert setup._is_gcc(_compiler()) == _is_gcc(_compiler())
    assert names == {library.library_path(folder, manifest).name,
                     library.library_path(folder, manifest, "simd").name}


def test_runtime_uses_what_the_install_built(tmp_path, monkeypatch):
    """With an empty cache, a built-in robot and the C helpers load from the install: nothing
    is compiled (the first torque of a fresh install costs no compile)."""
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    monkeypatch.delenv("PLANAR_SYM_PREBUILT", raising=False)
    built = library.installed_extension(ROOT / "planar_sym" / "motion" / "_newton.c")
    if built is None or not any(library.PREBUILT.glob("*.so")):
        pytest.fail("the install's C was not built: run `make venv` (pip install -e .)")
    lib = Library("parallel_3rrr")
    assert lib.path.parent == library.PREBUILT
    helper = library.load_helper(ROOT / "planar_sym" / "motion" / "_newton.c")
    assert Path(helper._name) == built
    assert not (tmp_path / "cache").exists() or not any((tmp_path / "cache").glob("*.so"))


def test_stale_installed_helper_is_not_loaded(tmp_path, monkeypatch):
    """A helper built at install from another version of its source is compiled anew."""
    monkeypatch.setenv("PLANAR_SYM_CACHE", str(tmp_path / "cache"))
    src = tmp_path / "_newton.c"
    src.write_text((ROOT / "planar_sym" / "motion" / "_newton.c").read_text() + "\n/* edit */\n")
    installed = library.installed_extension(ROOT / "planar_sym" / "motion" / "_newton.c")
    if installed is None:
        pytest.fail("the install's C was not built: run `make venv`")
    (tmp_path / installed.name).write_bytes(installed.read_bytes())  # built from the old source
    helper = library.load_helper(src)
    assert Path(helper._name).parent == tmp_path / "cache"


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    out = tmp_path_factory.mktemp("dist")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    proc = subprocess.run([sys.executable, "-m", "build", "--wheel", "--no-isolation",
                           "--outdir", str(out), str(ROOT)], capture_output=True, text=True,
                          env=env, timeout=600, check=False)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    (path,) = out.glob("*.whl")
    return path, proc.stdout + proc.stderr


def test_wheel_holds_the_runtime(wheel):
    path, _ = wheel
    names = set(zipfile.ZipFile(path).namelist())
    for module in (ROOT / "planar_sym").rglob("*.py"):
        assert module.relative_to(ROOT).as_posix() in names
    assert not any(n.startswith("derive/") for n in names)
    assert "planar_sym/_derive/codegen.py" in names
    assert "planar_sym/py.typed" in names and "planar_sym/model/_fastcall.pyi" in names
    assert "planar_sym/generated/parallel_3rrr/inverse_dynamics.casadi" in names
    for fmt in ("description", "study"):  # the formats' JSON Schemas, for editors
        assert f"planar_sym/schemas/{fmt}.schema.json" in names
    for stem in ("model/_fastcall", "dynamics/_integrate", "motion/_newton"):
        assert any(n.startswith(f"planar_sym/{stem}.") and n.endswith((".so", ".pyd"))
                   for n in names), stem
    robots = {n.split("/")[-1].split("-")[0] for n in names
              if n.startswith("planar_sym/model/prebuilt/") and n.endswith(".so")}
    assert robots == set(builtin_robots())


def test_wheel_metadata_and_a_quiet_build(wheel):
    path, log = wheel
    z = zipfile.ZipFile(path)
    (meta,) = [n for n in z.namelist() if n.endswith(".dist-info/METADATA")]
    info = Parser().parsestr(z.read(meta).decode())
    assert info["License-Expression"] == "BSD-3-Clause"
    assert any(n.endswith(".dist-info/licenses/LICENSE") for n in z.namelist())
    classifiers = info.get_all("Classifier")
    assert "Programming Language :: Python :: 3.13" in classifiers
    assert "Typing :: Typed" in classifiers
    assert {"filelock", "platformdirs"} <= {r.split(">")[0].split("=")[0].strip()
                                          for r in info.get_all("Requires-Dist")}
    noisy = [ln for ln in log.splitlines() if "warning" in ln.lower()]
    assert not noisy, "\n".join(noisy[:20])
