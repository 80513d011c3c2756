"""Pinocchio's inverse dynamics (and its mass matrix and forward dynamics) timed in a native C++
loop: the per-sample baseline for our compiled batch functions.

What is measured: ``pinocchio_native.cpp`` loads a URDF with ``pinocchio::urdf::buildModel``,
then runs ``pinocchio::rnea`` over N samples in a plain C++ loop, REPEATS times, timed with
``std::chrono::steady_clock``; the best and the median pass are reported in ns per sample.
A sample has our batch function's contract: angles, rates and accelerations in (our coordinate
order), torques out, so packing the angles into Pinocchio's configuration (cos q, sin q for a
URDF "continuous" joint) is inside the timed loop, as the trig is inside ours. Why native: a
Python loop over ``pin.rnea`` (``pinocchio_model.rnea_loop``) mostly measures the Python call,
not the dynamics, so it says nothing about per-sample cost against a compiled batch.

rnea is compiled from Pinocchio's headers with ``-O3 -march=native -DNDEBUG`` (the wheel's own
explicitly instantiated copy is built for generic x86-64); only URDF parsing runs in the
wheel's libraries. Their Eigen objects are 16-byte aligned and allocated with plain malloc, so
the program is built with ``EIGEN_MAX_ALIGN_BYTES=16 EIGEN_MALLOC_ALREADY_ALIGNED=1`` (without
them an AVX-512 build frees the parser's vectors with Eigen's own aligned free and crashes).

Needs a C++ compiler, the ``pin`` wheel (headers and libraries under ``cmeel.prefix``), Eigen
headers (CasADi's bundled copy, else ``cmeel-eigen`` or the system's) and the urdfdom headers
(``cmeel-urdfdom-headers``, which ``pin`` does not pull in). The executable is built once into
the project's cache folder (``planar_sym.model.folders.cache_dir()``), keyed by the source, the
flags, the paths and the CPU.

API::

    exe = build()                                              # path of the executable
    tau, best_ns, median_ns = time_rnea(urdf, q, qd, qdd, repeats)   # (N, n) arrays in
    info = run(urdf, q, qd, qdd, repeats)                      # all of the above, and more
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

SOURCE = Path(__file__).resolve().with_name("pinocchio_native.cpp")
CXXFLAGS = ("-std=c++17", "-O3", "-march=native", "-DNDEBUG",
            "-DEIGEN_MAX_ALIGN_BYTES=16", "-DEIGEN_MALLOC_ALREADY_ALIGNED=1")
#: what pinocchio's CMake targets (pinocchio_headers, pinocchio_parsers) add, if their file
#: cannot be read; PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION is left out on purpose
DEFAULT_DEFINES = ("BOOST_MPL_LIMIT_LIST_SIZE=30", "BOOST_MPL_LIMIT_VECTOR_SIZE=30",
                   "BOOST_MPL_CFG_NO_PREPROCESSED_HEADERS", "BOOST_FUSION_INVOKE_MAX_ARITY=12",
                   "PINOCCHIO_WITH_URDFDOM", "PINOCCHIO_URDFDOM_HEADERS_MAJOR_VERSION=3",
                   "PINOCCHIO_URDFDOM_HEADERS_MINOR_VERSION=0",
                   "PINOCCHIO_URDFDOM_HEADERS_PATCH_VERSION=0")
LIBS = ("-lpinocchio_parsers", "-lpinocchio_default", "-lurdfdom_model")


def _prefix() -> Path:
    """The ``cmeel.prefix`` folder of the installed ``pin`` wheel."""
    try:
        import pinocchio
    except ImportError as exc:
        raise RuntimeError(f"pinocchio is not importable ({exc}): pip install pin") from None
    for parent in Path(pinocchio.__file__).resolve().parents:
        if (parent / "include" / "pinocchio" / "algorithm" / "rnea.hpp").is_file():
            return parent
    raise RuntimeError(f"no Pinocchio C++ headers found above {pinocchio.__file__} (the pip "
                       "wheel 'pin' ships them in cmeel.prefix/include)")


def _eigen(prefix: Path) -> Path:
    """A folder holding ``Eigen/Core``: CasADi's bundled copy first."""
    candidates = []
    try:
        import casadi

        candidates.append(Path(casadi.__file__).resolve().parent / "include" / "eigen3")
    except ImportError:
        pass
    candidates += [prefix / "include" / "eigen3", Path("/usr/include/eigen3")]
    for c in candidates:
        if (c / "Eigen" / "Core").is_file():
            return c
    raise RuntimeError("no Eigen headers (looked in " + ", ".join(map(str, candidates))
                       + "): pip install cmeel-eigen, or apt-get install libeigen3-dev")


def _urdf_headers(prefix: Path) -> Path:
    candidates = [prefix / "include" / "urdfdom_headers", prefix / "include", Path("/usr/include")]
    for c in candidates:
        if (c / "urdf_model" / "model.h").is_file():
            return c
    raise RuntimeError("no urdfdom headers (urdf_model/model.h; looked in "
                       + ", ".join(map(str, candidates)) + "): pip install "
                       "cmeel-urdfdom-headers (pin ships urdfdom's libraries, not its headers)")


def _defines(prefix: Path) -> list[str]:
    """The compile definitions of pinocchio's CMake targets, read from its exported file."""
    targets = prefix / "lib" / "cmake" / "pinocchio" / "pinocchioTargets.cmake"
    try:
        text = targets.read_text()
    except OSError:
        return list(DEFAULT_DEFINES)
    out: list[str] = []
    for name in ("pinocchio_headers", "pinocchio_parsers"):
        m = re.search(rf"pinocchio::{name} PROPERTIES\s+INTERFACE_COMPILE_DEFINITIONS \"([^\"]*)\"",
                      text)
        for d in (m.group(1).split(";") if m else []):
            if d and "$<" not in d and d != "PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION" \
                    and d not in out:
                out.append(d)
    return out or list(DEFAULT_DEFINES)


def command(output: Path) -> list[str]:
    """The compiler command line that builds the executable ``output``."""
    cxx = os.environ.get("CXX") or shutil.which("c++") or shutil.which("g++") \
        or shutil.which("clang++")
    if not cxx:
        raise RuntimeError("no C++ compiler found (set CXX, or apt-get install g++)")
    prefix = _prefix()
    lib = prefix / "lib"
    if not any(lib.glob("libpinocchio_parsers.*")):
        raise RuntimeError(f"no libpinocchio_parsers in {lib}")
    urdf = _urdf_headers(prefix)
    incs = [prefix / "include", urdf, prefix / "include" / "urdfdom", _eigen(prefix)]
    return [cxx, *CXXFLAGS, *(f"-D{d}" for d in _defines(prefix)),
            *(f"-I{i}" for i in dict.fromkeys(incs)), str(SOURCE), "-o", str(output),
            f"-L{lib}", f"-Wl,-rpath,{lib}", *LIBS]


def build(folder: Path | None = None, force: bool = False) -> Path:
    """Compile ``pinocchio_native.cpp`` once (about a minute) and return the executable's path.

    ``folder``: where to keep it (default: the project's cache folder). Rebuilt when the
    source, the flags, the include paths or the CPU change. Raises RuntimeError naming what is
    missing (compiler, Pinocchio, Eigen or urdfdom headers) or the compiler's errors.
    """
    from filelock import FileLock

    from planar_sym.model.compile import _machine_key
    from planar_sym.model.folders import cache_dir

    folder = Path(folder) if folder is not None else cache_dir()
    probe = command(Path("EXE"))
    key = hashlib.sha256("\n".join([SOURCE.read_text(), *probe, _machine_key()]).encode())
    exe = folder / f"pinocchio_native-{key.hexdigest()[:12]}"
    folder.mkdir(parents=True, exist_ok=True)
    with FileLock(str(exe) + ".lock"):
        if exe.is_file() and not force:
            return exe
        tmp = exe.with_name(exe.name + f".tmp{os.getpid()}")
        done = subprocess.run(command(tmp), check=False, capture_output=True, text=True)
        if done.returncode != 0:
            tmp.unlink(missing_ok=True)
            raise RuntimeError(f"compiling {SOURCE.name} failed:\n{done.stderr[-4000:]}")
        os.replace(tmp, exe)
    return exe


def urdf_facts(urdf_path) -> tuple[list[float] | None, list[str] | None]:
    """(gravity, our coordinate names) from the comment ``planar_sym export`` writes, if any."""
    text = Path(urdf_path).read_text()
    g = re.search(r"set it in your engine to \[([^\]]*)\]", text)
    c = re.search(r"coordinates \(our q order\): ([^;\n]*)", text)
    gravity = [float(x) for x in g.group(1).replace(",", " ").split()] if g else None
    names = [s.strip() for s in c.group(1).split(",") if s.strip()] if c else None
    return gravity, names


def run(urdf_path, q, qd, qdd, repeats: int = 20, gravity=None, joints=None,
        exe: Path | None = None) -> dict:
    """Run the native loop; everything it reports, as a dict.

    ``q, qd, qdd``: (N, n) arrays in our coordinate order. ``gravity`` (3 numbers) and
    ``joints`` (URDF joint names, our order) default to what the exported URDF's comment says;
    a URDF without it needs ``gravity`` (``joints`` then defaults to Pinocchio's order).
    Keys: tau (N, n), best_ns, median_ns (the whole loop, per sample), rnea_best_ns,
    rnea_median_ns (rnea alone on inputs packed beforehand), regressor_best_ns,
    regressor_median_ns (``computeJointTorqueRegressor`` on the same inputs), crba_best_ns,
    crba_median_ns (``crba`` on them), crba_stored_best_ns, crba_stored_median_ns (``crba``
    with every matrix written out) and M (N, n, n, symmetric), aba_best_ns, aba_median_ns
    (``aba`` fed rnea's torques) and qdd (N, n, which gives qdd back), nq, nv, n.
    """
    g0, names0 = urdf_facts(urdf_path)
    gravity = g0 if gravity is None else list(gravity)
    if gravity is None or len(gravity) != 3:
        raise ValueError(f"{urdf_path}: no gravity in its comment; pass gravity=(gx, gy, gz)")
    joints = names0 if joints is None else list(joints)
    arrays = [np.ascontiguousarray(x, dtype=np.float64) for x in (q, qd, qdd)]
    if arrays[0].ndim != 2 or any(a.shape != arrays[0].shape for a in arrays):
        raise ValueError("q, qd, qdd must be (N, n) arrays of one shape")
    n_samples, n = arrays[0].shape
    if joints and len(joints) != n:
        raise ValueError(f"{urdf_path}: {len(joints)} coordinates {joints}, the arrays have {n}")
    exe = exe or build()
    with tempfile.TemporaryDirectory(prefix="pin_native_") as tmp:
        files = [Path(tmp) / f"{name}.bin" for name in ("q", "qd", "qdd", "tau")]
        for a, f in zip(arrays, files):
            a.tofile(f)
        cmd = [str(exe), str(urdf_path), str(n_samples), *map(str, files), str(int(repeats)),
               *(repr(float(x)) for x in gravity), *(joints or [])]
        done = subprocess.run(cmd, check=False, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"{exe.name} failed ({done.returncode}): {done.stderr.strip()}")
        out = {k: float(v) for k, v in (ln.split() for ln in done.stdout.splitlines())}
        if int(out["n"]) != n:
            raise ValueError(f"{urdf_path} has {int(out['n'])} coordinates, the arrays {n}")
        out["tau"] = np.fromfile(files[3], dtype=np.float64).reshape(n_samples, n)
        out["M"] = np.fromfile(f"{files[3]}.M", dtype=np.float64).reshape(n_samples, n, n)
        out["qdd"] = np.fromfile(f"{files[3]}.qdd", dtype=np.float64).reshape(n_samples, n)
    return out


def time_rnea(urdf_path, q, qd, qdd, repeats: int = 20, **kwargs):
    """(tau (N, n), best ns per sample, median ns per sample) of Pinocchio's rnea over the
    samples in a native loop (see ``run`` for the keyword arguments)."""
    out = run(urdf_path, q, qd, qdd, repeats, **kwargs)
    return out["tau"], out["best_ns"], out["median_ns"]
