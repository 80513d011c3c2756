"""``python -m derive [ROBOT ...] [--out DIR]``: derive, generate C, write generated/<robot>/.

All robots are derived in memory first; only then is each folder swapped in atomically, so a
failure or an interrupt leaves the committed files as they were.
"""

from __future__ import annotations

import argparse
import ctypes
import json
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

from filelock import FileLock

from planar_sym.errors import DescriptionError
from planar_sym.model.description import builtin_robots, load
from planar_sym.progress import Progress

from . import codegen


def _exchange(a: Path, b: Path) -> bool:
    """Swap two paths in one atomic step (Linux renameat2 RENAME_EXCHANGE); False if the
    system cannot."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    at_fdcwd, rename_exchange = -100, 2
    return renameat2(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0


def write_atomically(files: dict[str, bytes], target: Path) -> None:
    """Replace folder ``target`` by exactly ``files``: written beside it, then swapped in.

    The swap is one atomic exchange where the system has one, so an interrupt leaves the old
    folder or the new one, never neither; a lock keeps concurrent derives from interleaving,
    and hidden leftovers of a killed run are removed under it.
    """
    target.parent.mkdir(parents=True, exist_ok=True)
    with FileLock(target.parent / f".{target.name}.lock"):
        for stale in target.parent.glob(f".{target.name}.*"):
            if stale.is_dir():
                shutil.rmtree(stale, ignore_errors=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
        try:
            for name, data in files.items():
                (tmp / name).write_bytes(data)
                os.chmod(tmp / name, 0o644)
            os.chmod(tmp, 0o755)
            if not target.exists():
                os.replace(tmp, target)
            elif not _exchange(tmp, target):  # fallback: two renames, a short window
                old = target.with_name(f".{target.name}.old.{os.getpid()}")
                os.replace(target, old)
                os.replace(tmp, target)
                shutil.rmtree(old)
        finally:  # after an exchange, tmp holds the old folder
            if tmp.exists():
                shutil.rmtree(tmp)


def derive_robot(robot: str | Path, equations: str = "auto", stage=None
                 ) -> tuple[str, dict[str, bytes]]:
    desc = load(robot)
    return desc.name, codegen.render(desc, equations, stage)


def is_stale(robot: str | Path, out: Path) -> bool:
    desc = load(robot)
    try:
        manifest = json.loads((out / desc.name / "manifest.json").read_text())
    except (OSError, ValueError):
        return True
    return manifest.get("input_hash") != codegen.input_hash(desc)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m derive", description=__doc__.splitlines()[0])
    ap.add_argument("robots", nargs="*", help="built-in names or TOML paths (default: all built in)")
    ap.add_argument("--out", type=Path, default=codegen.ROOT / "generated",
                    help="output folder (default: generated/)")
    ap.add_argument("--quiet", action="store_true", help="print nothing but errors")
    ap.add_argument("--if-stale", action="store_true",
                    help="only robots whose manifest's input hash differs from the inputs")
    ap.add_argument("--equations", choices=codegen.EQUATIONS, default="auto", type=str.lower,
                    help="the report: expanded closed forms where they fit (auto, see "
                         "derive/size.py), always (closed: slow past a few links), or the "
                         "structure they are computed from (structure)")
    args = ap.parse_args(argv)
    robots = args.robots or builtin_robots()
    if args.if_stale:
        robots = [r for r in robots if is_stale(r, args.out)]
        if not robots and not args.quiet:
            print("generated/ is up to date", file=sys.stderr)
    rendered = []
    # "[k/N] deriving X ..." before each robot, on a terminal only (the lines below stay as
    # they were: they report what was done, after it is done)
    progress = Progress(len(robots), quiet=args.quiet)
    try:
        for r in robots:
            progress.step(f"deriving {r}")
            t0 = time.perf_counter()
            rendered.append(derive_robot(r, args.equations,
                                         lambda what: progress.note(f"{what} ...")))
            if not args.quiet:
                print(f"derived {rendered[-1][0]} in {time.perf_counter() - t0:.2f} s",
                      file=sys.stderr)
    except DescriptionError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    for name, files in rendered:
        write_atomically(files, args.out / name)
        if not args.quiet:
            print(f"wrote {args.out / name}/ ({', '.join(sorted(files))})", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
