"""Finding a robot by what a user types: a built-in name, a description file (derived on first
use) or a generated folder; loading it once per process."""

from __future__ import annotations

import copyreg
import json
import os
from pathlib import Path

import numpy as np

from ..errors import InputError, LibraryError
from ..spelling import did_you_mean
from .folders import cache_dir, find_generated
from .library import Library
from .robot import Robot

_CACHE: dict[tuple[Path, int, int], Library] = {}


def locate(robot: str | os.PathLike, generated: str | os.PathLike | None = None
           ) -> tuple[str, Path]:
    """(name, generated folder) of a robot: a built-in name, a description file or a folder.

    * a path ending in ``.toml`` is a robot description: derived and compiled on first use into
      the cache (needs SymPy the first time), keyed by the hash of the file and the derivation
      (``model.derived``);
    * a plain name (no path separator) is looked up in ``generated`` if given, else on
      ``PLANAR_SYM_GENERATED`` and among the built-in robots;
    * anything else (a ``Path``, or a string with a separator) is a folder holding
      ``manifest.json``, e.g. the ``DIR/<name>`` that ``planar-sym derive my_robot.toml --out
      DIR`` wrote.
    """
    if not isinstance(robot, (str, os.PathLike)):
        raise InputError(f"a robot is a built-in name, a description file or a generated folder "
                         f"(a str or Path), got {type(robot).__name__} {robot!r:.40}")
    text = os.fspath(robot)
    if text.endswith(".toml"):
        from .derived import derived_folder

        folder = derived_folder(text)
        return _manifest_name(folder), folder
    if isinstance(robot, os.PathLike) or os.sep in text or "/" in text:
        folder = Path(robot)
        if not (folder / "manifest.json").is_file():
            raise LibraryError(f"{folder} is not a generated robot folder (no manifest.json): "
                               "derive one with `planar-sym derive ROBOT.toml --out DIR`, then "
                               "load DIR/<name>, or name the description file ROBOT.toml")
        return _manifest_name(folder), folder
    if generated is not None:
        folder = Path(generated) / text
        if not (folder / "manifest.json").is_file():
            raise LibraryError(f"no generated robot {text!r} in {generated} (no "
                               f"{folder / 'manifest.json'}): run `planar-sym derive "
                               f"{text}.toml --out {generated}`")
        return text, folder
    if Path(text, "manifest.json").is_file() and not _is_known(text):
        # a folder in the working directory named like a robot: say how to load it
        raise LibraryError(f"no robot {text!r} among the built-in ones or on "
                           f"PLANAR_SYM_GENERATED; to load the folder ./{text}, pass a path: "
                           f"load('./{text}')")
    from .description import builtin_robots

    if not _is_known(text) and text not in builtin_robots():  # else: a stale checkout, below
        raise LibraryError(f"unknown robot {text!r}: not a built-in robot "
                           f"({', '.join(builtin_robots())}), nor a description file (.toml) "
                           f"or a generated folder (a path){did_you_mean(text, builtin_robots())}")
    return text, find_generated(text)


def _manifest_name(folder: Path) -> str:
    try:  # the name is the manifest's; Library re-reads and checks every file
        return str(json.loads((folder / "manifest.json").read_text())["robot"])
    except (OSError, ValueError, KeyError, TypeError):
        return folder.name


def _is_known(name: str) -> bool:
    try:
        find_generated(name)
    except LibraryError:
        return False
    return True


def load(robot: str | os.PathLike, generated: str | os.PathLike | None = None) -> Robot:
    """A robot, compiled on first use (cached by input hash, loaded once per process).

    ``load("serial_2dof")``: built in (or on ``PLANAR_SYM_GENERATED``).
    ``load("my_robot.toml")``: a description file, derived and compiled on first use (cached).
    ``load("out/four_bar")`` or ``load(Path("out") / "four_bar")``: a folder written by
    ``planar-sym derive four_bar.toml --out out``; ``load("four_bar", generated="out")`` is the
    same.
    """
    name, folder = locate(robot, generated)
    # keyed by the manifest file too: re-deriving into the same folder (a new manifest, swapped
    # in by rename) in the same process loads the new code, not the first one
    stat = (folder / "manifest.json").stat()
    key = (folder.resolve(), stat.st_ino, stat.st_mtime_ns)
    if key not in _CACHE:
        _CACHE[key] = Library(name, folder)
    return Robot(name, _CACHE[key])


def _reduce(robot: Robot):
    """A Robot pickles by reference (what a worker process or a cluster node needs to load the
    same robot): a built-in robot's name, or a user robot's generated folder with its
    description text (a node without the folder derives it again); the parameters and the
    ``exact`` flag travel as values. Each process compiles once into its own cache and loads
    once (``load``)."""
    ref = (robot.name, None, None) if robot.is_builtin else (
        robot.name, str(robot.library.folder.resolve()), _text_or_none(robot.description_file))
    return (_restore, (ref, robot.library.manifest["input_hash"], robot.p.copy(), robot.exact))


copyreg.pickle(Robot, _reduce)  # here, not in robot.py: loading by reference needs this module


def _text_or_none(path: Path | None) -> str | None:
    try:
        return path.read_text() if path is not None else None
    except OSError:
        return None


def _restore(ref: tuple[str, str | None, str | None], input_hash: str, p: np.ndarray,
             exact: bool) -> Robot:
    """A pickled Robot in this process: the same generated code (checked by its input hash),
    loaded once per process (``locate.load``), with the pickled parameters."""
    name, folder, description = ref
    if folder is None:
        robot = load(name)
    elif (Path(folder) / "manifest.json").is_file():
        robot = load(Path(folder))
    elif description is not None:  # another machine: derive it there from the same text
        path = cache_dir() / "descriptions" / f"{name}-{input_hash[:16]}.toml"
        path.parent.mkdir(parents=True, exist_ok=True)
        if not path.is_file():
            from ..files import atomic_files

            with atomic_files([path]) as (tmp,):
                tmp.write_text(description)
        robot = load(path)
    else:
        raise LibraryError(f"cannot load robot {name} here: its generated folder {folder} is "
                           "not on this machine and it has no description to derive it from")
    if robot.library.manifest["input_hash"] != input_hash:
        raise LibraryError(f"robot {name} here ({robot.library.folder}) was derived from other "
                           f"inputs (hash {robot.library.manifest['input_hash'][:16]}...) than "
                           f"the pickled one ({input_hash[:16]}...): derive the same description")
    if exact != robot.exact:
        robot = Robot(robot.name, robot.library, exact=exact)
    return robot.with_values(robot.parameters.with_vector(p, warn=False))  # judged before
