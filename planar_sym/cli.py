"""``planar-sym``: the command line. Each subcommand is a module in ``planar_sym.commands``."""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys
import warnings

from . import commands
from .errors import PlanarSymError


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog="planar-sym",
        description="Dynamics of planar robots: any robot, any move, compiled.")
    ap.add_argument("--quiet", action="store_true", help="print only errors")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        importlib.import_module(f"{commands.__name__}.{info.name}").register(sub)
    for p in sub.choices.values():  # --quiet before or after the command name
        p.add_argument("--quiet", action="store_true", default=argparse.SUPPRESS,
                       help="print only errors")
    return ap


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    with warnings.catch_warnings():  # a warning is one line, like an error: no source line
        warnings.showwarning = _show_warning
        return _run(args)


def _run(args) -> int:
    try:
        return args.fn(args)
    except PlanarSymError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:  # files are written whole or not at all: nothing to clean up
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # `planar-sym list | head -1`: the reader has what it wanted
        _silence_stdout()
        return 141
    except OSError as exc:  # disk full, permissions: say which file, no traceback
        print(f"error: {exc.strerror or exc} ({exc.filename or 'file system'})", file=sys.stderr)
        return 2


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    print(f"warning: {message}", file=sys.stderr)


def _silence_stdout() -> None:
    """Point stdout at /dev/null, so that flushing it at exit raises nothing more."""
    import os

    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
    except (OSError, ValueError):  # no real file descriptor (captured output)
        pass


if __name__ == "__main__":
    sys.exit(main())
