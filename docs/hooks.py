"""MkDocs hooks (``hooks:`` in mkdocs.yml): what the pages show that is generated, not typed.

* **Docstrings' reST literal blocks as Markdown.** The docstrings are numpy style with a few
  reST habits for formulas: ``.. code:: text`` (or ``python``) followed by an indented block,
  and a paragraph ending in ``::`` followed by an indented block. Markdown already renders the
  indented block as code; this drops the directive line and turns the ``::`` into ``:``, so
  neither shows up as text in the API reference. It runs before mkdocstrings sets up its own
  Markdown (higher priority), so the docstrings get it too.
* **Benchmark figures from BENCHMARKS.md** (written by ``make bench``, committed), never typed
  into a page: a line ``<!-- benchmarks -->`` becomes the whole file (its title dropped),
  ``<!-- benchmarks: 5. Closed-loop control -->`` one of its ``##`` sections, and
  ``<!-- benchmarks: 5. Closed-loop control | S3 (a) -->`` the table of that section whose bold
  title starts with ``S3 (a)`` (title included). Headings move down to sit under the page's.
* **The file formats' fields** from the JSON Schemas the package ships (``planar_sym/schemas``,
  generated from the validators' own tables): ``<!-- fields: description -->`` (or ``study``)
  becomes a table of every key, table by table, with its choices and meaning.
* **The environment variables** from ``planar_sym.environment.KNOWN``: ``<!-- environment -->``.
* **The command line's help** from its parser: ``<!-- help -->`` becomes ``planar-sym --help``,
  ``<!-- help: draw -->`` ``planar-sym draw --help``. The page holding them must have one for
  every command, so a new command cannot be left out of the reference.

* **Colours for the code blocks** (``css/pygments.css``, written into the site after the build
  from Pygments' default style: the theme has none for ``pymdownx.superfences``' classes, and
  highlight.js would be a script from a CDN; the site needs no network).

A marker that names nothing (a section or table BENCHMARKS.md no longer has, an unknown
command) fails the build, as ``mkdocs build --strict`` would for a broken link.
"""

from __future__ import annotations

import functools
import os
import re
from pathlib import Path

from markdown import Extension
from markdown.preprocessors import Preprocessor
from mkdocs.exceptions import PluginError
from mkdocs.plugins import event_priority

ROOT = Path(__file__).resolve().parent.parent
BENCHMARKS = ROOT / "BENCHMARKS.md"
DIRECTIVE = re.compile(r"^\s*\.\. code(?:-block)?::\s*\w*\s*$")
MARKER = re.compile(r"^<!-- (benchmarks|help|fields|environment)(?:: (.*?))? -->$",
                    re.MULTILINE)
CLI_PAGE = "reference/cli.md"  # the page that must show every command's help


class _ReSTBlocks(Preprocessor):
    def run(self, lines: list[str]) -> list[str]:
        out = []
        for line in lines:
            if DIRECTIVE.match(line):
                continue
            if line.rstrip().endswith("::") and not line.lstrip().startswith(":::"):
                line = line.rstrip()[:-1]  # "text::" -> "text:" (its block follows, indented)
            out.append(line)
        return out


class ReSTBlocks(Extension):
    def extendMarkdown(self, md) -> None:  # the name is Markdown's API
        md.preprocessors.register(_ReSTBlocks(md), "rest_blocks", 30)


PYGMENTS_CSS = "css/pygments.css"


@event_priority(100)  # before mkdocstrings reads the Markdown extensions
def on_config(config):
    config.markdown_extensions.append(ReSTBlocks())
    config.extra_css.append(PYGMENTS_CSS)  # written by on_post_build: colours, no script
    return config


def on_post_build(config) -> None:
    """The code blocks' colours (pymdownx.superfences marks tokens with Pygments' classes; the
    theme has no style for them, and highlight.js would be a script from a CDN)."""
    try:
        from pygments.formatters import HtmlFormatter
    except ImportError:  # no Pygments: superfences left the blocks plain
        css = ""
    else:
        css = HtmlFormatter(style="default").get_style_defs(".highlight")
    path = Path(config.site_dir) / PYGMENTS_CSS
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(css + "\n")


# -- BENCHMARKS.md ---------------------------------------------------------------------------------
def _escape_tags(line: str) -> str:
    """``<name>.c`` outside code spans is text, not an HTML tag."""
    parts = line.split("`")
    return "`".join(p.replace("<", "&lt;") if k % 2 == 0 else p for k, p in enumerate(parts))


def _demote(text: str, levels: int) -> str:
    return re.sub(r"^(#+) ", lambda m: "#" * min(6, len(m.group(1)) + levels) + " ", text,
                  flags=re.MULTILINE)


def benchmarks(what: str | None, page_level: int) -> str:
    """The part of BENCHMARKS.md a marker names, its headings below ``page_level``."""
    text = BENCHMARKS.read_text()
    sections = re.split(r"^(?=## )", text, flags=re.MULTILINE)
    if what is None:  # the whole file but its title; its "##" sections go to page_level
        out = _demote(text.split("\n", 1)[1], page_level - 2)
    else:
        name, _, table = (p.strip() for p in what.partition("|"))
        found = [s for s in sections if s.startswith(f"## {name}")]
        if len(found) != 1:
            raise PluginError(f"BENCHMARKS.md has no section '## {name}' (marker "
                              f"<!-- benchmarks: {what} -->): run make bench, or fix the marker")
        section = found[0].split("\n", 1)[1]
        if not table:
            out = _demote(section, page_level - 2)
        else:
            m = re.search(rf"^\*\*{re.escape(table)}.*?\*\*\n\n(?:\|.*\n)+", section,
                          re.MULTILINE)
            if not m:
                raise PluginError(f"BENCHMARKS.md's section '{name}' has no table titled "
                                  f"'{table}...' (marker <!-- benchmarks: {what} -->)")
            out = m.group(0)
    return "\n".join(_escape_tags(line) for line in out.strip().splitlines())


# -- the file formats' fields, from the shipped JSON Schemas --------------------------------------
SCHEMAS = ROOT / "planar_sym" / "schemas"


def _kind(s: dict) -> str:
    """What a value is, in a few words: its choices, or its type."""
    if "enum" in s:
        return ", ".join(f"`{str(v).lower() if isinstance(v, bool) else v}`" for v in s["enum"])
    types = s.get("type")
    types = [types] if isinstance(types, str) else list(types or [])
    if "anyOf" in s:
        types += [t for alt in s["anyOf"] for t in ([alt["type"]] if isinstance(
            alt.get("type"), str) else alt.get("type", []))]
    words = {"number": "number", "integer": "integer", "boolean": "`true`, `false`",
             "string": "text", "array": "list", "object": "table"}
    out = []
    for t in types:
        w = words.get(t, t)
        if w not in out:
            out.append(w)
    if "number" in out and "text" in out:  # a number may be an expression in a string
        out = [w for w in out if w != "text"]
        out[out.index("number")] = "number or expression"
    return ", ".join(out) or "any"


def _rows(props: dict) -> list[str]:
    cell = {k: v.get("description", "").replace("|", r"\|") for k, v in props.items()}
    return [f"| `{k}` | {_kind(v)} | {cell[k]} |" for k, v in props.items()]


def _sub_tables(props: dict, name: str) -> list[tuple[str, dict]]:
    """The tables under ``props`` (a key holding a table, a list of tables, or inline tables
    among its choices), each with the TOML heading it is written under."""
    out = []
    for k, v in props.items():
        if v.get("properties"):
            out.append((f"[{name}{k}]", v["properties"]))
            out += _sub_tables(v["properties"], f"{name}{k}.")
        elif isinstance(v.get("items"), dict) and v["items"].get("properties"):
            out.append((f"[[{name}{k}]]", v["items"]["properties"]))
            out += _sub_tables(v["items"]["properties"], f"{name}{k}.")
        for alt in v.get("anyOf", []):
            if alt.get("properties"):
                keys = ", ".join(alt["properties"])
                out.append((f"{name}{k} = {{ {keys} }}", alt["properties"]))
    return out


def fields(which: str) -> str:
    """Every key of a file format, table by table, as the validators know them."""
    path = SCHEMAS / f"{which}.schema.json"
    if not path.is_file():
        raise PluginError(f"<!-- fields: {which} -->: no {path.relative_to(ROOT)}")
    import json

    schema = json.loads(path.read_text())
    head = ["| key | value | meaning |", "|---|---|---|"]
    out = ["**top level**", "", *head, *_rows(schema["properties"])]
    for heading, props in _sub_tables(schema["properties"], ""):
        out += ["", f"**`{heading}`**", "", *head, *_rows(props)]
    return "\n".join(out)


# -- the environment variables ------------------------------------------------------------------
def environment() -> str:
    """The variables planar-sym reads, as ``planar_sym.environment`` lists them."""
    from planar_sym.environment import FLAGS, KNOWN

    rows = [f"| `{name}` | {what}{' (a flag: 0 or 1)' if name in FLAGS else ''} |"
            for name, what in KNOWN.items()]
    return "\n".join(["| variable | what |", "|---|---|", *rows])


# -- the command line's help ---------------------------------------------------------------------
@functools.cache
def _parsers():
    from planar_sym.cli import parser

    top = parser()
    sub = next(a for a in top._actions if a.dest == "command")
    return top, sub.choices


def cli_help(command: str | None) -> str:
    top, commands = _parsers()
    if command is not None and command not in commands:
        raise PluginError(f"<!-- help: {command} -->: planar-sym has no command {command!r}")
    old = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = "100"  # argparse wraps at the terminal's width: fix it
    try:
        text = (top if command is None else commands[command]).format_help()
    finally:
        if old is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = old
    return f"```text\n{text.rstrip()}\n```"


def on_page_markdown(markdown: str, page, config, files) -> str:
    level = 1  # the heading level above a marker: what an included heading goes under
    shown: set[str] = set()
    out, fenced = [], False
    for line in markdown.split("\n"):
        if line.startswith("```"):
            fenced = not fenced
        if not fenced and (h := re.match(r"^(#+) ", line)):
            level = len(h.group(1))
        m = None if fenced else MARKER.match(line.strip())
        if not m:
            out.append(line)
        elif m.group(1) == "benchmarks":
            out.append(benchmarks(m.group(2), level + 1))
        elif m.group(1) == "fields":
            out.append(fields(m.group(2) or ""))
        elif m.group(1) == "environment":
            out.append(environment())
        else:
            shown.add(m.group(2) or "")
            out.append(cli_help(m.group(2)))
    if page.file.src_uri == CLI_PAGE:
        missing = sorted(set(_parsers()[1]) - shown)
        if missing or "" not in shown:
            raise PluginError(f"{CLI_PAGE} lacks the help of: "
                              + ", ".join(f"<!-- help: {c} -->" for c in missing)
                              + ("" if "" in shown else " <!-- help -->"))
    return "\n".join(out)
