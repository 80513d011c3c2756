"""planar-sym: dynamics of planar robots, from data to compiled torques.

>>> import planar_sym as ps
>>> arm = ps.load("serial_2dof")
>>> tau = arm.inverse_dynamics(q, qd, qdd)          # (N, 2) arrays in, one compiled call

Runtime only: numpy, casadi-generated C via ctypes, SciPy and matplotlib on demand. SymPy is
needed only to derive new equations (``derive/``).
"""

from __future__ import annotations

from .errors import (
    DescriptionError,
    InputError,
    LibraryError,
    PlanarSymError,
    SeriesNotFound,
    SimulationError,
    WorkspaceError,
)
from .model.locate import load
from .model.robot import Robot
from .motion.profiles import JointTrajectory, Trajectory, cubic
from .outputs.equations import Equations, equations

__all__ = [
    "DescriptionError",
    "Equations",
    "InputError",
    "JointTrajectory",
    "LibraryError",
    "PlanarSymError",
    "Robot",
    "SeriesNotFound",
    "SimulationError",
    "Tracking",
    "Trajectory",
    "WorkspaceError",
    "atlas",
    "controller",
    "cubic",
    "equations",
    "explore",
    "export",
    "from_actuated",
    "inverse_along",
    "inverse_kinematics",
    "linearize",
    "load",
    "load_study",
    "lqr",
    "optimal_move",
    "plot",
    "run_study",
    "show",
    "simulate",
    "simulate_controlled",
    "studies",
    "sweep",
    "time_optimal",
    "track",
    "tvlqr",
    "validate",
    "write_result",
]
__version__ = "0.1.0"

_LAZY = {"simulate": ("dynamics.forward", "simulate"),
         "inverse_kinematics": ("motion.ik", "inverse_kinematics"),
         "run_study": ("study.run", "run"), "load_study": ("study.run", "load_study"),
         "studies": ("study.builtin", "names"), "plot": ("outputs.plots", "plot"),
         "write_result": ("outputs.results", "write"),
         "from_actuated": ("motion.closure", "from_actuated"),
         "validate": ("analysis.validate", "run_all"),
         "simulate_controlled": ("dynamics.engine", "simulate_controlled"),
         "controller": ("control.laws", "controller"),
         "linearize": ("dynamics.linearize", "linearize"), "lqr": ("control.lqr", "lqr"),
         "tvlqr": ("control.tvlqr", "tvlqr"),
         "time_optimal": ("optimal.time_optimal", "time_optimal"),
         "optimal_move": ("optimal.point_to_point", "optimal_move"),
         "inverse_along": ("dynamics.along", "inverse_along"),
         "track": ("control.track", "track"), "Tracking": ("control.track", "Tracking"),
         "sweep": ("analysis.sweep", "sweep"), "atlas": ("analysis.atlas", "atlas"),
         "show": ("outputs.notebook", "show"), "explore": ("outputs.explore", "explore"),
         "export": ("outputs.export", "write")}


def __getattr__(name: str):
    # SciPy and the scenario tables load on first use, keeping `import planar_sym` light
    if name in _LAZY:
        import importlib

        module, attr = _LAZY[name]
        return getattr(importlib.import_module(f".{module}", __name__), attr)
    raise AttributeError(f"module 'planar_sym' has no attribute {name!r}")


def _notebook_display() -> None:
    """Inside IPython (Jupyter, ``ipython``), show Robot, Result and Simulation as HTML
    (``outputs.notebook``); elsewhere nothing is imported for it."""
    import sys

    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if hasattr(ipython, "get_ipython") else None
    if shell is not None and hasattr(shell, "display_formatter"):
        from .outputs.notebook import register

        register(shell)


_notebook_display()
