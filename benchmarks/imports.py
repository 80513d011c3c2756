"""Section 4: start-up cost, as a user's script pays it.

Measured: wall time of a fresh ``python -c ...`` subprocess (same interpreter, same
environment), for ``import planar_sym`` and for import plus the first torque
(``planar_sym.load("serial_2dof").inverse_dynamics(...)``, the library already compiled in the
cache, so this is manifest checks, ``ctypes`` loading and one call), against ``python -c pass``
(the interpreter alone), ``import numpy`` (the only third-party module planar_sym imports),
``import numpy, casadi``, ``import pinocchio`` and ``import mujoco``. All commands run in the
same interleaved rounds; ratios are to ``import numpy, casadi``.
"""

from __future__ import annotations

import subprocess
import sys

from . import Config
from .report import Section, Table
from .timing import once_each, ratio

COMMANDS = {
    "python -c pass": "pass",
    "import numpy": "import numpy",
    "import numpy, casadi": "import numpy, casadi",
    "import planar_sym": "import planar_sym",
    "import planar_sym + first torque": (
        "import planar_sym; planar_sym.load('serial_2dof').inverse_dynamics("
        "[0.1, 0.2], [0.0, 0.0], [0.0, 0.0])"),
    "import pinocchio": "import pinocchio",
    "import mujoco": "import mujoco",
}
BASE = "import numpy, casadi"


def _cmd(code: str):
    def run():
        subprocess.run([sys.executable, "-c", code], check=True, capture_output=True)
    return run


def run(cfg: Config) -> Section:
    from planar_sym import load

    load("serial_2dof")  # compiled into the cache before timing: first torque is not a build
    sec = Section("imports", "4. Import and first-torque latency", __doc__.split("\n\n", 1)[1])
    st = once_each({k: _cmd(v) for k, v in COMMANDS.items()}, repeats=cfg.import_repeats)
    t = Table(f"Fresh interpreter, `python -c ...` ({cfg.import_repeats} rounds); "
              f"ratio to `{BASE}` in the same round", ["command", "wall time", "ratio"])
    for k in COMMANDS:
        t.add(f"`{k}`", st[k], ratio(st[k], st[BASE]) if k != BASE else "1")
    sec.tables.append(t)
    r = ratio(st["import planar_sym"], st[BASE])
    f = ratio(st["import planar_sym + first torque"], st[BASE])
    sec.headlines["import"] = (
        f"`import planar_sym`: **{r.median:.3g}x** [{r.min:.3g}-{r.max:.3g}] the time of "
        f"`import numpy, casadi` ({st['import planar_sym'].median * 1e3:.0f} ms vs "
        f"{st[BASE].median * 1e3:.0f} ms); with the first 2-DOF torque "
        f"{f.median:.3g}x ({st['import planar_sym + first torque'].median * 1e3:.0f} ms)")
    return sec
