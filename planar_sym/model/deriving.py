"""The build-time ``derive`` package (SymPy), imported only when a robot must be derived: the
runtime never needs SymPy otherwise."""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import PlanarSymError

NEEDS_SYMPY = "deriving needs SymPy: pip install planar-sym[derive]"


def derive_modules():
    """The build-time ``derive`` package, imported only now: the runtime never needs SymPy."""
    try:
        import sympy  # noqa: F401  (checked first: derive may be imported already in-process)
    except ImportError:
        raise PlanarSymError(NEEDS_SYMPY) from None
    try:  # installed: the build-time package ships inside planar_sym, not as a top-level `derive`
        import planar_sym._derive.__main__ as derive_main
    except ModuleNotFoundError as exc:
        if exc.name not in ("planar_sym._derive", "planar_sym._derive.__main__"):
            raise PlanarSymError(f"deriving needs {exc.name!r}, which is missing ({exc})") from None
        derive_main = _from_source_checkout()
    return derive_main


def _from_source_checkout():
    # run from a checkout without an install: derive/ sits beside planar_sym/
    root = Path(__file__).resolve().parents[2]
    if not (root / "derive" / "__init__.py").is_file():
        raise PlanarSymError("deriving needs the build-time `derive` package, which is not "
                             "installed: run from a source checkout of planar-sym")
    sys.path.insert(0, str(root))
    import derive.__main__ as derive_main

    return derive_main


def symbolic_model(desc):
    """The SymPy model of a validated description (``derive.model.build``)."""
    import importlib

    package = derive_modules().__name__.rpartition(".")[0]
    return importlib.import_module(f"{package}.model").build(desc)
