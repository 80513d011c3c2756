"""Every command takes a robot as a built-in name, a description file or a generated folder
alike, and gives the same answer for the same robot."""

from __future__ import annotations

from pathlib import Path

import pytest

from planar_sym.cli import main

ROOT = Path(__file__).resolve().parent.parent
FOUR_BAR = ROOT / "examples" / "four_bar.toml"
SERIAL = ROOT / "planar_sym" / "robots" / "serial_2dof.toml"


@pytest.fixture(scope="module")
def derived(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("derived")
    assert main(["--quiet", "derive", str(FOUR_BAR), "--out", str(out)]) == 0
    return out / "four_bar"


def test_equations_are_the_same_from_a_file_and_from_its_folder(derived, capsys):
    assert main(["equations", str(FOUR_BAR)]) == 0
    from_file = capsys.readouterr().out
    assert main(["equations", str(derived)]) == 0
    assert capsys.readouterr().out == from_file
    assert "Four-bar linkage" in from_file and "Phi1 =" in from_file


def test_a_copy_of_a_built_in_description_is_not_the_built_in(tmp_path, capsys):
    """The same equations, but it is the user's robot (no seed closed form for it)."""
    copy = tmp_path / "serial_2dof.toml"
    copy.write_text(SERIAL.read_text())
    assert main(["equations", str(copy)]) == 0
    mine = capsys.readouterr().out
    assert main(["equations", "serial_2dof"]) == 0
    assert capsys.readouterr().out == mine
    import planar_sym as ps

    assert not ps.load(copy).is_builtin and ps.load("serial_2dof").is_builtin


@pytest.mark.parametrize("form", ["file", "folder"])
def test_draw_and_validate_take_a_file_or_a_folder(derived, tmp_path, capsys, form):
    robot = str(FOUR_BAR if form == "file" else derived)
    out = tmp_path / "four_bar.png"
    assert main(["--quiet", "draw", robot, "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(["--quiet", "validate", robot, "--samples", "5"]) == 0


def test_move_and_animate_on_a_description_file(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["--quiet", "move", str(FOUR_BAR), "--joint", "--from", "60", "--by", "90",
                 "--duration", "1", "--samples", "21", "--animate", "--out", str(out)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["four_bar_move.csv", "four_bar_move.gif",
                                                      "four_bar_move.png"]
