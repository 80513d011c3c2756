"""The code imports one way: no import circle anywhere (the runtime, derive/, benchmarks/), and
each runtime layer imports only the layers below it. Imports inside functions count too: a lazy
import is still a dependency.

Layers, lowest first (DESIGN.md): base (errors, files, progress, environment,
expressions) -> model -> motion -> dynamics -> control -> identify -> study -> analysis -> outputs
-> commands and cli -> the package's public API (``planar_sym/__init__.py``). ``derive/`` (build
time) may import only the description stage of the model and the base.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

LAYERS = ("base", "model", "motion", "dynamics", "control", "optimal", "identify", "study", "analysis",
          "outputs",
          "commands", "api")
BASE = {"planar_sym.errors", "planar_sym.files", "planar_sym.progress", "planar_sym.environment",
        "planar_sym.toml_write", "planar_sym.expressions", "planar_sym.spelling"}
#: what derive/ may take from the runtime
DERIVE_MAY_IMPORT = {"planar_sym.errors", "planar_sym.progress", "planar_sym.model.units",
                     "planar_sym.model.description"}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def imports(path: Path, known: set[str]) -> set[str]:
    """Modules of ``known`` that ``path`` imports, anywhere in the file."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - node.level + 1]
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module or ""
            subs = [f"{stem}.{a.name}" for a in node.names]
            # `from pkg import mod` depends on mod; `from mod import name` on mod
            targets = [t for t in subs if t in known] or [stem]
        else:
            continue
        for t in targets:  # the deepest known module each import names
            if t.startswith("planar_sym._derive"):  # derive/, as installed inside the package
                t = "derive" + t.removeprefix("planar_sym._derive")
            while t and t not in known:
                t = t.rpartition(".")[0]
            if t and t != name:
                found.add(t)
    return found


def graph(*folders: str) -> dict[str, set[str]]:
    files = [p for f in folders for p in (ROOT / f).rglob("*.py")]
    known = {module_name(p) for p in files}
    return {module_name(p): imports(p, known) for p in files}


def cycles(g: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in g.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(g):
        if v not in index:
            visit(v)
    return out


def layer(module: str) -> str:
    if module == "planar_sym":
        return "api"
    if module in BASE:
        return "base"
    part = module.split(".")[1]
    if part in ("cli", "__main__", "commands"):
        return "commands"
    assert part in LAYERS, f"{module} is in no layer: place it in one of {LAYERS}"
    return part


def depth(g: dict[str, set[str]]) -> int:
    """Modules on the longest import chain."""
    memo: dict[str, int] = {}

    def d(v):
        if v not in memo:
            memo[v] = 1 + max((d(w) for w in g[v] if w in g), default=0)
        return memo[v]
    return max(d(v) for v in g)


def test_no_import_circle_anywhere():
    for folders in (("planar_sym",), ("derive", "planar_sym"), ("benchmarks", "planar_sym")):
        found = cycles(graph(*folders))
        assert not found, f"import circles: {found}"


def test_runtime_layers_import_only_downward():
    g = graph("planar_sym")
    upward = [f"{a} ({layer(a)}) imports {b} ({layer(b)})" for a, deps in g.items()
              for b in deps if LAYERS.index(layer(b)) > LAYERS.index(layer(a))]
    assert not upward, "\n".join(upward)
    print(f"\nruntime: {len(g)} modules, longest import chain {depth(g)} modules, no circle")


def test_derive_takes_only_the_description_stage_from_the_runtime():
    g = graph("derive", "planar_sym")
    taken = {b for a, deps in g.items() if a.startswith("derive") for b in deps
             if b.startswith("planar_sym")}
    assert taken <= DERIVE_MAY_IMPORT | {m for m in taken if m.startswith(
        "planar_sym.model.description.")}, taken - DERIVE_MAY_IMPORT
    # one gate: model.deriving imports the build-time package when a robot must be derived
    gates = {a for a, deps in g.items() if a.startswith("planar_sym")
             and any(b.startswith("derive") for b in deps)}
    assert gates == {"planar_sym.model.deriving"}, gates


def test_the_graph_sees_lazy_imports():
    """The test itself: a function-level relative import is an edge (commands.run imports
    study.run inside a function)."""
    g = graph("planar_sym")
    assert "planar_sym.study.run" in g["planar_sym.commands.run"]
    assert "planar_sym.model.robot" in g["planar_sym.motion.ik"]
