"""The command line at its edges: absurd sizes, Ctrl-C, closed pipes, conflicting options,
--out naming a file, a missing --description, and derive never replacing a user's folder."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from conftest import interruptible

from planar_sym.cli import main

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"


def _env() -> dict:
    return {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}


@pytest.mark.parametrize("argv, message", [
    (["run", "serial_2dof_joint_move", "--samples", "10000000000"], "--samples must be an integer from 2 to 1000000"),
    (["demo", "--samples", "0"], "--samples must be an integer from 2"),
    (["demo", "--frames", "100000"], "--frames must be an integer from 2 to 2000"),
    (["animate", "serial_2dof_joint_move", "--frames", "99999"], "--frames must be an integer from 2 to 2000"),
    (["animate", "serial_2dof_joint_move", "--dpi", "100000"], "--dpi must be an integer from 10 to 600"),
    # one rule for the resolution on every command (draw and atlas ran into std::bad_alloc)
    (["draw", "serial_2dof", "--dpi", "100000", "--out", "d.png"],
     "--dpi must be an integer from 10 to 600 (got 100000)"),
    (["atlas", "serial_2dof", "--dpi", "100000", "--out", "atlas"],
     "--dpi must be an integer from 10 to 600 (got 100000)"),
    (["draw", "serial_2dof", "--dpi", "0", "--out", "d.png"],
     "--dpi must be an integer from 10 to 600 (got 0)"),
    # found by tests/test_hypothesis_cli.py: PIL's OverflowError writing a 1e300 s frame delay
    (["animate", "serial_2dof_joint_move", "--fps", "1e-300"],
     "--fps must be a number from 0.1 to 100 (got 1e-300)"),
    (["run", "serial_2dof_joint_move", "--all"], "name studies or give --all, not both"),
])
def test_absurd_sizes_and_conflicts_get_one_line(tmp_path, monkeypatch, capsys, argv, message):
    monkeypatch.chdir(tmp_path)
    assert main([*argv, "--out", str(tmp_path / "out")] if argv[0] in ("run", "demo")
                else argv) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1, err
    assert list(tmp_path.iterdir()) == []


def test_conflicting_format_options_are_refused(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["equations", "serial_2dof", "--latex", "--format", "text"])
    assert exc.value.code == 2
    assert "not allowed with argument" in capsys.readouterr().err


@pytest.mark.parametrize("command", [["run", "serial_2dof_joint_move"], ["demo"],
                                     ["move", "serial_2dof", "--joint", "--from", "0,0",
                                      "--by", "10,0", "--duration", "1"]])
def test_out_naming_a_file_says_so(tmp_path, capsys, command):
    target = tmp_path / "results.txt"
    target.write_text("mine")
    assert main([*command, "--out", str(target)]) == 2
    assert f"--out {target} is a file, not a folder" in capsys.readouterr().err
    assert target.read_text() == "mine"


def test_validate_description_naming_a_missing_file_fails(capsys):
    assert main(["validate", "serial_2dof", "--description", "no_such.toml"]) == 2
    assert "--description no_such.toml: no such file" in capsys.readouterr().err


def test_derive_never_replaces_a_users_folder(tmp_path, capsys):
    out = tmp_path / "out"
    (out / "four_bar").mkdir(parents=True)
    (out / "four_bar" / "notes.txt").write_text("my notes")
    assert main(["derive", str(EXAMPLES / "four_bar.toml"), "--out", str(out), "--no-build"]) == 2
    assert "is not a generated robot folder" in capsys.readouterr().err
    assert (out / "four_bar" / "notes.txt").read_text() == "my notes"
    (out / "four_bar" / "notes.txt").unlink()
    (out / "four_bar").rmdir()
    assert main(["derive", str(EXAMPLES / "four_bar.toml"), "--out", str(out), "--no-build"]) == 0
    (out / "four_bar" / "notes.txt").write_text("added later")  # a derived folder, touched
    assert main(["derive", str(EXAMPLES / "four_bar.toml"), "--out", str(out), "--no-build"]) == 2
    assert "holds files planar-sym did not write (notes.txt)" in capsys.readouterr().err
    assert (out / "four_bar" / "notes.txt").read_text() == "added later"


def test_closed_pipe_is_quiet():
    proc = subprocess.run(f"{sys.executable} -m planar_sym list | head -1", shell=True,
                          cwd=ROOT, env=_env(), capture_output=True, text=True, timeout=120,
                          check=False)
    assert proc.stdout.startswith("Built-in robots")
    assert proc.stderr == "", proc.stderr


def test_ctrl_c_ends_with_one_line_130_and_no_partial_file(tmp_path):
    out = tmp_path / "res"
    proc = subprocess.Popen(interruptible("planar_sym", "demo", "--out", str(out), "--frames",
                                          "200"), cwd=tmp_path, env=_env(),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not (out.is_dir() and any(out.iterdir())) and time.monotonic() < deadline:
        time.sleep(0.05)  # wait until it is writing
    time.sleep(0.3)
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert err.strip().splitlines()[-1] == "interrupted"
    assert "Traceback" not in err
    assert not [p for p in out.iterdir() if p.name.startswith(".")]  # no temporary file left
