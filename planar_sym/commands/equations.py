"""``planar-sym equations``: a robot's closed-form equations, as derived (no SymPy needed)."""

from __future__ import annotations

import sys


def register(sub) -> None:
    p = sub.add_parser("equations", help="print a robot's closed-form equations of motion")
    p.add_argument("robot")
    p.add_argument("--latex", action="store_true", help="LaTeX instead of text")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..library import find_generated

    folder = find_generated(args.robot)
    name = "equations.tex" if args.latex else "equations.txt"
    text = (folder / name).read_text()
    body = text.split("\n\n", 1)[1] if text.startswith(("#", "%")) else text
    sys.stdout.write(body)
    return 0
