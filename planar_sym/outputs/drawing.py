"""Pictures of a mechanism: bodies, joints, centres of gravity and the task point, still or moving.

World positions come from the compiled body frames (``Robot.frames``) and the description's
body-frame points, so a picture shows the model the equations use, not a second copy of the
geometry. Everything is plotted in the length unit the description is typed in
(``[units].length``: a robot typed in cm is drawn in cm) with equal axes. Artists carry a ``gid``
(``joint:<name>``, ``cg:<body>``, ``body:<body>``, ``task``) so tests can read them back.
"""

from __future__ import annotations

import textwrap

import numpy as np

from ..model.description import GROUND, Description
from ..model.length_unit import per_metre, typed_length_unit
from .geometry import Geometry, geometry, joint_roles, outline, point_labels, to_world  # noqa: F401

#: where a joint's label goes, in order of preference: offset (points) and alignment
LABEL_CORNERS = ((6, 6, "left", "bottom"), (6, -6, "left", "top"), (-6, 6, "right", "bottom"),
                 (-6, -6, "right", "top"))
#: decimals of a length in each unit: 10 um in all
DIGITS = {"mm": 2, "cm": 3, "m": 5}



def _cg_marker():
    """The quartered-circle centre-of-gravity symbol: two opposite filled quadrants."""
    from matplotlib.path import Path

    return Path.make_compound_path(Path.wedge(0, 90), Path.wedge(180, 270))


class Scene:
    """A robot's artists on one Axes, moved to configuration ``k`` by ``show(k)``.

    Parameters
    ----------
    ax : matplotlib Axes
    desc : Description
    geo : Geometry
        Positions (m) over every configuration to be shown; the limits cover them all.
    labels : bool
        Name joints and points, and add a legend (the still drawing); off for animations.

    ``unit`` is the drawing's length unit (the description's ``[units].length``) and ``scale``
    the number of them in a metre: positions held here are in it.
    """

    def __init__(self, ax, desc: Description, geo: Geometry, labels: bool = True):
        self.ax, self.desc, self.labels = ax, desc, labels
        self.unit = typed_length_unit(desc.path)
        self.scale = scale = per_metre(self.unit)
        self.pts = {k: v * scale for k, v in geo.points.items()}
        self.cgs = {k: v * scale for k, v in geo.cgs.items()}
        low, high = (c * scale for c in geo.extent())
        # a robot that is one point (a cart drawn as its mass) has no span: 0.1 m to draw in
        # (matplotlib warned twice of identical limits, and the frame's arrows had no length)
        self.span = float(max(high - low)) or 0.1 * scale
        high = np.maximum(high, 0.15 * self.span)  # room for the base frame's arrows
        # each side at least 60 % of the other: a straight arm is not drawn in a sliver
        half = np.maximum(high - low, 0.6 * self.span) / 2 + 0.12 * self.span
        mid = (low + high) / 2
        ax.set_xlim(mid[0] - half[0], mid[0] + half[0])
        ax.set_ylim(mid[1] - half[1], mid[1] + half[1])
        ax.set_aspect("equal")
        ax.set_xlabel(f"x ({self.unit})")
        ax.set_ylabel(f"y ({self.unit})")
        ax.grid(True, alpha=0.3)
        self.moving: list[tuple[object, np.ndarray]] = []  # artist, positions (N, k, 2), drawing unit
        self._pending = {}
        self._ground()
        self._base_frame()
        self._bodies()
        self._sliders(geo)
        self._joints()
        self._cgs_and_task()
        self._labels()
        if labels:
            self._legend()
        self.show(0)

    # -- artists ----------------------------------------------------------------------------
    def _ground(self) -> None:
        from matplotlib.patches import Polygon

        s = 0.035 * self.span  # ground symbol size: scales with the robot
        for j in self.desc.tree_joints:
            if j.parent == GROUND:
                x, y = self.pts[(GROUND, j.parent_point)][0]
                self.ax.add_patch(Polygon([(x, y), (x - s, y - 1.5 * s), (x + s, y - 1.5 * s)],
                                          closed=True, facecolor="none", edgecolor="dimgray",
                                          hatch="///", lw=1.0, zorder=1))

    def _base_frame(self) -> None:
        length = 0.15 * self.span  # the limits leave room for it
        for tip, name, colour in (((length, 0), "x", "tab:red"), ((0, length), "y", "tab:green")):
            self.ax.annotate("", xy=tip, xytext=(0, 0), zorder=4, arrowprops={
                "arrowstyle": "-|>", "color": colour, "lw": 1.6, "shrinkA": 0, "shrinkB": 0})
            self.ax.annotate(f"{name}0", xy=tip, xytext=(3, 3), textcoords="offset points",
                             color=colour, fontsize=8, zorder=4)

    def _bodies(self) -> None:
        from matplotlib.patches import Polygon

        colours = iter(["tab:blue", "tab:orange", "tab:purple", "tab:brown", "tab:olive",
                        "tab:cyan", "tab:pink", "tab:gray"] * 4)
        for name, body in self.desc.bodies.items():
            if name == GROUND:
                continue
            order, plate = outline(body.points_m)
            if len(order) == 1:  # a welded point mass (motor): a square block
                art, = self.ax.plot([], [], "s", ms=13, color="dimgray", zorder=3)
            elif plate:
                art = self.ax.add_patch(Polygon(np.zeros((len(order), 2)), closed=True,
                                                alpha=0.5, facecolor=next(colours),
                                                edgecolor="black", zorder=3))
            else:
                art, = self.ax.plot([], [], "-", lw=7, alpha=0.8, color=next(colours),
                                    solid_capstyle="round", zorder=3)
            art.set_gid(f"body:{name}")
            self._move(art, *[self.pts[(name, p)] for p in order])

    def _sliders(self, geo: Geometry) -> None:
        """Each prismatic joint as a slider: a rail on the parent body along the axis, through
        the parent point and over the whole travel shown, and a block on the child point."""
        from matplotlib.patches import Polygon

        for j in self.desc.tree_joints:
            if j.type != "prismatic":
                continue
            ang = geo.angles[j.parent] if geo.angles else np.zeros(len(self.pts[
                (j.parent, j.parent_point)]))
            ux, uy = j.axis
            u = np.column_stack([np.cos(ang) * ux - np.sin(ang) * uy,
                                 np.sin(ang) * ux + np.cos(ang) * uy])
            n = np.column_stack([-u[:, 1], u[:, 0]])
            a, b = self.pts[(j.parent, j.parent_point)], self.pts[(j.child, j.child_point)]
            travel = np.sum((b - a) * u, axis=1)
            block = 0.07 * self.span
            lo = min(0.0, float(travel.min())) - block
            hi = max(0.0, float(travel.max())) + block
            rail, = self.ax.plot([], [], "-", lw=2.5, color="dimgray", zorder=2,
                                 solid_capstyle="butt")
            rail.set_gid(f"rail:{j.name}")
            self._move(rail, a + lo * u, a + hi * u)
            half_l, half_w = block / 2, 0.022 * self.span
            corners = [b + sl * half_l * u + sw * half_w * n
                       for sl, sw in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
            art = self.ax.add_patch(Polygon(np.zeros((4, 2)), closed=True, zorder=5, lw=1.4,
                                            facecolor="black" if j.actuated else "white",
                                            edgecolor="black"))
            art.set_gid(f"joint:{j.name}")
            self._move(art, *corners)
            if self.labels:
                self._label(j.name, (j.child, j.child_point))

    def _joints(self) -> None:
        style = {"actuated": {"mfc": "black", "mec": "black"},
                 "passive": {"mfc": "white", "mec": "black"},
                 "cut": {"mfc": "white", "mec": "red"}}
        for name, key, role in joint_roles(self.desc):
            art, = self.ax.plot([], [], "o", ms=9, mew=1.6, zorder=5, **style[role])
            art.set_gid(f"joint:{name}")
            self._move(art, self.pts[key])
            if role == "cut":
                cross, = self.ax.plot([], [], "x", ms=6, mew=1.4, color="red", zorder=6)
                self._move(cross, self.pts[key])
            if self.labels:
                self._label(f"{name} (cut)" if role == "cut" else name, key)

    def _cgs_and_task(self) -> None:
        for name in self.cgs:
            ring, = self.ax.plot([], [], "o", ms=9, mfc="white", mec="black", zorder=6)
            quarters, = self.ax.plot([], [], marker=_cg_marker(), ms=9, ls="", color="black",
                                     zorder=7)
            ring.set_gid(f"cg:{name}")
            self._move(ring, self.cgs[name])
            self._move(quarters, self.cgs[name])
        task = self.desc.task_point
        if task is not None:
            art, = self.ax.plot([], [], "*", ms=15, color="crimson", mec="black", zorder=8)
            art.set_gid("task")
            self._move(art, self.pts[task])
        if self.labels:
            for key, text in point_labels(self.desc).items():
                self._label(f"{text} (task)" if key == task else text, key)

    def _label(self, text: str, key: tuple[str, str]) -> None:
        """A name for the point ``key``, drawn by ``_labels``."""
        self._pending.setdefault(key, []).append(text)

    def _labels(self) -> None:
        """One label per place: the names of points that coincide in every configuration (a
        cart-pole's slide and hinge, two hips on one pelvis point) joined, not overprinted."""
        places: list[tuple[tuple[str, str], list[str]]] = []
        tol = 1e-9 * max(self.span, 1e-12)
        for key, texts in self._pending.items():
            for at, names in places:
                if np.abs(self.pts[at] - self.pts[key]).max() <= tol:
                    names.extend(t for t in texts if t not in names)
                    break
            else:
                places.append((key, list(texts)))
        self.label_artists = []
        for key, names in places:
            ann = self.ax.annotate(", ".join(names), xy=self.pts[key][0], xytext=(6, 6),
                                   fontsize=8, zorder=9, textcoords="offset points",
                                   bbox={"boxstyle": "round,pad=0.15", "fc": "white",
                                         "alpha": 0.7, "lw": 0})
            self.label_artists.append(ann)
            self._move(ann, self.pts[key])

    def declutter(self) -> None:
        """Move each label that would cover one placed before it to another corner of its
        joint (up-right, down-right, up-left, down-left; the first free): two joints close
        together on one row would print their names over each other. Call it once the figure
        is laid out (the boxes are measured as drawn)."""
        self.ax.apply_aspect()  # the equal-aspect box as it will be drawn
        placed = []
        for ann in self.label_artists:
            for dx, dy, ha, va in LABEL_CORNERS:
                ann.xyann, _ = (dx, dy), ann.set(ha=ha, va=va)
                box = ann.get_window_extent()
                if not any(box.overlaps(b) for b in placed):
                    break
            else:  # no corner free: the first, as before
                dx, dy, ha, va = LABEL_CORNERS[0]
                ann.xyann, _ = (dx, dy), ann.set(ha=ha, va=va)
                box = ann.get_window_extent()
            placed.append(box)

    def _legend(self) -> None:
        from matplotlib.lines import Line2D

        def mark(**kw):
            return Line2D([], [], ls="", **{"marker": "o", "ms": 8, **kw})

        handles = [mark(mfc="black", mec="black"), mark(mfc="white", mec="black"),
                   (mark(mfc="white", mec="red"), mark(marker="x", ms=5, color="red")),
                   (mark(mfc="white", mec="black"), mark(marker=_cg_marker(), color="black")),
                   mark(marker="*", ms=12, color="crimson", mec="black")]
        names = ["actuated joint", "passive joint", "cut joint (loop closure)",
                 "centre of gravity", "task point"]
        if self.desc.task_point is None:  # no end-effector: no task star to explain
            handles, names = handles[:-1], names[:-1]
        if any(j.type == "prismatic" for j in self.desc.tree_joints):
            handles.append(mark(marker="s", ms=9, mfc="white", mec="black"))
            names.append("slider (prismatic joint;\n filled: actuated)")
        self.ax.legend(handles, names, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                       fontsize=8, frameon=False)

    # -- motion -----------------------------------------------------------------------------
    def _move(self, art, *tracks: np.ndarray) -> None:
        """Register ``art`` to follow ``tracks`` (each (N, 2) in the drawing unit: one per
        vertex or marker)."""
        self.moving.append((art, np.stack(tracks, axis=1)))

    def show(self, k: int) -> list:
        """Move every artist to configuration ``k``; returns the artists changed."""
        for art, xy in self.moving:
            if hasattr(art, "set_xy"):
                art.set_xy(xy[k])
            elif hasattr(art, "set_data"):
                art.set_data(xy[k, :, 0], xy[k, :, 1])
            else:  # an annotation: its anchor moves, the text offset stays
                art.xy = tuple(xy[k, 0])
        return [art for art, _ in self.moving]


def drawn_frames(desc: Description) -> tuple[list[str], np.ndarray]:
    """(body names, frames (1, bodies, 3)) of the drawn configuration, from the description
    alone: what ``Robot.frames(q_drawn)`` computes, without deriving or compiling anything."""
    names = [b for b in desc.bodies if b != GROUND]
    frames = np.array([[(*desc.bodies[b].drawn_origin_m, desc.bodies[b].drawn_angle_rad)
                        for b in names]])
    return names, frames


def drawing_figure(robot_name: str, q=None):
    """A robot drawn at one configuration (default: the drawn one, ``robot.q_drawn``).

    A description file in its drawn configuration is drawn from the description alone, so
    ``planar-sym draw FILE``, the first check of a new robot, needs no derivation (SymPy) and no
    compiler; any other configuration, or a robot given by name or generated folder, uses the
    compiled body frames.

    Parameters
    ----------
    robot_name : str or Path
        A built-in robot (or one on ``PLANAR_SYM_GENERATED``), a description file or a
        generated folder.
    q : array_like, shape (n,), optional
        Every coordinate (rad).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..model.description import load as load_description
    from .plots import new_figure, tight

    if q is None and str(robot_name).endswith(".toml"):
        desc = load_description(robot_name)
        names, frames = drawn_frames(desc)
        coordinates, q = desc.coordinates, np.array(desc.q_drawn())
        which = "drawn configuration"
    else:
        from ..model.described import described
        from ..model.locate import load

        robot = load(robot_name)  # a built-in name, a description file or a generated folder
        desc = described(robot)
        which = "drawn configuration" if q is None else "configuration"
        q = robot.q_drawn if q is None else np.asarray(q, dtype=float)
        names, frames, coordinates = robot.body_names, robot.frames(q[None, :]), robot.coordinates
    geo = geometry(desc, names, frames)
    fig = new_figure((8.0, 6.0))
    ax = fig.add_subplot()
    scene = Scene(ax, desc, geo, labels=True)
    units = desc.coordinate_units
    digits = DIGITS[scene.unit]  # a slider's position to 10 um, in the drawing's unit
    angles = ", ".join(f"{c} {v * scene.scale:.{digits}f} {scene.unit}" if u == "m"
                       else f"{c} {np.degrees(v):.2f} deg" for c, v, u in zip(coordinates, q, units))
    # a long list of joints wraps instead of running off the figure's edges
    q_text = textwrap.fill(f"q: {angles}", 120)
    ax.set_title(f"{desc.name}: {which}\n{desc.title}\n{q_text}", fontsize=8)
    tight(fig)
    scene.declutter()
    return fig
