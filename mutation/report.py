"""``MUTATION.md``: one section per target (replaced when the target is run again) and a table of
every target's score at the top, rebuilt from the sections' summary lines."""

from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from .classify import Mutant

KILLED = ("killed", "timeout", "segfault", "caught by type check")
HEAD = """# Mutation testing

Made by `make mutate TARGET=...` (`python -m mutation`, mutmut underneath): each mutant is one
small planted bug (an operator, a number, a dropped call, a changed string) in a copy of the
package, tested by the target's test files (`mutation/targets.toml`). A mutant is *killed* when a
test fails (or times out), *survived* when every covering test passes, *no tests* when no listed
test reaches the function. The score is killed / all. Each survivor is listed with its change and
either the reason it is equivalent (`mutation/equivalent.toml` or a file of `mutation/equivalent/`, judged by a developer) or
"unexplained" (a test to write). Survivors that change only a message's wording are marked
"text"; they are counted like the others.

| target | mutants | killed | survived | no tests | score | survivors explained | run | commit |
|---|---|---|---|---|---|---|---|---|
"""


@dataclass
class Outcome:
    target: str
    tests: list[str]
    statuses: dict[str, str]
    survivors: list[Mutant]
    seconds: float
    commit: str

    def counts(self) -> Counter:
        return Counter(self.statuses.values())

    def score(self) -> float:
        c = self.counts()
        total = sum(c.values()) - c["skipped"] - c["not checked"]
        return sum(c[k] for k in KILLED) / total if total else float("nan")

    def summary_line(self) -> str:
        c = self.counts()
        explained = sum(m.reason is not None for m in self.survivors)
        return (f"| `{self.target}` | {sum(c.values())} | {sum(c[k] for k in KILLED)} | "
                f"{c['survived']} | {c['no tests']} | {100 * self.score():.1f}% | "
                f"{explained} of {len(self.survivors)} | {self.seconds / 60:.1f} min | "
                f"{self.commit} |")

    def section(self) -> str:
        lines = [f"<!-- mutation: {self.target} -->", f"## `{self.target}`", "",
                 f"Tests: {', '.join(f'`{t}`' for t in self.tests)}.", "",
                 f"<!-- summary {self.summary_line()} -->", ""]
        c = self.counts()
        lines.append("Outcomes: " + ", ".join(f"{k} {v}" for k, v in sorted(c.items())) + ".")
        text = sum(m.text_only for m in self.survivors)
        lines += ["", f"Survivors: {len(self.survivors)} ({text} text only).", ""]
        for m in self.survivors:
            why = m.reason or "unexplained"
            kind = "text" if m.text_only else "code"
            lines.append(f"- `{m.function}` ({m.status}, {kind}): `{' / '.join(m.before)}` -> "
                         f"`{' / '.join(m.after)}`: {why}")
        lines += ["", f"<!-- end mutation: {self.target} -->", ""]
        return "\n".join(lines)


_SECTION = re.compile(r"<!-- mutation: (?P<t>\S+) -->.*?<!-- end mutation: (?P=t) -->\n?", re.DOTALL)
_SUMMARY = re.compile(r"<!-- summary (?P<row>\|.*\|) -->")


def write_section(path: Path, outcome: Outcome) -> None:
    """Replace (or add) the target's section and rebuild the table; written atomically."""
    old = path.read_text() if path.is_file() else ""
    sections = {m["t"]: m.group(0).rstrip("\n") + "\n" for m in _SECTION.finditer(old)}
    sections[outcome.target] = outcome.section()
    rows = [_SUMMARY.search(sections[t])["row"] for t in sorted(sections)]
    body = HEAD + "\n".join(rows) + "\n\n" + "\n".join(sections[t] for t in sorted(sections))
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(body)
    tmp.replace(path)
