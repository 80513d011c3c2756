"""Optimal motion (issue 27): the fastest timing of a given path under torque and speed
limits (``time_optimal``), and the best rest-to-rest move between two poses
(``optimal_move``: minimum time or effort, by direct collocation with CasADi and IPOPT)."""

from .point_to_point import OptimalMove, optimal_move
from .time_optimal import TimeOptimal, time_optimal

__all__ = ["OptimalMove", "TimeOptimal", "optimal_move", "time_optimal"]
