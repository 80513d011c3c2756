"""A description file used directly as a robot: derived (SymPy) and compiled on first use, into a
folder of the cache keyed by the hash of everything the derivation reads.

The key covers the description's bytes and the sources of the derivation (``derive/`` and the
description stage), so an edited description or a new planar-sym derives again, and an
unchanged one is loaded from the cache without SymPy. Writing is atomic and locked (the same
``write_atomically`` as ``make derive``), so concurrent first uses derive once or harmlessly
twice, and never leave a half-written folder.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from ..errors import DescriptionError, LibraryError
from .folders import cache_dir

_PKG = Path(__file__).resolve().parent.parent

#: the copy of the description written next to the generated files
DESCRIPTION_COPY = "description.toml"


def _derive_sources() -> list[Path]:
    """Every source whose change can change a derivation, in a fixed order."""
    here = Path(__file__).resolve().parent
    roots = [p for p in (_PKG / "_derive", _PKG.parent / "derive") if p.is_dir()]
    files = sorted(p for root in roots for p in root.glob("*.py"))
    files += sorted(here.glob("description*.py")) + sorted(here.glob("description/*.py"))
    return files + [here / "units.py", _PKG / "expressions.py"]


def derivation_key(description: Path) -> str:
    """sha256 over the description file and the derivation's sources."""
    h = hashlib.sha256()
    for label, path in [("description", description), *(("source", p) for p in _derive_sources())]:
        data = path.read_bytes()
        h.update(f"{label}\0{path.name}\0{len(data)}\0".encode())
        h.update(data)
    return h.hexdigest()


def derived_folder(description: str | Path) -> Path:
    """The generated folder of a description file, derived and written on first use.

    Parameters
    ----------
    description : str or Path
        A robot description (``.toml``).

    Returns
    -------
    Path
        ``<cache>/derived/<name>-<key>/`` holding the generated C, manifest, equations and a
        copy of the description; load it with ``planar_sym.load``.
    """
    from .description import load as load_description

    path = Path(description)
    if not path.is_file():
        raise DescriptionError([f"{path}: no such description file"])
    desc = load_description(path)  # every problem of the file, before any SymPy
    folder = cache_dir() / "derived" / f"{desc.name}-{derivation_key(path)[:16]}"
    if (folder / "manifest.json").is_file():
        return folder
    from ..progress import announce
    from .deriving import derive_modules

    # seconds to a minute (6.6 s at 20 links, 42 s at 40): said, on a terminal (a trial
    # waited through ps.load with no word)
    announce(f"{desc.name}: deriving its equations from {path.name} (SymPy), once: kept in "
             "the cache")
    derive_main = derive_modules()
    name, files = derive_main.derive_robot(path)
    if name != desc.name:  # the file changed between the two reads
        raise LibraryError(f"{path} changed while it was being derived: run again")
    derive_main.write_atomically({**files, DESCRIPTION_COPY: path.read_bytes()}, folder)
    return folder
