"""Pictures: ``draw``, ``animate``, ``run --split``, ``demo`` and ``Result.plot``.

Every picture is checked by numbers: the drawing's markers against the description's own
drawn-configuration coordinates (read from the TOML, not through the runtime), GIF frame counts
and image sizes, the torque split against the total torques and against virtual work, and the
demo index against its CSV files.
"""

from __future__ import annotations

import re
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest
from conftest import (
    ALL_ROBOTS,
    BUILTIN_ROBOTS,
    CLOSED,
    ROBOTS_DIR,
    ROOT,
    seed_studies,
    serial_2dof_in_cm,
)
from PIL import Image

import planar_sym as ps
from planar_sym.cli import main
from planar_sym.dynamics.inverse import SPLIT_PARTS
from planar_sym.errors import PlanarSymError
from planar_sym.model.description import load as load_description
from planar_sym.model.locate import load
from planar_sym.model.units import factor
from planar_sym.motion.closure import complete_rates
from planar_sym.outputs.drawing import drawing_figure, geometry
from planar_sym.study.run import motion, run

SCENARIOS = seed_studies()

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def png_size(path: Path) -> tuple[int, int]:
    """Width and height (pixels) from a PNG's IHDR chunk; checks the signature first."""
    data = path.read_bytes()
    assert data[:8] == PNG_SIGNATURE, f"{path} is not a PNG"
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def toml_file(robot: str) -> Path:
    """A built-in robot's description, or a description file named by its path."""
    return Path(robot) if robot.endswith(".toml") else ROBOTS_DIR / f"{robot}.toml"


def typed_unit(robot: str) -> tuple[str, float]:
    """The description's length unit and how many of it make a metre: the drawing's unit."""
    unit = tomllib.loads(toml_file(robot).read_text())["units"]["length"]
    return unit, {"m": 1.0, "cm": 100.0, "mm": 1000.0}[unit]


def toml_world(robot: str) -> tuple[dict, dict]:
    """Drawn-configuration world points and centres of gravity (m), straight from the TOML."""
    raw = tomllib.loads(toml_file(robot).read_text())
    unit = factor("length", raw["units"]["length"])
    points = {("ground", p): np.array(xy) * unit for p, xy in raw["ground"]["points"].items()}
    cgs = {}
    for b in raw["bodies"]:
        pts = {p: np.array(xy) * unit for p, xy in b["points"].items()}
        points.update({(b["name"], p): xy for p, xy in pts.items()})
        base = np.zeros(2) if b["cg_from"] == "world" else pts[b["cg_from"]]
        cgs[b["name"]] = base + np.array(b["cg"]) * unit
    return points, cgs


def artists(fig) -> dict[str, object]:
    return {a.get_gid(): a for a in fig.axes[0].get_children() if a.get_gid()}


# -- the geometry behind every picture ------------------------------------------------------

@pytest.mark.parametrize("robot", ALL_ROBOTS)
def test_world_points_of_the_drawn_configuration_are_the_descriptions(robot):
    r = load(robot)
    geo = geometry(load_description(robot), r.body_names, r.frames(r.q_drawn))
    points, cgs = toml_world(robot)
    assert set(geo.points) == set(points)
    for key, xy in points.items():
        assert np.max(np.abs(geo.points[key][0] - xy)) < 1e-12, key
    for body, xy in cgs.items():
        assert np.max(np.abs(geo.cgs[body][0] - xy)) < 1e-12, body


@pytest.mark.parametrize("robot", ALL_ROBOTS)
def test_drawing_markers_sit_on_the_described_points(robot):
    """Every marker where the description puts it, in the unit the description is typed in
    (every built-in robot is typed in m)."""
    desc = load_description(robot)
    points, cgs = toml_world(robot)
    unit, k = typed_unit(robot)
    fig = drawing_figure(robot)
    arts = artists(fig)
    ax = fig.axes[0]
    colours = {"actuated": "black", "passive": "white"}
    for j in (*desc.tree_joints, *desc.loop_joints):
        if j.type != "revolute":
            continue
        marker = arts[f"joint:{j.name}"]
        xy_mm = np.column_stack(marker.get_data())[0]
        assert np.max(np.abs(xy_mm - points[(j.parent, j.parent_point)] * k)) < 1e-9 * k / 1e3
        # a loop closes (to 1e-2 mm)
        assert np.max(np.abs(xy_mm - points[(j.child, j.child_point)] * k)) < 1e-2 * k / 1e3
        role = "cut" if j.closes_loop else "actuated" if j.actuated else "passive"
        if role == "cut":
            assert marker.get_markeredgecolor() == "red"
        else:
            assert marker.get_markerfacecolor() == colours[role]
    for body, xy in cgs.items():
        got = np.column_stack(arts[f"cg:{body}"].get_data())[0]
        assert np.max(np.abs(got - xy * k)) < 1e-9 * k / 1e3
    if desc.task_point is not None:
        task = np.column_stack(arts["task"].get_data())[0]
        assert np.max(np.abs(task - points[desc.task_point] * k)) < 1e-9 * k / 1e3
    texts = {t.get_text() for t in ax.texts}
    assert {j.name for j in desc.tree_joints if j.type == "revolute"} <= texts
    assert desc.name in ax.get_title()
    assert ax.get_xlabel() == f"x ({unit})" and ax.get_ylabel() == f"y ({unit})"
    assert ax.get_aspect() == 1.0


@pytest.mark.parametrize(("example", "unit"), [("jansen_linkage", "cm"), ("four_bar", "mm"),
                                               ("serial_2dof_geared", "m")])
def test_a_robot_is_drawn_in_the_unit_it_is_typed_in(example, unit):
    """The Jansen leg typed in cm is drawn in cm, the four-bar in mm, a geared arm in m: each
    ground pivot's marker sits on the very numbers typed under [ground] points, the title
    and the animation use the same unit, and ``Robot.length_unit`` says which."""
    from planar_sym.outputs.animation import scene_figure

    path = ROOT / "examples" / f"{example}.toml"
    raw = tomllib.loads(path.read_text())
    desc = load_description(path)
    fig = drawing_figure(str(path))
    ax, arts = fig.axes[0], artists(fig)
    assert ax.get_xlabel() == f"x ({unit})" and ax.get_ylabel() == f"y ({unit})"
    grounded = [j for j in (*desc.tree_joints, *desc.loop_joints)
                if j.parent == "ground" and j.type == "revolute"]
    # a pivot away from the origin, where a wrong scale shows (the geared arm has one pivot)
    assert unit == "m" or any(np.any(raw["ground"]["points"][j.parent_point]) for j in grounded)
    for j in grounded:
        typed = np.array(raw["ground"]["points"][j.parent_point], dtype=float)
        got = np.column_stack(arts[f"joint:{j.name}"].get_data())[0]
        assert np.max(np.abs(got - typed)) < 1e-9 * max(1.0, np.max(np.abs(typed))), j.name
    robot = load(str(path))
    assert robot.length_unit == unit
    q = np.tile(robot.q_drawn, (3, 1))
    moving, _ = scene_figure(robot, np.array([0.0, 0.1, 0.2]), q, "title")
    assert moving.axes[0].get_xlabel() == f"x ({unit})"
    if unit == "cm":  # a span of about 1 m: axis limits of about a hundred, not a thousand
        assert 50 < np.ptp(ax.get_xlim()) < 300


def test_link_with_three_points_is_drawn_through_them_in_order():
    points, _ = toml_world("five_bar_type1")
    line = artists(drawing_figure("five_bar_type1"))["body:L_Link2"]
    want = np.array([points[("L_Link2", p)] for p in ("CS1", "CS2", "CS3")])  # B, C, P: in m
    assert np.max(np.abs(np.column_stack(line.get_data()) - want)) < 1e-9


# -- draw --------------------------------------------------------------------------------

def test_draw_command_writes_a_png_of_the_figure_size(tmp_path, capsys):
    out = tmp_path / "five.png"
    assert main(["draw", "five_bar_type1", "--out", str(out)]) == 0
    assert png_size(out) == (800, 600)  # 8 x 6 in at 100 dpi
    assert str(out) in capsys.readouterr().out
    assert main(["--quiet", "draw", "parallel_3rrr", "--out", str(out), "--dpi", "50"]) == 0
    assert png_size(out) == (400, 300)
    assert capsys.readouterr().out == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["five.png"]  # no temporary files


def test_a_robot_that_is_one_point_gets_a_frame_to_be_drawn_in(tmp_path):
    """A cart drawn as its mass on a rail: its span is zero, and matplotlib warned twice of
    identical axis limits (a user trial). It gets 0.1 m about the point, its frame's arrows
    a length."""
    import warnings

    path = tmp_path / "cart.toml"
    path.write_text('name = "cart"\ntitle = "cart"\ngravity = [0.0, -9.81]\n[units]\n'
                    'length = "m"\nmass = "kg"\nacceleration = "m/s^2"\n[ground]\n'
                    'points = { rail = [0.0, 0.0] }\n[[bodies]]\nname = "cart"\nmass = 2.0\n'
                    'mass_at = "C"\npoints = { C = [0.0, 0.0] }\n[[joints]]\nname = "slide"\n'
                    'type = "prismatic"\nparent = "ground.rail"\nchild = "cart.C"\n'
                    'actuated = true\naxis = [1.0, 0.0]\n')
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ax = drawing_figure(str(path)).axes[0]
    lo, hi = ax.get_xlim()
    assert 0.05 < hi - lo < 0.2 and lo < 0.0 < hi  # seen: 0.084 m


def test_draw_errors_write_nothing(tmp_path, capsys):
    assert main(["draw", "no_such_robot", "--out", str(tmp_path / "x.png")]) == 2
    assert "unknown robot" in capsys.readouterr().err
    assert main(["draw", "serial_2dof", "--out", str(tmp_path / "x.jpg")]) == 2
    assert ".png" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_draw_failing_midway_leaves_the_old_file(tmp_path, monkeypatch, capsys):
    from matplotlib.figure import Figure

    out = tmp_path / "arm.png"
    out.write_bytes(b"previous picture")

    def failing(self, path, **kw):
        Path(path).write_bytes(PNG_SIGNATURE + b"half")
        raise PlanarSymError("simulated failure while drawing")

    monkeypatch.setattr(Figure, "savefig", failing)
    assert main(["draw", "serial_2dof", "--out", str(out)]) == 2
    assert "simulated failure" in capsys.readouterr().err
    assert [p.name for p in tmp_path.iterdir()] == ["arm.png"]
    assert out.read_bytes() == b"previous picture"


# -- animate -----------------------------------------------------------------------------

@pytest.mark.parametrize("name, frames", [("five_bar_type1_move_x", 4),
                                          ("serial_2dof_free_swing", 3)])
def test_animate_gif_has_every_frame(tmp_path, name, frames):
    out = tmp_path / "a.gif"
    assert main(["--quiet", "animate", name, "--out", str(out), "--frames", str(frames),
                 "--fps", "10"]) == 0
    with Image.open(out) as im:
        assert im.format == "GIF"
        assert im.n_frames == frames
        assert im.size == (448, 368)  # 5.6 x 4.6 in at 80 dpi
        assert im.info["duration"] == 100  # ms per frame at 10 fps
    assert [p.name for p in tmp_path.iterdir()] == ["a.gif"]


def test_animation_motion_is_the_simulation_and_the_full_trajectory():
    robot, t, q = motion("serial_2dof_free_swing", 11)
    res = run("serial_2dof_free_swing", 11)
    assert np.array_equal(t, res.columns["t_s"])
    assert np.max(np.abs(q - np.column_stack([res.columns["q1_rad"], res.columns["q2_rad"]]))) < 1e-12
    robot, t, q = motion("five_bar_type1_move_x", 11)
    res = run("five_bar_type1_move_x", 11)
    assert q.shape == (11, 4)  # passive joints B and D too
    assert np.max(np.abs(robot.constraint(q))) < 1e-9
    for i in range(robot.n):  # every coordinate is in the CSV now
        assert np.max(np.abs(q[:, i] - res.columns[f"q{i + 1}_rad"])) < 1e-12


def test_animate_mp4_needs_ffmpeg(tmp_path, capsys):
    out = tmp_path / "a.mp4"
    code = main(["--quiet", "animate", "serial_2dof_joint_move", "--out", str(out),
                 "--frames", "3"])
    if shutil.which("ffmpeg"):
        assert code == 0 and out.stat().st_size > 0
    else:
        assert code == 2
        assert "ffmpeg" in capsys.readouterr().err
        assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("argv, message", [
    (["no_such_scenario"], "unknown study"),
    (["serial_2dof_joint_move", "--frames", "1"], "frames"),
    (["serial_2dof_joint_move", "--fps", "0"], "fps"),
    (["serial_2dof_joint_move", "--out", "a.avi"], ".gif")])
def test_animate_bad_requests(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.chdir(tmp_path)
    assert main(["animate", *argv]) == 2
    assert message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_animate_failing_midway_leaves_the_old_file(tmp_path, monkeypatch, capsys):
    from planar_sym.outputs import animation

    out = tmp_path / "a.gif"
    out.write_bytes(b"previous animation")

    def fails_while_writing(path, frames, fps):
        Path(path).write_bytes(b"GIF89a partial")
        raise PlanarSymError(f"simulated failure after frame 2 of {len(frames)}")

    monkeypatch.setattr(animation, "_write_gif", fails_while_writing)
    assert main(["animate", "serial_2dof_joint_move", "--out", str(out), "--frames", "4"]) == 2
    assert "frame 2" in capsys.readouterr().err
    assert [p.name for p in tmp_path.iterdir()] == ["a.gif"]
    assert out.read_bytes() == b"previous animation"


# -- the torque split --------------------------------------------------------------------

@pytest.mark.parametrize("name", list(SCENARIOS))
def test_split_parts_sum_to_the_torques(name):
    res = run(name, 21)
    parts = [res.split[k] for k in SPLIT_PARTS]
    total = sum(parts)
    taus = list(res.torques())  # tau<k>_n_m, and tau<k>_n for a prismatic joint's force
    if taus:
        want = np.column_stack([res.columns[k] for k in taus])
    else:  # the free swing: tau = 0, the parts balance
        want = np.zeros_like(total)
        assert max(np.max(np.abs(p)) for p in parts) > 0.01  # and are not all zero
    assert total.shape == want.shape
    assert np.max(np.abs(total - want)) < 1e-12


def test_split_gravity_of_the_2dof_arm_by_hand():
    """g(q) of the textbook 2-DOF arm written out by hand; the velocity part at qd = 0."""
    arm = load("serial_2dof")
    p = arm.parameters
    rng = np.random.default_rng(4)
    q = rng.uniform(-np.pi, np.pi, (7, 2))
    zero = np.zeros_like(q)
    from planar_sym.dynamics.inverse import torque_split

    parts = torque_split(arm, q, zero, zero)
    m1, m_m, m2 = p["m_link1"], p["m_motor2"], p["m_link2"]
    a1, lc1, lc2, g = p["px_link1_CS2"], p["cgx_link1"], p["cgx_link2"], p["g"]
    g2 = m2 * lc2 * g * np.cos(q[:, 0] + q[:, 1])
    g1 = (m1 * lc1 + (m_m + m2) * a1) * g * np.cos(q[:, 0]) + g2
    assert np.max(np.abs(parts["gravity"] - np.column_stack([g1, g2]))) < 1e-14
    assert np.max(np.abs(parts["inertial"])) == 0.0 and np.max(np.abs(parts["velocity"])) < 1e-15


@pytest.mark.parametrize("robot", CLOSED)
def test_closed_chain_split_by_virtual_work(robot):
    """Each part's actuated torques do the same virtual work as the part itself:
    tau_part[k] = part . v_k, with v_k the loop-consistent velocity of unit actuated rate k."""
    name = {"five_bar_type1": "five_bar_type1_move_y", "five_bar_type2": "five_bar_type2_move_x",
            "parallel_3rrr": "parallel_3rrr_move_x"}[robot]
    from planar_sym.dynamics.inverse import torque_split
    from planar_sym.study.motion import joint_motion

    r, st = load(robot), SCENARIOS[name]
    jt, _ = joint_motion(st, r, t=np.linspace(0.0, st.motion.duration_s, 9))
    parts = torque_split(r, jt.q, jt.qd, jt.qdd)
    n_s, n = jt.q.shape
    mass = r.mass_matrix(jt.q).reshape(n_s, n, n)
    h, g = r.bias(jt.q, jt.qd), r.gravity(jt.q)
    raw = {"inertial": (mass @ jt.qdd[..., None])[..., 0], "velocity": h - g, "gravity": g}
    zeros = np.zeros((n_s, len(r.actuated)))
    for k in range(len(r.actuated)):
        unit = zeros.copy()
        unit[:, k] = 1.0
        v, _ = complete_rates(r, jt.q, unit, zeros)
        for part, value in raw.items():
            work = np.sum(value * v, axis=1)
            assert np.max(np.abs(parts[part][:, k] - work)) < 1e-12 * max(1, np.max(np.abs(work)))


# -- run --split and Result.plot ---------------------------------------------------------

def test_run_split_writes_three_files(tmp_path):
    out = tmp_path / "res"
    assert main(["--quiet", "run", "parallel_3rrr_move_y", "--out", str(out), "--samples", "11",
                 "--split"]) == 0
    name = "parallel_3rrr_move_y"
    assert sorted(p.name for p in out.iterdir()) == [f"{name}.csv", f"{name}.png",
                                                     f"{name}_split.png"]
    assert png_size(out / f"{name}_split.png") == (770, 737)  # 7 x (1 + 1.9 * 3) in at 110 dpi


def test_result_plot_returns_figures():
    res = run("five_bar_type2_move_x", 11)
    fig = ps.plot(res)
    assert [ax.get_ylabel() for ax in fig.axes] == ["torque tau1 (N*m)", "torque tau3 (N*m)",
                                                     "joint load |F| (N)"]
    fig = ps.plot(res, split=True)
    assert len(fig.axes) == 2
    for k, ax in enumerate(fig.axes):
        lines = ax.get_lines()[:4]
        name = ("tau1", "tau3")[k]  # the actuated joints A = q1, E = q3
        assert [ln.get_label() for ln in lines] == [f"{name} (total)", "M qdd", "C qd", "g"]
        ys = [ln.get_ydata() for ln in lines]
        assert np.max(np.abs(ys[1] + ys[2] + ys[3] - ys[0])) < 1e-12
    assert fig.axes[-1].get_xlabel() == "time t (s)"
    swing = run("serial_2dof_free_swing", 11)
    assert ps.plot(swing).axes[0].get_ylabel() == "joint angle q1 (deg)"
    assert len(ps.plot(swing, split=True).axes) == 2


# -- demo --------------------------------------------------------------------------------

def test_demo_writes_everything_and_an_index(tmp_path, capsys):
    out = tmp_path / "demo"
    # 3 frames: the generic (Newton) inverse kinematics of a task move (serial_rpr,
    # parallel_3rpr) refuses a rest-to-rest move sampled at its two ends only, as it cannot tell
    # that step from a branch jump
    assert main(["demo", "--out", str(out), "--samples", "5", "--frames", "3"]) == 0
    progress = capsys.readouterr().err.strip().splitlines()
    robots = BUILTIN_ROBOTS
    assert len(progress) == 2 * len(SCENARIOS) + len(robots) + 1  # one line per item
    assert progress[-1].startswith(f"[{len(progress)}/{len(progress)}] index")
    index = (out / "README.md").read_text()
    for name in SCENARIOS:
        row = next(line for line in index.splitlines() if line.startswith(f"| `{name}` |"))
        for target in re.findall(r"\]\(([^)]+)\)", row):
            assert (out / target).is_file(), target
        assert SCENARIOS[name].title in row
        table = np.genfromtxt(out / f"{name}.csv", delimiter=",", names=True)
        # tau<k>_n_m, or tau<k>_n for a prismatic joint's force
        taus = [k for k in table.dtype.names if re.fullmatch(r"tau\d+_n(_m)?", k)]
        found = dict(re.findall(r"(tau\d+) = ([-+0-9.e]+)", row))
        assert sorted(found) == sorted(k.split("_")[0] for k in taus)
        for k in taus:
            assert float(found[k.split("_")[0]]) == pytest.approx(np.max(np.abs(table[k])),
                                                                   rel=1e-5)
        with Image.open(out / f"{name}.gif") as im:
            assert im.n_frames == 3
        assert png_size(out / f"{name}_split.png")[0] == 770
    for robot in robots:
        assert f"[{robot}.png]({robot}.png)" in index
        assert png_size(out / f"{robot}.png") == (800, 600)
    assert not [p for p in out.iterdir() if p.name.startswith(".")]  # no temporary files


def test_demo_failing_midway_leaves_no_partial_file(tmp_path, monkeypatch, capsys):
    from planar_sym.commands import run as run_command

    real, calls = run_command.animate_study, []

    def second_fails(st, path, **kw):
        calls.append(st.name)
        if len(calls) == 2:
            raise PlanarSymError("simulated failure in an animation")
        return real(st, path, **kw)

    monkeypatch.setattr(run_command, "animate_study", second_fails)
    out = tmp_path / "demo"
    assert main(["--quiet", "demo", "--out", str(out), "--samples", "5", "--frames", "2"]) == 2
    assert "simulated failure" in capsys.readouterr().err
    first, second = list(SCENARIOS)[:2]  # in name order, as demo runs them
    written = sorted(p.name for p in out.iterdir())
    assert written == sorted([f"{first}.csv", f"{first}.png", f"{first}_split.png",
                              f"{first}.gif", f"{second}.csv", f"{second}.png",
                              f"{second}_split.png"])  # complete files only, no index


def test_an_atlas_of_a_robot_typed_in_cm_is_mapped_in_cm(tmp_path):
    """The seed's 2-DOF arm typed again in cm: the same atlas (SI arrays to 1e-9), its maps'
    axes in cm with limits 100 times those of the arm typed in m, L_c in cm."""
    from planar_sym.outputs.atlas_plots import atlas_figure

    path = serial_2dof_in_cm(tmp_path)
    in_cm, in_m = ps.atlas(str(path), points=11), ps.atlas("serial_2dof", points=11)
    assert (in_cm.length_unit, in_m.length_unit) == ("cm", "m")
    assert np.allclose(in_cm.x_m, in_m.x_m, rtol=0, atol=1e-12)
    assert np.allclose(in_cm.gravity, in_m.gravity, rtol=1e-9, atol=1e-12, equal_nan=True)
    ax_cm, ax_m = atlas_figure(in_cm).axes[0], atlas_figure(in_m).axes[0]
    assert ax_cm.get_xlabel() == "x (cm)" and ax_m.get_xlabel() == "x (m)"
    assert np.allclose(np.array(ax_cm.get_xlim()), 100 * np.array(ax_m.get_xlim()), rtol=1e-12)
    title = atlas_figure(in_cm).get_suptitle()
    assert f"(L_c = {in_cm.length_scale_m * 100:.4g} cm)" in title, title


@pytest.mark.parametrize("robot", [*ALL_ROBOTS, str(ROOT / "examples" / "jansen_linkage.toml"),
                                   str(ROOT / "examples" / "cart_pole.toml")],
                         ids=lambda r: Path(r).stem)
def test_joint_labels_do_not_cover_each_other(robot):
    """Measured as drawn: no two labels' boxes overlap (the Jansen leg's crank and its j/k
    joint sit 15 cm apart on one row, closer than the crank's name is long)."""
    fig = drawing_figure(robot)
    fig.draw_without_rendering()
    labels = [t for t in fig.axes[0].texts if t.get_text() and t.get_text() not in ("x0", "y0")]
    boxes = [t.get_window_extent() for t in labels]
    for i, a in enumerate(boxes):
        for j in range(i):
            assert not a.overlaps(boxes[j]), (labels[i].get_text(), labels[j].get_text())
