"""``planar-sym``: the command line. Each subcommand is a module in ``planar_sym.commands``."""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys
import warnings

from . import __version__, commands
from .errors import InputError, PlanarSymError


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog="planar-sym",
        description="Dynamics of planar robots: any robot, any move, compiled.")
    ap.add_argument("--quiet", action="store_true", help="print only errors")
    ap.add_argument("--version", action="version", version=f"planar-sym {__version__}")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        importlib.import_module(f"{commands.__name__}.{info.name}").register(sub)
    for p in sub.choices.values():  # --quiet before or after the command name
        p.add_argument("--quiet", action="store_true", default=argparse.SUPPRESS,
                       help="print only errors")
    return ap


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    ap = parser()
    args = ap.parse_args(argv)
    from . import progress

    was, progress.QUIET = progress.QUIET, bool(getattr(args, "quiet", False))
    try:
        with warnings.catch_warnings():  # a warning is one line, like an error: no source line
            warnings.showwarning = _show_warning
            return _run(args, lambda: _checks(ap, args, argv))
    finally:
        progress.QUIET = was


def _checks(ap: argparse.ArgumentParser, args, argv: list[str]) -> None:
    """What argparse lets through: an option given twice (the last would silently win) and
    the environment's flags and unknown PLANAR_SYM_ names."""
    from .environment import check

    sub = ap._subparsers._group_actions[0].choices[args.command]
    repeated = _repeated([*ap._actions, *sub._actions], argv)
    if repeated:
        raise InputError(f"option {repeated} is given more than once: give it once (the last "
                         "would silently win)")
    check()


#: options that may be repeated: flags (twice is the same) and lists made by repeating
_REPEATABLE = (argparse._StoreTrueAction, argparse._StoreFalseAction, argparse._CountAction,
               argparse._AppendAction, argparse._HelpAction)


def _repeated(actions, argv: list[str]) -> str | None:
    """The first option of ``actions`` that ``argv`` gives twice (``--x 1 --x=2``, or an
    abbreviation argparse accepts), or None."""
    longs = {o: a for a in actions for o in a.option_strings}
    seen = {}
    for token in argv:
        if token == "--":
            break
        if not token.startswith("-") or token == "-":
            continue
        name = token.split("=", 1)[0]
        if name not in longs and name.startswith("--"):
            matches = {longs[o] for o in longs if o.startswith(name)}
            if len(matches) != 1:
                continue
            name = next(o for o in longs if o.startswith(name))
        action = longs.get(name)
        if action is None or isinstance(action, _REPEATABLE):
            continue
        if action in seen:
            return "/".join(action.option_strings)
        seen[action] = token
    return None


def _run(args, checks=None) -> int:
    try:
        if checks is not None:
            checks()
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
