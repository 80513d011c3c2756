"""The building blocks of the JSON Schemas (``schema``): entry types, and the object schema
of a validator's table checked against the entries that describe it.

An entry is ``(schema or NUM or INT, text)``: NUM takes its shape from the validator's
``NUMBERS`` (a number there may be an expression in a string), INT its range from ``INTEGERS``.
``_table`` raises ``SchemaDrift`` where a validator's table and the entries disagree.
"""

from __future__ import annotations

from ..expressions import BUILT_IN, FUNCTIONS, MAX_CONSTANTS
from ..model.description.fields import NAME

DRAFT = "http://json-schema.org/draft-07/schema#"

#: an identifier (``fields.NAME``): a robot, body, joint, point or constant name
IDENT = NAME.pattern
_WORD = IDENT.removeprefix("^").removesuffix("$")
#: "body.point"
REF = f"^{_WORD}\\.{_WORD}$"

#: entry types: NUM takes the place's shape from ``NUMBERS``, INT its range from ``INTEGERS``
NUM, INT = "number place", "integer place"
STRING = {"type": "string"}
TEXT = {"type": "string", "minLength": 1}
BOOL = {"type": "boolean"}
ANY: dict = {}
NOTES = (ANY, "Free text, not read.")
EXPRESSION = {"type": ["number", "string"]}


class SchemaDrift(RuntimeError):
    """A validator's table and the schema's entries disagree: a key without an entry, an
    entry for a key no validator knows, or a number's (an integer's) place typed otherwise."""


def _enum(options, default=None) -> dict:
    out = {"enum": list(options)}
    if default is not None:
        out["default"] = default
    return out


def _number(shape, pair: bool) -> dict:
    """The schema of a number place of a ``NUMBERS`` table (``expressions.numbers``): 0 a
    number, 1 a list of numbers (``pair``: two, [x, y]), 2 a list of such lists, (0, 1) a
    number or a list; every number may be an expression string."""
    if shape == (0, 1):
        return {"type": ["number", "string", "array"], "items": EXPRESSION, "minItems": 1}
    if shape == 0:
        return dict(EXPRESSION)
    if shape == 1:
        return {"type": "array", "items": EXPRESSION,
                **({"minItems": 2, "maxItems": 2} if pair else {"minItems": 1})}
    if shape == 2:
        return {"type": "array", "items": _number(1, pair), "minItems": 1}
    raise SchemaDrift(f"no schema for the number place {shape!r}")


def _leaf(shape) -> bool:
    """A number place itself (not a table or list of tables holding some)."""
    return isinstance(shape, int) or (isinstance(shape, tuple)
                                      and all(isinstance(s, int) for s in shape))


def _table(where: str, keys, entries: dict, numbers=None, integers=None, *, pair: bool = False,
           required=(), closed: bool = True, **rules) -> dict:
    """An object schema of the keys a validator knows (``keys``, its own table), each
    described by ``entries[key] = (schema or NUM or INT, text)``; ``numbers`` and ``integers``:
    the validator's tables at this level."""
    numbers = numbers if isinstance(numbers, dict) else {}
    integers = integers or {}
    where = where or "the top level"
    if set(keys) != set(entries):
        raise SchemaDrift(f"{where}: keys the validator knows but this module does not describe: "
                          f"{sorted(set(keys) - set(entries))}; described but unknown: "
                          f"{sorted(set(entries) - set(keys))}")
    unknown = (set(numbers) - {"*"} | set(integers)) - set(keys)
    if unknown or not set(required) <= set(keys):
        raise SchemaDrift(f"{where}: numbers, integers or required keys no validator knows: "
                          f"{sorted(unknown | (set(required) - set(keys)))}")
    props = {}
    for key in sorted(keys):
        kind, text = entries[key]
        is_number = key in numbers and _leaf(numbers[key])
        if (kind == NUM) != is_number or (kind == INT) != (key in integers):
            raise SchemaDrift(f"{where}.{key}: the validator's NUMBERS or INTEGERS and this "
                              "module's entry disagree on whether it is a number or an integer")
        if kind == NUM:
            schema = _number(numbers[key], pair)
        elif kind == INT:
            default, low, high = integers[key]
            schema = {"type": "integer", "minimum": low, "maximum": high, "default": default}
        else:
            schema = kind
        props[key] = {"description": text, **schema}
    out: dict = {"type": "object", "properties": props}
    if closed:
        out["additionalProperties"] = False
    if required:
        out["required"] = sorted(required)
    out.update(rules)
    return out


def _points(shape, text: str) -> tuple[dict, str]:
    """A table of named points, each [x, y] (``NUMBERS``: ``{"*": 1}``)."""
    return ({"type": "object", "minProperties": 1, "propertyNames": {"pattern": IDENT},
             "additionalProperties": _number(shape["*"], pair=True)}, text)


def _constants() -> tuple[dict, str]:
    return ({"type": "object", "maxProperties": MAX_CONSTANTS,
             "propertyNames": {"pattern": IDENT, "not": _enum([*BUILT_IN, *FUNCTIONS])},
             "additionalProperties": EXPRESSION},
            ("Names for the expressions of this file: name = a number or an expression of "
             "numbers and other constants (\"L = '2*a'\"); any number of the file may then be "
             "an expression using them (\"L/2\"). Built in: pi, deg = pi/180, sqrt, sin, cos, "
             "tan, asin, acos, atan, atan2, hypot."))
