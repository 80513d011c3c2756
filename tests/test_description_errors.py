"""Bad descriptions are refused with every problem listed, each naming the file and the field;
``python -m derive`` then writes nothing at all."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROBOTS_DIR

from derive.__main__ import main as derive_main
from planar_sym.errors import DescriptionError
from planar_sym.model import description

SERIAL = (ROBOTS_DIR / "serial_2dof.toml").read_text()
FIVE_BAR = (ROBOTS_DIR / "five_bar_type1.toml").read_text()


def edited(tmp_path: Path, text: str, *edits: tuple[str, str], name: str = "bad") -> Path:
    """A copy of ``text`` with each (old, new) replaced once; every ``old`` must be there."""
    for old, new in edits:
        assert text.count(old) >= 1, f"test edit does not apply: {old!r}"
        text = text.replace(old, new, 1)
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def problems_of(path: Path) -> list[str]:
    with pytest.raises(DescriptionError) as info:
        description.load(path)
    problems = info.value.problems
    assert problems, "DescriptionError without problems"
    for p in problems:
        assert p.startswith(f"{path}: "), f"problem does not name the file: {p}"
    assert all(p in str(info.value) for p in problems)
    return problems


def has(problems: list[str], path: Path, field: str, *words: str) -> bool:
    prefix = f"{path}: {field}: "
    return any(p.startswith(prefix) and all(w in p for w in words) for p in problems)


def test_the_unedited_copy_is_valid(tmp_path):
    """The edits below are the only problems: the copy itself loads."""
    assert description.load(edited(tmp_path, SERIAL)).name == "serial_2dof"
    assert description.load(edited(tmp_path, FIVE_BAR, name="fb")).name == "five_bar_type1"


@pytest.mark.parametrize("value", ["0.0", "-0.071"])
def test_non_positive_mass(tmp_path, value):
    path = edited(tmp_path, SERIAL, ("mass = 0.071", f"mass = {value}"))
    assert problems_of(path) == [
        f"{path}: bodies[0] (link1).mass: must be > 0 kg (got {float(value):g})"]


def test_negative_inertia(tmp_path):
    path = edited(tmp_path, SERIAL, ("izz = 109.864", "izz = -109.864"))
    problems = problems_of(path)
    assert has(problems, path, "bodies[2] (link2).izz", ">= 0", "-109.864")
    assert len(problems) == 1, problems


def test_two_problems_are_both_reported(tmp_path):
    path = edited(tmp_path, SERIAL, ("mass = 0.071", "mass = -1.0"),
                  ("izz = 109.864", "izz = -2.0"))
    problems = problems_of(path)
    assert has(problems, path, "bodies[0] (link1).mass", "> 0")
    assert has(problems, path, "bodies[2] (link2).izz", ">= 0")
    assert len(problems) == 2, problems


def test_unknown_body_in_a_joint(tmp_path):
    path = edited(tmp_path, SERIAL, ('child = "link2.CS1"', 'child = "link9.CS1"'))
    assert has(problems_of(path), path, "joints[2] (joint2).child", "unknown body", "'link9'")


def test_unknown_point(tmp_path):
    path = edited(tmp_path, SERIAL, ('child = "link2.CS1"', 'child = "link2.CS9"'))
    assert has(problems_of(path), path, "joints[2] (joint2).child", "no point", "'CS9'")


def test_missing_field(tmp_path):
    path = edited(tmp_path, SERIAL, ("izz = 89.395\n", ""))
    assert has(problems_of(path), path, "bodies[0] (link1).izz", "missing")


def test_unknown_key_typo(tmp_path):
    """One mistake, one message: the misspelt key is checked as the key it nearly is, so the
    body's mass is not also reported missing."""
    path = edited(tmp_path, SERIAL, ("mass = 0.071", "mas = 0.071"))
    assert problems_of(path) == [(f"{path}: bodies[0].mas: unknown key: did you mean 'mass'? "
                                 "(checked as mass below)")]


def test_a_misspelt_key_is_checked_where_it_belongs(tmp_path):
    """Its value is checked as the field's: a negative mass under the typo is reported too;
    a key near no known one lists the known keys, and one whose near key is there as well is
    not moved (both would be read)."""
    path = edited(tmp_path, SERIAL, ("mass = 0.071", "mas = -0.071"))
    problems = problems_of(path)
    assert problems[0].endswith("bodies[0].mas: unknown key: did you mean 'mass'? (checked as "
                                "mass below)")
    assert any("(link1).mass" in p and "-0.071" in p for p in problems[1:]), problems
    path = edited(tmp_path, SERIAL, ("mass = 0.071", "mass = 0.071\nmas = 1.0"))
    assert problems_of(path) == [(f"{path}: bodies[0].mas: unknown key (known: cg, cg_from, frame, "
                                 "izz, mass, mass_at, name, notes, points)")]


def test_unknown_length_unit(tmp_path):
    path = edited(tmp_path, SERIAL, ('length = "m"', 'length = "in"'))
    assert has(problems_of(path), path, "units.length", "'in'", "mm")


@pytest.mark.parametrize("edit", [('inertia = "kg*mm^2"', 'inertia = "kg*in^2"'),
                                  ('mass = "kg"', 'mass = "lb"')], ids=["inertia", "mass"])
def test_unknown_mass_or_inertia_unit(tmp_path, edit):
    path = edited(tmp_path, SERIAL, edit)
    quantity = "inertia" if "inertia" in edit[0] else "mass"
    assert has(problems_of(path), path, f"units.{quantity}", edit[1].split('"')[1])


def test_malformed_toml(tmp_path):
    path = edited(tmp_path, SERIAL, ("[units]", "[units"))
    (problem,) = problems_of(path)
    assert "not valid TOML" in problem and "line 10" in problem


def test_duplicate_body_name(tmp_path):
    path = edited(tmp_path, SERIAL, ('name = "link2"', 'name = "link1"'))
    assert has(problems_of(path), path, "bodies[2].name", "duplicate body name", "'link1'")


def test_loop_that_does_not_close(tmp_path):
    """R_Link2.CS2 moved 1 mm along x: the cut joint C no longer closes."""
    path = edited(tmp_path, FIVE_BAR, ("CS2 = [0.037, 0.140] }\nframe",
                                       "CS2 = [0.038, 0.140] }\nframe"))
    problems = problems_of(path)
    assert has(problems, path, "joints (C)", "loop does not close", "L_Link2.CS2", "R_Link2.CS2",
               "1 mm apart")
    assert len(problems) == 1, problems


def test_a_gap_within_tolerance_is_accepted(tmp_path):
    """Rounding of the seed's six decimals (1 um) is no error; 1 mm is (test above)."""
    path = edited(tmp_path, FIVE_BAR, ("CS2 = [0.037, 0.140] }\nframe",
                                       "CS2 = [0.037001, 0.140] }\nframe"))
    assert description.load(path).loop_joints[0].name == "C"


# -- python -m derive ---------------------------------------------------------------------------
def test_derive_refuses_and_writes_nothing(tmp_path, capsys):
    bad = edited(tmp_path, SERIAL, ("mass = 0.071", "mass = -1.0"))
    out = tmp_path / "out"
    out.mkdir()
    assert derive_main([str(bad), "--out", str(out), "--quiet"]) != 0
    assert list(out.iterdir()) == []
    err = capsys.readouterr().err
    assert str(bad) in err and "bodies[0] (link1).mass" in err


def test_one_bad_robot_means_nothing_is_written(tmp_path, capsys):
    """The good robot comes first (it is derived in memory), the bad one second; an older
    output folder of the good robot is left exactly as it was."""
    bad = edited(tmp_path, FIVE_BAR, ("CS2 = [0.037, 0.140] }\nframe",
                                      "CS2 = [0.038, 0.140] }\nframe"))
    out = tmp_path / "out"
    (out / "serial_2dof").mkdir(parents=True)
    (out / "serial_2dof" / "old.txt").write_text("previous run")
    assert derive_main(["serial_2dof", str(bad), "--out", str(out), "--quiet"]) != 0
    assert sorted(str(p.relative_to(out)) for p in out.rglob("*")) == [
        "serial_2dof", "serial_2dof/old.txt"]
    assert (out / "serial_2dof" / "old.txt").read_text() == "previous run"
    assert "joints (C)" in capsys.readouterr().err
