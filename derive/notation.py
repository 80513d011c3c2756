"""Textbook notation for the printed equations, and a small term tree that prints it.

``Notation`` turns a derived expression into teaching form: parameters get their display names
(the robot's ``[symbols]`` table), ``sin(q1 + q2)`` becomes ``s12`` (LaTeX ``s_{12}``) and so
on. ``grouped`` then arranges the terms for reading: grouped by one kind of factor after
another (masses, trigonometric factors, rates...), rational contents and common factors pulled
in front, factors in a fixed order. SymPy's own printer reorders sums, so the tree is printed
here, in text (SymPy-parsable with the notation symbols) and in LaTeX.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import sympy as sp

from planar_sym.errors import DescriptionError

#: factor order inside a product (and term order inside a sum): inertias, masses, lumped
#: parameters, g, lengths, then trigonometric factors, rates, accelerations, forces
RANK = {"inertia": 0, "mass": 1, "lumped": 2, "gravity": 3, "length": 4, "other": 5, "trig": 6,
        "rate": 7, "accel": 8, "force": 9}


#: names the report itself uses; a display name must not be one of them
def latex_name(sym: sp.Symbol) -> str:
    """A parameter's LaTeX: a base of several letters set as one word, \\mathit{lc}_{12}, not
    lc_{12}, which reads as l times c_{12}, a cosine of the same page (a lecturer's trial: 41
    such products on the 3-RRR's page); Greek names and one-letter bases as SymPy sets them."""
    latex = sp.latex(sym)
    base = sym.name.split("_", 1)[0]
    if len(base) > 1 and base.isalpha() and latex.startswith(base):
        return rf"\mathit{{{base}}}" + latex[len(base):]
    return latex


_RESERVED = re.compile(r"^([cs][0-9_]+|q(d|dd)?[0-9]+|d(d|dd)?[0-9]+|f[0-9]+|tau[0-9]+|g[0-9]+|D[0-9]+|M[0-9]+|C[0-9]+|"
                       r"Phi[0-9]*|gamma[0-9]*|lambda[0-9]*|T|V|L|pi_[0-9]+|alpha|beta|delta|"
                       r"epsilon|zeta|eta|theta|kappa|mu|nu|xi|rho|sigma|chi|psi|omega)$")


@dataclass(frozen=True)
class Info:
    rank: int
    key: tuple
    text: str
    latex: str


@dataclass
class Prod:
    """coef * factors; a factor is a SymPy base raised to an integer power, or a ``Sum``."""

    coef: sp.Expr
    factors: list = field(default_factory=list)


@dataclass
class Sum:
    terms: list[Prod]
    exp: int = 1  # as a factor: (terms)**exp


def _index(qs) -> tuple[str, str]:
    idx = [str(i) for i in qs]
    joined = "".join(idx) if all(len(i) == 1 for i in idx) else None
    return (joined or "_".join(idx)), (joined or ",".join(idx))


class Notation:
    """Display names and compact trigonometric symbols of one model."""

    def __init__(self, model) -> None:
        s, names = model.sym, model.desc.display
        self.q = s.q
        self.info: dict[sp.Symbol, Info] = {}
        self.sub: dict[sp.Expr, sp.Expr] = {}
        self.defs: dict[sp.Symbol, tuple[str, str]] = {}  # trig symbol -> (text, latex) meaning
        taken: set[str] = set()
        for p in s.p:
            shown = sp.Symbol(names.get(p.name, p.name), **p.assumptions0)
            if _RESERVED.match(shown.name) or shown.name in taken:
                msg = (f"{model.desc.path}: symbols.{p.name}: {shown.name!r} is taken by the "
                       "report's notation or another parameter")
                raise DescriptionError([msg])
            taken.add(shown.name)
            self.sub[p] = shown
            kind = ("inertia" if p.name.startswith("izz_") else "mass" if p.name.startswith("m_")
                    else "gravity" if p.name == "g" else "length")
            self.add(shown, kind, shown.name, latex_name(shown))
        for i, (q, qd, qdd, tau) in enumerate(zip(s.q, s.qd, s.qdd, s.tau), start=1):
            c = q.name[0]  # q, or d for a prismatic joint's displacement
            self.add(q, "other", q.name, f"{c}_{{{i}}}", (f"q{i:04d}",))
            self.add(qd, "rate", qd.name, rf"\dot{{{c}}}_{{{i}}}", (i,))
            self.add(qdd, "accel", qdd.name, rf"\ddot{{{c}}}_{{{i}}}", (i,))
            self.add(tau, "force", tau.name, f"f_{{{i}}}" if c == "d" else rf"\tau_{{{i}}}", (i,))

    def add(self, sym: sp.Symbol, kind: str, text: str, latex: str, key: tuple = ()) -> None:
        self.info[sym] = Info(RANK[kind], key or (sym.name,), text, latex)

    def symbol(self, name: str, kind: str, latex: str | None = None,
               key: tuple = ()) -> sp.Symbol:
        sym = sp.Symbol(name, real=True)
        self.add(sym, kind, name, latex or sp.latex(sym), key)
        return sym

    def compact(self, e: sp.Expr) -> sp.Expr:
        """Display names, and s/c symbols for sines and cosines of sums of joint angles."""
        e = sp.expand(e).xreplace(self.sub)
        e = _exact_floats(e)
        rep = {}
        for f in sorted(e.atoms(sp.sin, sp.cos), key=sp.default_sort_key):
            parts = f.args[0].as_coefficients_dict()
            if not all(k in self.q and v == 1 for k, v in parts.items()):
                continue  # e.g. cos(q1 - q3): left as it is, still correct
            ids = sorted(self.q.index(k) + 1 for k in parts)
            text_idx, latex_idx = _index(ids)
            head = "c" if isinstance(f, sp.cos) else "s"
            sym = sp.Symbol(f"{head}{text_idx}", real=True)
            if sym not in self.info:
                self.add(sym, "trig", sym.name, f"{head}_{{{latex_idx}}}",
                         (len(ids), tuple(ids), head))
                arg = " + ".join(f"q{i}" for i in ids)
                func = "cos" if head == "c" else "sin"
                latex_arg = " + ".join(f"q_{{{i}}}" for i in ids)
                self.defs[sym] = (f"{func}({arg})", rf"\{func}({latex_arg})")
            rep[f] = sym
        return e.xreplace(rep)

    def _info(self, base: sp.Expr) -> Info:
        if base in self.info:
            return self.info[base]
        return Info(RANK["other"], (sp.sstr(base),), sp.sstr(base), sp.latex(base))

    def is_kind(self, *kinds: str):
        ranks = {RANK[k] for k in kinds}
        return lambda base: self._info(base).rank in ranks

    # -- arranging ----------------------------------------------------------------------

    def grouped(self, e: sp.Expr, *levels) -> Sum:
        """Terms of ``e`` grouped by the factors each level's predicate picks, in turn."""
        terms = [t for t in sp.Add.make_args(sp.expand(e)) if t != 0]
        if not levels:
            return Sum(sorted((self._prod(t) for t in terms), key=self._term_key))
        pick, groups = levels[0], {}
        for t in terms:
            _, powers = _split(t)
            key = sp.Mul(*[b**x for b, x in powers.items() if pick(b)])
            groups.setdefault(key, []).append(t / key)
        out: list[Prod] = []
        for key, rest in groups.items():
            if key == 1:
                out += self.grouped(sp.Add(*rest), *levels[1:]).terms
            else:
                out.append(self._group(key, sp.Add(*rest), levels[1:]))
        return Sum(sorted(out, key=self._term_key))

    def _group(self, key: sp.Expr, inner: sp.Expr, levels) -> Prod:
        # pull out whole quantities (g, a mass, a lumped parameter) but not a length, unless
        # only rates would be left: m_2*(l_c2**2 + a_1*l_c2*c2), l_3*c12*(qd1 + qd2)**2
        head = list(_split(key)[1].items())
        if self._is_rate_poly(inner):
            factored = self._factored(inner, levels)
            if factored is not None:
                return Prod(factored.coef, self._sorted(head + factored.factors))
        content, common, rest = _common_factor(inner, self.is_kind("mass", "lumped", "gravity"))
        head += list(_split(common)[1].items())
        body = self.grouped(rest, *levels)
        if len(body.terms) == 1:
            only = body.terms[0]
            return Prod(content * only.coef, self._sorted(head + only.factors))
        return Prod(content, self._sorted(head + [body]))

    def _is_rate_poly(self, e: sp.Expr) -> bool:
        return any(self._info(b).rank == RANK["rate"] for b in e.free_symbols)

    def _factored(self, e: sp.Expr, levels) -> Prod | None:
        """A sum with rates as a product, when it is one: (b_1y - b_2y)*(qd1 + qd2)**2."""
        coef, parts = sp.factor(e).as_coeff_mul()
        factors = []
        for f in parts:
            base, x = f.as_base_exp()
            if not x.is_Integer:
                return None
            rates = [self._info(b).rank == RANK["rate"] for b in base.free_symbols]
            if any(rates) and not all(rates):
                return None  # a factor mixing rates and parameters: print the sum instead
            if base.is_Add:
                factors.append(Sum(self.grouped(base, *levels).terms, int(x)))
            else:
                factors.append((base, int(x)))
        if not any(isinstance(f, Sum) and (f.exp > 1 or not self._is_rate_poly(
                sp.Add(*[sp.Mul(*[b**x for b, x in t.factors]) for t in f.terms])))
                for f in factors):
            return None  # only a squared sum or a parameter sum beats the expanded form
        return Prod(coef, factors)

    def _prod(self, t: sp.Expr) -> Prod:
        coef, powers = _split(t)
        return Prod(coef, self._sorted(list(powers.items())))

    def _factor_key(self, f) -> tuple:
        if isinstance(f, Sum):  # a bracket sits just before the factors it contains
            inner = [self._factor_key(g) for t in f.terms for g in t.factors] or [(99,)]
            r = min(inner)
            return (r[0] - 0.5, r[1:])
        info = self._info(f[0])
        return (info.rank, info.key)

    def factor_keys(self, monomial: sp.Expr) -> tuple:
        return tuple(sorted(self._factor_key(f) for f in _split(monomial)[1].items()))

    def _sorted(self, factors: list) -> list:
        return sorted(factors, key=self._factor_key)

    def _term_key(self, p: Prod):
        """Constant (parameter-only) terms first, then by trig factors, rates..., then names."""
        keys = [self._factor_key(f) for f in p.factors]
        varying = tuple(sorted(k for k in keys if k[0] >= RANK["trig"] - 0.5))
        return (varying, tuple(keys), sp.default_sort_key(p.coef))

    # -- printing -----------------------------------------------------------------------

    def text(self, node) -> str:
        return _join(self.pieces(node, "text"))

    def latex(self, node) -> str:
        return _join(self.pieces(node, "latex"))

    def pieces(self, node, style: str, width: int | None = None,
               measure=len) -> list[tuple[str, str]]:
        """[(sign, body)] of the top-level terms, for line breaking. A term longer than
        ``width`` with one bracket is opened up: ``m_2*(a_1**2``, ``+ l_c2**2)``..."""
        if not isinstance(node, Sum):
            node = self.grouped(node)
        if not node.terms:
            return [("+", "0")]
        out = []
        for p in node.terms:
            sign, body = self._prod_str(p, style)
            sums = [f for f in p.factors if isinstance(f, Sum) and f.exp == 1]
            if width is None or measure(body) <= width or len(sums) != 1:
                out.append((sign, body))
                continue
            k = p.factors.index(sums[0])
            inner = self.pieces(sums[0], style, width, measure)
            sep = "*" if style == "text" else " "
            head = self._parts(abs(p.coef) if p.coef.is_Number else p.coef, p.factors[:k], style)
            tail = self._parts(sp.S.One, p.factors[k + 1:], style)
            s0, b0 = inner[0]
            out.append((sign, (head + sep if head else "") + "(" + ("-" if s0 == "-" else "") + b0))
            out += inner[1:-1]
            out.append((inner[-1][0], inner[-1][1] + ")" + (sep + tail if tail else "")))
        return out

    def _prod_str(self, p: Prod, style: str) -> tuple[str, str]:
        coef, sign = p.coef, "+"
        if coef.could_extract_minus_sign():
            coef, sign = -coef, "-"
        return sign, self._parts(coef, p.factors, style) or "1"

    def _parts(self, coef: sp.Expr, factors: list, style: str) -> str:
        parts = []
        for f in factors:
            if isinstance(f, Sum):
                inner = f"({_join(self.pieces(f, style))})"
                parts.append(inner if f.exp == 1 else (f"{inner}**{f.exp}" if style == "text"
                                                       else f"{inner}^{{{f.exp}}}"))
                continue
            info, x = self._info(f[0]), f[1]
            name = info.text if style == "text" else info.latex
            parts.append(name if x == 1 else (f"{name}**{x}" if style == "text"
                                              else f"{name}^{{{x}}}"))
        if coef != 1:
            if style == "latex" and isinstance(coef, sp.Rational) and coef.q != 1:
                parts.insert(0, rf"\frac{{{coef.p}}}{{{coef.q}}}")
            else:
                parts.insert(0, sp.sstr(coef) if style == "text" else sp.latex(coef))
        return ("*" if style == "text" else " ").join(parts)


def _join(pieces: list[tuple[str, str]]) -> str:
    out = ""
    for i, (sign, body) in enumerate(pieces):
        out += (f"-{body}" if sign == "-" else body) if i == 0 else f" {sign} {body}"
    return out


def _split(t: sp.Expr) -> tuple[sp.Expr, dict]:
    coef, rest = t.as_coeff_Mul()
    return coef, {b: x for b, x in rest.as_powers_dict().items() if b != 1}


def _common_factor(e: sp.Expr, pick=lambda b: True) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """e = content * common * rest: rational content, the common monomial of the picked bases;
    the content is negative only when every term is."""
    terms = [_split(t) for t in sp.Add.make_args(sp.expand(e))]
    common = {b: x for b, x in terms[0][1].items() if pick(b)}
    for _, powers in terms[1:]:
        common = {b: min(x, powers[b]) for b, x in common.items()
                  if b in powers and x > 0 and powers[b] > 0}
    coefs = [c for c, _ in terms]
    if all(isinstance(c, sp.Rational) for c in coefs):
        content = sp.Rational(sp.igcd(0, *[c.p for c in coefs]),
                              sp.ilcm(1, *[c.q for c in coefs]))
    else:
        content = sp.S.One
    mono = sp.Mul(*[b**x for b, x in common.items()])
    rest = sp.expand(e / (content * mono))
    if all(c.could_extract_minus_sign() for c in coefs):  # -beta*(...), not beta*(-... - ...)
        content, rest = -content, -rest
    return content, mono, rest


def _exact_floats(e: sp.Expr) -> sp.Expr:
    """Floats that a slanted rail's direction leaves in an expression (its sine squared plus
    its cosine squared printed ``1.00000000000000*m_cart``, half of it ``0.500000000000000``)
    as the simple fraction they round, to 1e-12; any other float as it is. Re-expanded, so
    ``1.0*x + 2*x`` collects."""
    rep = {}
    for f in e.atoms(sp.Float):
        exact = sp.Rational(f).limit_denominator(1000)
        if abs(float(exact) - float(f)) <= 1e-12 * max(1.0, abs(float(f))):
            rep[f] = exact
    return sp.expand(e.xreplace(rep)) if rep else e
