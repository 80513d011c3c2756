"""Exporting a robot to other engines' files: MJCF (MuJoCo, every robot) and URDF (trees).

>>> from planar_sym.outputs.export import to_mjcf, to_urdf, write
>>> text = to_mjcf(planar_sym.load("five_bar_type1"))       # str, the whole file
>>> write(planar_sym.load("serial_rpr"), "serial_rpr.urdf")  # format from the suffix

The files hold the robot's current parameters (``Robot.parameters``, SI, full precision) and a
header comment naming planar-sym, the robot, its description and the generated code's input
hash. Construction and conventions: ``export_mjcf`` and ``export_urdf``.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError
from ..files import atomic_files
from .export_mjcf import to_mjcf
from .export_urdf import to_urdf

#: format -> (writer, default suffix, suffixes that imply the format)
FORMATS = {"mjcf": (to_mjcf, ".xml", (".xml", ".mjcf")), "urdf": (to_urdf, ".urdf", (".urdf",))}

__all__ = ["FORMATS", "check_out", "format_of", "text", "to_mjcf", "to_urdf", "write"]


def format_of(fmt: str | None, path: Path | None) -> str:
    """The export format: ``fmt`` if given, else the one ``path``'s suffix implies, else mjcf.

    Raises InputError for an unknown ``fmt``, or a ``path`` whose suffix says another format.
    """
    suffix = Path(path).suffix.lower() if path is not None else ""
    implied = next((name for name, (_, _, s) in FORMATS.items() if suffix in s), None)
    if fmt is not None:
        given = fmt.lower()  # "URDF" as a student types it
        if given not in FORMATS:
            raise InputError(f"--format must be {' or '.join(FORMATS)} (got {fmt!r})")
        if implied is not None and implied != given:  # else an .urdf file holding MJCF
            article = "an" if implied == "mjcf" else "a"
            raise InputError(f"--format {given} but --out {path} names {article} "
                             f"{implied.upper()} file: give --format {implied}, or name the "
                             f"file {FORMATS[given][1]}")
        return given
    if path is None:
        return "mjcf"
    if implied is not None:
        return implied
    raise InputError(f"--out {path}: cannot tell the format from the suffix "
                     f"{suffix or '(none)'!r}; give --format {' or '.join(FORMATS)} (or name "
                     "the file .xml or .urdf)")


def check_out(path: Path, name: str = "ROBOT") -> None:
    """InputError unless ``path`` can be a file to write: not a folder, its folder existing."""
    if path.is_dir():
        raise InputError(f"--out {path} is a folder; give a file name, such as "
                         f"{path / (name + '.xml')}")
    if not path.parent.is_dir():
        what = "is a file, not a folder" if path.parent.exists() else "does not exist"
        raise InputError(f"--out {path}: its folder {path.parent} {what}; create it first")


def text(robot, fmt: str = "mjcf", ideal: bool = False) -> str:
    """The file's text: ``to_mjcf(robot, ideal)`` or ``to_urdf(robot, ideal)`` (``fmt``)."""
    fmt = format_of(fmt, None)
    return FORMATS[fmt][0](robot, ideal=ideal)


def write(robot, path: str | Path | None = None, fmt: str | None = None,
          ideal: bool = False) -> Path:
    """Write ``robot`` as MJCF or URDF to ``path``, whole or not at all.

    Parameters
    ----------
    robot : planar_sym.Robot
    path : str or Path, optional
        The file; default ``ROBOT.xml`` (MJCF) or ``ROBOT.urdf`` in the working folder. Its
        folder must exist; it must not be a folder.
    fmt : {"mjcf", "urdf"}, optional
        Default: from the suffix (.xml, .mjcf: MJCF; .urdf: URDF), else MJCF.
    ideal : bool
        The ideal machine (no rotors, friction, gears or limits); default the robot's drive
        train where the format has a place for it (``export_mjcf``, ``export_urdf``).

    Returns
    -------
    Path
        The file written.
    """
    if path is not None:
        check_out(Path(path), robot.name)
    fmt = format_of(fmt, None if path is None else Path(path))
    path = Path(path) if path is not None else Path(f"{robot.name}{FORMATS[fmt][1]}")
    content = text(robot, fmt, ideal)
    with atomic_files([path]) as (tmp,):
        tmp.write_text(content)
    return path
