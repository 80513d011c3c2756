"""A surviving mutant read from ``mutmut show``: where it is, what it changed, and whether the
change touches only the text of a message (a string literal) or the computation."""

from __future__ import annotations

import io
import re
import tokenize
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

EQUIVALENTS = Path(__file__).resolve().parent / "equivalent.toml"
_NAME = re.compile(r"^(?P<module>[\w.]+?)\.x(?:ǁ(?P<cls>\w+)ǁ|_)(?P<func>\w+?)__mutmut_\d+$")


@dataclass
class Mutant:
    name: str
    status: str  # "survived" or "no tests"
    module: str
    function: str
    before: list[str] = field(default_factory=list)
    after: list[str] = field(default_factory=list)
    reason: str | None = None  # why it is equivalent, when a developer judged it

    def key(self) -> tuple:
        """Stable across unrelated edits (mutmut's numbering is not)."""
        return (self.module, self.function, "\n".join(self.before), "\n".join(self.after))

    @property
    def text_only(self) -> bool:
        """True when only string literals differ: a message's wording, not a number."""
        before, after = _code_tokens(self.before), _code_tokens(self.after)
        return bool(self.before) and before is not None and before == after


def _code_tokens(lines: list[str]) -> list[str] | None:
    """The tokens that are not strings; None when the lines are not whole statements (a part
    of a call spanning lines cannot be judged text only)."""
    try:
        toks = list(tokenize.generate_tokens(io.StringIO("\n".join(lines) + "\n").readline))
    except (tokenize.TokenError, IndentationError, SyntaxError):
        return None
    skip = {tokenize.STRING, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT,
            tokenize.COMMENT, tokenize.ENDMARKER}
    skip |= {getattr(tokenize, n) for n in ("FSTRING_START", "FSTRING_MIDDLE", "FSTRING_END")
             if hasattr(tokenize, n)}
    return [t.string for t in toks if t.type not in skip]


def parse_show(name: str, status: str, shown: str) -> Mutant:
    """The mutant's changed lines from ``mutmut show NAME`` (a unified diff)."""
    m = _NAME.match(name)
    module = m["module"] if m else name.rsplit(".", 1)[0]
    function = (f"{m['cls']}.{m['func']}" if m and m["cls"] else m["func"]) if m else "?"
    mutant = Mutant(name=name, status=status, module=module, function=function)
    for line in shown.splitlines():
        if line.startswith(("---", "+++", "# ")):
            continue
        if line.startswith("-"):
            mutant.before.append(line[1:].strip())
        elif line.startswith("+"):
            mutant.after.append(line[1:].strip())
    return mutant


def load_equivalents() -> dict[tuple, str]:
    """Judged survivors: ``[[equivalent]]`` tables with module, function, before, after and
    reason (the lines as ``mutmut show`` prints them, stripped), from ``equivalent.toml`` and
    the files of ``equivalent/`` (one per area, so sessions judging different modules do not
    edit one file)."""
    files = [EQUIVALENTS] + sorted(EQUIVALENTS.with_suffix("").glob("*.toml"))
    table = [e for f in files if f.is_file()
             for e in tomllib.loads(f.read_text()).get("equivalent", [])]
    return {(e["module"], e["function"], e["before"], e["after"]): e["reason"] for e in table}
