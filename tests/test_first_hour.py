"""Frictions of a new user's first hour (issue 29, item 6), each checked against an
independent source: the installed package's metadata, the argument parsers, the study's own
result, the error catalogue's table, the generated equation report."""

from __future__ import annotations

import importlib.metadata
import re
from pathlib import Path

import numpy as np
import pytest

import planar_sym as ps
from planar_sym.cli import main, parser

ROOT = Path(__file__).resolve().parents[1]


def test_version_is_the_installed_packages(capsys):
    with pytest.raises(SystemExit) as done:
        main(["--version"])
    assert done.value.code == 0
    assert capsys.readouterr().out.strip() == \
        f"planar-sym {importlib.metadata.version('planar-sym')}"


def test_every_command_taking_a_robot_says_it_takes_a_description_file():
    sub = next(a for a in parser()._actions if a.dest == "command")
    took = []
    for name, p in sub.choices.items():
        for action in p._actions:
            if action.dest == "robot":
                took.append(name)
                assert ".toml" in action.help, f"`{name} --help`: {action.help!r}"
    assert {"draw", "validate", "export", "equations", "move"} <= set(took)


def test_control_run_prints_its_tracking_error(tmp_path, capsys):
    assert main(["run", "serial_2dof_cartesian_track", "--out", str(tmp_path)]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines()
                if ln.startswith("  tracking error:"))
    res = ps.run_study("serial_2dof_cartesian_track")
    e = [res.get("e", k).values for k in range(2)] + [res.get("e_task").values]
    want = [np.abs(v).max() for v in e] + [abs(v[-1]) for v in e]
    got = [float(x) for x in re.findall(r" ([0-9.e+-]+) (?:rad|mm)", line)]
    assert got == pytest.approx(want, rel=5e-3)  # printed to 3 significant digits


def test_readme_quotes_the_catalogues_count():
    rows = sum(1 for ln in (ROOT / "docs" / "errors.md").read_text().splitlines()
               if re.match(r"\| \d+ \|", ln))
    quoted = re.search(r"\[docs/errors.md\]\(docs/errors.md\) lists (\d+) bad inputs",
                       (ROOT / "README.md").read_text())
    assert quoted and int(quoted.group(1)) == rows


def test_passive_joint_of_a_tree_reads_zero_equals():
    """The cart-pole's free hinge: `0 = ...`, not an empty left-hand side."""
    robot = ps.load(ROOT / "tests" / "robots" / "cart_pole.toml")
    text = (robot.library.folder / "equations.txt").read_text()
    rows = [ln for ln in text.splitlines() if re.match(r"\s+(f1|0|tau2) = ", ln)]
    assert any(ln.lstrip().startswith("f1 = ") for ln in rows)
    assert any(ln.lstrip().startswith("0 = ") for ln in rows), rows
    assert not re.search(r"^\s+= ", text, re.MULTILINE)


@pytest.mark.parametrize("m2, text", [(1.322, "1.322 m^2"), (0.1322, "1322 cm^2"),
                                      (1.322e-3, "13.22 cm^2"), (5e-5, "50 mm^2")])
def test_atlas_areas_print_in_a_readable_unit(m2, text):
    """An area printed as 1.322e+04 cm^2 (issue 29) reads 1.322 m^2."""
    from planar_sym.commands.atlas import area_text

    assert area_text(m2) == text


def test_atlas_over_several_angles_names_its_files_by_angle(tmp_path):
    """`--phi -30 0 12.5` wrote atlas_phi0/1/2 (issue 29): the files carry the angle, and each
    map is drawn at the angle its name says (the atlas's own phi_rad)."""
    assert main(["--quiet", "atlas", "parallel_3rrr", "--phi", "-30", "0", "12.5", "--points",
                 "6", "--out", str(tmp_path)]) == 0
    names = sorted(p.name for p in (tmp_path).glob("atlas*phi*.png"))
    assert names == ["atlas_phi-30.png", "atlas_phi0.png", "atlas_phi12.5.png",
                     "atlas_torque_phi-30.png", "atlas_torque_phi0.png",
                     "atlas_torque_phi12.5.png"]
    with np.load(tmp_path / "atlas.npz") as z:
        assert np.degrees(z["phi_rad"]) == pytest.approx([-30.0, 0.0, 12.5])


def test_atlas_draws_no_rounding_noise_as_a_torque(tmp_path, capsys):
    """serial_rpr's atlas holds the wrist at one orientation, where the wrist's centre of
    gravity is straight above or below its axis: its gravity torque is rounding at every cell
    (the compiled g(q) at the atlas's poses, below), and the atlas holds it at 0 rather than
    printing 5.9e-16 N*m as a peak; the other joints' maps are untouched."""
    robot = ps.load("serial_rpr")
    assert main(["atlas", "serial_rpr", "--points", "8", "--x", "-300", "300", "--y", "-300",
                 "300", "--out", str(tmp_path)]) == 0
    assert "wrist 0 N*m" in capsys.readouterr().out
    with np.load(tmp_path / "atlas.npz") as z:
        grav, q = z["gravity"], z["q"]
    reach = np.isfinite(grav[..., 0])
    g = robot.gravity(q[reach])
    assert np.abs(g[:, 2]).max() < 1e-14 and np.abs(g[:, 0]).max() > 1.0
    assert np.all(grav[..., 2][reach] == 0.0)
    assert np.abs(grav[..., 0][reach] - g[:, 0]).max() < 1e-12  # the shoulder: as computed
