"""The committed generated/ matches the descriptions and the derive sources.

Fast: input hashes and file checksums against the manifests. Slow: a full re-derivation
(in fresh processes with different hash seeds) byte-compared with generated/.
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys

import pytest
from conftest import BUILTIN_ROBOTS, GENERATED, ROOT

from derive.codegen import input_hash
from planar_sym.model import description

FIX = "generated/ is stale: run `make derive`"


def manifest(robot: str) -> dict:
    return json.loads((GENERATED / robot / "manifest.json").read_text())


def test_every_builtin_robot_is_generated():
    assert sorted(description.builtin_robots()) == sorted(BUILTIN_ROBOTS)
    generated = sorted(p.parent.name for p in GENERATED.glob("*/manifest.json"))
    assert generated == sorted(BUILTIN_ROBOTS), FIX


@pytest.mark.parametrize("robot", BUILTIN_ROBOTS)
def test_input_hash_is_current(robot):
    want = input_hash(description.load(robot))
    have = manifest(robot)["input_hash"]
    assert have == want, (f"{robot}: manifest input hash {have[:16]}... but the description and "
                          f"derive sources hash to {want[:16]}...: {FIX}")


@pytest.mark.parametrize("robot", BUILTIN_ROBOTS)
def test_files_match_manifest(robot):
    m = manifest(robot)
    folder = GENERATED / robot
    listed = set(m["files"])
    present = {p.name for p in folder.iterdir()} - {"manifest.json"}
    assert listed == present, (f"{robot}: files {sorted(present ^ listed)} are not both on disk "
                               f"and in the manifest: {FIX}")
    for name, digest in m["files"].items():
        actual = hashlib.sha256((folder / name).read_bytes()).hexdigest()
        assert actual == digest, f"{folder / name} does not match its manifest sha256: {FIX}"
    for name in listed - {"manifest.json"}:
        if name.endswith(".casadi"):  # Function.save's format has no comments: the manifest
            continue  # hashes it, and test_casadi_evaluator compares it with the C
        text = (folder / name).read_text()
        assert m["input_hash"] in text, f"{folder / name} names another input hash: {FIX}"


@pytest.mark.parametrize("robot", BUILTIN_ROBOTS)
def test_manifest_parameters_are_the_description(robot):
    desc = description.load(robot)
    m = manifest(robot)
    assert [(p["name"], p["value"]) for p in m["parameters"]] == \
        [(p.name, p.value) for p in desc.parameters()], FIX
    assert m["coordinates"] == list(desc.coordinates), FIX


def _derive(out, *robots, seed: str) -> None:
    env = {**os.environ, "PYTHONHASHSEED": seed}
    proc = subprocess.run([sys.executable, "-m", "derive", *robots, "--out", str(out), "--quiet"],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=600,
                          check=False)
    assert proc.returncode == 0, proc.stderr


def _tree(folder) -> dict[str, bytes]:
    """Every generated file by relative path; hidden ones (derive's lock files) are not output."""
    return {str(p.relative_to(folder)): p.read_bytes()
            for p in sorted(folder.rglob("*"))
            if p.is_file() and not any(part.startswith(".") for part in p.relative_to(folder).parts)}


@pytest.mark.slow
def test_rederivation_reproduces_generated(tmp_path):
    out = tmp_path / "all"
    _derive(out, seed="1")
    fresh = _tree(out)
    committed = {k: v for k, v in _tree(GENERATED).items()
                 if "/" in k and not k.startswith("__pycache__")}  # not __init__.py
    assert sorted(fresh) == sorted(committed), FIX
    for name in fresh:
        assert fresh[name] == committed[name], \
            f"generated/{name} differs from a re-derivation: {FIX}"


@pytest.mark.slow
def test_derivation_is_deterministic(tmp_path):
    """The same robot twice, in processes with different hash seeds: identical bytes."""
    _derive(tmp_path / "a", "serial_2dof", seed="2")
    _derive(tmp_path / "b", "serial_2dof", seed="12345")
    a, b = _tree(tmp_path / "a"), _tree(tmp_path / "b")
    # 7 files, and 14 functions saved for CasADi (the regressor, ik_terms and the two fused
    # tracking functions too)
    assert a.keys() == b.keys() and len(a) == 21
    for name in a:
        assert a[name] == b[name], f"{name} differs between two derivations"
