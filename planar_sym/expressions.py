"""Numbers typed as expressions: wherever a robot description or a study file takes a number, a
string holding an expression of numbers is taken too (``"100*cos(30*deg)"``, ``"50*40^2/12"``,
``"L/2"``), evaluated once when the file is read.

The rules
---------

* numbers (``3``, ``0.5``, ``1e-3``), ``+ - * /``, ``**`` or its synonym ``^`` for a power (the
  same operator: ``2*3^2`` is 18, ``-2^2`` is -4, ``2^3^2`` is 2^9), unary minus and plus,
  parentheses;
* the functions ``sqrt sin cos tan asin acos atan atan2(y, x) hypot(x, y)``, angles in radians;
* ``pi``, and ``deg`` = pi/180, a plain number: ``30*deg`` is 30 degrees in radians (0.5236), so
  ``cos(30*deg)``; ``atan2(1, 2)/deg`` is an angle in degrees. An expression has no unit: its
  value is read in the file's ``[units]`` like a typed number, so with ``angle = "deg"`` an
  angle field takes ``30`` or ``atan2(1, 2)/deg``, never ``30*deg`` (that is 0.52 deg). Only a
  study's ``[parameters]`` and ``[control.plant]`` strings carry a unit, after the expression:
  ``"2*0.3 kg"`` (``quantity``);
* the names of the file's top-level ``[constants]`` table (``a = 0.5``, ``L = "2*a"``): each a
  number or an expression of numbers and other constants, in any order; a name is an identifier
  other than the built-in ones; an unknown name or a cycle is an error;
* every value is a float, and every step must be finite: ``1e308*10`` is an error, not inf.

Safety: the text is parsed by Python's ``ast`` and only the nodes above are evaluated, never by
``eval``: attribute access, indexing, strings, keyword arguments, any other name or call are
errors naming what was found. Arithmetic is in floats, so no power can run for ever (``9^9^9``
overflows at once: an error); a text is at most ``MAX_LENGTH`` characters and ``MAX_DEPTH``
operations deep, a file has at most ``MAX_CONSTANTS`` constants.

How the readers use it: each names the places where its file takes numbers in a schema
(``numbers``), and every string there is evaluated right after the file is read and its
``[constants]`` resolved, so the checks and everything after them see the floats a typed
decimal gives (a file without expressions reads exactly as before). A string that is not an
expression becomes a ``Bad``, which the field's check reports where it checks that field, so one
mistake gives one message and whatever depends on the field is skipped as for any bad value:
``<file>: <field>: "<text>": <what is wrong>``. A problem in ``[constants]`` is reported alone:
each field using the constant would only repeat it.
"""

from __future__ import annotations

import ast
import math
import operator
import re
from collections.abc import Mapping
from dataclasses import dataclass

from .errors import InputError

MAX_LENGTH = 500
MAX_DEPTH = 100
MAX_CONSTANTS = 200

#: built-in names: plain numbers
BUILT_IN = {"pi": math.pi, "deg": math.pi / 180.0}
#: name -> (function, number of arguments)
FUNCTIONS = {"sqrt": (math.sqrt, 1), "sin": (math.sin, 1), "cos": (math.cos, 1),
             "tan": (math.tan, 1), "asin": (math.asin, 1), "acos": (math.acos, 1),
             "atan": (math.atan, 1), "atan2": (math.atan2, 2), "hypot": (math.hypot, 2)}
NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")

_BINARY = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul,
           ast.Div: operator.truediv, ast.Pow: math.pow}  # math.pow: floats, raises on overflow
_UNARY = {ast.USub: operator.neg, ast.UAdd: operator.pos}
#: what was written, for an operator or node outside the rules
_SHOWN = {ast.Mod: "%", ast.FloorDiv: "//", ast.MatMult: "@", ast.LShift: "<<", ast.RShift: ">>",
          ast.BitOr: "|", ast.BitAnd: "&", ast.Not: "not", ast.Invert: "~",
          ast.Attribute: "attribute access (.)", ast.Subscript: "indexing ([])",
          ast.Compare: "a comparison", ast.BoolOp: "and/or", ast.IfExp: "if/else",
          ast.Lambda: "lambda", ast.List: "a list", ast.Tuple: "a tuple", ast.Dict: "a table",
          ast.Set: "a set", ast.JoinedStr: "a string", ast.Starred: "*", ast.NamedExpr: ":="}
#: a number (or closing bracket) and a word side by side: "30 deg", "0.5 kg"
_SIDE_BY_SIDE = re.compile(r"[\d.)]\s+[A-Za-z_(]")
#: "<expression> <unit>": the unit is the last word
_WITH_UNIT = re.compile(r"(.*\S)\s+([A-Za-z][A-Za-z0-9_*/^]*)", re.DOTALL)


class ExpressionError(InputError):
    """A string at a number's place that is no expression of numbers: ``"<text>": <reason>``."""

    def __init__(self, text: str, reason: str):
        self.text, self.reason = text, reason
        super().__init__(f"{_quoted(text)}: {reason}")


@dataclass(frozen=True)
class Bad:
    """What a number's place held when it was no expression: the field's check reports
    ``message`` at the field followed by ``index`` ("[0]" for an element of a list, "" for a
    number)."""

    index: str
    message: str

    def __repr__(self) -> str:  # a check that shows the value shows what is wrong with it
        return self.message


def evaluate(text: str, names: Mapping[str, float] | None = None) -> float:
    """The value of expression ``text``, a finite float; ``names``: the file's constants.

    Raises
    ------
    ExpressionError
        ``"<text>": <what is wrong>``.
    """
    return _value(_parse(text), text, names or {})


def quantity(text: str, names: Mapping[str, float] | None = None) -> tuple[float, str | None]:
    """(value, unit or None) of ``"<expression>"`` or ``"<expression> <unit>"`` (``"0.5 kg"``,
    ``"2*0.3 kg"``, ``"90.992 kg*mm^2"``): the last word is the unit when the whole text is no
    expression. The unit is not checked here. Raises ExpressionError."""
    try:
        tree, unit = _parse(text), None
    except ExpressionError:  # only a text that does not parse whole may end in a unit
        m = _WITH_UNIT.fullmatch(text.strip())
        if m is None:
            raise
        try:
            tree, unit = _parse(m.group(1)), m.group(2)
        except ExpressionError as exc:  # the whole text in the message, not its first part
            raise ExpressionError(text, exc.reason) from None
    return _value(tree, text, names or {}), unit


def constants(table) -> tuple[dict[str, float], list[tuple[str, str]]]:
    """The values of a ``[constants]`` table (None: none) and its problems, each (field,
    message); a constant that uses one with a problem has no value and no message of its own."""
    if table is None:
        return {}, []
    if not isinstance(table, dict):
        why = f"must be a table of name = number or expression (got {table!r:.60})"
        return {}, [("constants", why)]
    if len(table) > MAX_CONSTANTS:
        return {}, [("constants", f"more than {MAX_CONSTANTS} constants")]
    values: dict[str, float] = {}
    trees: dict[str, ast.expr] = {}
    problems: list[tuple[str, str]] = []
    broken: set[str] = set()
    named = [n for n in table if NAME.match(n) and n not in BUILT_IN and n not in FUNCTIONS]
    for name, v in table.items():
        fld = f"constants.{name}"
        if name not in named:
            why = ("is built in: choose another name" if NAME.match(name) else
                   "is not a name (letters, digits and _, a letter first)")
            problems.append((fld, f"{name!r} {why}"))
        elif isinstance(v, str):
            try:
                trees[name] = _parse(v)
                continue
            except ExpressionError as exc:
                problems.append((fld, str(exc)))
        elif isinstance(v, bool) or not isinstance(v, (int, float)):
            problems.append((fld, f"must be a number or an expression (got {v!r:.60})"))
        elif not _finite(v):
            problems.append((fld, f"must be finite (got {v!r:.40})"))
        else:
            values[name] = float(v)
            continue
        broken.add(name)

    def resolve(name: str, chain: list[str]) -> None:
        if name in values or name in broken:
            return
        if name in chain:  # reported once, at the first constant of the cycle
            cycle = chain[chain.index(name):] + [name]
            problems.append((f"constants.{cycle[0]}", "a cycle: " + " -> ".join(cycle)))
            broken.update(cycle)
            return
        used = _names(trees[name]) & set(table)
        for other in sorted(used):
            resolve(other, [*chain, name])
        if name in broken or used & broken:  # its only problem is reported at the other
            broken.add(name)
            return
        try:
            values[name] = _value(trees[name], table[name], values, known=named)
        except ExpressionError as exc:
            problems.append((f"constants.{name}", str(exc)))
            broken.add(name)

    for name in trees:
        resolve(name, [])
    return values, problems


def numbers(data, schema, names: Mapping[str, float]):
    """``data`` (TOML) with every string at a number's place of ``schema`` evaluated: a float, or
    a ``Bad``. Nothing else is touched, and ``data`` itself is not changed.

    ``schema``: a dict of key (``"*"``: any other key) -> schema; ``[schema]``: each table of
    an array of tables; an int ``d``: numbers ``d`` lists deep (0 a number, 1 a list of numbers
    ``[x, y]``, 2 a list of such lists), a string outside lists there left as it is (not a
    number's place: "must be a list" is the message); a tuple: alternatives, each applied
    (a number or a list of numbers)."""
    if isinstance(schema, tuple):
        for s in schema:
            data = numbers(data, s, names)
        return data
    if isinstance(schema, dict):
        if not isinstance(data, dict):
            return data
        return {k: numbers(v, schema[k] if k in schema else schema.get("*"), names)
                for k, v in data.items()}
    if isinstance(schema, list):
        return [numbers(v, schema[0], names) for v in data] if isinstance(data, list) else data
    if isinstance(schema, int):
        return _number(data, schema, names, "")
    return data


def _number(v, depth: int, names, index: str):
    if depth == 0:
        if not isinstance(v, str):
            return v
        try:
            return evaluate(v, names)
        except ExpressionError as exc:
            return Bad(index, str(exc))
    if isinstance(v, list):
        return [_number(x, depth - 1, names, f"[{i}]") for i, x in enumerate(v)]
    return v


# -- parsing and evaluating -----------------------------------------------------------------------

def _parse(text: str) -> ast.expr:
    """The tree of ``text``, every node within the rules (names are checked when evaluated)."""
    if len(text) > MAX_LENGTH:
        raise ExpressionError(text, f"longer than {MAX_LENGTH} characters")
    if not text.strip():
        raise ExpressionError(text, "empty: give a number or an expression")
    try:  # ^ becomes ** before parsing, so it has the power's precedence
        tree = ast.parse(text.strip().replace("^", "**"), mode="eval").body
    except (SyntaxError, ValueError) as exc:
        if _SIDE_BY_SIDE.search(text):
            reason = ("two terms side by side: a product needs * (30*deg), and no unit is "
                      "written here (the file's [units] give it)")
        else:
            reason = f"not an expression ({getattr(exc, 'msg', exc)})"
        raise ExpressionError(text, reason) from None
    for node in ast.walk(tree):
        _allowed(node, text)
    return tree


def _allowed(node: ast.AST, text: str) -> None:
    if isinstance(node, ast.BinOp | ast.UnaryOp):
        if type(node.op) not in _BINARY and type(node.op) not in _UNARY:
            raise ExpressionError(text, f"operator {_SHOWN.get(type(node.op), '?')} is not "
                                        "allowed (only + - * / ** ^)")
    elif isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, int | float):
            raise ExpressionError(text, f"{node.value!r} is not a number")
    elif isinstance(node, ast.Call):
        if not isinstance(node.func, ast.Name):
            raise ExpressionError(text, f"only these functions may be called: {_known()}")
        name = node.func.id
        if name in BUILT_IN:
            raise ExpressionError(text, f"{name} is a number, not a function")
        if name not in FUNCTIONS:
            raise ExpressionError(text, f"unknown function {name} (known: {_known()})")
        if node.keywords:
            raise ExpressionError(text, f"{name}: keyword arguments are not allowed")
        wanted = FUNCTIONS[name][1]
        if len(node.args) != wanted:
            raise ExpressionError(text, f"{name} takes {wanted} argument"
                                        f"{'s' if wanted > 1 else ''} (got {len(node.args)})")
    elif not isinstance(node, ast.Name | ast.expr_context | ast.operator | ast.unaryop):
        raise ExpressionError(text, f"{_SHOWN.get(type(node), type(node).__name__)} is not "
                                    "allowed (only numbers, + - * / ** ^, parentheses, "
                                    "functions and names)")


def _value(tree: ast.expr, text: str, names: Mapping[str, float], known=None) -> float:
    """The value of a checked tree; ``known``: the names to list when one is unknown."""
    source = text.strip().replace("^", "**")

    def shown(node) -> str:
        seg = ast.get_source_segment(source, node) or "?"
        seg = seg.replace("**", "^") if "^" in text else seg
        return seg if len(seg) <= 40 else seg[:37] + "..."

    def ev(node, depth: int) -> float:
        if depth > MAX_DEPTH:
            raise ExpressionError(text, f"more than {MAX_DEPTH} operations deep")
        try:
            if isinstance(node, ast.Constant):
                v = float(node.value)
            elif isinstance(node, ast.Name):
                v = _name(node.id, text, names, known)
            elif isinstance(node, ast.UnaryOp):
                v = _UNARY[type(node.op)](ev(node.operand, depth + 1))
            elif isinstance(node, ast.BinOp):
                a, b = ev(node.left, depth + 1), ev(node.right, depth + 1)
                v = _BINARY[type(node.op)](a, b)
            else:  # a call of a known function (checked by _allowed)
                args = [ev(a, depth + 1) for a in node.args]
                v = FUNCTIONS[node.func.id][0](*args)
        except ZeroDivisionError:
            raise ExpressionError(text, f"division by zero in {shown(node)}") from None
        except OverflowError:
            raise ExpressionError(text, f"{shown(node)} is too large") from None
        except ExpressionError:
            raise
        except ValueError:  # math: sqrt(-1), asin(2), (-8)^(1/3), 0^-1
            raise ExpressionError(text, f"{shown(node)} is undefined") from None
        if not math.isfinite(v):  # 1e308*10: inf without an exception
            raise ExpressionError(text, f"{shown(node)} is too large")
        return v

    return ev(tree, 0)


def _name(name: str, text: str, names: Mapping[str, float], known) -> float:
    if name in BUILT_IN:
        return BUILT_IN[name]
    if name in names:
        return names[name]
    if name in FUNCTIONS:
        raise ExpressionError(text, f"{name} is a function: call it, {name}(x)")
    own = sorted(known if known is not None else names)
    listed = f"; [constants]: {', '.join(own)}" if own else "; a file's own go in [constants]"
    raise ExpressionError(text, f"unknown name {name} (known: {', '.join(BUILT_IN)}{listed})")


def _names(tree: ast.expr) -> set[str]:
    """The names an expression uses (functions aside)."""
    return {n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and n.id not in FUNCTIONS}


def _known() -> str:
    return ", ".join(FUNCTIONS)


def _quoted(text: str) -> str:
    """The text in double quotes, as in the TOML file (shortened when very long)."""
    return '"' + (text if len(text) <= 80 else text[:77] + "...") + '"'


def _finite(v) -> bool:
    try:
        return math.isfinite(float(v))
    except OverflowError:
        return False
