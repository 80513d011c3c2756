"""The Pinocchio model of a description, shared with the benchmarks (one builder, one place)."""

import sys
from pathlib import Path

# `python -m pytest` puts the project root on sys.path, the `pytest` script does not: the
# builder lives in benchmarks/ (no package install), so make the root importable either way
_ROOT = str(Path(__file__).resolve().parent.parent)
if _ROOT not in sys.path:
    sys.path.insert(0, _ROOT)

from benchmarks.baselines.pinocchio_model import (
    PinocchioTree,
    depth_first,
    pinocchio_model,
    pinocchio_tree,
    rotz,
    xyz,
)

__all__ = ["PinocchioTree", "depth_first", "pinocchio_model", "pinocchio_tree", "rotz", "xyz"]
