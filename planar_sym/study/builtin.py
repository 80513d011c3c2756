"""The built-in studies: the seed chapter's scenarios as study files in ``planar_sym/studies``."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..spelling import did_you_mean


def studies_dir() -> Path:
    """Folder of the built-in study files."""
    return Path(__file__).resolve().parents[1] / "studies"


def names(folder: Path | None = None) -> list[str]:
    """Study names (file stems) in ``folder``, default the built-in ones, sorted."""
    return sorted(p.stem for p in (folder or studies_dir()).glob("*.toml"))


def find(name: str) -> Path:
    """The file of a built-in study; an unknown name lists the known ones."""
    path = studies_dir() / f"{name}.toml"
    if not path.is_file():
        from ..model.description import builtin_robots

        robot = (f"; {name} is a robot: `planar-sym move {name} ...` runs a move of it without "
                 "a study" if name in builtin_robots() else did_you_mean(name, names()))
        raise InputError(f"unknown study {name!r}: not a built-in study ({', '.join(names())}) "
                         f"nor a study file (.toml){robot}")
    return path
