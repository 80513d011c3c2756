"""Shared by the lecture notebooks: the printed closed forms evaluated with numpy, and the
motors' work, so each notebook can check the compiled code against its own equations.

The text form of ``planar_sym.equations(robot)`` is Python syntax (``c2*qdd1 + beta*s2*qd1**2``):
with every symbol valued (the symbol table names the robot parameter behind each), the joint
variables as arrays and the notation's ``c12 = cos(q1 + q2)`` evaluated, ``eval`` computes any
printed equation over a whole motion.
"""

from __future__ import annotations

import re

import numpy as np

import planar_sym as ps

#: one entry of the notation line: c12 = cos(q1 + q2) (the line may wrap anywhere)
NOTATION = re.compile(r"\b([cs]\d+)\s+=\s+(cos|sin)\(([^)]*)\)")


def namespace(robot: ps.Robot, q, qd=None, qdd=None) -> dict:
    """Every name the printed equations use, valued.

    Parameters
    ----------
    robot : planar_sym.Robot
        Its parameters (SI) value the equations' symbols (``m_2`` is ``m_link2``, ...).
    q, qd, qdd : ndarray, shape (N, n)
        Coordinates (rad, or m for a slider), their rates and accelerations (SI).

    Returns
    -------
    dict
        Symbol -> float; ``q1``, ``qd1``, ``qdd1``, ``c1``, ``s12``, ... -> ndarray (N,).
    """
    text = ps.equations(robot.name).text
    ns: dict = {}
    table = text.split("\nSymbols (", 1)[1].split("\n\n", 1)[0].splitlines()[1:]
    for line in table:
        symbol, *rest = line.split()
        ns[symbol] = next(robot.parameters[w] for w in rest if w in robot.parameters)
    for name, arr in (("q", q), ("qd", qd), ("qdd", qdd)):
        if arr is not None:
            ns.update({f"{name}{k + 1}": np.asarray(arr)[:, k] for k in range(robot.n)})
    for short, fn, arg in NOTATION.findall(" ".join(text.split())):
        ns[short] = getattr(np, fn)(eval(arg, {}, ns))
    return ns


def evaluate(robot: ps.Robot, section: str, ns: dict) -> dict:
    """Every ``label = right-hand side`` of one section of the printed equations (the first
    whose heading starts with ``section``, e.g. "Gravity terms"), evaluated in order (later ones
    may use earlier ones) into ``ns``; returns {label: value}."""
    sections = ps.equations(robot.name).sections()
    heading = next(h for h in sections if h.startswith(section))
    out = {}
    for label, rhs in sections[heading].items():
        out[label] = ns[label] = eval(rhs, {}, ns)
    return out


def motor_work(result) -> float:
    """Work (J) the actuators do over a study: the integral of sum_k tau_k qd_k dt, from the
    result's torque and rate columns (Simpson's rule: its error, like the power's fourth
    derivative times the step^4, is far below the numbers compared)."""
    from scipy.integrate import simpson

    t = result.columns["t_s"]
    power = sum(result.columns[col] * result.columns[f"qd{col[3:].split('_')[0]}_rad_s"]
                for col in result.torques())
    return float(simpson(power, x=t))


def energy_change(robot: ps.Robot, result) -> float:
    """Kinetic plus potential energy (J) at the end of a study minus at its start, from the
    compiled energy function (not from the torques)."""
    q, qd = joints(robot, result, "q"), joints(robot, result, "qd")
    kinetic, potential = robot.energy(q[[0, -1]], qd[[0, -1]])
    return float((kinetic[1] + potential[1]) - (kinetic[0] + potential[0]))


def joints(robot: ps.Robot, result, kind: str = "q") -> np.ndarray:
    """One of the result's joint arrays, shape (N, n): ``kind`` q (rad), qd (rad/s) or qdd
    (rad/s^2)."""
    suffix = {"q": "rad", "qd": "rad_s", "qdd": "rad_s2"}[kind]
    return np.column_stack([result.columns[f"{kind}{k + 1}_{suffix}"] for k in range(robot.n)])
