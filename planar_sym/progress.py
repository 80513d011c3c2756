"""Progress lines for work that takes seconds (deriving, compiling, validating, simulating).

Shown on standard error, and only when it is a terminal: a pipe, a log file or a CI job gets
nothing, so captured output stays exactly the results. ``--quiet`` silences it too.

.. code:: python

    progress = Progress(len(robots), quiet=args.quiet)
    for robot in robots:
        progress.step(f"deriving {robot}")    # "[2/5] deriving serial_3dof ..."
        ...
    progress.done()                            # "done: 5 in 9.8 s"
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterable, Iterator
from typing import TextIO, TypeVar

T = TypeVar("T")


def wanted(stream: TextIO | None = None, quiet: bool = False) -> bool:
    """Whether progress goes to ``stream`` (default standard error): a terminal, not quiet."""
    stream = sys.stderr if stream is None else stream
    if quiet:
        return False
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or a closed stream: not a terminal
        return False


class Progress:
    """Counts steps of a known total and prints one line per step (when ``wanted``)."""

    def __init__(self, total: int, *, quiet: bool = False, stream: TextIO | None = None):
        # resolved now, not at import: pytest and callers swap sys.stderr at run time
        self.stream = sys.stderr if stream is None else stream
        self.enabled = wanted(self.stream, quiet)
        self.total = total
        self.count = 0
        self.start = time.perf_counter()

    def _print(self, text: str) -> None:
        if self.enabled:
            print(text, file=self.stream, flush=True)

    def step(self, what: str) -> None:
        """Announce the next step *before* it runs, so a slow step shows what it is doing."""
        self.count += 1
        self._print(f"[{self.count}/{self.total}] {what} ...")

    def note(self, text: str) -> None:
        self._print(f"      {text}")

    def done(self) -> None:
        self._print(f"done: {self.count} in {time.perf_counter() - self.start:.1f} s")


def track(items: Iterable[T], what: str, *, quiet: bool = False,
          stream: TextIO | None = None) -> Iterator[T]:
    """Iterate over ``items``, one progress line each: ``[k/N] {what} {item} ...``."""
    items = list(items)
    progress = Progress(len(items), quiet=quiet, stream=stream)
    for item in items:
        progress.step(f"{what} {item}")
        yield item
    progress.done()
