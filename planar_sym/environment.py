"""The environment variables planar-sym reads, each checked by one rule: a flag is 0 or 1 (or
unset), never silently read as "off"; an unknown ``PLANAR_SYM_`` name (a typo such as
``PLANAR_SYM_CACH``) is warned about, never ignored without a word."""

from __future__ import annotations

import os
import warnings

from .errors import InputError

#: every variable the package, its tests and examples read, and what it does
KNOWN = {
    "PLANAR_SYM_CACHE": "the folder of compiled libraries and derived robots",
    "PLANAR_SYM_GENERATED": "more folders of generated robots (separated by the path separator)",
    "PLANAR_SYM_EXACT": "1: CasADi's exact evaluator instead of the compiled C callers",
    "PLANAR_SYM_PREBUILT": "0: compile built-in robots into the cache, not the installed "
                           "libraries",
    "PLANAR_SYM_PLOTS": "the folder the lecture examples write their plots to",
    "PLANAR_SYM_REQUIRE_BROWSER": "1: the test of the HTML page must run, not skip (make test)",
    "PLANAR_SYM_FUZZ_CASES": "how many cases the command-line fuzzer of the tests runs",
}

#: the flags among them: 0 or 1
FLAGS = ("PLANAR_SYM_EXACT", "PLANAR_SYM_PREBUILT", "PLANAR_SYM_REQUIRE_BROWSER")


def flag(name: str) -> bool | None:
    """A flag's value: True (1), False (0), or None when unset or empty; anything else raises
    InputError naming the variable, its value and what it does."""
    value = os.environ.get(name, "")
    if value == "":
        return None
    if value in ("0", "1"):
        return value == "1"
    raise InputError(f"environment variable {name}={value!r} must be 0 or 1 ({KNOWN[name]})")


def check() -> None:
    """Every flag set in the environment checked, and a warning for each unknown
    ``PLANAR_SYM_`` variable (what the command line does first)."""
    for name in FLAGS:
        flag(name)
    for name in sorted(os.environ):
        if name.startswith("PLANAR_SYM_") and name not in KNOWN:
            warnings.warn(f"unknown environment variable {name} is not read by planar-sym "
                          f"(known: {', '.join(sorted(KNOWN))})", stacklevel=2)
