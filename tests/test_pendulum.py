"""An analytic case end to end: tests/robots/pendulum.toml -> derive -> compile -> runtime.

q is measured from +x, counter-clockwise; gravity along -y; J = izz + m l^2 about the pivot:

    M = J,  g(q) = m g l cos q,  qdd = (tau - m g l cos q) / J,
    T = J qd^2 / 2,  V = m g l sin q,
    small oscillations about q = -pi/2: period 2 pi sqrt(J / m g l)
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import TEST_ROBOTS, record, rel_err
from scipy.integrate import solve_ivp

from derive.__main__ import main as derive_main
from planar_sym.model.library import Library
from planar_sym.model.robot import Robot

TOL = 1e-12
N = 40
m, izz, l, g0, tip = 1.5, 0.02, 0.25, 9.81, 0.4
J = izz + m * l**2


@pytest.fixture(scope="module")
def pendulum(tmp_path_factory):
    out = tmp_path_factory.mktemp("generated")
    cache = tmp_path_factory.mktemp("cache")
    assert derive_main([str(TEST_ROBOTS / "pendulum.toml"), "--out", str(out), "--quiet"]) == 0
    manifest = json.loads((out / "pendulum" / "manifest.json").read_text())
    assert sorted(p.name for p in (out / "pendulum").iterdir()) == sorted(
        [*manifest["files"], "manifest.json"])  # exactly the files the manifest vouches for
    assert {"pendulum.c", "pendulum.h"} <= set(manifest["files"])
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("PLANAR_SYM_CACHE", str(cache))  # keep the test robot out of the user's cache
        return Robot("pendulum", Library("pendulum", folder=out / "pendulum"))


@pytest.fixture
def states():
    rng = np.random.default_rng(11)
    return rng.uniform(-np.pi, np.pi, (N, 1)), rng.uniform(-5, 5, (N, 1)), \
        rng.uniform(-3, 3, (N, 1))


def per_sample(a) -> np.ndarray:
    """(N, ...) -> (N, size): the values only; the shapes are checked by test_output_shapes."""
    a = np.asarray(a)
    return a.reshape(a.shape[0], -1) if a.ndim else a.reshape(1, 1)


def test_output_shapes(pendulum, states):
    """The documented shapes hold for n = 1 as for any n: M (N, n, n), g (N, n), J (N, 2, n)."""
    q, qd, qdd = states
    shapes = {
        "M": pendulum.mass_matrix(q).shape, "g": pendulum.gravity(q).shape,
        "h": pendulum.bias(q, qd).shape, "tau": pendulum.inverse_dynamics(q, qd, qdd).shape,
        "qdd": pendulum.forward_dynamics(q, qd, qdd).shape, "J": pendulum.task(q, qd)[1].shape,
        "M one sample": np.shape(pendulum.mass_matrix(q[0])),
        "g one sample": np.shape(pendulum.gravity(q[0])),
    }
    assert shapes == {"M": (N, 1, 1), "g": (N, 1), "h": (N, 1), "tau": (N, 1), "qdd": (N, 1),
                      "J": (N, 2, 1), "M one sample": (1, 1), "g one sample": (1,)}


def test_parameters(pendulum):
    assert pendulum.coordinates == ("pivot",)
    assert pendulum.parameters == {"g": g0, "m_rod": m, "izz_rod": izz, "cgx_rod": l,
                                   "px_rod_CS2": tip}


def test_mass_matrix_and_gravity(pendulum, states, worst_errors):
    q, qd, _ = states
    M = per_sample(pendulum.mass_matrix(q))
    assert record(worst_errors, "pendulum M", rel_err(M, np.full((N, 1), J))) < TOL
    G = per_sample(pendulum.gravity(q))
    assert record(worst_errors, "pendulum g", rel_err(G, m * g0 * l * np.cos(q))) < TOL
    # no velocity terms for one rotating body: h = g
    assert record(worst_errors, "pendulum h", rel_err(per_sample(pendulum.bias(q, qd)), G)) < TOL


def test_forward_and_inverse_dynamics(pendulum, states, worst_errors):
    q, qd, tau = states
    free = per_sample(pendulum.forward_dynamics(q, qd, np.zeros_like(q)))
    assert record(worst_errors, "pendulum qdd free",
                  rel_err(free, -m * g0 * l * np.cos(q) / J)) < TOL
    driven = per_sample(pendulum.forward_dynamics(q, qd, tau))
    assert record(worst_errors, "pendulum qdd driven",
                  rel_err(driven, (tau - m * g0 * l * np.cos(q)) / J)) < TOL
    back = per_sample(pendulum.inverse_dynamics(q, qd, driven))
    assert record(worst_errors, "pendulum tau round trip", rel_err(back, tau)) < 1e-12


def test_energy_and_task(pendulum, states, worst_errors):
    q, qd, _ = states
    T, V = pendulum.energy(q, qd)
    assert record(worst_errors, "pendulum T", rel_err(T, 0.5 * J * qd[:, 0] ** 2)) < TOL
    assert record(worst_errors, "pendulum V", rel_err(V, m * g0 * l * np.sin(q[:, 0]))) < TOL
    x, Jac, jdq = pendulum.task(q, qd)
    c, s = np.cos(q[:, 0]), np.sin(q[:, 0])
    assert rel_err(x, tip * np.stack([c, s], -1)) < TOL
    assert rel_err(per_sample(Jac), tip * np.stack([-s, c], -1)) < TOL
    assert rel_err(jdq, -tip * qd**2 * np.stack([c, s], -1)) < TOL


def test_linearisation_about_the_hanging_pose(pendulum, worst_errors):
    """d qdd / dq at q = -pi/2 is -m g l / J (the squared natural frequency)."""
    q = np.array([[-math.pi / 2]])
    raw = pendulum.library.functions["forward_dynamics_jacobian"](
        1, {"q": q, "qd": np.zeros((1, 1)), "tau": np.zeros((1, 1)), "p": pendulum.p})
    # (d qdd / d qd is structurally zero here and not written by the C code: see the
    # sparse-output bug in test_codegen_vs_sympy.py)
    dq = per_sample(raw["dqdd_dq"])[0, 0]
    err = record(worst_errors, "pendulum omega^2", abs(dq + m * g0 * l / J) / (m * g0 * l / J))
    assert err < TOL



def test_small_oscillation_period(pendulum, worst_errors):
    """Integrate the compiled forward dynamics; the period matches 2 pi sqrt(J / m g l)."""
    amp = 1e-3
    omega = math.sqrt(m * g0 * l / J)
    # finite-amplitude correction of the pendulum period: (1 + amp^2 / 16 + ...)
    period = 2 * math.pi / omega * (1 + amp**2 / 16)

    def rhs(_t, y):
        qdd = pendulum.forward_dynamics(y[None, :1], y[None, 1:], [[0.0]])
        return [y[1], float(per_sample(qdd)[0, 0])]

    def upward(_t, y):
        return y[0] + math.pi / 2
    upward.direction = 1.0

    sol = solve_ivp(rhs, (0.0, 3.2 * period), [-math.pi / 2 - amp, 0.0], method="DOP853",
                    rtol=1e-12, atol=1e-15, events=upward)
    crossings = sol.t_events[0]
    assert len(crossings) == 3
    measured = float(np.mean(np.diff(crossings)))
    err = record(worst_errors, "pendulum period", abs(measured - period) / period)
    assert err < 1e-8
    # the energy is conserved along the way
    T, V = pendulum.energy(sol.y[:1].T, sol.y[1:].T)
    assert np.ptp(T + V) < 1e-6 * np.max(T)  # exchanged energy ~1.8e-6 J, kept to 1e-12 J
