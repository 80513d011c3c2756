"""The public API is documented, and the API reference (mkdocs + mkdocstrings) shows all of it.

What counts as public:

* every name in ``planar_sym.__all__`` (the lazy ones resolved through ``getattr``);
* the **public modules**: every module that hosts an object the reference renders (each
  ``::: dotted.path`` in ``docs/api/*.md``), so documenting one object of a module puts the
  whole module under these checks; in them, every public function and class (defined there,
  name not starting with ``_``);
* of every public class: its public methods and properties (and ``__call__``), and its public
  attributes (dataclass fields, or ``self.<name> = ...`` in ``__init__``).

Each must have a docstring. Beyond presence, **shapes and units** (the rule, ``needs_arrays``):
a callable handles arrays when a parameter or its return is annotated with ``ndarray``, or a
parameter has one of the names that are arrays throughout the package (``ARRAY_PARAMETERS``:
``q``, ``qd``, ``qdd``, ``t``, ...); a class, when its constructor does or one of its
attributes is an array. Its docstring (a class's: its own) must then state

* a shape: the word "shape" or a shape tuple such as ``(N, n)``, ``(N,)``, ``(n,)``,
  ``(D,)``, ``(len(t), channels)`` (``SHAPE``), and
* a unit: an SI unit symbol (rad, m, s, kg, N*m, m/s^2, J, ...), "SI", deg, or
  "dimensionless" (``UNIT``; shape tuples are removed first, so the N of ``(N, n)`` is no
  newton).

``NO_SHAPES_OR_UNITS`` is the allow-list of callables the rule would flag but where shapes
and units make no sense, each with its reason. A class's attributes must each be named in its
docstring (in backticks, or as a numpy ``Attributes`` entry): the reference shows a dataclass's
fields only through that docstring.

The reference itself: every name of ``planar_sym.__all__`` and every public class is rendered
on a page, and ``mkdocs build --strict`` (no warning: a broken reference, a docstring griffe
cannot parse) succeeds.
"""

from __future__ import annotations

import ast
import dataclasses
import importlib
import importlib.util
import inspect
import re
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

import planar_sym

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs" / "api"

#: parameter names that hold arrays wherever they appear in the package (unannotated, mostly)
ARRAY_PARAMETERS = {
    "q", "qd", "qdd", "tau", "q0", "qd0", "t", "t_s", "t_eval", "x0", "dx", "q_act", "qd_act",
    "qdd_act", "q_guess", "q_start", "values", "cond", "phi", "phi_v", "phi_a", "x", "J", "rhs",
    "y0", "sp", "sv", "ep", "ev",
}

#: callables the rule would flag where shapes or units make no sense (qualified names)
NO_SHAPES_OR_UNITS = {
    # picks a solver by name: only whether a start pose is given matters, not its values
    "planar_sym.motion.ik.choose_solver": "q_start is only tested for None",
    # returns integer indices of coordinates: no unit
    "planar_sym.motion.closure.partition": "returns index arrays, no physical quantity",
}
# (a callable with no array parameter or result, e.g. load(robot) or studies(), is never
# flagged: it needs no entry here)

#: a shape: the word, or a tuple of sample/size symbols, e.g. (N, n), (N,), (n,), (len(t), 2n)
SHAPE = re.compile(r"\bshape\b|\((?:N|D|n|n_task|nphi|frames|cells|channels|width|"
                   r"len\(t\)|actuated|bodies)\b\s*[,)]")
#: a tuple of sizes, removed before looking for units: "(N, n)", "(N,)", "(N, 2 * loops)"
SHAPE_TUPLE = re.compile(r"\((?:[\w()]+(?: ?[*+] ?[\w()]+)*,\s*)+(?:[\w()]+(?: ?[*+] ?\w+)*)?\)")
#: a unit: SI symbols and compounds, "SI", deg, or "dimensionless"; bare N, J and W only where
#: they cannot be a sample count, a Jacobian or a width: "(N)", "(J)", "in N", "N*m", ...; or
#: a name that carries its unit as the package's columns do (``t_s``, ``tau1_n_m``)
UNIT = re.compile(r"""
    \b(?:N|m|rad|kg|s|J|W|1)(?:[*/](?:N|m|rad|kg|s|J|W)(?:\^\d)?)+\b | \bm\^2
    | (?<![\w'/*^])(?:rad|m|s|kg|deg|SI|Hz)(?![\w'*/^])
    | \((?:N|J|W)[),;] | \bin\ (?:N|J|W)\b | \bdimensionless\b
    | [\w>]_(?:rad|rad_s2?|m|m_s2?|m2|s|n|n_m|j|w|kg|kg_m2|deg|mm)\b  # a column's unit suffix
""", re.VERBOSE)


# -- what is public ---------------------------------------------------------------------------
def documented_paths() -> list[str]:
    """Every ``::: dotted.path`` the reference renders, in page order."""
    return [m.group(1) for page in sorted(DOCS.glob("*.md"))
            for m in re.finditer(r"^::: ([\w.]+)\s*$", page.read_text(), re.MULTILINE)]


def resolve(path: str):
    """The object of a dotted path: the longest importable module, then attributes."""
    parts = path.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        for attr in parts[k:]:
            obj = getattr(obj, attr)
        return obj
    raise ImportError(path)


def public_modules() -> list:
    """Modules hosting a rendered object (a rendered module counts itself)."""
    names = set()
    for path in documented_paths():
        obj = resolve(path)
        if inspect.ismodule(obj):
            names.add(obj.__name__)
        elif inspect.isclass(obj) or inspect.isfunction(obj):
            names.add(obj.__module__)
    return [importlib.import_module(n) for n in sorted(names)]


def api_objects() -> dict[str, object]:
    """Qualified name -> object: ``__all__``, then the public functions and classes of the
    public modules."""
    out = {}
    for name in planar_sym.__all__:
        obj = getattr(planar_sym, name)
        out[f"{obj.__module__}.{obj.__qualname__}"] = obj
    for mod in public_modules():
        for name, obj in vars(mod).items():
            if name.startswith("_") or not (inspect.isfunction(obj) or inspect.isclass(obj)):
                continue
            if obj.__module__ == mod.__name__:
                out[f"{mod.__name__}.{name}"] = obj
    return out


def public_classes() -> dict[str, type]:
    return {k: v for k, v in api_objects().items() if inspect.isclass(v)}


def members(cls: type) -> dict[str, object]:
    """Public methods and properties of ``cls`` (its own and its package bases'), as their
    functions (a property's getter)."""
    out = {}
    for klass in reversed(cls.__mro__):
        if not klass.__module__.startswith("planar_sym"):
            continue
        for name, attr in vars(klass).items():
            if name.startswith("_") and name != "__call__":
                continue
            if isinstance(attr, property):
                out[name] = attr.fget
            elif isinstance(attr, (staticmethod, classmethod)):
                out[name] = attr.__func__
            elif inspect.isfunction(attr):
                out[name] = attr
    return out


def attributes(cls: type) -> dict[str, str]:
    """Public attributes of ``cls`` -> annotation (or the assigned expression) as text:
    dataclass fields, or ``self.<name> = ...`` in a hand-written ``__init__``."""
    if dataclasses.is_dataclass(cls):
        return {f.name: str(f.type) for f in dataclasses.fields(cls)
                if not f.name.startswith("_")}
    init = vars(cls).get("__init__")
    if init is None or not inspect.isfunction(init):
        return {}
    tree = ast.parse(textwrap.dedent(inspect.getsource(init)))
    out = {}
    for node in ast.walk(tree):
        targets = (node.targets if isinstance(node, ast.Assign) else
                   [node.target] if isinstance(node, ast.AnnAssign) else [])
        for tgt in targets:
            if (isinstance(tgt, ast.Attribute) and isinstance(tgt.value, ast.Name)
                    and tgt.value.id == "self" and not tgt.attr.startswith("_")):
                hint = node.annotation if isinstance(node, ast.AnnAssign) else node.value
                out[tgt.attr] = ast.unparse(hint)
    return out


# -- the shape and unit rule --------------------------------------------------------------------
def is_array_hint(text: str) -> bool:
    return "ndarray" in text or re.search(r"\bnp\.(array|zeros|empty|asarray)\b", text) is not None


def needs_arrays(fn) -> bool:
    """Whether a callable takes or returns arrays (annotations, or the package's array names)."""
    try:
        sig = inspect.signature(fn)
    except (TypeError, ValueError):
        return False
    for name, par in sig.parameters.items():
        hint = par.annotation if par.annotation is not inspect.Parameter.empty else ""
        named = name in ARRAY_PARAMETERS and par.kind not in (par.VAR_POSITIONAL,
                                                               par.VAR_KEYWORD)
        if named or is_array_hint(str(hint)):
            return True
    ret = sig.return_annotation
    return ret is not inspect.Signature.empty and is_array_hint(str(ret))


def shapes_and_units(doc: str) -> list[str]:
    """What ``doc`` lacks of a shape and a unit (empty: it has both)."""
    missing = []
    if not SHAPE.search(doc):
        missing.append("a shape, e.g. (N, n)")
    if not UNIT.search(SHAPE_TUPLE.sub("", doc)):
        missing.append("units, e.g. rad, N*m, SI")
    return missing


def names_attribute(doc: str, name: str) -> bool:
    """``name`` in backticks, or as a numpy ``Attributes`` entry ("a, name : type")."""
    n = re.escape(name)
    return bool(re.search(rf"`{n}`|^\s*(?:\w+,\s*)*{n}(?:,\s*\w+)*\s*(?::|$)", doc, re.MULTILINE))


def own_doc(obj) -> str:
    return obj.__doc__ if isinstance(obj.__doc__, str) else ""


def test_the_rule_itself():
    """The regular expressions catch what they should, and not what they should not."""
    assert not shapes_and_units("Joint torques (N*m), shape (N, n).")
    assert not shapes_and_units("Kinetic and potential energy (J), each (N,).")
    assert shapes_and_units("M(q) for every sample.") == ["a shape, e.g. (N, n)",
                                                          "units, e.g. rad, N*m, SI"]
    # the N of a shape is no newton, a possessive s no second, J = dx/dq no joule
    assert shapes_and_units("The robot's Jacobian J = dx/dq, (N, n) samples.") == [
        "units, e.g. rad, N*m, SI"]
    assert not shapes_and_units("Cut-joint forces (N, 2 * loops) in N.")
    assert not shapes_and_units("Times t_s (N,) s.")
    assert not shapes_and_units("Columns ``q<k>_rad``, ``tau<k>_n_m``, each (N,).")
    assert shapes_and_units("Names ``task_names``, shape (N,).") == ["units, e.g. rad, N*m, SI"]
    assert names_attribute("``q``, ``qd`` (N, n)", "qd")
    assert names_attribute("Attributes\n----------\nx_m, y_m : ndarray\n", "y_m")
    assert not names_attribute("every coordinate q and its rate", "q")
    assert needs_arrays(planar_sym.Robot.inverse_dynamics)
    assert not needs_arrays(planar_sym.load)


# -- the docstrings ------------------------------------------------------------------------------
def test_every_public_name_resolves_and_has_a_docstring():
    missing = [name for name in planar_sym.__all__ if not own_doc(getattr(planar_sym, name))]
    assert not missing, f"public names without a docstring: {missing}"


def test_every_public_function_and_class_has_a_docstring():
    missing = [name for name, obj in api_objects().items() if not own_doc(obj).strip()]
    assert not missing, "without a docstring:\n  " + "\n  ".join(missing)


def test_every_public_method_and_property_has_a_docstring():
    missing = [f"{cname}.{name}" for cname, cls in public_classes().items()
               for name, fn in members(cls).items() if not own_doc(fn).strip()]
    assert not missing, "without a docstring:\n  " + "\n  ".join(missing)


def test_array_callables_state_shapes_and_units():
    """The rule of the module docstring, on functions, methods, properties and classes."""
    found = []
    callables = {k: v for k, v in api_objects().items() if inspect.isfunction(v)}
    for cname, cls in public_classes().items():
        callables.update({f"{cname}.{name}": fn for name, fn in members(cls).items()})
    for name, fn in callables.items():
        if name in NO_SHAPES_OR_UNITS or not needs_arrays(fn):
            continue
        if lacking := shapes_and_units(own_doc(fn)):
            found.append(f"{name}: lacks {' and '.join(lacking)}")
    for cname, cls in public_classes().items():
        array_attrs = any(is_array_hint(h) for h in attributes(cls).values())
        if cname in NO_SHAPES_OR_UNITS or not (array_attrs or needs_arrays(cls)):
            continue
        if lacking := shapes_and_units(own_doc(cls)):
            found.append(f"{cname} (class): lacks {' and '.join(lacking)}")
    assert not found, "docstrings without shapes or units:\n  " + "\n  ".join(found)


def test_every_class_attribute_is_documented_in_the_class_docstring():
    found = [f"{cname}.{attr}" for cname, cls in public_classes().items()
             for attr in attributes(cls) if not names_attribute(own_doc(cls), attr)]
    assert not found, ("attributes the class docstring does not name (``name`` or an "
                       "Attributes entry):\n  " + "\n  ".join(found))


def test_the_allow_list_is_current():
    """Every allow-listed callable exists and the rule would flag it."""
    objects = api_objects()
    for name in NO_SHAPES_OR_UNITS:
        assert name in objects, f"{name} in NO_SHAPES_OR_UNITS is no public callable"
        assert needs_arrays(objects[name]), f"{name} needs no allow-listing"


# -- the reference -------------------------------------------------------------------------------
def test_the_reference_renders_every_public_name_and_class():
    rendered = set(documented_paths())
    missing = []
    for name in planar_sym.__all__:
        obj = getattr(planar_sym, name)
        if not {f"planar_sym.{name}", f"{obj.__module__}.{obj.__qualname__}"} & rendered:
            missing.append(f"{name} (::: {obj.__module__}.{obj.__qualname__})")
    missing += [f"class {c}" for c in public_classes() if c not in rendered]
    assert not missing, ("not rendered on any page of docs/api/ (add a `::: path` line):\n  "
                         + "\n  ".join(missing))
    for path in rendered:
        resolve(path)  # every rendered path imports


def test_mkdocs_build_strict(tmp_path):
    if importlib.util.find_spec("mkdocs") is None:
        pytest.skip("mkdocs is not installed: pip install -e '.[docs]' to build the reference")
    site = tmp_path / "site"
    start = time.perf_counter()
    run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file",
                          str(ROOT / "mkdocs.yml"), "--site-dir", str(site)],
                         check=False, cwd=ROOT, capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, f"mkdocs build --strict failed:\n{run.stdout}\n{run.stderr}"
    print(f"\nmkdocs build --strict: {time.perf_counter() - start:.1f} s")
    robot = (site / "api" / "robot" / "index.html").read_text()
    for text in ("inverse_dynamics", "closed_chain_inverse_dynamics", "shape (N, n)", "N*m",
                 "rad/s^2"):
        assert text in robot, f"the Robot page lacks {text!r}"
    top = (site / "api" / "planar_sym" / "index.html").read_text()
    for name in planar_sym.__all__:
        obj = getattr(planar_sym, name)
        if inspect.isfunction(obj):
            assert f"planar_sym.{name}" in top, f"the planar_sym page lacks planar_sym.{name}"
