"""Optimal motion (issue 27): the fastest timing of a given path under torque and speed
limits (``time_optimal``)."""

from .time_optimal import TimeOptimal, time_optimal

__all__ = ["TimeOptimal", "time_optimal"]
