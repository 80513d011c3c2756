"""MkDocs hook (``hooks:`` in mkdocs.yml): the docstrings' reST literal blocks as Markdown.

The docstrings are numpy style with a few reST habits for formulas:

* ``.. code:: text`` (or ``python``) followed by an indented block;
* a paragraph ending in ``::`` followed by an indented block.

Markdown already renders the indented block as code; this drops the directive line and turns
the ``::`` into ``:``, so neither shows up as text in the API reference. It runs before
mkdocstrings sets up its own Markdown (higher priority), so the docstrings get it too.
"""

from __future__ import annotations

import re

from markdown import Extension
from markdown.preprocessors import Preprocessor
from mkdocs.plugins import event_priority

DIRECTIVE = re.compile(r"^\s*\.\. code(?:-block)?::\s*\w*\s*$")


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


@event_priority(100)  # before mkdocstrings reads the Markdown extensions
def on_config(config):
    config.markdown_extensions.append(ReSTBlocks())
    return config
