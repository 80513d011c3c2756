"""Finite Fourier series per actuated joint (Swevers' form): periodic, so an excitation can be
repeated and averaged, with rates and accelerations in closed form.

.. code:: text

    q_j(t)   = q0_j + sum_l  a_jl / (w l) sin(w l t) - b_jl / (w l) cos(w l t)
    qd_j(t)  =        sum_l  a_jl cos(w l t) + b_jl sin(w l t)
    qdd_j(t) =        sum_l  w l (-a_jl sin(w l t) + b_jl cos(w l t))

``w = 2 pi / period``; a_jl, b_jl in rad/s (m/s at a slider).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class FourierMotion:
    """``q0`` (joints,), ``a``, ``b`` (joints, harmonics) in rad and rad/s, ``period_s``."""

    q0: np.ndarray
    a: np.ndarray
    b: np.ndarray
    period_s: float

    def __call__(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q, qd, qdd), each (N, joints), at times ``t`` (N,) in s."""
        return self.at(basis(t, self.period_s, self.a.shape[1]))

    def at(self, base: tuple[np.ndarray, np.ndarray, np.ndarray]):
        """(q, qd, qdd) from ``basis(t, period_s, harmonics)``: the sines and cosines computed
        once for many coefficient sets (an optimiser's)."""
        s, c, wl = base
        q = self.q0 + s @ (self.a / wl).T - c @ (self.b / wl).T
        qd = c @ self.a.T + s @ self.b.T
        qdd = -s @ (self.a * wl).T + c @ (self.b * wl).T
        return q, qd, qdd

    @property
    def vector(self) -> np.ndarray:
        """a and b flattened: what an optimiser varies."""
        return np.concatenate([self.a.ravel(), self.b.ravel()])

    def with_vector(self, x) -> FourierMotion:
        a, b = np.split(np.asarray(x, dtype=float), 2)
        return FourierMotion(self.q0, a.reshape(self.a.shape), b.reshape(self.b.shape),
                             self.period_s)


def basis(t, period_s: float, harmonics: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """sin(w l t), cos(w l t), each (N, harmonics), and w l (harmonics,) in rad/s."""
    t = np.asarray(t, dtype=float)
    wl = 2 * np.pi / period_s * np.arange(1, harmonics + 1)
    return np.sin(np.outer(t, wl)), np.cos(np.outer(t, wl)), wl
