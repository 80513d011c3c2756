"""Misspelt names: the nearest known one, and a misspelt key read as the key it nearly is.

One mistake gives one message: ``[motoin]`` for ``[motion]``, or ``mas`` for ``mass``, used to
give the unknown key and then every field it holds as missing (six messages for one typo). A
key whose nearest known key (difflib, similarity at least ``CUTOFF``) is not in the table too
is reported once, "did you mean", and moved to that key for the checks that follow, so its
contents are checked where they belong; the file is still refused.
"""

from __future__ import annotations

import difflib
from collections.abc import Callable, Iterable

#: difflib's similarity ratio a name must reach to be suggested: one letter wrong, missing,
#: extra or two swapped in a word of five or more letters
CUTOFF = 0.75


def nearest(name: str, known: Iterable[str]) -> str | None:
    """The known name ``name`` most likely misspells, or None."""
    found = difflib.get_close_matches(name, sorted(known), n=1, cutoff=CUTOFF)
    return found[0] if found else None


def did_you_mean(name: str, known: Iterable[str]) -> str:
    """``"; did you mean 'x'?"`` for the nearest known name, or ``""``."""
    guess = nearest(name, known)
    return f"; did you mean {guess!r}?" if guess is not None else ""


def unknown_keys(table: dict, known: Iterable[str], report: Callable[[str, str], None]) -> None:
    """``report(key, message)`` for each key of ``table`` not in ``known``; a likely misspelling
    of a known key that ``table`` lacks is moved to that key (``table`` is changed: give a
    copy of the user's) and reported once."""
    known = sorted(known)
    for key in sorted(set(table) - set(known)):
        guess = nearest(key, known)
        if guess is not None and guess not in table:
            table[guess] = table.pop(key)
            report(key, f"unknown key: did you mean {guess!r}? (checked as {guess} below)")
        else:
            report(key, f"unknown key (known: {', '.join(known)})")
