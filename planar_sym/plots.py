"""Figures like the seed's Scope windows: one axis per joint, quantities and units labelled."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .results import Result


def figure(result: Result):
    """A matplotlib Figure of a result (joint angles in deg, or torques in N*m, against t in s)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    if result.plot == "angles":
        keys = [k for k in result.columns if k.startswith("q") and k[1:].isdigit()]
        label, scale = "joint angle {} (deg)", 180 / np.pi
    else:
        keys = [k for k in result.columns if k.startswith("tau") and k[3:].isdigit()]
        label, scale = "torque {} (N*m)", 1.0
    fig, axes = plt.subplots(len(keys), 1, sharex=True, figsize=(7, 1.0 + 1.9 * len(keys)),
                             squeeze=False)
    t = result.columns["t"]
    for ax, key in zip(axes[:, 0], keys):
        ax.plot(t, result.columns[key] * scale, lw=1.6)
        ax.set_ylabel(label.format(key))
        ax.grid(True, alpha=0.4)
    axes[-1, 0].set_xlabel("time t (s)")
    fig.suptitle(f"{result.name}\n{result.summary}", fontsize=9)
    if result.note:
        fig.text(0.01, 0.005, result.note, fontsize=7, alpha=0.7)
    fig.tight_layout()
    return fig


def save_figure(result: Result, path: Path) -> None:
    import matplotlib.pyplot as plt

    fig = figure(result)
    try:
        fig.savefig(path, dpi=110, format="png")
    finally:
        plt.close(fig)
