"""Robots under control, in the compiled loop: control laws and gains (``laws``), signals of
time evaluated in C (``signals``), events (``events``) and the simulation (``loop``)."""

from .events import Event
from .laws import KINDS, Controller, controller
from .loop import ControlledRun, simulate_controlled
from .signals import INTERPOLATIONS, Signal, from_motion, from_table

__all__ = ["INTERPOLATIONS", "KINDS", "ControlledRun", "Controller", "Event", "Signal",
           "controller", "from_motion", "from_table", "simulate_controlled"]
