"""Figures like the seed's Scope windows: one axis per joint, quantities and units labelled.

Figures are made with ``matplotlib.figure.Figure``, never through pyplot, and rendered by Agg when
saved: no display is needed, nothing is registered globally (no figure to close, safe in
threads), and a notebook still shows a returned Figure.
"""

from __future__ import annotations

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
    # a study without a title is titled by its name: once, not "swing / swing"
    fig.suptitle(result.name if title in ("", result.name) else f"{result.name}\n{title}",
                 fontsize=9)
    lines = textwrap.wrap(result.note, 120)
    if lines:
        fig.text(0.01, 0.005, "\n".join(lines), fontsize=7, alpha=0.7, va="bottom")
    # leave room for the note under the axes: 7 pt lines, about 0.12 in each
    fig.tight_layout(rect=(0, 0.12 * len(lines) / fig.get_figheight(), 1, 1))
    fig.set_layout_engine(None)


#: how a series is drawn, by its unit: (scale from its unit, axis label with {} its stem)
DRAWN = {"rad": (180 / np.pi, "joint angle {} (deg)"), "m": (1e3, "joint {} (mm)"),
         "N*m": (1.0, "torque {} (N*m)"), "N": (1.0, "force {} (N)")}


def figure(result: Result):
    """A matplotlib Figure of a result (joint angles in deg, or torques in N*m, against t in s;
    a slider's displacement in mm, its force in N).

    Below the torques of an inverse-dynamics result, one more axis: every joint's bearing load
    ``|F|`` (N), the ``jload`` series (columns ``jload_<joint>_n``).
    """
    if result.kind == "control":
        return control_figure(result)
    series = result.series("q" if result.kind == "angles" else "tau")
    loads = result.series("jload")
    fig, axes = _axes(len(series) + bool(loads))
    t = result.get("t").values
    for ax, s in zip(axes, series):
        scale, label = DRAWN[s.unit]
        ax.plot(t, s.values * scale, lw=1.6)
        ax.set_ylabel(label.format(s.stem))
        ax.grid(True, alpha=0.4)
    if loads:
        ax = axes[-1]
        for s in loads:
            ax.plot(t, s.values, lw=1.3, label=s.joint)
        ax.set_ylabel("joint load |F| (N)")
        ax.grid(True, alpha=0.4)
        ax.legend(fontsize=7, ncol=min(len(loads), 5), loc="best")
    _finish(fig, axes, result, result.summary)
    return fig


#: a coordinate's value or error as drawn, by its unit: (scale, unit shown)
COORDINATE_SHOWN = {"rad": (180 / np.pi, "deg"), "m": (1e3, "mm")}


def control_figure(result: Result):
    """A control study: per tracked joint (the actuated ones, and the passive ones a full-state
    law tracks) its reference (dashed) and actual motion (deg, or mm for a slider); the
    tracking errors; the commanded (dashed) and applied torques (N*m or
    N); and, for a robot with a tool point, the tool's distance from its reference (mm)."""
    t = result.get("t").values
    act = list(result.actuated)
    # every coordinate the controller tracks: the actuated ones, and a full-state law's
    # passive ones too (the cart-pole's pole is the point of its swing-up)
    tracked = sorted(set(act) | {e.index for e in result.series("e")})
    task = result.series("e_task")
    fig, axes = _axes(len(tracked) + 2 + bool(task))
    for ax, i in zip(axes, tracked):
        q = result.get("q", i)
        scale, shown = COORDINATE_SHOWN[q.unit]
        if result.series("q_ref", i):
            ax.plot(t, result.get("q_ref", i).values * scale, "--", color="grey", lw=1.6,
                    label="reference")
        ax.plot(t, q.values * scale, color="tab:blue", lw=1.3, label="actual")
        ax.set_ylabel(f"{q.stem} ({shown})" + ("" if i in act else ", passive"))
        ax.grid(True, alpha=0.4)
    axes[0].legend(fontsize=7, loc="best")
    ax = axes[len(tracked)]
    for i in tracked:
        e = result.get("e", i)
        scale, shown = COORDINATE_SHOWN[e.unit]
        ax.plot(t, e.values * scale, lw=1.3, label=f"{e.stem} ({shown})")
    ax.axhline(0.0, color="grey", lw=0.6)
    ax.set_ylabel("error q_ref - q")
    ax.legend(fontsize=7, ncol=len(tracked), loc="best")
    ax.grid(True, alpha=0.4)
    ax = axes[len(tracked) + 1]
    for k, i in enumerate(act):
        tau = result.get("tau", i)
        colour = f"C{k}"
        ax.plot(t, result.get("tau_cmd", i).values, "--", color=colour, lw=1.0)
        ax.plot(t, tau.values, color=colour, lw=1.4, label=f"{tau.stem} ({tau.unit})")
    ax.set_ylabel("torque (-- commanded)")
    ax.legend(fontsize=7, ncol=len(act), loc="best")
    ax.grid(True, alpha=0.4)
    if task:
        ax = axes[-1]
        ax.plot(t, task[0].values, color="crimson", lw=1.3)
        ax.set_ylabel("tool error |x_ref - x| (mm)")
        ax.grid(True, alpha=0.4)
    _finish(fig, axes, result, result.summary)
    return fig


def split_figure(result: Result):
    """Each actuated torque (N*m) against t (s) with its parts M qdd, C qd, g and, where the
    drive train has them, friction D(qd) and the rotors' share.

    The parts are ``result.split`` (see ``dynamics.inverse.torque_split``); the total is the torque
    series ``tau`` of the coordinate where the result has one (column ``tau<k>_n_m``), else
    (forward dynamics, zero torque) their sum. k numbers the robot's coordinates: the actuated
    ones are ``result.actuated``.
    """
    # the drive train's parts only where they are not zero throughout (no actuator model)
    shown = [k for i, k in enumerate(SPLIT_PARTS)
             if k in result.split and (i < 3 or np.any(result.split[k]))]
    parts = [result.split[k] for k in shown]
    labels = [SPLIT_PARTS[k] for k in shown]
    colours = [SPLIT_COLOURS[list(SPLIT_PARTS).index(k)] for k in shown]
    n_act = parts[0].shape[1]
    fig, axes = _axes(n_act)
    t = result.get("t").values
    coords = list(result.actuated) or list(range(n_act))
    for k, ax in enumerate(axes):
        name = f"tau{coords[k] + 1}"
        tau = result.series("tau", coords[k])
        force = bool(tau) and tau[0].unit == "N"  # a prismatic joint's force (N)
        total = tau[0].values if tau else sum(p[:, k] for p in parts)
        ax.plot(t, total, color="black", lw=2.2, label=f"{name} (total)")
        for part, label, colour in zip(parts, labels, colours):
            ax.plot(t, part[:, k], color=colour, lw=1.3, label=label)
        ax.axhline(0.0, color="grey", lw=0.6)
        ax.set_ylabel(f"force {name} (N)" if force else f"torque {name} (N*m)")
        ax.grid(True, alpha=0.4)
    axes[0].legend(fontsize=7, ncol=4, loc="best")
    # cut-joint forces mark a closed chain, whose parts went through the multiplier solve
    closed = bool(result.series("fx"))
    # the sum the parts make, with the drive train's where it shows (a trial: the title said
    # M qdd + C qd + g above friction and rotor curves)
    terms = {"inertial": "M qdd", "velocity": "C qd", "gravity": "g", "friction": "D(qd)",
             "rotor": "rotors"}
    how = ("each part through [S^T Phi_q^T], as tau is" if closed
           else "tau = " + " + ".join(terms[k] for k in shown))
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
