"""The typed study a study file is read into (``spec.parse``): ``Study`` and its sections
``Motion``, ``Simulation``, ``Optimise`` and ``Outputs``, numbers in the file's units.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from ..model.units import factor
from .control_spec import ControlSpec, EventsSpec, TorqueInput
from .optimal_spec import OptimalSpec


@dataclass(frozen=True)
class Motion:
    """The move of an inverse-dynamics study, in the file's units (converted when run)."""

    space: str
    profile: str
    start: tuple[float, ...] = ()
    by: tuple[float, ...] | None = None
    end: tuple[float, ...] | None = None
    duration_s: float | None = None
    samples: int = 201
    v_max: tuple[float, ...] | None = None
    a_max: tuple[float, ...] | None = None
    times_s: tuple[float, ...] | None = None
    points: tuple[tuple[float, ...], ...] | None = None
    table: Path | None = None
    ik: str = "auto"
    start_pose: tuple[float, ...] | None = None


@dataclass(frozen=True)
class Simulation:
    """The run of a forward-dynamics study, in the file's units."""

    q0: tuple[float, ...]
    duration_s: float
    qd0: tuple[float, ...] | None = None
    samples: int = 1001
    torque: TorqueInput | None = None
    method: str = "dopri5"
    rtol: float = 1e-11
    atol: float = 1e-12


@dataclass(frozen=True)
class Optimise:
    """Time the motion's path as fast as the limits allow (``planar_sym.time_optimal``):
    torque limits in N*m (N at a slider) per motor, None for the description's; speed limits
    per coordinate in the file's units per s, None for none."""

    torque_limit: tuple[float, ...] | None = None
    speed_limit: tuple[float, ...] | None = None


@dataclass(frozen=True)
class Outputs:
    csv: bool = True
    plot: bool = True
    split: bool = False
    animation: str | None = None
    frames: int = 60


@dataclass(frozen=True)
class Study:
    """One study: a robot, its parameter overrides, and a motion (or a simulation)."""

    name: str
    title: str
    robot: str  # a built-in name, or an absolute path (description file or generated folder)
    kind: str  # "inverse" or "forward"
    length_unit: str = "m"
    angle_unit: str = "rad"
    parameters: dict[str, tuple[float, str | None]] = field(default_factory=dict)
    motion: Motion | None = None
    simulation: Simulation | None = None
    outputs: Outputs = Outputs()
    path: Path | None = None
    control: ControlSpec | None = None
    events: EventsSpec | None = None
    optimise: Optimise | None = None
    optimal: OptimalSpec | None = None

    @property
    def length_si(self) -> float:
        return factor("length", self.length_unit)

    @property
    def angle_si(self) -> float:
        return factor("angle", self.angle_unit)
