"""A sweep's figures against a varied parameter: one axis per figure, units in the labels (from
the table's typed columns, ``SweepResult.info``)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..analysis.sweep import SweepResult
from ..errors import InputError
from .plots import new_figure, tight


def label(result: SweepResult, column: str) -> str:
    """``peak_tau1_n_m`` -> ``peak_tau1 (N*m)``: the column's stem, its unit in brackets, from
    its typed entry in ``result.info`` (the bare name for a pure number, or a column the
    result does not type)."""
    figure = result.info.get(column)
    return column if figure is None else figure.label


def sweep_figure(result: SweepResult, x: str | None = None, figures=None):
    """Figures (default: the peak torques, or every figure if there are none) against the
    varied parameter ``x`` (default the first that changes: a control sweep on the plant only
    holds the model's column); with a second varied parameter on a grid, one line per its
    value (at most 8, else points). A column that holds one value is no dimension. Designs
    over an actuator limit (``over_limits``) are ringed in red."""
    x = x or next((v for v in result.varied if _changes(result.columns[v])), result.varied[0])
    if x not in result.columns:
        raise InputError(f"no column {x!r} in the sweep (columns: {', '.join(result.columns)})")
    figs = list(figures or [f for f in result.figures if _peak_torque(result, f)]
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
                        label=None if group is None else
                        f"{label(result, group)} = {level:.4g}")
        else:
            sc = ax.scatter(xs, ys, c=result.columns[group], s=6)
            fig.colorbar(sc, ax=ax, label=label(result, group))
        over = np.array(sorted(result.over_limits), dtype=int)
        if len(over):
            ax.scatter(xs[over], ys[over], s=40, facecolors="none", edgecolors="red", zorder=5,
                       label="over an actuator limit" if ax is axes[0] else None)
        ax.set_ylabel(label(result, name))
        ax.grid(True, alpha=0.3)
    if (lines and group is not None) or len(result.over_limits):
        axes[0].legend(fontsize=7)
    axes[-1].set_xlabel(label(result, x))
    failed = f", {len(result.failed)} failed" if result.failed else ""
    if result.over_limits:
        failed += f", {len(result.over_limits)} over an actuator limit"
    axes[0].set_title(f"sweep of {result.study}: {len(result)} designs{failed}", fontsize=9)
    tight(fig)
    return fig


def _peak_torque(result: SweepResult, column: str) -> bool:
    """Whether ``column`` is a joint's peak torque (the default figures)."""
    figure = result.info.get(column)
    return figure is not None and (figure.statistic, figure.quantity) == ("peak", "tau")


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


