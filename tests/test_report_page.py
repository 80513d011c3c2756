"""``planar-sym report STUDY... --out DIR`` (issue 29, item 2): the page ``index.html`` for the
user's own robot and studies, its numbers checked against the CSV files the same command wrote
and against the robot's description file, and opened in headless Chromium (the harness of
``test_html_index.py``)."""

from __future__ import annotations

import html
import re
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest
from test_html_index import IMAGES, SHOT, DevTools, chromium

import planar_sym as ps
from planar_sym.cli import main, parser

ROOT = Path(__file__).resolve().parent.parent
ROBOT = ROOT / "tests" / "robots" / "actuated_2dof.toml"  # geared: a sizing with gears
trapezoid = getattr(np, "trapezoid", None) or np.trapz  # numpy 2 renamed trapz

MOVE = """title = "geared arm: both joints 60 deg in 1 s"
robot = "actuated_2dof.toml"
kind = "inverse"
[units]
angle = "deg"
[motion]
space = "joint"
profile = "quintic"
start = [0.0, 30.0]
by = [60.0, 60.0]
duration = 1.0
samples = 51
"""

TRACK = """title = "geared arm tracked, start 2 deg off, forearm heavier in the plant"
robot = "actuated_2dof.toml"
kind = "control"
[units]
length = "mm"
angle = "deg"
[motion]
space = "task"
profile = "cubic"
start = [100.0, 100.0]
by = [-50.0, 0.0]
duration = 1.0
samples = 41
start_pose = [30.0, 60.0]
[control]
law = "computed_torque"
natural_frequency_hz = 5.0
duration = 1.2
samples = 61
start_error = [2.0, -2.0]
[control.plant]
m_link2 = 0.09
"""


@pytest.fixture(scope="module")
def made(tmp_path_factory) -> tuple[Path, Path]:
    """A folder with a user robot and two studies of it; DIR holds a sweep and an atlas of
    them (which `report` does not run, but shows) and then `report`'s files and page."""
    work = tmp_path_factory.mktemp("mine")
    shutil.copy(ROBOT, work)
    (work / "arm_move.toml").write_text(MOVE)
    (work / "arm_track.toml").write_text(TRACK)
    out = work / "page"
    assert main(["--quiet", "sweep", str(work / "arm_move.toml"), "--vary",
                 "gear_joint1=10:50:3", "--workers", "1", "--out", str(out)]) == 0
    assert main(["--quiet", "atlas", str(work / "actuated_2dof.toml"), "--points", "8",
                 "--q-start", "30", "60", "--out", str(out)]) == 0
    assert main(["--quiet", "report", str(work / "arm_move.toml"), str(work / "arm_track.toml"),
                 "--out", str(out)]) == 0
    return work, out


def table_after(page: str, heading: str, nth: int = 0) -> list[list[str]]:
    """The cells (text) of the first table after the ``nth`` occurrence of ``heading``."""
    start = [m.end() for m in re.finditer(re.escape(heading), page)][nth]
    table = page[start:].split("<table>", 1)[1].split("</table>", 1)[0]
    return [[html.unescape(c) for c in re.findall(r"<t[hd]>(.*?)</t[hd]>", row)]
            for row in re.findall(r"<tr>(.*?)</tr>", table)]


def csv_columns(path: Path) -> dict[str, np.ndarray]:
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {name: data[name] for name in data.dtype.names}


def test_sizing_table_is_the_csvs_numbers(made):
    """Peak and RMS torque at the joint and the motor, speed, power, energy: each recomputed
    from arm_move.csv and the gear ratios in the description file, to the 4 printed digits."""
    out = made[1]
    page = (out / "index.html").read_text()
    header, *body = table_after(page[page.index('id="study-arm_move"'):], "actuator sizing")
    assert header[:3] == ["joint", "gear", "peak / RMS joint torque"]
    c = csv_columns(out / "arm_move.csv")
    t = c["t_s"]
    gears = [j["actuator"]["gear_ratio"] for j in tomllib.loads(ROBOT.read_text())["joints"]
             if "actuator" in j]
    assert len(body) == len(gears) == 2
    for k, (row, gear) in enumerate(zip(body, gears), start=1):
        tau, qd = c[f"tau{k}_n_m"], c[f"qd{k}_rad_s"]
        rms = np.sqrt(trapezoid(tau**2, t) / (t[-1] - t[0]))
        power = tau * qd
        energy = trapezoid(power, t)
        g = lambda v: f"{v:.4g}"  # the table's precision
        assert row == [f"joint{k}", g(gear), f"{g(np.abs(tau).max())} / {g(rms)} N*m",
                       f"{g(np.abs(tau).max() / gear)} / {g(rms / gear)}",
                       f"{g(np.abs(qd).max())} rad/s",
                       g(np.abs(qd).max() * gear * 60 / (2 * np.pi)),
                       f"{g(np.abs(power).max())} / {g(energy / (t[-1] - t[0]))}", g(energy),
                       "within"]


def test_tracking_errors_are_the_csvs(made):
    out = made[1]
    page = (out / "index.html").read_text()
    rows = table_after(page[page.index('id="study-arm_track"'):], "tracking error")
    c = csv_columns(out / "arm_track.csv")
    want = [[name, f"{np.abs(c[col]).max():.3g} {unit}", f"{abs(c[col][-1]):.3g} {unit}"]
            for name, col, unit in (("e1", "e1_rad", "rad"), ("e2", "e2_rad", "rad"),
                                    ("tool point", "e_task_mm", "mm"))]
    assert rows == [["error", "largest |e|", "|e| at the end"], *want]


def test_sweep_table_is_the_sweeps_csv(made):
    out = made[1]
    page = (out / "index.html").read_text()
    header, *rows = table_after(page, '<section id="sweep-arm_move_sweep">')
    import csv

    def cell(v: str) -> str:  # numbers to 6 digits; the limits column's text as it is
        try:
            return f"{float(v):.6g}"
        except ValueError:
            return v

    lines = list(csv.reader((out / "arm_move_sweep.csv").read_text().splitlines()))
    assert header == lines[0]
    assert rows == [[cell(v) for v in line] for line in lines[1:]]
    assert len(rows) == 3
    # the study's own CSV is not taken for a sweep's, and the atlas is there with its tables
    assert 'id="sweep-arm_move"' not in page
    assert '<a href="atlas.csv">atlas.csv</a>' in page


def test_missing_study_file_is_named_and_nothing_is_written(tmp_path, capsys):
    missing = tmp_path / "nowhere" / "gone.toml"
    out = tmp_path / "page"
    assert main(["report", str(missing), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and str(missing) in err and err.count("\n") <= 3
    assert not out.exists()


def test_failing_study_is_named_and_nothing_is_written(made, tmp_path, capsys):
    """The first study runs, the second cannot (its target is out of reach): no file at all."""
    work, _ = made
    bad = work / "too_far.toml"
    bad.write_text(TRACK.replace('kind = "control"', 'kind = "inverse"')
                   .replace("by = [-50.0, 0.0]", "by = [900.0, 0.0]").split("[control]")[0])
    out = tmp_path / "page"
    assert main(["report", str(work / "arm_move.toml"), str(bad), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {bad}: ") and "reach" in err
    assert not out.exists()


def test_help_says_it_takes_study_files_or_builtin_names():
    sub = next(a for a in parser()._actions if a.dest == "command")
    text = " ".join(sub.choices["report"].format_help().split())
    assert "study file (.toml) or a built-in study name" in text
    assert "index.html" in text


# -- in a real browser -----------------------------------------------------------------

@pytest.fixture(scope="module")
def shown(made, tmp_path_factory) -> dict:
    """What Chromium makes of the page, read once: problems, images, links, sizes, text."""
    tools = DevTools(chromium(), tmp_path_factory.mktemp("chromium-profile"))
    try:
        tools.open((made[1] / "index.html").as_uri())
        return {"problems": tools.problems(), "images": tools.js(IMAGES),
                "text": tools.js("document.body.innerText"),
                "window": tools.js("window.innerWidth"),
                "page_width": tools.js("document.documentElement.scrollWidth"),
                "pictures": tools.js("""[...document.images].map(i => ({
                    src: i.getAttribute('src'), width: i.getBoundingClientRect().width,
                    link: i.parentElement.tagName === 'A' ? i.parentElement.href : null}))"""),
                "equations": tools.js("""[...document.querySelectorAll('section[id^=robot-]')]
                    .map(s => [s.id, s.querySelector('pre')?.textContent])""")}
    finally:
        tools.close()


def test_page_opens_clean_with_every_picture(made, shown):
    out = made[1]
    assert shown["problems"] == []
    assert all(i["ok"] for i in shown["images"]), [i for i in shown["images"] if not i["ok"]]
    # every picture in DIR is on the page: plots, the drawing, the sweep, the atlas maps
    assert sorted(p["src"] for p in shown["pictures"]) == sorted(p.name for p in out.glob("*.png"))
    assert {"arm_move.png", "arm_track.png", "actuated_2dof.png", "arm_move_sweep.png",
            "atlas.png"} <= {p["src"] for p in shown["pictures"]}


def test_every_picture_is_a_link_to_its_file(made, shown):
    out = made[1]
    for p in shown["pictures"]:
        assert p["link"] == (out / p["src"]).as_uri(), p
        assert (out / p["src"]).is_file()


def test_pictures_are_readable_on_a_laptop_screen(shown):
    """At least 600 CSS px wide in a 1280 px window (the old page capped them at 460 px), and
    the page is no wider than the window (the sweep's wide table scrolls on its own)."""
    assert shown["window"] == SHOT[0] == 1280
    narrow = [(p["src"], p["width"]) for p in shown["pictures"] if p["width"] < 600]
    assert narrow == []
    assert shown["page_width"] <= shown["window"]


def test_user_robot_has_its_drawing_title_and_equations(shown):
    text = shown["text"]
    for wrong in ("unknown robot", "equations not available", "description not readable"):
        assert wrong not in text
    assert dict(shown["equations"]) == {"robot-actuated_2dof": ps.equations(ROBOT).text}
    assert tomllib.loads(ROBOT.read_text())["title"] in text
