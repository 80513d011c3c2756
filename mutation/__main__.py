"""``python -m mutation TARGET [TARGET ...] [--tests FILE ...] [--jobs N]`` (``make mutate``).

Mutation testing of one runtime module or folder with mutmut: plant small bugs (an operator, a
constant, a dropped call) one at a time and run the tests that cover the mutated function; a
mutant the tests do not kill is a bug they would not see. The result is written into
``MUTATION.md`` (this target's section replaced, the others kept), with each survivor's diff and,
where a developer has judged it, why it is equivalent (``mutation/equivalent.toml``).

mutmut mutates a copy of the package in ``mutants/`` of a work folder, so the checkout is never
touched; the work folder is ``.mutation/<target>/`` (git-ignored, made anew each run). The test
files that cover each target are listed in ``mutation/targets.toml``. Only tests that call the
package in their own process can kill a mutant: a command run as a subprocess runs the checkout.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import time
import tomllib
from pathlib import Path

from .classify import Mutant, load_equivalents, parse_show
from .report import Outcome, write_section

ROOT = Path(__file__).resolve().parent.parent
TARGETS = Path(__file__).resolve().parent / "targets.toml"
WORK = ROOT / ".mutation"
#: what the tests read beside the package (the robots' generated code, examples, docs)
ALSO_COPY = ["derive", "generated", "examples", "benchmarks", "docs", "README.md", "Makefile",
             "setup.py", "constraints.txt", "mkdocs.yml"]


#: appended to the work copy's tests/conftest.py. Each mutant is forked from the process that
#: ran the clean tests (mutmut's default, fast), so a result a module cached then (the joint
#: loads' structure, the plausibility tables) would meet the mutant instead of its code: emptied
#: before every test. Loaded libraries are kept (compiled code is never mutated); mutmut's
#: forkserver isolation avoids all this too but was 5x slower (a robot loaded per mutant).
FRESH_CACHES = """

# -- added by make mutate (mutation/__main__.py) --
import sys as _sys

import pytest as _pytest


@_pytest.fixture(autouse=True)
def _mutation_fresh_caches():
    for _name, _mod in list(_sys.modules.items()):
        if not _name.startswith("planar_sym") or _name == "planar_sym.model.locate":
            continue
        for _value in list(vars(_mod).values()):
            if callable(getattr(_value, "cache_clear", None)):
                _value.cache_clear()
        if isinstance(vars(_mod).get("_CACHE"), dict):
            _mod._CACHE.clear()
    yield
"""


def _targets() -> dict[str, list[str]]:
    return {k: v["tests"] for k, v in tomllib.loads(TARGETS.read_text())["target"].items()}


def _tests_for(target: str, given: list[str] | None) -> list[str]:
    if given:
        return given
    table = _targets()
    if target not in table:
        raise SystemExit(f"mutation: no test files listed for {target!r} in {TARGETS.name}; add a "
                         f"[target.\"{target}\"] table with tests = [...] or pass --tests "
                         f"(listed: {', '.join(sorted(table))})")
    return table[target]


def _glob(target: str) -> str:
    """mutmut's only_mutate pattern for a file or a folder."""
    return target if target.endswith(".py") else target.rstrip("/") + "/*"


def _prepare(work: Path, target: str, tests: list[str]) -> None:
    """A fresh work folder: the package, what the tests read, and mutmut's configuration."""
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    ignore = shutil.ignore_patterns("__pycache__", "*.egg-info")
    for name in ["planar_sym", "tests", *ALSO_COPY]:
        src = ROOT / name
        (shutil.copytree(src, work / name, ignore=ignore) if src.is_dir()
         else shutil.copy2(src, work / name))
    config = (ROOT / "pyproject.toml").read_text() + "\n".join([
        "", "[tool.mutmut]", 'source_paths = ["planar_sym"]',
        f"only_mutate = [{_glob(target)!r}]",
        f"also_copy = {ALSO_COPY!r}",
        f"pytest_add_cli_args_test_selection = {tests!r}",
        # -x: a mutant is killed by its first failing test; no cache writes into the copy
        'pytest_add_cli_args = ["-x", "-q", "-p", "no:cacheprovider", "-m", "not slow"]',
        "timeout_multiplier = 5.0", ""]).replace("'", '"')
    (work / "pyproject.toml").write_text(config)
    with (work / "tests" / "conftest.py").open("a") as f:
        f.write(FRESH_CACHES)


def _mutmut(work: Path, *args: str, capture: bool = True) -> str:
    exe = Path(sys.executable).with_name("mutmut")
    # mutmut puts mutants/ first on the tests' sys.path itself (a PYTHONPATH of ours breaks its
    # set-up); so a test's subprocess (the CLI tests) runs the checkout's code and kills nothing
    env = dict(os.environ)
    env.setdefault("MPLBACKEND", "Agg")
    res = subprocess.run([str(exe), *args], cwd=work, env=env, text=True, check=False,
                         stdout=subprocess.PIPE if capture else subprocess.DEVNULL,
                         stderr=subprocess.STDOUT if capture else subprocess.DEVNULL)
    if res.returncode != 0:
        tail = (res.stdout or "")[-3000:]
        raise SystemExit(f"mutation: mutmut {' '.join(args)} failed ({res.returncode}):\n{tail}")
    return res.stdout or ""


def _statuses(work: Path) -> dict[str, str]:
    out = _mutmut(work, "results", "--all", "true")
    found = {}
    for line in out.splitlines():
        name, sep, status = line.strip().rpartition(": ")
        if sep and name.startswith("planar_sym."):
            found[name] = status
    return found


def run_target(target: str, tests: list[str], jobs: int) -> Outcome:
    slug = target.replace("/", "_").removesuffix(".py").strip("_")
    work = WORK / slug
    _prepare(work, target, tests)
    t0 = time.perf_counter()
    print(f"mutation: {target}: mutmut run over {len(tests)} test file(s), {jobs} at a time",
          file=sys.stderr)
    _mutmut(work, "run", "--max-children", str(jobs), capture=False)
    seconds = time.perf_counter() - t0
    statuses = _statuses(work)
    equivalents = load_equivalents()
    names = [n for n, status in sorted(statuses.items()) if status in ("survived", "no tests")]
    survivors = []
    for name, shown in _diffs(work, names).items():
        mutant: Mutant = parse_show(name, statuses[name], shown)
        mutant.reason = equivalents.get(mutant.key())
        survivors.append(mutant)
    return Outcome(target=target, tests=tests, statuses=statuses, survivors=survivors,
                   seconds=seconds, commit=_commit())


def report_target(target: str, tests: list[str], out: Path) -> Outcome:
    """The target's outcome re-read from its last run's work folder, with today's
    equivalence judgments (``--report-only``): a survivor judged since the run is marked
    without running every mutant again. The run time and commit stay the last run's."""
    slug = target.replace("/", "_").removesuffix(".py").strip("_")
    work = WORK / slug
    if not (work / "mutants").is_dir():
        raise SystemExit(f"mutation: {target}: no earlier run in {work} to report from")
    statuses = _statuses(work)
    equivalents = load_equivalents()
    names = [n for n, status in sorted(statuses.items()) if status in ("survived", "no tests")]
    survivors = []
    for name, shown in _diffs(work, names).items():
        mutant: Mutant = parse_show(name, statuses[name], shown)
        mutant.reason = equivalents.get(mutant.key())
        survivors.append(mutant)
    seconds, commit = 0.0, _commit()
    old = out.read_text() if out.is_file() else ""
    row = re.search(rf"<!-- summary \| `{re.escape(target)}` \|(.*)\| -->", old)
    if row:  # the run's own time and commit
        cells = [c.strip() for c in row.group(1).split("|")]
        seconds, commit = float(cells[-2].split()[0]) * 60, cells[-1]
    return Outcome(target=target, tests=tests, statuses=statuses, survivors=survivors,
                   seconds=seconds, commit=commit)


def _diffs(work: Path, names: list[str]) -> dict[str, str]:
    """``mutmut show`` of each mutant, in this process with mutmut's own line index of the
    mutated files (one ``mutmut show`` process per mutant took minutes on a folder)."""
    try:
        from difflib import unified_diff

        import libcst as cst
        from mutmut.mutation.diff_apply import read_functions_from_index
    except ImportError:  # another mutmut than the pinned 3.x: its command line
        return {name: _mutmut(work, "show", name) for name in names}
    out = {}
    for name in names:
        module = name.split(".x", 1)[0]
        base = work / "mutants" / Path(*module.split("."))
        path = base.with_suffix(".py") if base.with_suffix(".py").is_file() else \
            base / "__init__.py"
        funcs = read_functions_from_index(name, path)
        if funcs is None:  # no usable index: mutmut parses the file
            out[name] = _mutmut(work, "show", name)
            continue
        orig, mutant = (cst.Module([f]).code.strip() for f in funcs)
        out[name] = "\n".join(unified_diff(orig.split("\n"), mutant.split("\n"), lineterm=""))
    return out


def _commit() -> str:
    res = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, text=True,
                         capture_output=True, check=False)
    dirty = subprocess.run(["git", "status", "--porcelain", "planar_sym", "tests"], cwd=ROOT,
                           text=True, capture_output=True, check=False).stdout.strip()
    return (res.stdout.strip() or "unknown") + (" (with uncommitted changes)" if dirty else "")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m mutation", description=__doc__.splitlines()[0])
    ap.add_argument("targets", nargs="*", metavar="TARGET",
                    help="a module or folder under planar_sym/ (see mutation/targets.toml)")
    ap.add_argument("--tests", nargs="+", metavar="FILE",
                    help="test files to run instead of the ones listed for the target")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="mutants tested at once (default: the number of cores)")
    ap.add_argument("--out", type=Path, default=ROOT / "MUTATION.md",
                    help="the report whose section for each target is replaced")
    ap.add_argument("--list", action="store_true", help="list the targets and their test files")
    ap.add_argument("--report-only", action="store_true",
                    help="rewrite the targets' sections from their last run with today's "
                         "equivalence judgments (mutation/equivalent.toml and mutation/equivalent/*.toml), running nothing")
    args = ap.parse_args(argv)
    if args.list or not args.targets:
        for target, tests in sorted(_targets().items()):
            print(f"{target}: {' '.join(tests)}")
        return 0
    for target in args.targets:
        if not (ROOT / target).exists():
            ap.error(f"{target}: no such module or folder")
        tests = _tests_for(target, args.tests)
        outcome = (report_target(target, tests, args.out) if args.report_only
                   else run_target(target, tests, args.jobs))
        write_section(args.out, outcome)
        print(outcome.summary_line())
    return 0


if __name__ == "__main__":
    sys.exit(main())
