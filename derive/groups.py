"""Compile groups: which generated functions are compiled together, and so when.

A robot whose functions hold up to ``GROUP_PAST_OPS`` operations in all compiles as one group:
one exact library and one library of sample loops, built on first use of the robot (a few
seconds; every built-in robot, the largest the 3-RRR with 4,282 operations, and so each is
compiled at install). Past that (a chain of six links) every function is a group of its own,
compiled the first time it is called: a user asking for torques waits for the inverse dynamics
alone, not for the forward dynamics' Jacobian (three quarters of a 20-link chain's operations,
needed only by implicit integrators and linearisation) or the regressor; and no compiler
process ever holds more than one function.

The exact file guards each function's section (CasADi's ``casadi_f<k>`` with its public entry
points, and its ``_batch`` wrapper) with ``PLANAR_SYM_GROUP``; each group compiles as its own
shared library, so the shared preamble (sparsity patterns, helpers, the input hash) is simply
in every one. A whole-file build (no ``-DPLANAR_SYM_GROUP``) holds every function, as before.
"""

from __future__ import annotations

import re

#: operations of all functions past which each function compiles as its own group, on first
#: use: below it the whole robot compiles in a few seconds, and one library loads fastest
GROUP_PAST_OPS = 5000

#: defines PLANAR_SYM_ALL: 1 in a whole-file build, 0 when one group is compiled
EXACT_PRELUDE = """/* compile groups: built whole, or one group per -DPLANAR_SYM_GROUP=k (the manifest's
   groups), each its own library holding some of the functions */
#ifdef PLANAR_SYM_GROUP
#define PLANAR_SYM_ALL 0
#else
#define PLANAR_SYM_ALL 1
#define PLANAR_SYM_GROUP 0
#endif
"""

_SECTION = re.compile(r"^static int casadi_f\d+\(", re.MULTILINE)
_END = '#ifdef __cplusplus\n} /* extern "C" */'


def assign(operations: dict[str, int], past: int | None = None) -> list[list[str]]:
    """The groups, in manifest order: all functions in one, or (past ``past`` operations in
    all, default ``GROUP_PAST_OPS``) one function each."""
    past = GROUP_PAST_OPS if past is None else past
    names = list(operations)
    if sum(operations.values()) <= past:
        return [names]
    return [[q] for q in names]


def guard(body: str, symbols: dict[str, str], group_of: dict[str, int]) -> str:
    """CasADi's file ``body`` with each function's section compiled only in its group.

    ``symbols`` maps each quantity to its C name. A section runs from its ``casadi_f<k>`` to
    the next one (or the file's closing ``extern "C"``); it is the function whose entry point
    ``<name>(const casadi_real** arg`` it defines.
    """
    starts = [m.start() for m in _SECTION.finditer(body)]
    end = body.rfind(_END)
    if not starts or end < starts[-1]:
        raise ValueError("CasADi's generated C is not laid out as derive/groups.py expects "
                         "(casadi_f<k> sections, then the closing extern \"C\")")
    by_name = {name: q for q, name in symbols.items()}
    out = [body[:starts[0]]]
    for a, b in zip(starts, [*starts[1:], end]):
        section = body[a:b]
        found = [by_name[m.group(1)] for m in re.finditer(
            r"^CASADI_SYMBOL_EXPORT int (\w+)\(const casadi_real\*\* arg", section, re.MULTILINE)
            if m.group(1) in by_name]
        if len(found) != 1:
            raise ValueError(f"a section of CasADi's generated C defines {len(found)} of the "
                             "robot's functions, not one")
        out.append(within(group_of[found[0]], section))
    return "".join(out) + body[end:]


def within(group: int, source: str) -> str:
    """``source`` compiled only in group ``group`` (and in a whole-file build)."""
    return f"#if PLANAR_SYM_ALL || PLANAR_SYM_GROUP == {group}\n{source}#endif\n"
