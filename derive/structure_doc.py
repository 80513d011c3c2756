"""The structure report's document: equations in blocks under captions, parts under titles,
one ``Structure`` per robot; ``structure_print`` writes it as text, LaTeX and Markdown."""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from .report_parts import Rich


class Code(str):
    """A command in running text: backticks in text and Markdown, ``\\texttt`` in LaTeX."""


class Strong(str):
    """A word to find the block by: plain in text, bold in LaTeX and Markdown."""


@dataclass
class Eq:
    lhs: tuple[str, str]  # (text, latex)
    rhs: list[sp.Expr] | tuple[str, str]  # SymPy terms in print order, or fixed math


@dataclass
class Block:
    """Equations under an optional caption (a comment line in text, a paragraph elsewhere)."""

    caption: Rich | None
    eqs: list[Eq]


@dataclass
class Part:
    title: Rich
    intro: list[Rich] = field(default_factory=list)
    blocks: list[Block] = field(default_factory=list)
    notes: list[Rich] = field(default_factory=list)


@dataclass
class Structure:
    name: str
    title: str
    preamble: list[Rich]
    parts: list[Part]
    functions: list[tuple[str, int, str]]  # (quantity, operations per sample, route)
    table: list[dict[str, str]]  # symbol table rows, as report._table gives them
    latex_names: dict[sp.Symbol, str]  # the coordinates' and intermediate terms' LaTeX
