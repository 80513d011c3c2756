"""The base parameters in closed form (identification, issue 26), for the equation report.

The torques are linear in the *standard parameters* (per body its mass m, first moments about
the frame's origin mcx = m cx, mcy = m cy and inertia about that origin izo = I + m |c|^2; per
motor its rotor inertia jm, viscous fv and Coulomb fc friction), ``tau = Y pi``. Only some
combinations, the base parameters, change any torque. Here they are found as
``planar_sym.identify.base`` finds them numerically (Gautier's method: the columns of Y, in
the same order of preference, kept when independent of those kept before), but exactly:

* Y is differentiated by SymPy from energies written in the standard parameters (not the
  CasADi route of ``regressor.py``: the report's test compares the two);
* the independence test runs on Y at exact rational states (points on the unit circle
  ``((1 - t^2)/(1 + t^2), 2t/(1 + t^2))`` for every angle) with the geometry at the
  description's values, as exact rationals;
* each dropped column's regrouping coefficients are solved with the geometry left as symbols
  on as many stacked rows as there are base parameters, then checked on all the others
  (states not used to find them): what is printed holds for any lengths.

Trees up to ``MAX_COORDINATES`` coordinates only: past that, and for closed chains (their
torques pass through the constraint Jacobian's inverse), the closed forms are too long to
teach from, and ``planar-sym identify`` gives the base parameters numerically.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import sympy as sp
from sympy.polys.matrices import DomainMatrix

from planar_sym.model.description import COULOMB_SMOOTHING, GROUND

from .kinematics import angle_rate, frames
from .lagrange import gravity_direction
from .model import Model

#: trees with more coordinates get no closed forms (too long to print)
MAX_COORDINATES = 3
#: the same preference as planar_sym.identify.base (kind per owner; bodies, then joints)
_ORDER = {"izo": 0, "mcx": 1, "mcy": 2, "m": 3, "jm": 4, "fv": 5, "fc": 6}
SEED = 20261126


@dataclass(frozen=True)
class BaseForms:
    """``standard``: name -> symbol, in the columns' order (as ``regressor.py``); ``y``: Y (n,
    columns) in SymPy; ``names``: the base parameters' names (the kept standard parameter's,
    with ``R`` where others regroup into it), ``expressions`` their closed forms in the
    standard symbols and the geometry (the model's raw parameter symbols); ``unidentifiable``:
    standard parameters with no effect on any torque."""

    standard: dict[str, sp.Symbol]
    y: sp.Matrix
    names: tuple[str, ...]
    expressions: tuple[sp.Expr, ...]
    unidentifiable: tuple[str, ...]

    def express(self, e: sp.Expr, zeros: dict) -> sp.Expr | None:
        """``e`` (linear in the standard parameters) as a combination of the base parameters
        with geometric coefficients, or None when it is not one; ``zeros``: the standard
        parameters the description holds at zero (a centre of gravity on a body axis)."""
        e = sp.expand(e.xreplace(zeros))
        base = [sp.Symbol(n, real=True) for n in self.names]
        coef = [e.coeff(self.standard[n.removesuffix("R")]) for n in self.names]
        combo = sum((c * b for c, b in zip(coef, base)), sp.S.Zero)
        back = combo.xreplace({b: x.xreplace(zeros) for b, x in zip(base, self.expressions)})
        return sp.expand(combo) if sp.expand(back - e) == 0 else None


def base_forms(model: Model) -> BaseForms | str:
    """The closed forms, or why there are none (a sentence for the report)."""
    desc, s = model.desc, model.sym
    if model.constraints.count:
        return ("a closed chain's torques pass through the inverse of its constraint "
                "Jacobian: its base parameters are found numerically (planar-sym identify, "
                "planar_sym.identify.base_parameters)")
    if len(s.q) > MAX_COORDINATES:
        return (f"more than {MAX_COORDINATES} coordinates: the closed forms are too long to "
                "print; planar-sym identify gives the base parameters numerically")
    standard, tau = _torques(model)
    cols = list(standard.values())
    y = sp.Matrix([[sp.expand(sp.expand_trig(sp.diff(t, c))) for c in cols] for t in tau])
    if y.xreplace({t: sp.Dummy() for t in y.atoms(sp.tanh)}).atoms(sp.Float):
        # a turned slide, a weld at an angle, gravity off the axes: no exact closed form
        return ("the description has angles that are not exact (a turned slide or weld): "
                "planar-sym identify gives the base parameters numerically")
    geometry = sorted(y.free_symbols - _state_symbols(model, y), key=sp.default_sort_key)
    values = {p: sp.nsimplify(par.value, rational=True) for p, par in zip(s.p, desc.parameters())
              if p in geometry}
    rng = random.Random(SEED)
    # twice the rows the columns need: half of them check the regrouping found on the others
    rows = _stacked(model, y, rng, 2 * len(cols) // len(s.q) + 3)
    names = list(standard)
    zero = [j for j in range(len(cols)) if all(r[j] == 0 for r in rows)]
    owners = list(dict.fromkeys(n.split("_", 1)[1] for n in names))
    order = sorted((j for j in range(len(cols)) if j not in zero),
                   key=lambda j: (owners.index(names[j].split("_", 1)[1]),
                                  _ORDER[names[j].split("_", 1)[0]]))
    # exact linear algebra in SymPy's domains (rationals; rational functions of the lengths)
    numeric = DomainMatrix.from_Matrix(sp.Matrix(rows).xreplace(values)).convert_to(sp.QQ)
    kept: list[int] = []
    for j in order:
        if numeric.extract(range(numeric.shape[0]), kept + [j]).rank() > len(kept):
            kept.append(j)
    kept.sort()
    dropped = [j for j in order if j not in kept]
    coefficients = {}
    if dropped:
        stacked = DomainMatrix.from_Matrix(sp.Matrix(rows)).to_field()
        every = range(stacked.shape[0])
        pick = list(numeric.extract(every, kept).transpose().rref()[1])  # independent rows
        beta = stacked.extract(pick, kept).lu_solve(stacked.extract(pick, dropped))
        # the solution holds on every stacked row (states never used to find it), so for
        # these exact generic states and symbolic lengths, not only at the drawn geometry
        if not (stacked.extract(every, kept) * beta - stacked.extract(every, dropped)).is_zero_matrix:
            return ("at these lengths some columns of Y are dependent that are not for other "
                    "lengths: planar-sym identify gives the base parameters numerically")
        solved = beta.to_Matrix()
        coefficients = {d: solved[:, c].applyfunc(sp.factor) for c, d in enumerate(dropped)}
    exprs = []
    for k, j in enumerate(kept):
        exprs.append(cols[j] + sum((coefficients[d][k] * cols[d] for d in dropped), sp.S.Zero))
    base_names = tuple(names[j] + ("R" if any(coefficients[d][k] != 0 for d in dropped) else "")
                       for k, j in enumerate(kept))
    return BaseForms(standard, y, base_names, tuple(exprs), tuple(names[j] for j in zero))


def _torques(model: Model) -> tuple[dict[str, sp.Symbol], list[sp.Expr]]:
    """The standard parameters' symbols and the Euler-Lagrange torques in them."""
    desc, s = model.desc, model.sym
    fr, rate = frames(desc, s), angle_rate(s)
    ux, uy = gravity_direction(desc)
    g = s.param("g")
    std: dict[str, sp.Symbol] = {}
    kinetic, potential, subs = sp.S.Zero, sp.S.Zero, {}
    for b in (b for b in desc.bodies if b != GROUND):
        # plain symbols: distinct from the description's own (real) parameter symbols
        m, mx, my, io = (sp.Symbol(f"{k}_{b}") for k in ("m", "mcx", "mcy", "izo"))
        std.update({f"m_{b}": m, f"mcx_{b}": mx, f"mcy_{b}": my, f"izo_{b}": io})
        cx, cy, izz = sp.Dummy("cx"), sp.Dummy("cy"), sp.Dummy("izz")
        cg = fr[b].point((cx, cy))
        kinetic += m * cg.speed_squared(rate) / 2 + izz * rate(fr[b].angle) ** 2 / 2
        pos = cg.position()
        potential += -m * g * (ux * pos[0] + uy * pos[1])
        subs.update({cx: mx / m, cy: my / m, izz: io - (mx**2 + my**2) / m})
    friction = [sp.S.Zero] * len(s.q)
    moving = [j for j in desc.tree_joints if j.moves]
    for k, j in enumerate(moving):
        if not j.actuated:
            continue
        if j.actuator is not None and "rotor_inertia" in j.actuator.given:
            jm = std.setdefault(f"jm_{j.name}", sp.Symbol(f"jm_{j.name}"))
            gear = s.by_name.get(f"gear_{j.name}", sp.S.One)
            kinetic += jm * (rate(fr[j.parent].angle) + gear * s.qd[k]) ** 2 / 2
        fv = std.setdefault(f"fv_{j.name}", sp.Symbol(f"fv_{j.name}"))
        fc = std.setdefault(f"fc_{j.name}", sp.Symbol(f"fc_{j.name}"))
        smooth = s.by_name.get(f"vs_{j.name}", sp.Float(COULOMB_SMOOTHING))
        friction[k] = fv * s.qd[k] + fc * sp.tanh(s.qd[k] / smooth)
    kinetic = sp.expand(kinetic.xreplace(subs))
    potential = sp.expand(potential.xreplace(subs))
    tau = []
    for i, (q, qd) in enumerate(zip(s.q, s.qd)):
        p = sp.diff(kinetic, qd)
        dp = sum((sp.diff(p, a) * b for a, b in zip((*s.q, *s.qd), (*s.qd, *s.qdd))), sp.S.Zero)
        tau.append(sp.expand(dp - sp.diff(kinetic, q) + sp.diff(potential, q) + friction[i]))
    return std, tau


def _state_symbols(model: Model, y: sp.Matrix) -> set:
    s = model.sym
    return set(s.q) | set(s.qd) | set(s.qdd) | {s.param("g")} - {sp.S.Zero}


def _state(model: Model, y: sp.Matrix, rng: random.Random) -> dict:
    """Exact rational values of every state symbol (and of sin, cos, tanh of them)."""
    s = model.sym

    def r() -> sp.Rational:
        return sp.Rational(rng.randint(-40, 40), rng.randint(7, 23))

    at: dict = {}
    for i, q in enumerate(s.q):
        if model.desc.coordinate_units[i] == "rad":
            t = r()
            at[sp.cos(q)] = (1 - t**2) / (1 + t**2)
            at[sp.sin(q)] = 2 * t / (1 + t**2)
        else:
            at[q] = r()
    at.update({v: r() for v in (*s.qd, *s.qdd)})
    at.update({f: r() for f in y.atoms(sp.tanh)})
    if s.param("g") != 0:
        at[s.param("g")] = r()
    return at


def _stacked(model: Model, y: sp.Matrix, rng: random.Random, samples: int) -> list[list]:
    rows = []
    for _ in range(samples):
        at = _state(model, y, rng)
        trig = {k: v for k, v in at.items() if isinstance(k, (sp.sin, sp.cos, sp.tanh))}
        rest = {k: v for k, v in at.items() if k not in trig}
        values = y.xreplace(trig).xreplace(rest).applyfunc(sp.expand)
        rows += values.tolist()
    return rows
