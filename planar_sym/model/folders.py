"""Where a robot's generated code and its compiled libraries live, and its manifest read with
every generated file checked against the hash it lists.

Generated folders are looked for in ``$PLANAR_SYM_GENERATED`` (paths, first match wins), then
the package's own ``generated/`` (inside the installed package, or the checkout's). Compiled
libraries go to ``$PLANAR_SYM_CACHE``, else the user cache folder of ``platformdirs``
(``~/.cache/planar_sym`` on Linux).
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

from ..errors import LibraryError

_DIR = Path(__file__).resolve().parent  # planar_sym/model: _fastcall.c
_PKG = _DIR.parent  # planar_sym: generated/ ships inside it


def builtin_generated_dirs() -> list[Path]:
    """The built-in robots' generated folders: inside the installed package, or the checkout's."""
    return [(_PKG / "generated").resolve(), (_PKG.parent / "generated").resolve()]


def generated_dirs() -> list[Path]:
    """Where generated robots are looked for, first match wins."""
    dirs = [Path(d) for d in os.environ.get("PLANAR_SYM_GENERATED", "").split(os.pathsep) if d]
    return dirs + builtin_generated_dirs()


def find_generated(robot: str) -> Path:
    for d in generated_dirs():
        if (d / robot / "manifest.json").is_file():
            return d / robot
    raise LibraryError(
        f"no generated code for robot {robot!r} (looked in "
        f"{', '.join(str(d) for d in generated_dirs())}): run `make derive`")


def cache_dir() -> Path:
    """Where compiled libraries are kept: ``$PLANAR_SYM_CACHE``, else the user cache folder."""
    if os.environ.get("PLANAR_SYM_CACHE"):
        return Path(os.environ["PLANAR_SYM_CACHE"])
    from platformdirs import user_cache_dir

    return Path(user_cache_dir("planar_sym", appauthor=False))


def read_manifest(folder: Path) -> dict:
    """The manifest, after checking every generated file against the hashes it lists."""
    try:
        manifest = json.loads((folder / "manifest.json").read_text())
    except (OSError, ValueError) as exc:
        raise LibraryError(f"{folder / 'manifest.json'} is unreadable ({exc}): "
                           "run `make derive`") from None
    for name, digest in manifest.get("files", {}).items():
        path = folder / name
        if not path.is_file():
            raise LibraryError(f"{path} is missing: run `make derive`")
        if hashlib.sha256(path.read_bytes()).hexdigest() != digest:
            raise LibraryError(f"{path} does not match {folder / 'manifest.json'} (edited by "
                               "hand or half-written): run `make derive`")
    return manifest
