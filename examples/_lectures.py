"""Shared by the lecture scripts: their options, equation lines and optional plots.

Every lecture takes ``--samples N`` (default: each scenario's own) and ``--plot DIR`` (default:
the environment variable ``PLANAR_SYM_PLOTS``; unset, no file is written).
"""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from planar_sym.model.folders import find_generated
from planar_sym.study.result import Result


def options(doc: str) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--samples", type=int, default=None,
                    help="samples per scenario (default: the scenario's own)")
    ap.add_argument("--plot", type=Path, default=os.environ.get("PLANAR_SYM_PLOTS") or None,
                    help="save each scenario's figure as DIR/<scenario>.png "
                         "(default: $PLANAR_SYM_PLOTS; unset: no files)")
    return ap.parse_args()


def equation_lines(text: str, labels: tuple[str, ...]) -> list[str]:
    """The equations ``label = ...`` of an equations.txt, each with its continuation lines (the
    more deeply indented lines after it), in the file's order."""
    out: list[str] = []
    keep_indent = None  # indentation of the equation being copied, None when not copying
    for line in text.splitlines():
        indent = len(line) - len(line.lstrip())
        if keep_indent is not None and line.strip() and indent > keep_indent:
            out.append(line[keep_indent:])
            continue
        keep_indent = indent if line.strip().split(" = ", 1)[0] in labels else None
        if keep_indent is not None:
            out.append(line.strip())
    return out


def equations(robot: str, labels: tuple[str, ...]) -> list[str]:
    """Those lines of ``generated/<robot>/equations.txt``, before its identification sections
    (their alpha, beta, ... in base parameters printed a second definition under the first, with
    no heading between: a lecturer's trial)."""
    text = (find_generated(robot) / "equations.txt").read_text()
    return equation_lines(text.split("\nBase parameters", 1)[0], labels)


def print_equations(robot: str, labels: tuple[str, ...]) -> None:
    print(f"Closed-form equations (planar-sym equations {robot}):")
    for line in equations(robot, labels):
        print(f"  {line}")
    print()


def report(result: Result, plot_dir: Path | None) -> None:
    """Peak |torque| per joint (one parsable line each), the note, and the figure if asked."""
    for key, value in result.peak_torques().items():
        print(f"{result.name}: peak |{key}| = {value:.12g} N*m")
    if result.note:
        print(f"{result.name}: {result.note}")
    if plot_dir is not None:
        from planar_sym.outputs.plots import save_figure

        plot_dir.mkdir(parents=True, exist_ok=True)
        save_figure(result, plot_dir / f"{result.name}.png")
        print(f"{result.name}: figure {plot_dir / (result.name + '.png')}")


def report_forces(result: Result) -> None:
    """Peak magnitude of the reaction force at each cut joint (closed chains)."""
    for key in [k for k in result.columns if k.startswith("fx_")]:
        joint = key[3:-2]
        f = (result.columns[key] ** 2 + result.columns[f"fy_{joint}_n"] ** 2) ** 0.5
        print(f"{result.name}: peak |force at cut joint {joint}| = {f.max():.6g} N")
