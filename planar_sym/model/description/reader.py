"""Finding and reading a description: a built-in robot's name or a ``.toml`` path -> TOML data,
handed to the validator with the file's hash."""

from __future__ import annotations

import hashlib
import tomllib
from pathlib import Path

from ...errors import DescriptionError
from ...spelling import did_you_mean
from .types import Description
from .validator import Validator


def robots_dir() -> Path:
    """Folder of the built-in robot descriptions (``planar_sym/robots``)."""
    return Path(__file__).resolve().parents[2] / "robots"


def builtin_robots() -> list[str]:
    """Names of the built-in robots, sorted."""
    return sorted(p.stem for p in robots_dir().glob("*.toml"))


def resolve(robot: str | Path) -> Path:
    """The description file of a built-in robot name, or ``robot`` itself when it ends in .toml.

    Raises
    ------
    DescriptionError
        ``robot`` is neither a ``.toml`` path nor a built-in name (the message lists them).
    """
    p = Path(robot)
    if p.suffix == ".toml":
        return p
    candidate = robots_dir() / f"{robot}.toml"
    if not candidate.exists():
        raise DescriptionError(
            [(f"unknown robot {robot!r}; built in: {', '.join(builtin_robots())}"
              f"{did_you_mean(robot, builtin_robots())}")]
        )
    return candidate


def load(robot: str | Path) -> Description:
    """Read and validate a description.

    Parameters
    ----------
    robot : str or Path
        A built-in robot name or a path to a ``.toml`` description.

    Returns
    -------
    Description
        In SI units and body frames; with ``pose = "joints"`` or ``assemble = true`` the loops
        are closed and ``Description.assembly`` says what moved.

    Raises
    ------
    DescriptionError
        Listing every problem of the file at once, each naming the file, the field and the value.
    """
    path = resolve(robot)
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise DescriptionError([f"{path}: cannot read ({exc.strerror})"]) from None
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise DescriptionError([f"{path}: not valid TOML: {exc}"]) from None
    return Validator(path, data, hashlib.sha256(raw).hexdigest()).run()
