"""Rich display in notebooks: a Robot, a study Result and a Simulation as HTML.

Each ``*_html`` function returns one self-contained HTML fragment: a summary table (values with
their SI units) and PNG pictures embedded as ``data:`` URIs, so a saved notebook shows them with
no file beside it and no network. A Simulation shown with its robot (``show(sim, robot)``) also
carries a short GIF of the mechanism moving (it plays with no JavaScript, so also in an
untrusted notebook); so does one that names its robot (``Simulation.robot``) when that robot's
parameters are the ones that ran.

The model layer knows nothing of this: ``planar_sym/__init__.py`` calls ``register`` when it is
imported inside IPython (Jupyter, ``ipython``), which hooks these functions into IPython's
``text/html`` formatter. Matplotlib is imported only when something is shown.
"""

from __future__ import annotations

import base64
import html
import io
import tempfile
from pathlib import Path

import numpy as np

from ..dynamics.integrate import Simulation
from ..model.robot import Robot
from ..study.result import Result

#: dots per inch of the embedded pictures: small enough to keep a notebook light
DPI = 72
#: frames of an embedded animation (each about 30 ms to render, a few kB in the GIF)
FRAMES = 30

_STYLE = ("<style>.planar-sym table{border-collapse:collapse;font-size:0.9em;margin:0.3em 0}"
          ".planar-sym td,.planar-sym th{border:1px solid #ccc;padding:2px 8px;"
          "text-align:left;vertical-align:top}.planar-sym th{background:#f3f3f3}"
          ".planar-sym img{max-width:100%}</style>")


def png_bytes(fig, dpi: int = DPI) -> bytes:
    """A matplotlib Figure rendered as PNG bytes (``figsize * dpi`` pixels)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    return buf.getvalue()


def data_uri(data: bytes, mime: str) -> str:
    """``data:<mime>;base64,...``: a picture inside the page, no file and no network."""
    return f"data:{mime};base64,{base64.b64encode(data).decode('ascii')}"


def img_tag(data: bytes, mime: str, alt: str) -> str:
    """An ``<img>`` holding ``data`` (PNG or GIF bytes) as a data URI."""
    return f'<img src="{data_uri(data, mime)}" alt="{html.escape(alt)}">'


def _table(rows: list[tuple[str, str]], header: tuple[str, ...] | None = None) -> str:
    """Rows of (label, value) cells; every cell escaped."""
    out = ["<table>"]
    if header:
        out.append("<tr>" + "".join(f"<th>{html.escape(h)}</th>" for h in header) + "</tr>")
    for row in rows:
        cells = "".join(f"<td>{html.escape(str(c))}</td>" for c in row)
        out.append(f"<tr>{cells}</tr>")
    out.append("</table>")
    return "".join(out)


def _wrap(title: str, *parts: str) -> str:
    return (f'<div class="planar-sym">{_STYLE}<h3>{html.escape(title)}</h3>'
            + "".join(parts) + "</div>")


def _coordinate_unit(unit: str) -> str:
    return {"rad": "rad (revolute)", "m": "m (prismatic)"}.get(unit, unit)


def robot_drawing(robot: Robot):
    """The robot drawn in its drawn configuration ``robot.q_drawn`` with its own parameters.

    Returns
    -------
    matplotlib.figure.Figure or None
        8 x 6 in (mm axes); None when no description is at hand to draw it.
    """
    from ..model.described import described
    from .drawing import Scene, geometry
    from .plots import new_figure, tight

    if robot.description_file is None:
        return None
    desc = described(robot)
    geo = geometry(desc, robot.body_names, robot.frames(robot.q_drawn[None, :]))
    fig = new_figure((8.0, 6.0))
    ax = fig.add_subplot()
    Scene(ax, desc, geo, labels=True)
    ax.set_title(f"{robot.name}: drawn configuration\n{robot.title}", fontsize=8)
    tight(fig)
    return fig


def robot_html(robot: Robot, picture: bool = True) -> str:
    """A robot as HTML: what it is, its coordinates, parameters (SI) and its drawing.

    Parameters
    ----------
    robot : Robot
    picture : bool
        Embed the drawing (a PNG of 576 x 432 pixels).

    Returns
    -------
    str
        An HTML fragment: a summary table (name, coordinates with units, actuated joints, cut
        joints of the loops, task coordinates), the drawing as a ``data:image/png`` ``<img>``,
        and the parameters (name, value, SI unit, meaning; folded when more than 16).
    """
    coords = ", ".join(f"q{k + 1} = {c} ({_coordinate_unit(u)})"
                       for k, (c, u) in enumerate(zip(robot.coordinates, robot.coordinate_units)))
    actuated = ", ".join(f"q{i + 1} = {robot.coordinates[i]}" for i in robot.actuated) or "none"
    loops = (f"{len(robot.loops)} (cut at {', '.join(robot.loops)}; "
             f"{robot.n_constraints} loop equations)" if robot.loops else "none (a tree)")
    summary = _table([("name", robot.name), ("what", robot.title),
                      ("coordinates", coords), ("actuated", actuated), ("loops", loops),
                      ("task", ", ".join(robot.task_names) or "none"),
                      ("bodies", ", ".join(robot.body_names))])
    params = _table([(p.name, f"{v:.6g}", p.unit, p.meaning)
                     for p, v in zip(robot.parameter_list, robot.p)],
                    header=("parameter", "value", "unit (SI)", "meaning"))
    count = len(robot.parameter_list)
    parts = [summary]
    if picture:
        fig = robot_drawing(robot)
        if fig is not None:
            parts.append(img_tag(png_bytes(fig), "image/png", f"{robot.name} drawn"))
    # a long list starts folded (a click opens it), so the drawing stays in view
    opened = " open" if count <= 16 else ""
    parts.append(f"<details{opened}><summary>parameters ({count})</summary>{params}</details>")
    return _wrap(f"Robot {robot.name}", *parts)


def result_html(result: Result, picture: bool = True) -> str:
    """A study result as HTML: its summary, peak torques and its figure.

    Parameters
    ----------
    result : Result
    picture : bool
        Embed the figure (``outputs.plots.figure``: 504 pixels wide).

    Returns
    -------
    str
        An HTML fragment: a table (study, robot, what it shows, samples, duration in s, the
        inverse kinematics used, the peak |torque| of every actuated joint in N*m, or N for a
        slider, and the note) and the figure as a ``data:image/png`` ``<img>``.
    """
    from .plots import figure

    t = result.get("t").values
    rows = [("study", result.name), ("what", result.summary), ("robot", result.robot),
            ("shows", result.kind), ("samples", str(len(t))),
            ("duration", f"{t[-1] - t[0]:.6g} s")]
    if result.solver:
        rows.append(("inverse kinematics", result.solver))
    for key, (peak, unit) in result.peak_torques_with_units().items():
        rows.append((f"peak |{key}|", f"{peak:.6g} {unit}"))
    for energy in result.series("energy"):
        e = energy.values
        rows.append(("energy E(end) - E(0)", f"{e[-1] - e[0]:.3g} J"))
    if result.note:
        rows.append(("note", result.note))
    rows += [("warning", w) for w in result.warnings]
    parts = [_table(rows)]
    if picture:
        parts.append(img_tag(png_bytes(figure(result)), "image/png", f"{result.name} plot"))
    return _wrap(f"Study {result.name}", *parts)


def simulation_figure(sim: Simulation, robot: Robot | None = None):
    """Coordinates and energies of a forward run against time (s).

    Parameters
    ----------
    sim : Simulation
        ``q`` of shape (N, n) at ``t_s`` (N,).
    robot : Robot, optional
        Names the coordinates and gives their units: angles drawn in deg, sliders in mm (so
        does the run's own ``coordinate_units``, where it has them). Without either, every
        coordinate is drawn in its SI unit (rad, or m for a slider).

    Returns
    -------
    matplotlib.figure.Figure
        Two axes: the coordinates, and the kinetic, potential and total energy (J).
    """
    from .plots import new_figure, tight

    fig = new_figure((7.0, 4.8))
    ax_q, ax_e = fig.subplots(2, 1, sharex=True)
    n = sim.q.shape[1]
    units = (robot.coordinate_units if robot is not None
             else tuple(getattr(sim, "coordinate_units", ())))
    known = len(units) == n
    units = units if known else ("",) * n
    names = robot.coordinates if robot is not None else tuple(f"q{k + 1}" for k in range(n))
    for k in range(n):
        scale, unit = {"rad": (180 / np.pi, "deg"), "m": (1e3, "mm")}.get(units[k], (1.0, "SI"))
        label = f"q{k + 1} {names[k]}" if robot is not None else names[k]
        ax_q.plot(sim.t_s, sim.q[:, k] * scale, lw=1.4, label=f"{label} ({unit})")
    ax_q.set_ylabel("coordinate (deg; mm for a slider)" if known
                    else "coordinate (rad; m for a slider)")
    ax_q.legend(fontsize=7, ncol=min(n, 4), loc="best")
    ax_q.grid(True, alpha=0.4)
    ax_e.plot(sim.t_s, sim.kinetic_j, lw=1.2, label="kinetic T")
    ax_e.plot(sim.t_s, sim.potential_j, lw=1.2, label="potential V")
    ax_e.plot(sim.t_s, sim.energy_j, color="black", lw=1.8, label="total T + V")
    ax_e.set_ylabel("energy (J)")
    ax_e.set_xlabel("time t (s)")
    ax_e.legend(fontsize=7, ncol=3, loc="best")
    ax_e.grid(True, alpha=0.4)
    fig.suptitle(f"forward dynamics{f' of {robot.name}' if robot is not None else ''}: "
                 f"{sim.method}, rtol {sim.rtol:g}", fontsize=9)
    tight(fig)
    return fig


def simulation_gif(sim: Simulation, robot: Robot, frames: int = FRAMES, fps: float = 10.0,
                   dpi: int = 60) -> bytes | None:
    """The mechanism moving along a simulation, as GIF bytes (None: no description to draw).

    Parameters
    ----------
    sim : Simulation
        ``q`` (N, n): every coordinate (rad, or m for a slider) at ``t_s`` (N,), in s.
    robot : Robot
        The simulated robot.
    frames : int
        At most this many evenly spaced samples are drawn (at least 2).
    fps : float
        Playback frames per second.
    dpi : int
        Pixels per inch of the 4.8 x 4 in frame.
    """
    from .animation import write_animation

    if robot.description_file is None or len(sim.t_s) < 2:
        return None
    pick = np.unique(np.linspace(0, len(sim.t_s) - 1, max(2, min(frames, len(sim.t_s))))
                     .round().astype(int))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "simulation.gif"
        write_animation(robot, sim.t_s[pick],
                        sim.q[pick], path, f"{robot.name}: forward dynamics ({sim.method})",
                        fps=fps, dpi=dpi, figsize=(4.8, 4.0))
        return path.read_bytes()


def _drift_label(sim: Simulation) -> str:
    """A free run's energy drift checks the integrator; where the actuators did work or
    friction took some (a user trial: "drift" 0.91 beside a balance of 1e-11), it is the
    change the balance accounts for, and is named so."""
    moved = [a for a in (sim.work_j, sim.friction_j) if a is not None and np.any(a != 0.0)]
    if moved:
        return "energy change max|E - E(0)| / scale (work and friction change E)"
    return "energy drift max|E - E(0)| / scale"


def robot_of(sim: Simulation) -> tuple[Robot | None, str]:
    """The robot a Simulation names (its ``robot`` field), if its parameters are the ones that
    ran: its compiled energies at three samples must match the run's to 1e-9 relative (a robot
    whose parameters were changed with ``with_parameters`` would be drawn wrongly otherwise).

    Returns
    -------
    (Robot or None, str)
        The robot, or None with the reason it is not used ("" when the run names none).
    """
    from ..errors import PlanarSymError
    from ..model.locate import load

    name = getattr(sim, "robot", "")
    if not isinstance(name, str) or not name:
        return None, ""
    try:
        robot = load(name)
    except PlanarSymError as exc:
        return None, f"{name} not loadable here ({exc})"
    pick = np.unique(np.linspace(0, len(sim.t_s) - 1, 3).round().astype(int))
    if robot.n != sim.q.shape[1]:
        return None, f"{name} has {robot.n} coordinates, the run {sim.q.shape[1]}"
    kinetic, potential = robot.energy(sim.q[pick], sim.qd[pick])
    ran = np.concatenate([sim.kinetic_j[pick], sim.potential_j[pick]])
    scale = max(float(np.max(np.abs(ran))), 1e-12)
    if np.max(np.abs(np.concatenate([kinetic, potential]) - ran)) > 1e-9 * scale:
        return None, (f"the run's energies differ from {name}'s own: its parameters were "
                      "changed; show(sim, robot) with the robot that ran draws it")
    return robot, ""


def simulation_html(sim: Simulation, robot: Robot | None = None, picture: bool = True) -> str:
    """A forward-dynamics run as HTML: how it was integrated, how well, and what happened.

    Parameters
    ----------
    sim : Simulation
    robot : Robot, optional
        The simulated robot: names the coordinates and adds an animation (a GIF of at most
        ``FRAMES`` frames). Default: the robot the run names (``robot_of``), when its
        parameters are those that ran; else the table and the plot only.
    picture : bool
        Embed the plot (and the animation).

    Returns
    -------
    str
        An HTML fragment: a table (method, rtol, atol, samples, duration in s, right-hand-side
        evaluations, relative energy drift, loop drift in m, initial correction in rad), the
        plot (``simulation_figure``) and, with a robot, the animation, each an ``<img>`` with a
        data URI.
    """
    why = ""
    if robot is None:
        robot, why = robot_of(sim)
    t = sim.t_s
    rows = [("method", sim.method), ("rtol", f"{sim.rtol:g}"), ("atol", f"{sim.atol:g}"),
            ("samples", str(len(t))), ("duration", f"{t[-1] - t[0]:.6g} s"),
            ("right-hand-side evaluations", str(sim.n_rhs)),
            (_drift_label(sim), f"{sim.energy_drift:.3g}"),
            ("energy E(0), E(end)", f"{sim.energy_j[0]:.6g} J, {sim.energy_j[-1]:.6g} J")]
    if sim.balance_residual is not None:  # the check of a driven or rubbing run
        rows.append(("energy balance max|E - E(0) - (W - F)| / scale",
                     f"{sim.balance_residual:.3g}"))
    if robot is not None:
        rows.insert(0, ("robot", robot.name))
    if (robot is not None and robot.is_closed_chain) or sim.constraint_drift_m:
        rows.append(("loop drift max|Phi|", f"{sim.constraint_drift_m:.3g} m"))
    if sim.initial_correction_rad:
        rows.append(("initial correction", f"{sim.initial_correction_rad:.3g} rad"))
    if why:
        rows.append(("not animated", why))
    parts = [_table(rows)]
    if picture:
        parts.append(img_tag(png_bytes(simulation_figure(sim, robot)), "image/png",
                             "simulation plot"))
        gif = simulation_gif(sim, robot) if robot is not None else None
        if gif is not None:
            parts.append(img_tag(gif, "image/gif", f"{robot.name} moving"))
    return _wrap("Simulation" + (f" of {robot.name}" if robot is not None else ""), *parts)


class Shown:
    """Something displayed in a notebook by its HTML (``_repr_html_``): ``fragment``, one
    self-contained HTML fragment (pictures embedded as data URIs)."""

    def __init__(self, fragment: str):
        self.fragment = fragment

    def _repr_html_(self) -> str:
        return self.fragment


def show(obj, robot: Robot | None = None) -> Shown:
    """A notebook display of a Robot, Result or Simulation (with its robot: animated).

    Parameters
    ----------
    obj : Robot, Result or Simulation
    robot : Robot, optional
        For a Simulation: the simulated robot, to name its coordinates and animate it.
    """
    if isinstance(obj, Simulation):
        return Shown(simulation_html(obj, robot))
    if isinstance(obj, Robot):
        return Shown(robot_html(obj))
    if isinstance(obj, Result):
        return Shown(result_html(obj))
    from ..errors import InputError

    raise InputError(f"show takes a Robot, a study Result or a Simulation, got "
                     f"{type(obj).__name__}")


def register(shell) -> None:
    """Show Robot, Result and Simulation as HTML in an IPython ``shell`` (``get_ipython()``).

    Registered by type with the shell's ``text/html`` formatter; calling it again replaces the
    same entries. The plain-text ``repr`` stays as it was (terminals, doctests).
    """
    formatter = shell.display_formatter.formatters["text/html"]
    formatter.for_type(Robot, robot_html)
    formatter.for_type(Result, result_html)
    formatter.for_type(Simulation, simulation_html)
