"""One mistake in a description, one message at the field that holds it (a user trial, trial H):
each case gave two or three lines before, or named the wrong field."""

from __future__ import annotations

import pytest
from conftest import ROOT

from planar_sym.errors import DescriptionError
from planar_sym.model.description import load as load_description

SEED = (ROOT / "planar_sym" / "robots" / "serial_2dof.toml").read_text()


def problems_of(tmp_path, old: str, new: str) -> list[str]:
    assert old in SEED
    path = tmp_path / "arm.toml"
    path.write_text(SEED.replace(old, new, 1))
    with pytest.raises(DescriptionError) as err:
        load_description(path)
    return [p.split(": ", 1)[1] for p in err.value.problems]


def test_a_misspelt_unit_quantity_is_read_as_the_one_it_nearly_is(tmp_path):
    """``lenght = "m"``: 'unknown quantity' and 'units.length: missing' before."""
    assert problems_of(tmp_path, 'length = "m"', 'lenght = "cm"') == [
        "units.lenght: unknown quantity: did you mean 'length'? (checked as length below)",
        *problems_of(tmp_path, 'length = "m"', 'length = "cm"')]


def test_a_joint_to_its_own_body_is_said_once(tmp_path):
    """A joint whose parent and child are one body: not also 'does not close'."""
    got = problems_of(tmp_path, 'parent = "link1.CS2"\nchild = "link2.CS1"',
                      'parent = "link2.CS2"\nchild = "link2.CS1"')
    assert [p for p in got if "link2" in p] == ["joints[2] (joint2): joins body 'link2' to itself"]


def test_a_mass_slip_is_blamed_on_the_mass(tmp_path):
    """1e-9 kg makes izz's radius of gyration 300 m: the message is at the mass, with both."""
    (got,) = problems_of(tmp_path, "mass = 0.071", "mass = 1e-9")
    assert got.startswith("bodies[0] (link1).mass: 1e-09 kg (read in kg) is below the "
                          "plausible 0.0001 kg for a mass of a body")
    assert "radius of gyration of 2.99e+05 mm" in got  # sqrt(8.9395e-5 / 1e-9) m


def test_a_link_typed_far_off_its_sketch_is_warned_when_the_loops_close(tmp_path):
    """A student typed a four-bar's coupler 20 mm for 120: closing the loops turned the rocker
    79 degrees from its given angle without a word. Beyond 30 degrees it is warned, with the
    gap closed; the shipped four-bar's rough angles (1.6 degrees) are not."""
    import warnings

    text = (ROOT / "examples" / "four_bar_joints.toml").read_text()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_description(ROOT / "examples" / "four_bar_joints.toml")
    assert "B = [120.0, 0.0]" in text
    path = tmp_path / "short.toml"
    path.write_text(text.replace("B = [120.0, 0.0]", "B = [20.0, 0.0]", 1))
    with pytest.warns(RuntimeWarning, match=r"joints \((\w+)\): closing the loops turned \1 "
                                             r"[0-9.]+ deg from its given angle \(a warning beyond "
                                             r"30; the loops' gap was [0-9.]+ mm\): do the links' "
                                             r"lengths match the sketch\?"):
        desc = load_description(path)
    assert desc.assembly is not None
