"""Every example in the documentation runs as written: README.md and every page under docs/.

Each page runs on its own (one test per page, so pytest-xdist shares them between workers), in
document order, in a fresh folder holding a copy of ``examples/``, as a checkout does:

* each ```python block, as a script of its own;
* each command of a ```sh block: ``planar-sym ...`` (as ``python -m planar_sym ...``) and
  ``python ...`` (this interpreter); a ```sh block with any other command (``make``, ``cd``,
  ``pip``) must be marked not run, so no command is skipped silently;
* each ```toml block whose first line is ``# <file>.toml: ...`` is written to that file first,
  so the commands after it can use it; every ```toml block must parse;
* a ```text block preceded by the line ``<!-- output -->`` is what the block above it prints:
  each of its lines must appear, in order, in that block's output (``...`` in a line stands
  for any text; a line of only ``...`` for lines left out), so the figures it quotes are
  checked against a fresh run.

Other ```text blocks (synopses, formulas) are not run, and neither is a block preceded by the
line ``<!-- not run: why -->``. Beside the runs: every page of docs/ is in the site's nav, and
every relative link of the README leads to a file that exists.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
import time
import tomllib
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.MULTILINE | re.DOTALL)
NOT_RUN, OUTPUT = "<!-- not run", "<!-- output -->"
#: pages of docs/ written by other tools, with no examples of their own to run
GENERATED = {"errors.md"}


def pages() -> list[str]:
    """README.md and every Markdown page of the site, as paths relative to the checkout."""
    return ["README.md"] + sorted(str(p.relative_to(ROOT)) for p in DOCS.rglob("*.md")
                                  if str(p.relative_to(DOCS)) not in GENERATED)


@dataclass(frozen=True)
class Block:
    lang: str
    body: str
    line: int      # of the opening fence, 1-based
    marker: str    # the line before the fence: "<!-- not run: ... -->", "<!-- output -->" or ""


def blocks(page: str) -> list[Block]:
    """Every fenced block of a page (at the start of a line), in document order."""
    text = (ROOT / page).read_text()
    out = []
    for m in FENCE.finditer(text):
        before = text[:m.start()].rstrip("\n").rsplit("\n", 1)[-1].strip()
        marker = before if before.startswith((NOT_RUN, OUTPUT)) else ""
        out.append(Block(m.group(1), m.group(2), text.count("\n", 0, m.start()) + 1, marker))
    return out


def commands(body: str) -> list[str]:
    """The commands of a ```sh block: continuation lines joined, comments dropped."""
    lines, joined = [], ""
    for line in body.splitlines():
        joined += line.rstrip("\\").strip() + " " if line.endswith("\\") else line.strip()
        if line.endswith("\\"):
            continue
        code = joined.split(" # ")[0].split("   #")[0].strip()
        joined = ""
        if code and not code.startswith("#"):
            lines.append(code)
    return lines


def argv_of(command: str) -> list[str] | None:
    """How the test runs a command of a ```sh block, or None if it cannot."""
    words = shlex.split(command)
    if words[0] == "planar-sym":
        return [sys.executable, "-m", "planar_sym", *words[1:]]
    if words[0] == "python":
        return [sys.executable, *words[1:]]
    return None


def runs(block: Block) -> list[list[str]]:
    """The processes one block runs (none for a block that is not run)."""
    if block.marker.startswith(NOT_RUN):
        return []
    if block.lang == "python":
        return [[sys.executable, "-c", block.body]]
    if block.lang == "sh":
        return [argv_of(c) for c in commands(block.body)]
    return []


def expected_lines(body: str) -> list[tuple[str, re.Pattern]]:
    """An output block's lines, each with its pattern: ``...`` stands for any text."""
    return [(line.rstrip(), re.compile(".*".join(re.escape(p) for p in line.rstrip().split("..."))))
            for line in body.splitlines() if line.strip() and line.strip() != "..."]


def missing_output(body: str, printed: str) -> list[str]:
    """The lines of an output block that the run did not print (in order)."""
    actual = [ln.rstrip() for ln in printed.splitlines()]
    at, missing = 0, []
    for line, pattern in expected_lines(body):
        for k in range(at, len(actual)):
            if pattern.fullmatch(actual[k]):
                at = k + 1
                break
        else:
            missing.append(line)
    return missing


# -- what the pages hold, read without running them ---------------------------------------------
def test_the_readme_has_examples_of_each_kind():
    kinds = {b.lang for b in blocks("README.md") if runs(b)}
    assert kinds == {"python", "sh"}


def test_the_docs_have_examples_to_run():
    counted = {page: sum(len(runs(b)) for b in blocks(page)) for page in pages()}
    assert counted["README.md"] >= 4, counted  # the README's first result and its Python
    assert sum(counted.values()) >= 60, counted  # fewer: the extraction lost some


@pytest.mark.parametrize("page", pages())
def test_every_command_is_run_or_says_why_not(page):
    indented = re.search(r"^[ \t]+```(python|sh|toml)\b", (ROOT / page).read_text(), re.MULTILINE)
    assert not indented, f"{page}: an indented ```{indented.group(1)} block would not be run"
    for b in blocks(page):
        where = f"{page} line {b.line}"
        if b.lang == "sh" and not b.marker.startswith(NOT_RUN):
            for c in commands(b.body):
                assert argv_of(c), (f"{where}: `{c}` is not a command the test can run: "
                                    "mark the block <!-- not run: why -->")
        if b.lang == "toml":
            try:
                tomllib.loads(b.body)
            except tomllib.TOMLDecodeError as e:
                pytest.fail(f"{where}: the TOML does not parse: {e}")
        if b.marker == OUTPUT:
            assert b.lang == "text", f"{where}: an output block is ```text"
            assert expected_lines(b.body), f"{where}: an output block quotes nothing"


def test_every_page_is_in_the_nav():
    yaml = pytest.importorskip("yaml")
    config = yaml.safe_load((ROOT / "mkdocs.yml").read_text())

    def files(node):
        if isinstance(node, str):
            yield node
        elif isinstance(node, dict):
            for v in node.values():
                yield from files(v)
        elif isinstance(node, list):
            for v in node:
                yield from files(v)

    nav = {f for f in files(config["nav"]) if f.endswith(".md")}
    on_disk = {str(p.relative_to(DOCS)) for p in DOCS.rglob("*.md")}
    assert on_disk - nav == set(), "pages missing from the nav of mkdocs.yml"
    assert nav - on_disk == set(), "nav entries with no page"


LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def test_the_readme_links_lead_somewhere():
    text = (ROOT / "README.md").read_text()
    targets = [t for t in LINK.findall(text) if not re.match(r"[a-z]+:", t)]
    assert len(targets) >= 8, targets  # the README points into the site
    for target in targets:
        path = target.split("#")[0]
        assert (ROOT / path).exists(), f"README links to {target}, which does not exist"
        if "#" in target and path.endswith(".md"):
            anchor = target.split("#")[1]
            headings = re.findall(r"^#+ (.+)$", (ROOT / path).read_text(), re.MULTILINE)
            slugs = {re.sub(r"[\s]+", "-", re.sub(r"[^\w\s-]", "", h).strip().lower())
                     for h in headings}
            assert anchor in slugs, f"README links to {target}: no such heading"


# -- running them --------------------------------------------------------------------------------
@pytest.mark.parametrize("page", [p for p in pages() if any(runs(b) for b in blocks(p))])
def test_every_example_runs(page, tmp_path):
    shutil.copytree(ROOT / "examples", tmp_path / "examples",
                    ignore=shutil.ignore_patterns("*.o", "serial_2dof_tau", "__pycache__"))
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "MPLBACKEND": "Agg"}
    ran, planned, printed, timings = 0, 0, None, []
    for b in blocks(page):
        where = f"{page} line {b.line}"
        if b.lang == "toml" and not b.marker.startswith(NOT_RUN):
            if m := re.match(r"# ([\w.-]+\.toml):", b.body.splitlines()[0]):
                (tmp_path / m.group(1)).write_text(b.body)
            continue
        if b.marker == OUTPUT:
            assert printed is not None, f"{where}: an output block with no run block above it"
            missing = missing_output(b.body, printed)
            assert not missing, (f"{where}: the block above did not print\n  "
                                 + "\n  ".join(missing) + f"\nIt printed:\n{printed}")
            continue
        if b.marker.startswith(NOT_RUN):
            printed = None  # an output block after it would quote a block that did not run
        argvs = runs(b)
        if not argvs:
            continue
        planned += len(argvs)
        printed = ""
        for argv in argvs:
            start = time.perf_counter()
            proc = subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True,
                                  timeout=600, check=False)
            what = " ".join(argv[3:]) if b.lang == "sh" else "the python block"
            assert proc.returncode == 0, (f"{where}: {what} failed:\n"
                                          f"{proc.stdout}\n{proc.stderr}")
            assert "Traceback" not in proc.stderr, f"{where}: {proc.stderr}"
            printed += proc.stdout + proc.stderr
            timings.append((time.perf_counter() - start, b.line))
            ran += 1
    assert ran == planned > 0
    slowest = ", ".join(f"line {line} {s:.1f} s" for s, line in sorted(timings)[::-1][:3])
    print(f"\n{page}: {ran} examples ran in {sum(s for s, _ in timings):.1f} s "
          f"(slowest: {slowest})")


@pytest.mark.parametrize("text, expected", [
    ("planar-sym run a.toml --out r   # comment\nmake demo\n",
     ["planar-sym run a.toml --out r", "make demo"]),
    ("planar-sym move x --from 1,2 \\\n    --by 3,4\n", ["planar-sym move x --from 1,2 --by 3,4"]),
    ("# a comment line\n\npython examples/own_robot.py\n", ["python examples/own_robot.py"]),
])
def test_command_extraction(text, expected):
    assert commands(text) == expected


@pytest.mark.parametrize("body, printed, missing", [
    ("a 1.5 s\n...\nb ... N\n", "a 1.5 s\nx\nb 2 N\n", []),
    ("a 1.5 s\n", "a 1.6 s\n", ["a 1.5 s"]),
    ("b\na\n", "a\nb\n", ["a"]),  # in order
])
def test_output_matching(body, printed, missing):
    assert missing_output(body, printed) == missing
