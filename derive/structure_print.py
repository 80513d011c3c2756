"""The structure report written out: text (headings ending in ``:``, ``  label = rhs`` lines in
SymPy syntax), a complete LaTeX document and Markdown with ``$$`` blocks, in the look of the
closed-form report (``report_format``)."""

from __future__ import annotations

import textwrap

import sympy as sp

from . import report_format as fmt
from .report_parts import Rich
from .structure_doc import Code, Eq, Strong, Structure


def num(c) -> str:
    c = sp.sympify(c)
    if isinstance(c, sp.Float):
        return f"{float(c):.10g}"
    return sp.sstr(c)


def _split(t: sp.Expr) -> tuple[str, sp.Expr, sp.Expr]:
    coef, rest = t.as_coeff_Mul()
    if coef < 0:
        return "-", -coef, rest
    return "+", coef, rest


def text_pieces(eq: Eq) -> list[tuple[str, str]]:
    if not eq.rhs:
        return [("+", "0")]
    out = []
    for t in eq.rhs:
        sign, coef, rest = _split(t)
        if rest == 1:
            out.append((sign, num(coef)))
        else:
            body = sp.sstr(rest)
            out.append((sign, body if coef == 1 else f"{num(coef)}*{body}"))
    return out


def latex_pieces(eq: Eq, names: dict[sp.Symbol, str]) -> list[tuple[str, str]]:
    if not eq.rhs:
        return [("+", "0")]
    out = []
    for t in eq.rhs:
        sign, coef, rest = _split(t)
        if rest == 1:
            out.append((sign, num(coef)))
            continue
        body = sp.latex(rest, symbol_names=names, fold_func_brackets=True)
        if coef == 1:
            out.append((sign, body))
        elif isinstance(coef, sp.Rational) and coef.q != 1:
            out.append((sign, rf"\frac{{{coef.p}}}{{{coef.q}}} {body}"))
        else:
            out.append((sign, f"{num(coef)} {body}"))
    return out


def join_pieces(pieces: list[tuple[str, str]]) -> str:
    return fmt._lines(pieces, 10**9)[0]


def _rhs(st: Structure, eq: Eq, style: str, width: int) -> list[str]:
    if isinstance(eq.rhs, tuple):
        return [eq.rhs[0] if style == "text" else eq.rhs[1]]
    if style == "text":
        return fmt._lines(text_pieces(eq), width)
    return fmt._lines(latex_pieces(eq, st.latex_names), width, fmt.visible)


def _rich(r: Rich, style: str) -> str:
    out = []
    for part in r:
        if isinstance(part, Code):  # in text kept on one line (see _wrap)
            out.append(f"\\texttt{{{fmt.tex_escape(part)}}}" if style == "latex" else
                       f"`{part}`" if style == "markdown" else f"`{part.replace(' ', _NBSP)}`")
        elif isinstance(part, Strong) and style != "text":
            out.append(f"\\textbf{{{fmt.tex_escape(part)}}}" if style == "latex"
                       else f"**{fmt.md_escape(part)}**")
        else:
            out.append(fmt.rich((part,), style))
    return "".join(out)


_NBSP = "\x00"  # a space that text wrapping does not break at (a command stays whole)


def _wrap(s: str, indent: str = "") -> list[str]:
    lines = textwrap.wrap(s, fmt.WIDTH, initial_indent=indent, subsequent_indent=indent,
                          break_on_hyphens=False, break_long_words=False)
    return [line.replace(_NBSP, " ") for line in lines]


def text(st: Structure) -> str:
    out = [st.title, ""]
    for p in st.preamble:
        out += _wrap(_rich(p, "text"))
    out.append("")
    for part in st.parts:
        out.append(_rich(part.title, "text") + ":")
        for note in part.intro:
            out += _wrap(_rich(note, "text"), "  # ")
        for block in part.blocks:
            if block.caption is not None:
                out += _wrap(_rich(block.caption, "text"), "  # ")
            for eq in block.eqs:
                head = f"  {eq.lhs[0]} = "
                body = _rhs(st, eq, "text", fmt.WIDTH - len(head))
                out.append(head + body[0])
                out += [" " * len(head) + line for line in body[1:]]
        for note in part.notes:
            out += _wrap(_rich(note, "text"), "  # ")
        out.append("")
    out.append("Generated functions (operations per sample, route):")
    if st.functions:
        wq = max(len(q) for q, _, _ in st.functions)
        wo = max(len(str(o)) for _, o, _ in st.functions)
        out += [f"  {q:<{wq}}  {o:>{wo}}  {r}" for q, o, r in st.functions]
    out += _wrap(_FUNCTIONS_NOTE, "  # ")
    out += ["", _SYMBOLS_HEADING]
    cells = [(r["symbol"], f"{r['value']} {r['unit']}" + (f" [{r['seed']}]" if r["seed"] else ""),
              r["parameter"], r["meaning"]) for r in st.table]
    widths = [max((len(c[k]) for c in cells), default=0) for k in range(3)]
    for c in cells:
        out.append("  " + "  ".join(f"{c[k]:<{widths[k]}}" for k in range(3)) + f"  {c[3]}")
    return "\n".join(out) + "\n"


_SYMBOLS_HEADING = ("Symbols (name, value in SI [and as the description gives it], parameter, "
                    "meaning):")
_FUNCTIONS_NOTE = ("operations: arithmetic and trigonometric operations per sample of each "
                   "generated C function (inputs, outputs and constants not counted); route: "
                   "where the expression came from.")


def _aligned(st: Structure, eqs: list[Eq]) -> list[str]:
    rows = []
    lhs = max(fmt.visible(eq.lhs[1]) for eq in eqs)
    for eq in eqs:
        lines = _rhs(st, eq, "latex", max(fmt.TEX_WIDTH - lhs, 30))
        rows.append(f"{eq.lhs[1]} &= {lines[0]}")
        rows += [rf"&\quad {line}" for line in lines[1:]]
    return [row + r" \\" for row in rows[:-1]] + rows[-1:]


def _sym_latex(name: str) -> str:
    return sp.latex(sp.Symbol(name))


def latex(st: Structure) -> str:
    out = [r"\documentclass[10pt]{article}", r"\usepackage{amsmath}", r"\usepackage{longtable}",
           r"\allowdisplaybreaks", r"\begin{document}",
           rf"\section*{{{fmt.tex_escape(st.name)}: equations of motion (structure)}}",
           fmt.tex_escape(st.title), ""]
    for p in st.preamble:
        out += [_rich(p, "latex"), ""]
    for part in st.parts:
        out.append(rf"\subsection*{{{_rich(part.title, 'latex')}}}")
        for note in part.intro:
            out += [_rich(note, "latex"), ""]
        for block in part.blocks:
            if block.caption is not None:
                out += [r"\medskip\noindent " + _rich(block.caption, "latex"), ""]
            out += [r"\begin{align*}", *_aligned(st, block.eqs), r"\end{align*}"]
        for note in part.notes:
            out += [_rich(note, "latex"), ""]
    out += [r"\subsection*{Generated functions}", r"\begin{tabular}{lrl}",
            r"quantity & operations per sample & route \\ \hline"]
    out += [rf"\texttt{{{fmt.tex_escape(q)}}} & {o} & {fmt.tex_escape(r)} \\"
            for q, o, r in st.functions]
    out += [r"\end{tabular}", "", fmt.tex_escape(_FUNCTIONS_NOTE), ""]
    out += [r"\subsection*{Symbols}", r"{\small\begin{longtable}{llp{2.9cm}p{3.9cm}}",
            r"symbol & parameter & value (SI; as described) & meaning \\ \hline"]
    for r in st.table:
        value = r["value"] + " " + r["unit"] + (f"; {r['seed']}" if r["seed"] else "")
        out.append(f"${_sym_latex(r['symbol'])}$ & \\texttt{{{fmt.tex_escape(r['parameter'])}}}"
                   f" & {fmt.tex_escape(value)} & {fmt.tex_escape(r['meaning'])} \\\\")
    out += [r"\end{longtable}}", r"\end{document}"]
    return "\n".join(out) + "\n"


def markdown(st: Structure) -> str:
    out = [f"# {fmt.md_escape(st.name)}: equations of motion (structure)", "",
           fmt.md_escape(st.title), ""]
    for p in st.preamble:
        out += [_rich(p, "markdown"), ""]
    for part in st.parts:
        out += [f"## {_rich(part.title, 'markdown')}", ""]
        for note in part.intro:
            out += [_rich(note, "markdown"), ""]
        for block in part.blocks:
            if block.caption is not None:
                out += [_rich(block.caption, "markdown"), ""]
            out += ["$$", r"\begin{aligned}", *_aligned(st, block.eqs), r"\end{aligned}", "$$",
                    ""]
        for note in part.notes:
            out += [_rich(note, "markdown"), ""]
    out += ["## Generated functions", "", "| quantity | operations per sample | route |",
            "|---|--:|---|"]
    out += [f"| `{q}` | {o} | {fmt.md_escape(r)} |" for q, o, r in st.functions]
    out += ["", fmt.md_escape(_FUNCTIONS_NOTE), ""]
    out += ["## Symbols", "", "| symbol | parameter | value (SI) | as described | meaning |",
            "|---|---|---|---|---|"]
    for r in st.table:
        out.append(f"| ${_sym_latex(r['symbol'])}$ | `{r['parameter']}` | "
                   f"`{r['value']} {r['unit']}` | {'`' + r['seed'] + '`' if r['seed'] else ''}"
                   f" | {fmt.md_escape(r['meaning'])} |")
    return "\n".join(out) + "\n"
