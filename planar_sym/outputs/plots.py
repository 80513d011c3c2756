"""Figures like the seed's Scope windows: one axis per joint, quantities and units labelled.

Figures are made with ``matplotlib.figure.Figure``, never through pyplot, and rendered by Agg when
saved: no display is needed, nothing is registered globally (no figure to close, safe in
threads), and a notebook still shows a returned Figure.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ..dynamics.inverse import SPLIT_PARTS
from ..study.result import Result

#: colours of the split parts (plotting order of dynamics.inverse.SPLIT_PARTS), total in black
SPLIT_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple")


def new_figure(figsize: tuple[float, float]):
    """An empty Figure (inches), outside pyplot.

    Its canvas is matplotlib's base canvas, which never draws by itself: ``savefig`` (and an
    animation writer's frame grab) renders with Agg, exactly once per image. An Agg canvas
    would also redraw on every ``draw_idle`` of an animation, about 1.7 times the work.
    """
    from matplotlib.figure import Figure

    return Figure(figsize=figsize)


def tight(fig) -> None:
    """``tight_layout`` once, then no layout engine.

    ``tight_layout`` leaves a placeholder engine behind, and with any engine set every
    ``savefig`` lays the figure out again in an extra draw pass: twice the text layout work per
    animation frame.
    """
    fig.tight_layout()
    fig.set_layout_engine(None)


def _axes(n: int):
    fig = new_figure((7, 1.0 + 1.9 * n))
    axes = fig.subplots(n, 1, sharex=True, squeeze=False)[:, 0]
    return fig, axes


def _finish(fig, axes, result: Result, title: str) -> None:
    import textwrap

    axes[-1].set_xlabel("time t (s)")
    fig.suptitle(f"{result.name}\n{title}", fontsize=9)
    lines = textwrap.wrap(result.note, 120)
    if lines:
        fig.text(0.01, 0.005, "\n".join(lines), fontsize=7, alpha=0.7, va="bottom")
    # leave room for the note under the axes: 7 pt lines, about 0.12 in each
    fig.tight_layout(rect=(0, 0.12 * len(lines) / fig.get_figheight(), 1, 1))
    fig.set_layout_engine(None)


#: a joint's bearing load column: jload_<joint>_n, |F| in N (study.run.load_columns)
JOINT_LOAD = re.compile(r"^jload_(\w+)_n$")


def figure(result: Result):
    """A matplotlib Figure of a result (joint angles in deg, or torques in N*m, against t in s).

    Below the torques of an inverse-dynamics result, one more axis: every joint's bearing load
    ``|F|`` (N), the ``jload_<joint>_n`` columns.
    """
    if result.kind == "control":
        return control_figure(result)
    if result.kind == "angles":
        series, label, scale = result.angles(), "joint angle {} (deg)", 180 / np.pi
    else:
        series, label, scale = result.torques(), "torque {} (N*m)", 1.0
    loads = {m.group(1): v for k, v in result.columns.items() if (m := JOINT_LOAD.match(k))}
    fig, axes = _axes(len(series) + bool(loads))
    t = result.columns["t_s"]
    for ax, (key, values) in zip(axes, series.items()):
        # a prismatic joint: a force tau<k>_n (N), a displacement q<k>_m (drawn in mm)
        force = key.endswith("_m" if result.kind == "angles" else "_n")
        ax.plot(t, values * (1e3 if result.kind == "angles" and force else scale), lw=1.6)
        which = key.split("_")[0]
        ax.set_ylabel((f"joint {which} (mm)" if result.kind == "angles" else f"force {which} (N)")
                      if force else label.format(which))
        ax.grid(True, alpha=0.4)
    if loads:
        ax = axes[-1]
        for joint, values in loads.items():
            ax.plot(t, values, lw=1.3, label=joint)
        ax.set_ylabel("joint load |F| (N)")
        ax.grid(True, alpha=0.4)
        ax.legend(fontsize=7, ncol=min(len(loads), 5), loc="best")
    _finish(fig, axes, result, result.summary)
    return fig


def control_figure(result: Result):
    """A control study: per actuated joint its reference (dashed) and actual motion (deg, or
    mm for a slider); the tracking errors; the commanded (dashed) and applied torques (N*m or
    N); and, for a robot with a tool point, the tool's distance from its reference (mm)."""
    cols, t = result.columns, result.columns["t_s"]
    act = list(result.actuated)
    task = "e_task_mm" in cols
    fig, axes = _axes(len(act) + 2 + task)
    for ax, i in zip(axes, act):
        slider = f"q{i + 1}_m" in cols
        unit, scale = ("m", 1e3) if slider else ("rad", 180 / np.pi)
        ax.plot(t, cols[f"q{i + 1}_ref_{unit}"] * scale, "--", color="grey", lw=1.6,
                label="reference")
        ax.plot(t, cols[f"q{i + 1}_{unit}"] * scale, color="tab:blue", lw=1.3, label="actual")
        ax.set_ylabel(f"q{i + 1} ({'mm' if slider else 'deg'})")
        ax.grid(True, alpha=0.4)
    axes[0].legend(fontsize=7, loc="best")
    ax = axes[len(act)]
    for i in act:
        slider = f"e{i + 1}_m" in cols
        values = cols[f"e{i + 1}_m"] * 1e3 if slider else cols[f"e{i + 1}_rad"] * 180 / np.pi
        ax.plot(t, values, lw=1.3, label=f"e{i + 1} ({'mm' if slider else 'deg'})")
    ax.axhline(0.0, color="grey", lw=0.6)
    ax.set_ylabel("error q_ref - q")
    ax.legend(fontsize=7, ncol=len(act), loc="best")
    ax.grid(True, alpha=0.4)
    ax = axes[len(act) + 1]
    for k, i in enumerate(act):
        name = next(c for c in (f"tau{i + 1}_n_m", f"tau{i + 1}_n") if c in cols)
        colour = f"C{k}"
        ax.plot(t, cols[name.replace("tau", "tau_cmd", 1)], "--", color=colour, lw=1.0)
        ax.plot(t, cols[name], color=colour, lw=1.4,
                label=f"tau{i + 1} ({'N' if name.endswith('_n') else 'N*m'})")
    ax.set_ylabel("torque: applied, commanded --")
    ax.legend(fontsize=7, ncol=len(act), loc="best")
    ax.grid(True, alpha=0.4)
    if task:
        ax = axes[-1]
        ax.plot(t, cols["e_task_mm"], color="crimson", lw=1.3)
        ax.set_ylabel("tool error |x_ref - x| (mm)")
        ax.grid(True, alpha=0.4)
    _finish(fig, axes, result, result.summary)
    return fig


def split_figure(result: Result):
    """Each actuated torque (N*m) against t (s) with its parts M qdd, C qd, g and, where the
    drive train has them, friction D(qd) and the rotors' share.

    The parts are ``result.split`` (see ``dynamics.inverse.torque_split``); the total is the torque
    column ``tau<k>_n_m`` where the result has one, else (forward dynamics, zero torque) their
    sum. k numbers the robot's coordinates: the actuated ones are ``result.actuated``.
    """
    # the drive train's parts only where they are not zero throughout (no actuator model)
    shown = [k for i, k in enumerate(SPLIT_PARTS)
             if k in result.split and (i < 3 or np.any(result.split[k]))]
    parts = [result.split[k] for k in shown]
    labels = [SPLIT_PARTS[k] for k in shown]
    colours = [SPLIT_COLOURS[list(SPLIT_PARTS).index(k)] for k in shown]
    n_act = parts[0].shape[1]
    fig, axes = _axes(n_act)
    t = result.columns["t_s"]
    coords = list(result.actuated) or list(range(n_act))
    for k, ax in enumerate(axes):
        name = f"tau{coords[k] + 1}"
        force = f"{name}_n" in result.columns  # a prismatic joint's force (N)
        total = result.columns.get(f"{name}_n_m", result.columns.get(f"{name}_n",
                                                                     sum(p[:, k] for p in parts)))
        ax.plot(t, total, color="black", lw=2.2, label=f"{name} (total)")
        for part, label, colour in zip(parts, labels, colours):
            ax.plot(t, part[:, k], color=colour, lw=1.3, label=label)
        ax.axhline(0.0, color="grey", lw=0.6)
        ax.set_ylabel(f"force {name} (N)" if force else f"torque {name} (N*m)")
        ax.grid(True, alpha=0.4)
    axes[0].legend(fontsize=7, ncol=4, loc="best")
    # cut-joint force columns mark a closed chain, whose parts went through the multiplier solve
    closed = any(k.startswith("fx_") for k in result.columns)
    how = "each part through [S^T Phi_q^T], as tau is" if closed else "tau = M qdd + C qd + g"
    if not result.torques():
        how += "; tau = 0 here: the parts balance"
    names = {"inertial": "inertial M qdd", "velocity": "velocity C qd", "gravity": "gravity g",
             "friction": "friction D(qd)", "rotor": "rotors"}
    _finish(fig, axes, result, f"torque split: {', '.join(names[k] for k in shown)}\n({how})")
    return fig


def save_figure(result: Result, path: Path, split: bool = False) -> None:
    """Write the result's figure (or its torque split) as PNG to ``path``."""
    fig = split_figure(result) if split else figure(result)
    fig.savefig(path, dpi=110, format="png")


def plot(result: Result, split: bool = False):
    """A study result's matplotlib Figure (for notebooks): the seed-like plot, or the split.

    Parameters
    ----------
    result : Result
    split : bool
        False: joint angles (deg) or torques (N*m) against time (s), with every joint's
        bearing load (N) under the torques. True: each actuated torque (N*m) with its parts
        ``M qdd``, ``C qd`` and ``g``.
    """
    if not isinstance(result, Result):
        from ..errors import InputError

        raise InputError(f"plot takes a study Result (planar_sym.run_study), got "
                         f"{type(result).__name__}")
    if not split:
        return figure(result)
    if not result.split:
        from ..errors import InputError

        raise InputError(f"{result.name} has no torque split")
    return split_figure(result)
