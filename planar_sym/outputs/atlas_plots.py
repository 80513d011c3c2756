"""Pictures of a robot's atlas (outputs stage): maps over the task plane, in the length unit
the robot's description is typed in, with the start pose drawn over them, and the atlas's files (PNG, NPZ, CSV), written whole or not at all.

Per orientation: ``atlas_figure`` (reachable region with both singular loci, the Type I and
Type II measures, dexterity) and ``torque_figure`` (per actuator, gravity torque and torque
envelope); along a study, ``along_figure``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..analysis.atlas import Atlas, EnvelopeAlong, write_csv, write_npz
from ..model.length_unit import per_metre
from .plots import new_figure, tight


def scale(atlas: Atlas) -> float:
    """The maps' length unit (``Atlas.length_unit``) per metre."""
    return per_metre(atlas.length_unit)

#: colour scales end at this percentile of the reachable cells' values: near a singular pose
#: torques grow without bound and would wash out the rest of the map
PERCENTILE = 95.0
#: the start pose's stick figure
STICK = {"color": "0.35", "lw": 2.2, "alpha": 0.85, "solid_capstyle": "round", "zorder": 6}
TYPE1_STYLE = {"colors": "black", "linewidths": 1.3, "linestyles": "--"}
TYPE2_STYLE = {"colors": "crimson", "linewidths": 1.6}
SAME, OTHER = "#9ecae1", "#fdbf6f"


def _extent(atlas: Atlas) -> list[float]:
    dx = (atlas.x_m[1] - atlas.x_m[0]) / 2
    dy = (atlas.y_m[1] - atlas.y_m[0]) / 2
    s = scale(atlas)
    return [(atlas.x_m[0] - dx) * s, (atlas.x_m[-1] + dx) * s,
            (atlas.y_m[0] - dy) * s, (atlas.y_m[-1] + dy) * s]


def _layer_title(atlas: Atlas, layer: int) -> str:
    if not len(atlas.phi_rad):
        return ""
    return f", phi = {round(float(np.degrees(atlas.phi_rad[layer])), 6) + 0.0:g} deg"


def _loci(ax, atlas: Atlas, layer: int) -> None:
    """Type I: the edge of the reachable region (a leg stretched or folded); Type II: the zero
    contour of det_type2 between reachable cells."""
    X, Y = np.meshgrid(atlas.x_m * scale(atlas), atlas.y_m * scale(atlas))
    reach = atlas.reachable[layer]
    if reach.any() and not reach.all():
        ax.contour(X, Y, reach.astype(float), levels=[0.5], **TYPE1_STYLE)
    det = np.ma.masked_invalid(atlas.det_type2[layer])
    if det.count() and det.min() < 0 < det.max():
        ax.contour(X, Y, det, levels=[0.0], **TYPE2_STYLE)


def _stick(ax, atlas: Atlas) -> None:
    """The start pose, light grey."""
    d, k = atlas.start_drawing, scale(atlas)
    for line in d.get("bodies", []):
        ax.plot(line[:, 0] * k, line[:, 1] * k, "-", **STICK)
    if len(d.get("joints", [])):
        ax.plot(d["joints"][:, 0] * k, d["joints"][:, 1] * k, "o", ms=4, mfc="white",
                mec="0.3", zorder=7)
    if len(d.get("ground", [])):
        ax.plot(d["ground"][:, 0] * k, d["ground"][:, 1] * k, "^", ms=8, color="0.3",
                zorder=7)
    if "task" in d:
        ax.plot(d["task"][0] * k, d["task"][1] * k, "*", ms=11, color="crimson", mec="black",
                zorder=8)


def _frame(ax, atlas: Atlas, title: str, along: EnvelopeAlong | None) -> None:
    _stick(ax, atlas)
    if along is not None:
        s = scale(atlas)
        ax.plot(along.x[:, 0] * s, along.x[:, 1] * s, "-", color="black", lw=2.0, zorder=9)
    ext = _extent(atlas)
    ax.set_xlim(ext[:2])
    ax.set_ylim(ext[2:])
    ax.set_aspect("equal")
    ax.set_xlabel(f"x ({atlas.length_unit})")
    ax.set_ylabel(f"y ({atlas.length_unit})")
    ax.set_title(title, fontsize=9)


def _map(fig, ax, atlas: Atlas, values: np.ndarray, layer: int, label: str, cmap: str,
         limits: tuple[float, float] | None = None, extend: str = "neither") -> None:
    data = np.ma.masked_invalid(values[layer])
    lo, hi = limits if limits is not None else (0.0, 1.0)
    img = ax.imshow(data, origin="lower", extent=_extent(atlas), cmap=cmap, vmin=lo, vmax=hi,
                    interpolation="nearest", zorder=1)
    fig.colorbar(img, ax=ax, label=label, extend=extend, shrink=0.85)
    _loci(ax, atlas, layer)


def _robust(values: np.ndarray, symmetric: bool = False) -> tuple[float, float]:
    v = values[np.isfinite(values)]
    if not v.size:
        return 0.0, 1.0
    if symmetric:
        top = float(np.percentile(np.abs(v), PERCENTILE)) or 1.0
        return -top, top
    return 0.0, float(np.percentile(v, PERCENTILE)) or 1.0


def atlas_figure(atlas: Atlas, layer: int = 0, along: EnvelopeAlong | None = None):
    """Four maps of one orientation: reachable region (start assembly mode shaded apart) with
    the Type I (dashed black) and Type II (red) singular loci; the Type I and Type II measures
    and the dexterity (1 / condition number, dimensionless); the start pose drawn over each.

    Parameters
    ----------
    atlas : Atlas
    layer : int
        Index of the orientation (``atlas.phi_rad``); 0 for a robot without one.
    along : EnvelopeAlong, optional
        A study's path, drawn over the maps.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    fig = new_figure((12.0, 10.0))
    axes = fig.subplots(2, 2).ravel()
    kind = np.where(atlas.reachable[layer], atlas.same_assembly[layer].astype(float), np.nan)
    axes[0].imshow(np.ma.masked_invalid(kind), origin="lower", extent=_extent(atlas),
                   cmap=ListedColormap([OTHER, SAME]), vmin=0, vmax=1, interpolation="nearest")
    _loci(axes[0], atlas, layer)
    s = atlas.summary()
    _frame(axes[0], atlas, f"reachable from the start pose ({s['area_m2'] * 1e4:.4g} cm^2)",
           along)
    handles = [Patch(color=SAME, label="reachable, start assembly mode"),
               Patch(color=OTHER, label="reachable, other assembly mode"),
               Line2D([], [], color="black", ls="--", label="Type I singular (workspace edge)"),
               Line2D([], [], color="crimson", label="Type II singular (det Phi_p = 0)"),
               Line2D([], [], color="0.35", lw=2.2, label="start pose")]
    axes[0].legend(handles=handles, fontsize=7, loc="upper left", framealpha=0.85)
    tree = atlas.n_constraints == 0
    for ax, key, what in zip(axes[1:], ("type1", "type2", "dexterity"), (
            "Type I measure 1/cond [Phi_q; J] (-)", "Type II measure 1/cond Phi_p (-)",
            "dexterity 1/cond J_x (-)")):
        values = getattr(atlas, key)
        top = float(np.nanmax(values[layer])) if np.isfinite(values[layer]).any() else 1.0
        _map(fig, ax, atlas, values, layer, what, "viridis", (0.0, top if top > 0 else 1.0))
        note = " (a tree: none, 1 everywhere)" if tree and key == "type2" else ""
        _frame(ax, atlas, what.split(" (")[0] + note, along)
    lc = f"L_c = {atlas.length_scale_m * scale(atlas):.4g} {atlas.length_unit}"
    fig.suptitle(f"{atlas.robot}: atlas of the start pose's working mode"
                 f"{_layer_title(atlas, layer)} ({lc})", fontsize=11)
    tight(fig)
    return fig


def torque_figure(atlas: Atlas, layer: int = 0, along: EnvelopeAlong | None = None):
    """Per actuator (rows): gravity torque at rest and the torque envelope, the largest
    |torque| for a task acceleration of size ``atlas.accel_m_s2`` in the worst direction
    (N*m, or N for a slider); colour scales end at the PERCENTILE-th percentile.

    Parameters
    ----------
    atlas : Atlas
    layer : int
        Index of the orientation.
    along : EnvelopeAlong, optional
        A study's path, drawn over the maps.

    Returns
    -------
    matplotlib.figure.Figure
    """
    na = len(atlas.actuated)
    fig = new_figure((12.0, 4.6 * na))
    axes = fig.subplots(na, 2, squeeze=False)
    for k, (i, unit) in enumerate(zip(atlas.actuated, atlas.actuator_units)):
        name = atlas.coordinates[i] if atlas.coordinates else f"q{i + 1}"
        g, env = atlas.gravity[..., k], atlas.envelope[..., k]
        _map(fig, axes[k, 0], atlas, g, layer, f"gravity torque {name} ({unit})", "RdBu_r",
             _robust(g[layer], symmetric=True), "both")
        _frame(axes[k, 0], atlas, f"joint {name}: gravity torque at rest", along)
        _map(fig, axes[k, 1], atlas, env, layer, f"max |torque {name}| ({unit})", "magma_r",
             _robust(env[layer]), "max")
        _frame(axes[k, 1], atlas, f"joint {name}: envelope at rest, |a| = "
               f"{atlas.accel_m_s2:g} m/s^2 (worst x-y direction)", along)
    fig.suptitle(f"{atlas.robot}: torques{_layer_title(atlas, layer)}", fontsize=11)
    tight(fig)
    return fig


def along_figure(along: EnvelopeAlong):
    """Per actuator against time (s): the study's torque, the torque with the task
    acceleration removed (b), and the band +- envelope (N*m or N)."""
    na = len(along.actuated)
    fig = new_figure((8.0, 1.2 + 2.3 * na))
    axes = fig.subplots(na, 1, sharex=True, squeeze=False)[:, 0]
    for k, (ax, unit) in enumerate(zip(axes, along.actuator_units)):
        i = along.actuated[k]
        ax.fill_between(along.t_s, -along.envelope[:, k], along.envelope[:, k], color="0.85",
                        label=f"+- envelope, |a| = {along.accel_m_s2:g} m/s^2")
        ax.plot(along.t_s, along.tau_study[:, k], color="black", lw=1.6, label="study")
        ax.plot(along.t_s, along.b[:, k], "--", color="tab:blue", lw=1.2,
                label="task acceleration 0")
        ax.set_ylabel(f"tau{i + 1} ({unit})")
        ax.grid(True, alpha=0.4)
    axes[0].legend(fontsize=7, loc="best")
    axes[-1].set_xlabel("time t (s)")
    fig.suptitle(f"{along.study}: torque envelope along the path ({along.robot})", fontsize=10)
    tight(fig)
    return fig


def write_atlas(atlas: Atlas, out_dir, along: EnvelopeAlong | None = None,
                dpi: int = 100) -> list[Path]:
    """Write the atlas's files into ``out_dir``, all of them or none.

    atlas.png and atlas_torque.png (``atlas_phi<deg>.png``, ``atlas_torque_phi<deg>.png``
    per orientation when there are several, named by the angle in degrees: ``atlas_phi-30.png``,
    ``atlas_phi12.5.png``), atlas.npz (``Atlas.arrays``), atlas.csv (one row
    per cell, units in the header); with a study, envelope_along.csv and envelope_along.png.

    Returns
    -------
    list of Path
        The files written.
    """
    from ..files import atomic_files

    out = Path(out_dir)
    layers = atlas.reachable.shape[0]
    figures = {}
    for k in range(layers):
        tag = f"_phi{np.degrees(atlas.phi_rad[k]):.4g}" if layers > 1 else ""
        figures[out / f"atlas{tag}.png"] = atlas_figure(atlas, k, along)
        figures[out / f"atlas_torque{tag}.png"] = torque_figure(atlas, k, along)
    if along is not None:
        figures[out / "envelope_along.png"] = along_figure(along)
    paths = [*figures, out / "atlas.npz", out / "atlas.csv"]
    if along is not None:
        paths.append(out / "envelope_along.csv")
    with atomic_files(paths) as temps:
        for tmp, fig in zip(temps, figures.values()):
            fig.savefig(tmp, dpi=dpi, format="png")
        write_npz(atlas, temps[len(figures)])
        write_csv(atlas, temps[len(figures) + 1])
        if along is not None:
            names, values = along.table()
            np.savetxt(temps[-1], values, delimiter=",", header=",".join(names), comments="",
                       fmt="%.10g")
    return paths
