"""The Pinocchio model of a description, shared with the benchmarks (one builder, one place)."""

from benchmarks.baselines.pinocchio_model import pinocchio_model, rotz, xyz

__all__ = ["pinocchio_model", "rotz", "xyz"]
