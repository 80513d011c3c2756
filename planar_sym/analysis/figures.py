"""A sweep's columns, typed: each figure (and each varied parameter) with its unit and what it
is a statistic of, kept beside its name so that tables and plots choose and label columns from
these fields, never by reading the name back."""

from __future__ import annotations

from dataclasses import dataclass

from ..dynamics.series import Series, column_name, column_stem
from .designs import unit_suffix


@dataclass(frozen=True)
class Figure:
    """One column of a sweep's table: ``name`` (the column, its unit in it), ``stem`` (the name
    without its unit, what a plot's label shows beside the unit), ``unit`` (``"N*m"``, ``"N"``,
    ``"rad"``, ``"mm"``, ``"J"``, ``"rpm"``, ``"W"``, a parameter's SI unit such as ``"kg"``;
    ``""`` or ``"1"`` for a pure number), and what it is: the ``statistic`` (``"peak"``,
    ``"rms"``, ``"max_abs"``, ``"final"``, ``"change"``, ``"max"``; ``""`` for a varied
    parameter or an atlas figure) of a run's ``quantity`` (``"tau"``, ``"fx"``, ``"e"``,
    ``"motor_tau"``, ``"work"``, ...; a varied parameter's name) at coordinate ``index``
    (0-based) or ``joint``.

    Attributes
    ----------
    name, stem, unit, statistic, quantity : str
        As above.
    index : int or None
        The coordinate (0-based) it is of, if any.
    joint : str or None
        The joint or loop cut it is of, if any.
    """

    name: str
    stem: str
    unit: str = ""
    statistic: str = ""
    quantity: str = ""
    index: int | None = None
    joint: str | None = None

    @classmethod
    def of(cls, statistic: str, quantity: str, unit: str, index: int | None = None,
           joint: str | None = None) -> Figure:
        """``statistic`` of a series of ``quantity`` in ``unit`` (at coordinate ``index`` or
        ``joint``), named ``<statistic>_<its column>``: ``peak_tau2_n``, ``max_abs_e1_rad``."""
        return cls(f"{statistic}_{column_name(quantity, unit, index, joint)}",
                   f"{statistic}_{column_stem(quantity, index, joint)}", unit, statistic,
                   quantity, index, joint)

    @classmethod
    def of_series(cls, statistic: str, series: Series) -> Figure:
        """``statistic`` of ``series`` (its quantity, unit, coordinate and joint)."""
        return cls.of(statistic, series.quantity, series.unit, series.index, series.joint)

    @property
    def label(self) -> str:
        """What a plot's axis says: ``peak_tau1 (N*m)``, ``m_link2 (kg)``; the bare name for a
        pure number (``max_cond_phi_p``)."""
        return f"{self.stem} ({self.unit})" if self.unit not in ("", "1") else self.name


#: the worst conditioning of a closed chain's passive-joint constraint Jacobian over the motion
COND = Figure("max_cond_phi_p", "max_cond_phi_p", "", "max", "cond_phi_p")
#: the change of the plant's energy over a run, E(end) - E(0) (J)
ENERGY_CHANGE = Figure("energy_change_j", "energy_change", "J", "change", "energy")


def named(figures: dict[Figure, object]) -> tuple[dict[str, object], dict[str, Figure]]:
    """Figure-keyed values as the table keeps them: name -> values, and name -> Figure."""
    return {f.name: v for f, v in figures.items()}, {f.name: f for f in figures}


def parameter_figure(name: str, unit: str, prefix: str = "") -> Figure:
    """A varied parameter's column (its SI value per design, in ``unit``): ``m_link2_kg``,
    ``plant_m_link2_kg`` with ``prefix="plant_"``, named as ``DesignSpace.columns`` names it."""
    return Figure(f"{prefix}{name}_{unit_suffix(unit)}", f"{prefix}{name}", unit, "", name)
