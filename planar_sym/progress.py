"""Progress lines for work that takes seconds (deriving, compiling, validating, simulating,
writing an animation, sweeping designs).

Shown on standard error, and only when it is a terminal: a pipe, a log file or a CI job gets
nothing, so captured output stays exactly the results. ``--quiet`` silences it too.

.. code:: python

    progress = Progress(len(robots), quiet=args.quiet)
    for robot in robots:
        progress.step(f"deriving {robot}")    # "[2/5] deriving serial_3dof ..."
        ...
    progress.done()                            # "done: 5 in 9.8 s"

    meter = Meter(frames, "writing s3.gif")    # one job counted in units: one line,
    for k in range(frames):                    # rewritten in place on a terminal
        ...
        meter(k + 1)                           # "writing s3.gif: 31/60 (51 %)"
    meter.close()                              # "writing s3.gif: 60/60 in 12.3 s"
"""

from __future__ import annotations

import sys
import time
from collections.abc import Iterable, Iterator
from contextvars import ContextVar
from typing import TextIO, TypeVar

T = TypeVar("T")


#: the command line's ``--quiet`` for lines no caller can pass it to (``announce``): set for
#: the length of one command (``cli.main``)
QUIET = False


def wanted(stream: TextIO | None = None, quiet: bool = False) -> bool:
    """Whether progress goes to ``stream`` (default standard error): a terminal, not quiet."""
    stream = sys.stderr if stream is None else stream
    if quiet or QUIET:
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


def announce(text: str, *, stream: TextIO | None = None) -> None:
    """One line before a wait no caller sees coming (a big robot's function compiled the first
    time it is called): ``text ...``, when ``wanted``."""
    stream = sys.stderr if stream is None else stream
    if wanted(stream):
        print(f"{text} ...", file=stream, flush=True)


def track(items: Iterable[T], what: str, *, quiet: bool = False,
          stream: TextIO | None = None) -> Iterator[T]:
    """Iterate over ``items``, one progress line each: ``[k/N] {what} {item} ...``."""
    items = list(items)
    progress = Progress(len(items), quiet=quiet, stream=stream)
    for item in items:
        progress.step(f"{what} {item}")
        yield item
    progress.done()


#: a Meter rewrites its line at most this often (s): a terminal is not flooded
INTERVAL_S = 0.5


class Meter:
    """Progress of one long job counted in units (frames, designs): one line on a terminal
    (``wanted``), rewritten in place at most every ``INTERVAL_S``; call it with the units done
    (it is the ``progress`` callback the animation and the sweep take), then ``close``."""

    def __init__(self, total: int, what: str, *, quiet: bool = False,
                 stream: TextIO | None = None):
        self.stream = sys.stderr if stream is None else stream
        self.enabled = wanted(self.stream, quiet)
        self.total, self.what, self.done = total, what, 0
        self.start = time.perf_counter()
        self._shown = -INTERVAL_S

    def __call__(self, done: int, total: int | None = None) -> None:
        """``done`` units so far (of ``total``, where the caller knows it better)."""
        self.done = done
        self.total = self.total if total is None else total
        now = time.perf_counter() - self.start
        if self.enabled and self.total > 0 and (now - self._shown >= INTERVAL_S
                                                or done >= self.total):
            self._shown = now
            print(f"\r{self.what}: {done}/{self.total} ({100 * done // self.total} %)", end="",
                  file=self.stream, flush=True)

    def close(self) -> None:
        """End the line with the count and the time taken."""
        if self.enabled and self.total > 0:
            print(f"\r{self.what}: {self.done}/{self.total} in "
                  f"{time.perf_counter() - self.start:.1f} s", file=self.stream, flush=True)


#: a simulation shows its clock only once it has run this long (s): short runs print nothing
DELAY_S = 1.0


class Clock:
    """Progress of a simulation in simulated time, one line rewritten in place on a terminal:
    ``S1: simulating, t = 2.4 of 10 s (24 %)``. Call it with the time reached and the end time
    (it is the ``progress`` callback ``simulate`` and ``simulate_controlled`` take), then
    ``close``. Nothing is printed before ``DELAY_S`` of wall time, so quick runs stay silent."""

    def __init__(self, what: str, *, quiet: bool = False, stream: TextIO | None = None):
        self.stream = sys.stderr if stream is None else stream
        self.enabled = wanted(self.stream, quiet)
        self.what = what
        self.start = time.perf_counter()
        self._shown = None  # wall time of the last line, None before the first

    def __call__(self, t_s: float, t_end_s: float) -> None:
        now = time.perf_counter() - self.start
        if not self.enabled or now < DELAY_S or (self._shown is not None
                                                 and now - self._shown < INTERVAL_S):
            return
        self._shown = now
        share = 100 * t_s / t_end_s if t_end_s > 0 else 100
        print(f"\r{self.what}, t = {t_s:.4g} of {t_end_s:.4g} s ({share:.0f} %)", end="",
              file=self.stream, flush=True)

    def close(self) -> None:
        """End the line (if one was shown) with the wall time taken."""
        if self._shown is not None:
            print(f"\r{self.what}: done in {time.perf_counter() - self.start:.1f} s"
                  + " " * 20, file=self.stream, flush=True)
            self._shown = None


#: the clock of the run under way (see ``watching``); a context variable, so threads and
#: tasks each see their own
_AMBIENT: ContextVar = ContextVar("planar_sym_clock", default=None)


class watching:
    """``with watching(clock):`` every simulation run inside reports to ``clock`` unless given
    its own ``progress``: the command line sets it once around a study instead of passing a
    callback down through every layer of the study runner."""

    def __init__(self, clock):
        self.clock = clock

    def __enter__(self):
        self._token = _AMBIENT.set(self.clock)
        return self.clock

    def __exit__(self, *exc):
        _AMBIENT.reset(self._token)
        if hasattr(self.clock, "close"):
            self.clock.close()


def ambient():
    """The innermost ``watching`` clock, or None."""
    return _AMBIENT.get()
