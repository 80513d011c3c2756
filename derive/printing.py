"""Closed-form equations for teaching: the report of one robot as text, LaTeX and Markdown.

``derive/report.py`` decides what the report says (compact notation ``s1, c12``, terms collected
by physical parameter, lumped parameters, Christoffel C, loop closure, symbol table, checked
properties); ``derive/report_format.py`` prints it. ``codegen.render`` writes the three forms to
``generated/<robot>/equations.txt``, ``.tex`` and ``.md`` under the generated-file header.
"""

from __future__ import annotations

from . import report, report_format
from .model import Model


def render(model: Model) -> dict[str, str]:
    """{'text': ..., 'latex': ..., 'markdown': ...} for one robot."""
    rep = report.build(model)
    return {"text": report_format.text(rep), "latex": report_format.latex(rep),
            "markdown": report_format.markdown(rep)}
