"""Every example in the README runs as written, in document order, in a fresh folder:

* each ```python block, as a script of its own;
* each ```sh line that starts with ``planar-sym`` (as ``python -m planar_sym``);
* each ```toml block whose first line is ``# <file>.toml: ...`` is written to that file first,
  so the commands after it can use it.

```text blocks (synopses, printed output) are not run, and neither is a block preceded by the
line ``<!-- not run: why -->``. The folder holds a copy of ``examples/``, as a checkout does.
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.MULTILINE | re.DOTALL)


def blocks() -> list[tuple[str, str, int]]:
    """(language, body, line number) of every fenced block the test runs, in order."""
    text = README.read_text()
    out = []
    for m in FENCE.finditer(text):
        before = text[:m.start()].rstrip("\n").rsplit("\n", 1)[-1]
        if before.startswith("<!-- not run"):
            continue
        out.append((m.group(1), m.group(2), text.count("\n", 0, m.start()) + 1))
    return out


def commands(body: str) -> list[str]:
    lines, joined = [], ""
    for line in body.splitlines():
        joined += line.rstrip("\\").strip() + " " if line.endswith("\\") else line.strip()
        if line.endswith("\\"):
            continue
        code = joined.split(" # ")[0].split("   #")[0].strip()
        joined = ""
        if code.startswith("planar-sym "):
            lines.append(code)
    return lines


def test_the_readme_has_examples_of_each_kind():
    kinds = {lang for lang, body, _ in blocks()
             if lang == "python" or (lang == "sh" and commands(body))}
    assert kinds == {"python", "sh"}


def test_every_readme_example_runs(tmp_path):
    shutil.copytree(ROOT / "examples", tmp_path / "examples",
                    ignore=shutil.ignore_patterns("*.o", "serial_2dof_tau"))
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "MPLBACKEND": "Agg"}
    ran = 0
    for lang, body, line in blocks():
        if lang == "toml":
            first = body.splitlines()[0]
            if m := re.match(r"# ([\w.-]+\.toml):", first):
                (tmp_path / m.group(1)).write_text(body)
            continue
        if lang == "python":
            runs = [[sys.executable, "-c", body]]
        elif lang == "sh":
            runs = [[sys.executable, "-m", "planar_sym", *shlex.split(c)[1:]]
                    for c in commands(body)]
        else:
            continue
        for argv in runs:
            proc = subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True,
                                  timeout=600, check=False)
            what = " ".join(argv[3:]) if lang == "sh" else "the python block"
            assert proc.returncode == 0, (f"README line {line}: {what} failed:\n"
                                          f"{proc.stdout}\n{proc.stderr}")
            assert "Traceback" not in proc.stderr, proc.stderr
            ran += 1
    assert ran >= 8
    print(f"\nREADME: {ran} examples ran")


@pytest.mark.parametrize("text, expected", [
    ("planar-sym run a.toml --out r   # comment\nmake demo\n", ["planar-sym run a.toml --out r"]),
    ("planar-sym move x --from 1,2 \\\n    --by 3,4\n", ["planar-sym move x --from 1,2 --by 3,4"]),
])
def test_command_extraction(text, expected):
    assert commands(text) == expected
