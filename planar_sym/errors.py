"""Errors a user sees: each names the file, field, time or sample at fault."""

from __future__ import annotations


class PlanarSymError(Exception):
    """Base class of every error this package raises on purpose."""


class DescriptionError(PlanarSymError):
    """A robot description with problems; ``problems`` lists every one, each naming its field."""

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        super().__init__("invalid robot description:\n  " + "\n  ".join(self.problems))


class LibraryError(PlanarSymError):
    """Generated code or compiled library missing, stale or corrupt; says which command fixes it."""


class InputError(PlanarSymError, ValueError):
    """Bad runtime input: wrong shape, NaN or infinite value (names the sample)."""


class SeriesNotFound(InputError, KeyError):
    """No one series of a result matches the quantity, coordinate or joint asked for (a KeyError
    too, for code that catches that); the message names those there are."""

    __str__ = Exception.__str__  # KeyError's would print the message quoted, as a key


class WorkspaceError(PlanarSymError, ValueError):
    """A task-space target the robot cannot reach (names the time and the target)."""


class SimulationError(PlanarSymError, RuntimeError):
    """The integrator failed; names the time it happened."""


def warn_caller(text: str, category: type[Warning] = RuntimeWarning) -> None:
    """A warning shown at the first frame outside this package (the user's line), however
    deep the route that found the problem."""
    import sys
    import warnings
    from pathlib import Path

    here, level, frame = str(Path(__file__).resolve().parent), 2, sys._getframe(1)
    while frame is not None and str(Path(frame.f_code.co_filename).resolve()).startswith(here):
        frame, level = frame.f_back, level + 1
    warnings.warn(text, category, stacklevel=level)
