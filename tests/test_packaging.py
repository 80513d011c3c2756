"""A wheel holds every runtime package: pyproject's explicit list names each folder of
planar_sym that has Python modules (the control layer was once missing from it, which an
editable install hides)."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def test_every_runtime_package_is_listed():
    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
                 ["packages"])
    folders = {".".join(d.relative_to(ROOT).parts) for d in (ROOT / "planar_sym").rglob("*")
               if d.is_dir() and any(d.glob("*.py")) and "__pycache__" not in d.parts}
    assert folders | {"planar_sym"} <= listed, sorted(folders - listed)
