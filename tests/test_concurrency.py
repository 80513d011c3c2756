"""Concurrent processes sharing one compiled-library cache, and concurrent derivations into one
output folder.

* ``PROCESSES`` (6) processes on an empty ``PLANAR_SYM_CACHE``, released together by a start
  file, each load serial_2dof and five_bar_type1 (so they race to build the same libraries:
  the exact and vectorised robot libraries, ``_fastcall`` and ``_integrate``) and compute
  torques along a trajectory and a short simulation. Every one must exit 0 with the torques the
  parent computes with its own (already built) libraries; the cache ends with exactly one file
  per library and no temporary folder.
* Two ``python -m derive serial_2dof --out DIR`` started at once, two rounds (the first into an
  empty folder, then over an existing one): each succeeds or fails cleanly (exit code, no
  traceback), and the folder ends consistent: its files are exactly the manifest's, with the
  manifest's hashes, the same bytes in both rounds, and no hidden leftovers.
* Fixed, found here: the folder swap in ``derive/__main__.py write_atomically`` was two
  renames, so a deriver running between them crashed the first and readers found no robot in
  between. It is now one atomic exchange under a lock (tested by a reader polling throughout).
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np

import planar_sym as ps
from planar_sym.motion.ik import inverse_kinematics

ROOT = Path(__file__).resolve().parent.parent
PROCESSES = 6

CHILD = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    import numpy as np
    import planar_sym as ps
    from planar_sym.motion.ik import inverse_kinematics

    go, out = Path(sys.argv[1]), sys.argv[2]
    while not go.exists():  # everyone imported: start together
        time.sleep(0.005)
    arm = ps.load("serial_2dof")
    five = ps.load("five_bar_type1")
    t = np.linspace(0.0, 5.0, 201)
    j = inverse_kinematics(arm, ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, t))
    tau = arm.inverse_dynamics(j.q, j.qd, j.qdd)
    t2 = np.linspace(0.0, 2.0, 101)
    j5 = inverse_kinematics(five, ps.cubic([60.852e-3, 154.665e-3], [0.05, 0.0], 2.0, t2))
    tau5, lam5 = five.closed_chain_inverse_dynamics(j5.q, j5.qd, j5.qdd)
    swing = ps.simulate(arm, np.radians([-60.0, 0.0]), [0.0, 0.0], (0.0, 0.5))
    np.savez(out, tau=tau, tau5=tau5, lam5=lam5, q=swing.q,
             libs=np.array([str(arm.library.path), str(five.library.path)]))
""")


def _reference():
    arm, five = ps.load("serial_2dof"), ps.load("five_bar_type1")
    t = np.linspace(0.0, 5.0, 201)
    j = inverse_kinematics(arm, ps.cubic([0.1, 0.1], [-0.2, 0.0], 5.0, t))
    t2 = np.linspace(0.0, 2.0, 101)
    j5 = inverse_kinematics(five, ps.cubic([60.852e-3, 154.665e-3], [0.05, 0.0], 2.0, t2))
    tau5, lam5 = five.closed_chain_inverse_dynamics(j5.q, j5.qd, j5.qdd)
    swing = ps.simulate(arm, np.radians([-60.0, 0.0]), [0.0, 0.0], (0.0, 0.5))
    return {"tau": arm.inverse_dynamics(j.q, j.qd, j.qdd), "tau5": tau5, "lam5": lam5,
            "q": swing.q}


def _env(**extra) -> dict:
    env = dict(os.environ, **extra)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    env.pop("PLANAR_SYM_EXACT", None)
    return env


def test_processes_racing_to_build_one_cache(tmp_path):
    cache = tmp_path / "cache"  # does not exist yet: every process finds it empty
    go = tmp_path / "go"
    script = tmp_path / "child.py"
    script.write_text(CHILD)
    env = _env(PLANAR_SYM_CACHE=str(cache), PLANAR_SYM_PREBUILT="0")  # not the install's
    procs = [subprocess.Popen([sys.executable, str(script), str(go), str(tmp_path / f"r{k}.npz")],
                              env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for k in range(PROCESSES)]
    time.sleep(1.0)  # let them import numpy and planar_sym
    go.touch()
    results = [p.communicate(timeout=120) for p in procs]
    reference = _reference()
    for k, (p, (out, err)) in enumerate(zip(procs, results)):
        assert p.returncode == 0, f"process {k} exited {p.returncode}:\n{err}"
        got = np.load(tmp_path / f"r{k}.npz")
        for key, ref in reference.items():
            np.testing.assert_allclose(got[key], ref, rtol=1e-13, atol=1e-15,
                                       err_msg=f"process {k}: {key}")
        assert all(Path(p).parent == cache for p in got["libs"])
    files = sorted(p.name for p in cache.iterdir())
    libraries = [f for f in files if f.endswith(".so")]
    # besides each library: its lock and the hash recorded when it was built
    assert sorted(f for f in files if not f.endswith((".lock", ".so.sha256"))) == libraries, (
        f"temporary files left in the cache: {files}")
    assert sorted(f[:-len(".sha256")] for f in files if f.endswith(".sha256")) == libraries
    kinds = sorted(f.split("-")[0] + ("-simd" if f.endswith("-simd.so") else "")
                   for f in libraries)
    # the C helpers (_fastcall, _integrate, _newton) come from the install, not the cache
    assert kinds == sorted(["five_bar_type1", "five_bar_type1-simd",
                            "serial_2dof", "serial_2dof-simd"]), files


# -- two derivations into one folder ----------------------------------------------------------------

def folder_problems(folder: Path) -> list[str]:
    """What is wrong with a generated folder: files not exactly the manifest's, or hashes off."""
    try:
        manifest = json.loads((folder / "manifest.json").read_text())
    except (OSError, ValueError) as exc:
        return [f"{folder}: no readable manifest ({exc})"]
    problems = []
    present = {p.name for p in folder.iterdir()}
    if present != set(manifest["files"]) | {"manifest.json"}:
        problems.append(f"{folder}: files {sorted(present)} != manifest's "
                        f"{sorted(manifest['files'])}")
    for name, digest in manifest["files"].items():
        path = folder / name
        if path.is_file() and hashlib.sha256(path.read_bytes()).hexdigest() != digest:
            problems.append(f"{path}: sha256 differs from the manifest")
    return problems


def _derive(out: Path, *extra: str) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, *extra, "-m", "derive", "serial_2dof", "--out",
                             str(out), "--quiet"], cwd=ROOT, env=_env(),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def test_two_derivations_into_one_folder(tmp_path):
    out = tmp_path / "out"
    contents = []
    for round_ in range(2):
        procs = [_derive(out), _derive(out)]
        results = [p.communicate(timeout=120) for p in procs]
        codes = [p.returncode for p in procs]
        for code, (_, err) in zip(codes, results):
            assert "Traceback" not in err, f"round {round_}: a derivation crashed:\n{err}"
            assert code == 0 or (code > 0 and err.strip()), (code, err)
        assert 0 in codes, f"round {round_}: neither derivation succeeded: {results}"
        folder = out / "serial_2dof"
        assert folder_problems(folder) == []
        contents.append({p.name: p.read_bytes() for p in folder.iterdir()})
        kept = sorted(p.name for p in out.iterdir() if not p.name.endswith(".lock"))
        assert kept == ["serial_2dof"], f"leftovers: {kept}"
    assert contents[0] == contents[1]  # derive is deterministic, raced or not


def test_folder_is_never_missing_while_derive_swaps_it(tmp_path):
    """The swap is one atomic exchange (renameat2): a reader polling the folder while it is
    re-derived again and again never finds it missing or half-written."""
    out = tmp_path / "out"
    assert _derive(out).wait(timeout=120) == 0
    writer = subprocess.Popen(
        [sys.executable, "-c", ("import sys; from derive.__main__ import main\n"
         "for _ in range(4): assert main(['serial_2dof', '--out', sys.argv[1], '--quiet']) == 0"),
         str(out)], cwd=ROOT, env=_env(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True)
    polls, missing = 0, 0
    while writer.poll() is None:
        polls += 1
        missing += not (out / "serial_2dof" / "manifest.json").is_file()
    err = writer.communicate()[1]
    assert writer.returncode == 0, err
    assert polls > 100 and missing == 0, (polls, missing)
    assert folder_problems(out / "serial_2dof") == []
    assert sorted(p.name for p in out.iterdir() if not p.name.endswith(".lock")) == [
        "serial_2dof"]
