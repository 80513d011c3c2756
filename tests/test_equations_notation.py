"""The printed equations read as a lecturer writes them (a lecturer's trial, trial J).

* A parameter whose name's base has several letters is one italic word: ``\\mathit{lc}_{12}``.
  ``lc_{12}`` read as l times c_{12}, a cosine defined on the same page: 41 such products on
  the 3-RRR's page, 32 on the five-bar's.
* A unit's power in the LaTeX text is a superscript, not a stray caret (``rad/s\\^{}2``).
"""

from __future__ import annotations

import re

import sympy as sp
from conftest import ROOT

from derive.notation import latex_name
from derive.report_format import tex_escape


def test_multi_letter_bases_are_one_word():
    assert latex_name(sp.Symbol("lc_12")) == r"\mathit{lc}_{12}"
    assert latex_name(sp.Symbol("lcy_L1")) == r"\mathit{lcy}_{L1}"
    for name, want in (("l_3e", "l_{3e}"), ("alpha", r"\alpha"), ("I_P", "I_{P}"),
                       ("m_M2", "m_{M2}"), ("a1", "a_{1}")):
        assert latex_name(sp.Symbol(name)) == want


def test_the_committed_pages_have_no_product_looking_names():
    for robot in ("parallel_3rrr", "five_bar_type1", "five_bar_type2"):
        tex = (ROOT / "generated" / robot / "equations.tex").read_text()
        md = (ROOT / "generated" / robot / "equations.md").read_text()
        for page in (tex, md):
            assert not re.search(r"(?<![\\{a-zA-Z])lcy?_\{", page), robot
            assert r"\mathit{lc}_{" in page, robot
        assert r"rad/s\^{}2" not in tex and "rad/s$^{2}$" in tex


def test_tex_escape_sets_powers():
    assert tex_escape("accelerations (rad/s^2), m_1, 50 %") == (
        r"accelerations (rad/s$^{2}$), m\_1, 50 \%")
