"""What the numbers were measured on: CPU (lscpu), SIMD flags, load, compiler and versions.

Recorded with every report because absolute times are meaningless without it, and because the
C floor depends on the SIMD width the compiler may use (``-march=native``).
"""

from __future__ import annotations

import datetime
import os
import platform
import shutil
import subprocess
import sys
from importlib import metadata

SIMD_FLAGS = ("sse4_2", "avx", "avx2", "fma", "avx512f", "avx512dq", "avx512vl")


def _lscpu() -> dict[str, str]:
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return {}
    info = {}
    for line in out.splitlines():
        key, _, value = line.partition(":")
        info[key.strip()] = value.strip()
    return info


def _cpu_flags(info: dict[str, str]) -> set[str]:
    flags = info.get("Flags", "")
    if not flags and os.path.exists("/proc/cpuinfo"):
        with open("/proc/cpuinfo") as f:
            flags = next((line.partition(":")[2] for line in f if line.startswith("flags")), "")
    return set(flags.split())


def _version(module: str, dist: str) -> str:
    try:
        mod = __import__(module)
        return str(getattr(mod, "__version__", None) or metadata.version(dist))
    except Exception as exc:  # noqa: BLE001 - a missing optional baseline is reported
        return f"not available ({type(exc).__name__})"


def _compiler() -> str:
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if not cc:
        return "none"
    try:
        return subprocess.run([cc, "--version"], check=False, capture_output=True,
                              text=True).stdout.splitlines()[0]
    except (OSError, IndexError):
        return cc


def describe() -> dict[str, str]:
    """Machine and software, as an ordered mapping of label -> text."""
    info = _lscpu()
    flags = _cpu_flags(info)
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    return {
        "date": datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z"),
        "cpu": info.get("Model name", platform.processor() or "unknown"),
        "cores": f"{os.cpu_count()} logical CPUs (lscpu: {info.get('CPU(s)', '?')} CPUs, "
                 f"{info.get('Thread(s) per core', '?')} thread(s) per core, "
                 f"{info.get('Core(s) per socket', '?')} core(s) per socket)",
        "hypervisor": info.get("Hypervisor vendor", "none reported"),
        "simd": ", ".join(f"{f} {'yes' if f in flags else 'no'}" for f in SIMD_FLAGS),
        "load average at start": " ".join(f"{x:.2f}" for x in load),
        "os": platform.platform(),
        "compiler": _compiler(),
        "python": sys.version.split()[0],
        "numpy": _version("numpy", "numpy"),
        "scipy": _version("scipy", "scipy"),
        "casadi": _version("casadi", "casadi"),
        "sympy": _version("sympy", "sympy"),
        "pinocchio": _version("pinocchio", "pin"),
        "mujoco": _version("mujoco", "mujoco"),
    }


def load_now() -> str:
    return " ".join(f"{x:.2f}" for x in os.getloadavg()) if hasattr(os, "getloadavg") else "?"
