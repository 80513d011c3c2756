"""Atlases of several robots side by side, on one scale: which reaches further, and which has
singular poses inside its workspace (``planar-sym atlas ROBOT ROBOT ... --out DIR``)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..analysis.atlas import Atlas
from .atlas_plots import OTHER, SAME, _frame, _loci, _map, scale
from .plots import new_figure, tight


def compare_figure(atlases: list[Atlas]):
    """One row per atlas: its reachable region (start assembly mode shaded apart) with both
    singular loci, and its dexterity; every panel on the same x and y limits, in the first
    robot's length unit, so sizes compare by eye. The first orientation of robots with one."""
    from matplotlib.colors import ListedColormap

    fig = new_figure((10.0, 4.2 * len(atlases)))
    axes = fig.subplots(len(atlases), 2, squeeze=False)
    atlases = [replace(a, length_unit=atlases[0].length_unit) for a in atlases]  # one scale
    k = scale(atlases[0])
    lo = np.min([[a.x_m[0], a.y_m[0]] for a in atlases], axis=0) * k
    hi = np.max([[a.x_m[-1], a.y_m[-1]] for a in atlases], axis=0) * k
    for row, a in zip(axes, atlases):
        s = a.summary()
        kind = np.where(a.reachable[0], a.same_assembly[0].astype(float), np.nan)
        dx, dy = (a.x_m[1] - a.x_m[0]) / 2 * k, (a.y_m[1] - a.y_m[0]) / 2 * k
        extent = [a.x_m[0] * k - dx, a.x_m[-1] * k + dx, a.y_m[0] * k - dy,
                  a.y_m[-1] * k + dy]
        row[0].imshow(np.ma.masked_invalid(kind), origin="lower", extent=extent,
                      cmap=ListedColormap([OTHER, SAME]), vmin=0, vmax=1,
                      interpolation="nearest")
        _loci(row[0], a, 0)
        same = s.get("area_same_assembly_m2", np.nan) * 1e4
        _frame(row[0], a, f"{a.robot}: {s['area_m2'] * 1e4:.4g} cm^2 reachable, "
                          f"{same:.4g} cm^2 in the start assembly mode", None)
        _map(fig, row[1], a, a.dexterity, 0, "dexterity 1/cond J_x (-)", "viridis")
        _frame(row[1], a, f"{a.robot}: dexterity (red: Type II singular)", None)
        for ax in row:
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
    fig.suptitle("blue: reachable in the start pose's assembly mode; orange: in the other; "
                 "dashed: Type I (workspace edge); red: Type II", fontsize=9)
    tight(fig)
    return fig
