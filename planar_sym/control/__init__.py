"""Robots under control: the laws and their gains (``laws``), LQR about an equilibrium
(``lqr``), time-varying LQR along a motion (``tvlqr``), tracking a motion from one typed
request (``track``: ``Tracking`` in, ``Tracked`` out). The simulation engine that runs
them is ``planar_sym.dynamics.engine`` (with the events and SUNDIALS beside it), the signals of
time it evaluates ``planar_sym.motion.signals``; their public names are re-exported here."""

from ..dynamics.engine import ControlledRun, simulate_controlled
from ..dynamics.events import Event
from ..dynamics.linearize import Linearization, linearize
from ..motion.signals import INTERPOLATIONS, Signal, from_motion, from_table
from .laws import KINDS, Controller, bandwidth_gains, controller, effective_inertia
from .lqr import LQR, lqr
from .track import Tracked, Tracking, track
from .tvlqr import TVLQR, tvlqr

__all__ = [
           "INTERPOLATIONS",
           "KINDS",
           "LQR",
           "TVLQR",
           "ControlledRun",
           "Controller",
           "Event",
           "Linearization",
           "Signal",
           "Tracked",
           "Tracking",
           "bandwidth_gains",
           "controller",
           "effective_inertia",
           "from_motion",
           "from_table",
           "linearize",
           "lqr",
           "simulate_controlled",
           "track",
           "tvlqr",
]
