"""A sweep's figures against a varied parameter: one axis per figure, units in the labels."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..analysis.sweep import SweepResult
from ..errors import InputError
from .plots import new_figure, tight

#: column suffix -> unit as a label shows it
_UNITS = {"n_m": "N*m", "n": "N", "kg": "kg", "kg_m2": "kg*m^2", "m": "m", "m_s2": "m/s^2",
          "j": "J", "mm": "mm", "m2": "m^2", "rad": "rad", "rpm": "rpm", "w": "W"}


def label(column: str) -> str:
    """``peak_tau1_n_m`` -> ``peak_tau1 (N*m)``: the name, its unit in brackets."""
    for suffix in sorted(_UNITS, key=len, reverse=True):
        if column.endswith("_" + suffix):
            return f"{column[:-len(suffix) - 1]} ({_UNITS[suffix]})"
    return column


def sweep_figure(result: SweepResult, x: str | None = None, figures=None):
    """Figures (default: the peak torques, or every figure if there are none) against the
    varied parameter ``x`` (default the first that changes: a control sweep on the plant only
    holds the model's column); with a second varied parameter on a grid, one line per its
    value (at most 8, else points). A column that holds one value is no dimension."""
    x = x or next((v for v in result.varied if _changes(result.columns[v])), result.varied[0])
    if x not in result.columns:
        raise InputError(f"no column {x!r} in the sweep (columns: {', '.join(result.columns)})")
    figs = list(figures or [f for f in result.figures if f.startswith("peak_tau")]
                or result.figures)
    missing = [f for f in figs if f not in result.columns]
    if missing or not figs:
        raise InputError(f"no figure {', '.join(missing) or '(none)'} in the sweep (figures: "
                         f"{', '.join(result.figures)})")
    xs = result.columns[x]
    # a parameter tied to x (the same values) is not a second dimension
    others = [v for v in result.varied if v != x and not np.array_equal(result.columns[v], xs)
              and _changes(result.columns[v])]
    group = others[0] if others else None
    levels = np.unique(result.columns[group]) if group else np.array([np.nan])
    lines = group is None or len(levels) <= 8
    fig = new_figure((7, 1.2 + 2.0 * len(figs)))
    axes = fig.subplots(len(figs), 1, sharex=True, squeeze=False)[:, 0]
    for ax, name in zip(axes, figs):
        ys = result.columns[name]
        if lines:
            for level in levels:
                pick = np.ones(len(xs), bool) if group is None else result.columns[group] == level
                order = np.argsort(xs[pick], kind="stable")
                ax.plot(xs[pick][order], ys[pick][order], marker=".",
                        label=None if group is None else f"{label(group)} = {level:.4g}")
        else:
            sc = ax.scatter(xs, ys, c=result.columns[group], s=6)
            fig.colorbar(sc, ax=ax, label=label(group))
        ax.set_ylabel(label(name))
        ax.grid(True, alpha=0.3)
    if lines and group is not None:
        axes[0].legend(fontsize=7)
    axes[-1].set_xlabel(label(x))
    failed = f", {len(result.failed)} failed" if result.failed else ""
    axes[0].set_title(f"sweep of {result.study}: {len(result)} designs{failed}", fontsize=9)
    tight(fig)
    return fig


def _changes(values: np.ndarray) -> bool:
    return len(values) > 0 and bool(np.any(values != values[0]))


def write_sweep(result: SweepResult, csv: Path | None, png: Path | None, x: str | None = None,
                figures=None) -> list[Path]:
    """The table (CSV) and the figure (PNG), whole or not at all."""
    from ..files import atomic_files

    targets = [p for p in (csv, png) if p is not None]
    fig = sweep_figure(result, x, figures) if png is not None else None
    with atomic_files(targets) as temps:
        for target, tmp in zip(targets, temps):
            if target == csv:
                tmp.write_text(result.csv_text())
            else:
                fig.savefig(tmp, dpi=100, format="png")
    return targets


