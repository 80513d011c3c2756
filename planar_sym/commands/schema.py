"""``planar-sym schema [--out FOLDER] [--check]``: the JSON Schemas of the robot description and
study formats, for editors (checking and completing a TOML file as it is typed).

They are generated from the validators' own tables (``planar_sym.study.schema``) into FOLDER,
or, without ``--out``, into the package's ``planar_sym/schemas`` only where a file there is
stale (a developer's step after changing a validator): up-to-date shipped files are named, not
rewritten, so a user asking for the schemas never writes into an installed package. ``--check``
writes nothing: exit code 1 when a file there is missing or differs from what would be written.
"""

from __future__ import annotations

import sys
from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("schema", help="write the JSON Schemas of the description and study "
                                      "formats, for editors")
    p.add_argument("--out", type=Path, default=None, metavar="FOLDER",
                   help="folder to write description.schema.json and study.schema.json to "
                        "(default: name the package's planar_sym/schemas, rewritten only if "
                        "stale)")
    p.add_argument("--check", action="store_true",
                   help="write nothing; exit 1 if the files in the folder are missing or stale")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..study.schema import FOLDER, stale, write

    folder = args.out if args.out is not None else FOLDER
    if args.check:
        old = stale(folder)
        for path in old:
            print(f"stale: {path} (run `planar-sym schema"
                  f"{'' if args.out is None else f' --out {folder}'}`)", file=sys.stderr)
        return 1 if old else 0
    if args.out is None and not stale(folder):
        if not args.quiet:
            for path in sorted(folder.glob("*.schema.json")):
                print(f"up to date: {path} (point your editor here, or --out FOLDER for a copy)")
        return 0
    for path in write(folder):
        if not args.quiet:
            print(f"wrote {path}")
    return 0
