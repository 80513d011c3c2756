"""The plain-C floor: hand-written inverse dynamics of the serial arms, compiled here, via ctypes.

``floor_2dof.c`` is the textbook closed form; ``floor_3dof.c`` is planar Newton-Euler unrolled by
hand. Both take structure-of-arrays inputs (q1[N], q2[N], ...) and write into preallocated
outputs, and are compiled with ``cc -O3 -march=native -ffast-math -fPIC -shared`` so gcc can
vectorise the sample loop with libmvec's SIMD sin/cos. Whether it did is read back from the
library's dynamic symbols (libmvec's vector functions are named ``_ZGV...``) and reported.
"""

from __future__ import annotations

import ctypes
import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
CFLAGS = ("-O3", "-march=native", "-ffast-math", "-fPIC", "-shared", "-std=c99")

#: the C kernels' parameter order, as names of planar_sym parameters
PARAMS = {
    "serial_2dof": ("g", "m_link1", "izz_link1", "cgx_link1", "m_motor2", "izz_motor2",
                    "m_link2", "izz_link2", "cgx_link2", "px_link1_CS2"),
    "serial_3dof": ("g", "m_link1", "izz_link1", "cgx_link1", "m_motor2", "izz_motor2",
                    "m_link2", "izz_link2", "cgx_link2", "m_motor3", "izz_motor3", "m_link3",
                    "izz_link3", "cgx_link3", "px_link1_CS2", "px_link2_CS2"),
}
SOURCES = {"serial_2dof": "floor_2dof.c", "serial_3dof": "floor_3dof.c"}


@dataclass
class Floor:
    """One compiled kernel, bound to a robot's parameter values."""

    robot: str
    n: int
    fn: ctypes._CFuncPtr
    p: np.ndarray
    vector_math: tuple[str, ...]  # libmvec symbols the library calls (empty: not vectorised)
    command: str

    def soa(self, q, qd, qdd) -> list[np.ndarray]:
        """(N, n) arrays to the kernel's 3n contiguous columns (done once, outside timing)."""
        return [np.ascontiguousarray(a[:, i]) for a in (q, qd, qdd) for i in range(self.n)]

    def outputs(self, n_samples: int) -> list[np.ndarray]:
        return [np.empty(n_samples) for _ in range(self.n)]

    def call(self, cols: list[np.ndarray], outs: list[np.ndarray]) -> None:
        self.bind(cols, outs)()

    def bind(self, cols: list[np.ndarray], outs: list[np.ndarray]):
        """A no-argument call with every pointer computed once (``arr.ctypes.data`` costs about
        1 us per array, which would dominate a one-sample call): the floor of a ctypes call."""
        fn = self.fn
        args = (len(outs[0]), self.p.ctypes.data, *[c.ctypes.data for c in cols],
                *[o.ctypes.data for o in outs])
        keep = (cols, outs)  # the arrays must outlive the pointers

        def call():
            return fn(*args), keep

        return call

    def __call__(self, q, qd, qdd) -> np.ndarray:
        """Torques (N, n), for checking against planar_sym."""
        q = np.atleast_2d(q)
        outs = self.outputs(len(q))
        self.call(self.soa(q, np.atleast_2d(qd), np.atleast_2d(qdd)), outs)
        return np.column_stack(outs)


def _vector_symbols(lib: Path) -> tuple[str, ...]:
    nm = shutil.which("nm")
    if not nm:
        return ("(nm not found: not checked)",)
    out = subprocess.run([nm, "-D", "--undefined-only", str(lib)], check=False,
                         capture_output=True,
                         text=True).stdout
    return tuple(sorted({line.split()[-1].split("@")[0] for line in out.splitlines()
                         if "_ZGV" in line}))


def compile_floor(robot: str, parameters: dict[str, float], workdir: Path | None = None) -> Floor:
    """Compile the robot's kernel into ``workdir`` (default: a fresh temp folder) and bind it."""
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if not cc:
        raise RuntimeError("no C compiler (cc/gcc) for the C floor")
    workdir = Path(workdir or tempfile.mkdtemp(prefix="planar_sym_floor_"))
    src = HERE / SOURCES[robot]
    lib = workdir / f"{src.stem}.so"
    # compile with fast math, link without: gcc 12 links crtfastmath.o into a -ffast-math
    # -shared link, and loading the kernel would switch the whole process to flush-to-zero
    obj = workdir / f"{src.stem}.o"
    cmd = [cc, *[f for f in CFLAGS if f != "-shared"], "-c", "-o", str(obj), str(src)]
    for step in (cmd, [cc, "-shared", "-o", str(lib), str(obj), "-lm"]):
        proc = subprocess.run(step, check=False, capture_output=True, text=True)
        if proc.returncode != 0:
            raise RuntimeError(f"compiling {src} failed:\n{proc.stderr}")
    n = 2 if robot == "serial_2dof" else 3
    fn = getattr(ctypes.CDLL(str(lib)), src.stem)
    fn.restype = None
    fn.argtypes = [ctypes.c_long] + [ctypes.c_void_p] * (1 + 4 * n)
    p = np.array([parameters.get(k, 0.0) for k in PARAMS[robot]], dtype=np.float64)
    shown = " ".join(Path(c).name if c == cc else c for c in cmd[:len(CFLAGS) + 1])
    return Floor(robot, n, fn, p, _vector_symbols(lib), shown)
