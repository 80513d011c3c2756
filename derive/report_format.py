"""The equation report printed three ways: terminal text, a LaTeX document, GitHub Markdown.

Text: a heading per section (ending in ``:``, sections separated by blank lines), then one
``  label = rhs`` per equation (wrapped at term boundaries, continuation lines indented further)
in SymPy syntax, so ``sympify`` reads a right-hand side back with the notation symbols;
commentary as ``  # `` lines. LaTeX is a
complete document (amsmath ``align*``, ``longtable``). Markdown uses ``$$ ... $$`` blocks with
``aligned`` inside, which GitHub and Jupyter both render; long sums are broken over lines.
"""

from __future__ import annotations

import re
import textwrap

from .report_parts import Eq, Report, Rich

WIDTH = 100  # text columns
TEX_WIDTH = 66  # rendered characters per displayed line of LaTeX (see visible), lhs included

_MD = {c: "\\" + c for c in "\\`*_[]<>|$#"}
_TEX = {"\\": r"\textbackslash{}", "_": r"\_", "%": r"\%", "&": r"\&", "#": r"\#", "$": r"\$",
        "{": r"\{", "}": r"\}", "^": r"\^{}", "~": r"\~{}"}


def md_escape(s: str) -> str:
    return "".join(_MD.get(c, c) for c in s)


def tex_escape(s: str) -> str:
    """Plain text for LaTeX; a unit's power (rad/s^2) set as one, not a stray caret."""
    parts = re.split(r"\^(-?[0-9]+)", s)
    return "".join(f"$^{{{p}}}$" if k % 2 else "".join(_TEX.get(c, c) for c in p)
                   for k, p in enumerate(parts))


def visible(latex: str) -> int:
    """Rough rendered width of LaTeX math in characters: \\dot{q}_{1} counts 2, \\alpha 1,
    \\frac{1}{2} 2, a binary + or - with its spacing 3."""
    plain = re.sub(r"\\(dot|ddot|frac|tfrac|left|right|mathrm|text)\b", "", latex)
    plain = re.sub(r" [-+=] ", "ooo", plain)
    return len(re.sub(r"[{}^_ ]", "", re.sub(r"\\[a-zA-Z]+", "x", plain)))


def rich(r: Rich, style: str) -> str:
    out = []
    for part in r:
        if isinstance(part, str):
            out.append(part if style == "text" else
                       md_escape(part) if style == "markdown" else tex_escape(part))
        else:
            out.append(part[0] if style == "text" else f"${part[1]}$")
    return "".join(out)


def _rhs(rep: Report, eq: Eq, style: str, width: int) -> list[str]:
    """The right-hand side in lines of about ``width``, broken only between terms."""
    if isinstance(eq.rhs, tuple):
        return [eq.rhs[0] if style == "text" else eq.rhs[1]]
    measure = len if style == "text" else visible
    return _lines(rep.nt.pieces(eq.rhs, style, width, measure), width, measure)


def _lines(pieces: list[tuple[str, str]], width: int, measure=len) -> list[str]:
    lines, cur = [], ""
    for i, (sign, body) in enumerate(pieces):
        term = (f"-{body}" if sign == "-" else body) if i == 0 else f"{sign} {body}"
        if cur and measure(cur) + measure(term) + 1 > width:
            lines.append(cur)
            cur = term
        else:
            cur = f"{cur} {term}" if cur else term
    return lines + [cur]


def text(rep: Report) -> str:
    out = [rep.title, ""]
    for p in rep.preamble:
        out += textwrap.wrap(rich(p, "text"), WIDTH, break_on_hyphens=False)
    out.append("")
    for sec in rep.sections:
        out.append(rich(sec.title, "text") + ":")
        for note in sec.intro:
            out += _comment(rich(note, "text"))
        for eq in sec.eqs:
            head = f"  {eq.lhs[0]} = "
            body = _rhs(rep, eq, "text", WIDTH - len(head))
            out.append(head + body[0])
            out += [" " * len(head) + line for line in body[1:]]
        for note in sec.notes:
            out += _comment(rich(note, "text"))
        out.append("")
    out.append("Symbols (name, value in SI [and as the description gives it], parameter, "
               "meaning):")
    cells = [(r["symbol"], f"{r['value']} {r['unit']}" + (f" [{r['seed']}]" if r["seed"] else ""),
              r["parameter"], r["meaning"]) for r in rep.table]
    widths = [max(len(c[k]) for c in cells) for k in range(3)]
    for c in cells:
        out.append("  " + "  ".join(f"{c[k]:<{widths[k]}}" for k in range(3)) + f"  {c[3]}")
    out += ["", "Properties (checked at derive time):"]
    for p in rep.properties:
        out += textwrap.wrap(rich(p, "text"), WIDTH, initial_indent="  - ",
                             subsequent_indent="    ", break_on_hyphens=False)
    return "\n".join(out) + "\n"


def _comment(note: str) -> list[str]:
    """Commentary under a heading, as ``  # `` lines: equations stay the only ``label = ...``."""
    return textwrap.wrap(note, WIDTH, initial_indent="  # ", subsequent_indent="  # ",
                         break_on_hyphens=False)


def _aligned(rep: Report, eqs: list[Eq]) -> list[str]:
    rows = []
    lhs = max(visible(eq.lhs[1]) for eq in eqs)  # aligned: every line starts after the lhs
    for eq in eqs:
        lines = _rhs(rep, eq, "latex", max(TEX_WIDTH - lhs, 30))
        rows.append(f"{eq.lhs[1]} &= {lines[0]}")
        rows += [rf"&\quad {line}" for line in lines[1:]]
    return [row + r" \\" for row in rows[:-1]] + rows[-1:]


def latex(rep: Report) -> str:
    out = [r"\documentclass[10pt]{article}", r"\usepackage{amsmath}", r"\usepackage{longtable}",
           r"\allowdisplaybreaks", r"\begin{document}",
           rf"\section*{{{tex_escape(rep.name)}: equations of motion}}",
           tex_escape(rep.title), ""]
    for p in rep.preamble:
        out += [rich(p, "latex"), ""]
    for sec in rep.sections:
        out.append(rf"\subsection*{{{rich(sec.title, 'latex')}}}")
        for note in sec.intro:
            out += [rich(note, "latex"), ""]
        if sec.eqs:
            out += [r"\begin{align*}", *_aligned(rep, sec.eqs), r"\end{align*}"]
        for note in sec.notes:
            out += [rich(note, "latex"), ""]
    out += [r"\subsection*{Symbols}", r"{\small\begin{longtable}{llp{2.9cm}p{3.9cm}}",
            r"symbol & parameter & value (SI; as described) & meaning \\ \hline"]
    for r in rep.table:
        value = r["value"] + " " + r["unit"] + (f"; {r['seed']}" if r["seed"] else "")
        out.append(f"${_sym_latex(rep, r['symbol'])}$ & \\texttt{{{tex_escape(r['parameter'])}}}"
                   f" & {tex_escape(value)} & {tex_escape(r['meaning'])} \\\\")
    out += [r"\end{longtable}}", r"\subsection*{Properties checked at derive time}",
            r"\begin{itemize}"]
    out += [rf"\item {rich(p, 'latex')}" for p in rep.properties]
    out += [r"\end{itemize}", r"\end{document}"]
    return "\n".join(out) + "\n"


def markdown(rep: Report) -> str:
    out = [f"# {md_escape(rep.name)}: equations of motion", "", md_escape(rep.title), ""]
    for p in rep.preamble:
        out += [rich(p, "markdown"), ""]
    for sec in rep.sections:
        out += [f"## {rich(sec.title, 'markdown')}", ""]
        for note in sec.intro:
            out += [rich(note, "markdown"), ""]
        if sec.eqs:
            out += ["$$", r"\begin{aligned}", *_aligned(rep, sec.eqs), r"\end{aligned}", "$$", ""]
        for note in sec.notes:
            out += [rich(note, "markdown"), ""]
    out += ["## Symbols", "", "| symbol | parameter | value (SI) | as described | meaning |",
            "|---|---|---|---|---|"]
    for r in rep.table:
        out.append(f"| ${_sym_latex(rep, r['symbol'])}$ | `{r['parameter']}` | "
                   f"`{r['value']} {r['unit']}` | {'`' + r['seed'] + '`' if r['seed'] else ''}"
                   f" | {md_escape(r['meaning'])} |")
    out += ["", "## Properties checked at derive time", ""]
    out += [f"- {rich(p, 'markdown')}" for p in rep.properties]
    return "\n".join(out) + "\n"


def _sym_latex(rep: Report, name: str) -> str:
    for sym, info in rep.nt.info.items():
        if sym.name == name and info.rank <= 4:
            return info.latex
    return tex_escape(name)
