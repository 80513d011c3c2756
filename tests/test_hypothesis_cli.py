"""The command line fuzzed (issue 25, class 4): random options and values for the commands that
answer in a second (`move`, `run`, `draw`, `equations`, `export`, `animate`), mixing sensible
values with hostile ones (huge, negative, zero, NaN, inf, empty, unicode, option-like).
Whatever comes in, a command ends with exit code 0, or 2 and one `error:` line (or argparse's
usage line), never a traceback; and a command that fails leaves no file behind.

The suite runs 30 cases (under half a minute); ``PLANAR_SYM_FUZZ_CASES=2000 pytest
tests/test_hypothesis_cli.py`` runs it longer.
"""

from __future__ import annotations

import os
from pathlib import Path

from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st

from planar_sym.cli import main

MAX_EXAMPLES = int(os.environ.get("PLANAR_SYM_FUZZ_CASES") or 30)

NASTY_NUMBERS = ["0", "-1", "1e400", "-1e400", "nan", "inf", "-0", "1e-300", "3.5", "2", "1",
                 "10000000000", "0.5", "-200,0", "1,2", "1,2,3", "", " ", "x", "é", "--x",
                 "1e6", "45", "-45", "90,0", "0,0"]
ROBOTS = ["serial_2dof", "five_bar_type1", "slider_crank"]
WORDS = ROBOTS * 4 + ["no_such", "", "../x", "a b", "é"]  # mostly real robots: reach deeper
STUDIES = ["serial_2dof_joint_move", "slider_crank_turn", "five_bar_type1_move_x"] * 3 + ["nope"]


def _value(kind: str):
    if kind == "number":
        return st.sampled_from(NASTY_NUMBERS)
    if kind == "robot":
        return st.sampled_from(WORDS)
    if kind == "study":
        return st.sampled_from(STUDIES)
    if kind == "file":
        return st.sampled_from(["out.png", "out.svg", "out.txt", "out", "sub/out.png", "out.xml",
                                "out.urdf", "out.gif", ""])
    return st.sampled_from(kind.split("|"))


#: each command: its positional arguments and options, with the kind of value each takes
COMMANDS = {
    "move": (["robot"], {"--task": None, "--joint": None, "--from": "number", "--by": "number",
                         "--to": "number", "--duration": "number",
                         "--profile": "cubic|quintic|linear", "--samples": "number",
                         "--set": "m_link1=2|m_link1=-1|nope=1|m_link1=x|=", "--length": "mm|m|in|",
                         "--angle": "deg|rad|grad", "--ik": "auto|seed|newton|x"}),
    "run": (["study"], {"--samples": "number", "--split": None, "--npz": None}),
    "draw": (["robot"], {"--dpi": "number"}),
    "equations": (["robot"], {"--format": "text|latex|markdown|html", "--latex": None}),
    "export": (["robot"], {"--format": "mjcf|urdf|json", "--ideal": None}),
    "animate": (["study"], {"--frames": "2|3|0|-1|x|100000", "--fps": "number",
                            "--dpi": "number"}),
}


@st.composite
def argv(draw):
    command = draw(st.sampled_from(sorted(COMMANDS)))
    positional, options = COMMANDS[command]
    args = [command] + [draw(_value(k)) for k in positional]
    for opt in draw(st.lists(st.sampled_from(sorted(options)), max_size=4, unique=True)):
        kind = options[opt]
        args.append(opt)
        if kind is not None:
            value = draw(_value(kind))
            if value.startswith("-") and value != "-":
                args[-1] = f"{opt}={value}"  # argparse takes a negative value only this way
            else:
                args.append(value)
    out = {"draw": "file", "export": "file", "animate": "file"}.get(command, "dir")
    files = {"draw": "out.png", "export": "out.xml", "animate": "out.gif"}
    name = draw(st.one_of(st.just(files.get(command, "out")), _value("file")))
    if command != "equations":  # (it prints)
        args += ["--out", name if out == "file" else "out"]
    return args


@settings(max_examples=MAX_EXAMPLES, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(args=argv())
# found by the long run: a GIF's frame delay overflowed PIL's 16-bit field (OverflowError)
@example(args=["animate", "serial_2dof_joint_move", "--fps", "1e-300", "--out", "out.gif"])
def test_every_command_ends_cleanly(args, tmp_path_factory, capsys):
    folder = tmp_path_factory.mktemp("cli")
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        capsys.readouterr()
        try:
            code = main(args)
        except SystemExit as exc:  # argparse: usage and one error line, exit 2
            code = exc.code
        err = capsys.readouterr().err
    finally:
        os.chdir(cwd)
    event(f"{args[0]}: exit {code}")  # --hypothesis-show-statistics: how many got through
    assert "Traceback" not in err, (args, err)
    assert code in (0, 2), (args, code, err)
    if code == 2:  # our "error: ..." (a file's problems on the lines after), or argparse's
        lines = err.strip().splitlines()
        assert any(x.startswith("error:") or (x.startswith("planar-sym") and ": error: " in x)
                   for x in lines), (args, err)
        left = [p for p in Path(folder).rglob("*") if p.is_file()]
        assert not left, (args, err, left)
