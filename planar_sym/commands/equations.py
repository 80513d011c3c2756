"""``planar-sym equations``: a robot's equation report, as derived (no SymPy needed)."""

from __future__ import annotations

import sys


def register(sub) -> None:
    p = sub.add_parser("equations", help="print a robot's equations of motion (text, LaTeX, "
                       "Markdown)")
    p.add_argument("robot", help="built-in robot name, a description file (.toml) or a "
                                 "generated folder")
    fmt = p.add_mutually_exclusive_group()
    fmt.add_argument("--format", choices=("text", "latex", "markdown"), default=None,
                     help="text for the terminal (default), a LaTeX document, or GitHub Markdown")
    fmt.add_argument("--latex", dest="format", action="store_const", const="latex",
                     help="same as --format latex")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..outputs.equations import equations

    sys.stdout.write(equations(args.robot).format(args.format or "text"))
    return 0
