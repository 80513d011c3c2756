"""What argparse lets through, refused at the command line's door (issue 25, class 6): an
option given twice (the last would silently win), and the environment: a flag that is not 0
or 1 is an error on every route (command line and API), an unknown PLANAR_SYM_ name a warning."""

from __future__ import annotations

import warnings

import pytest

import planar_sym as ps
from planar_sym.cli import main
from planar_sym.errors import InputError

TWICE = ("error: option --samples is given more than once: give it once (the last would "
         "silently win)")


def _run(capsys, *args):
    capsys.readouterr()
    code = main(list(args))
    return code, capsys.readouterr().err.strip()


@pytest.mark.parametrize("given", [["--samples", "5", "--samples", "7"],
                                   ["--samples=5", "--samples", "7"],
                                   ["--samples", "5", "--sam=7"]],
                         ids=["twice", "with =", "abbreviated"])
def test_an_option_given_twice_is_refused(capsys, tmp_path, given):
    code, err = _run(capsys, "run", "serial_2dof_free_swing", *given, "--out",
                     str(tmp_path / "res"))
    assert (code, err) == (2, TWICE)
    assert not (tmp_path / "res").exists()


def test_options_that_repeat_by_design_still_do(capsys, tmp_path):
    """A flag twice is the same flag; --set is a list made by repeating it."""
    code, err = _run(capsys, "--quiet", "run", "serial_2dof_free_swing", "--samples", "5",
                     "--out", str(tmp_path / "res"), "--quiet")
    assert code == 0 and err == ""
    code, err = _run(capsys, "atlas", "serial_2dof", "--x", "0", "0.1", "--x", "0", "0.2",
                     "--out", str(tmp_path / "a"))
    assert (code, err) == (2, TWICE.replace("--samples", "--x"))
    # --set repeats for different parameters, not for the same one (tried as a student)
    code, err = _run(capsys, "move", "serial_2dof", "--joint", "--from", "0,0", "--by", "10,0",
                     "--duration", "1", "--set", "m_link1=2", "--set", "m_link1=3", "--out",
                     str(tmp_path / "m"))
    assert (code, err) == (2, "error: --set m_link1 is given more than once: give it once")
    assert not (tmp_path / "m").exists()
    code, err = _run(capsys, "move", "serial_2dof", "--joint", "--from", "0,0", "--by", "10,0",
                     "--duration", "1", "--set", "m_link1=2", "--set", "m_link2=3", "--out",
                     str(tmp_path / "m"), "--quiet")
    assert (code, err) == (0, "")


def test_the_environment_is_read_by_one_rule(capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("PLANAR_SYM_EXACT", "yes")
    message = ("environment variable PLANAR_SYM_EXACT='yes' must be 0 or 1 (1: CasADi's exact "
               "evaluator instead of the compiled C callers)")
    code, err = _run(capsys, "run", "serial_2dof_free_swing", "--samples", "5", "--out",
                     str(tmp_path / "res"))
    assert (code, err) == (2, f"error: {message}")
    with pytest.raises(InputError) as info:  # the API reads the same flag by the same rule
        ps.load("serial_2dof")
    assert str(info.value) == message
    for value, exact in (("1", True), ("0", False), ("", False)):
        monkeypatch.setenv("PLANAR_SYM_EXACT", value)
        assert ps.load("serial_2dof").exact is exact
    monkeypatch.setenv("PLANAR_SYM_EXACT", "0")
    monkeypatch.setenv("PLANAR_SYM_CACH", str(tmp_path))  # a typo of PLANAR_SYM_CACHE
    code, err = _run(capsys, "run", "serial_2dof_free_swing", "--samples", "5", "--out",
                     str(tmp_path / "res"))
    assert code == 0
    assert err.startswith("warning: unknown environment variable PLANAR_SYM_CACH is not read "
                          "by planar-sym (known: PLANAR_SYM_CACHE, PLANAR_SYM_EXACT, ")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        monkeypatch.delenv("PLANAR_SYM_CACH")
        assert main(["run", "serial_2dof_free_swing", "--samples", "5", "--out",
                     str(tmp_path / "res"), "--quiet"]) == 0
