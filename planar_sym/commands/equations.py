"""``planar-sym equations``: a robot's equation report, as derived (no SymPy needed)."""

from __future__ import annotations

import sys


def register(sub) -> None:
    p = sub.add_parser("equations", help="print a robot's equations of motion (text, LaTeX, "
                       "Markdown)")
    p.add_argument("robot")
    p.add_argument("--format", choices=("text", "latex", "markdown"), default="text",
                   help="text for the terminal (default), a LaTeX document, or GitHub Markdown")
    p.add_argument("--latex", dest="format", action="store_const", const="latex",
                   help="same as --format latex")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..outputs.equations import equations

    sys.stdout.write(equations(args.robot).format(args.format))
    return 0
