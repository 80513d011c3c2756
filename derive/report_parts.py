"""The pieces of an equation report: equations, sections and the report, as rich text (plain
strings and (text, latex) math pairs) that ``report_format`` prints per format."""

from __future__ import annotations

from dataclasses import dataclass, field

from .notation import Notation, Sum

#: rich text: plain strings and (text, latex) math pairs, printed per format
Rich = tuple


@dataclass
class Eq:
    lhs: tuple[str, str]  # (text, latex)
    rhs: Sum | tuple[str, str]


@dataclass
class Section:
    title: Rich
    eqs: list[Eq] = field(default_factory=list)
    notes: list[Rich] = field(default_factory=list)  # paragraphs after the equations
    intro: list[Rich] = field(default_factory=list)  # paragraphs before them


@dataclass
class Report:
    name: str
    title: str
    preamble: list[Rich]
    sections: list[Section]
    table: list[dict[str, str]]  # symbol table rows
    properties: list[Rich]
    nt: Notation


def m(text: str, latex: str | None = None) -> tuple[str, str]:
    """A piece of math: its text form and its LaTeX form."""
    return (text, text if latex is None else latex)
