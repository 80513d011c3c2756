"""Properties of random valid robots, and of random runtime inputs.

1. ``test_random_serial_robots`` (Hypothesis, ``ROBOT_EXAMPLES`` examples, each derives and
   compiles a robot, about 1-2 s): a random serial arm of 1-3 links (lengths 0.05-0.3 m, masses
   0.05-1 kg, centre of gravity on or off the link axis, a plausible izz, an optional welded
   point-mass motor, optional tilted gravity, random drawn angles and units) is derived with
   ``python -m derive`` into a temporary folder, compiled into a private cache and loaded; then

   * M(q) and g(q) equal an independent evaluation (sum over bodies of m Jv^T Jv + I Jw^T Jw,
     and -sum m Jv^T g, written here from the description), M symmetric positive definite at
     random q (both compiled copies, fast and exact);
   * energy is conserved in a 1 s free swing (``simulate``, relative drift < 1e-8);
   * power balance along a random smooth joint motion: sum tau_i qd_i = dE/dt, dE/dt from the
     compiled energy by 4th-order central differences (relative 1e-7);
   * forward(inverse) is the identity: forward_dynamics(q, qd, inverse_dynamics(q, qd, qdd)) =
     qdd (relative 1e-9).

2. ``test_random_runtime_inputs`` (Hypothesis, ``INPUT_EXAMPLES`` examples, milliseconds each):
   arrays of random shapes (0-3 dimensions), dtypes and containers (float64, float32, int,
   non-contiguous views, nested lists), with NaN and inf sprinkled in, fed to every array method
   of a built-in tree (serial_2dof) and closed chain (five_bar_type1), fast and exact paths: either
   the right result (equal to a sample-by-sample evaluation on clean float64 input) or an
   InputError; never another exception, never a crash.
"""

from __future__ import annotations

import itertools
import math
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import planar_sym as ps
from planar_sym.errors import InputError
from planar_sym.model.description import ZERO_SNAP_M
from planar_sym.model.robot import Robot

ROBOT_EXAMPLES = 8
INPUT_EXAMPLES = int(os.environ.get("PLANAR_SYM_FUZZ_CASES") or 300)  # more for a long run

# -- 1. random valid serial robots ------------------------------------------------------------------

LENGTH_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}
MASS_UNITS = {"kg": 1.0, "g": 1e-3}
INERTIA_UNITS = {"kg*m^2": 1.0, "kg*mm^2": 1e-6, "g*cm^2": 1e-7}


def _f(x: float) -> str:
    return repr(float(x))


@st.composite
def serial_robots(draw):
    """A random valid serial arm: (TOML text, the same robot as plain SI numbers)."""
    n = draw(st.integers(1, 3))
    unit = {"length": draw(st.sampled_from(sorted(LENGTH_UNITS))),
            "mass": draw(st.sampled_from(sorted(MASS_UNITS))),
            "inertia": draw(st.sampled_from(sorted(INERTIA_UNITS)))}
    lu, mu, iu = (LENGTH_UNITS[unit["length"]], MASS_UNITS[unit["mass"]],
                  INERTIA_UNITS[unit["inertia"]])
    def real(lo, hi):  # no subnormals: a process in flush-to-zero mode cannot make them
        return st.floats(lo, hi, allow_subnormal=False)

    links = []
    start = np.zeros(2)
    for i in range(n):
        length = draw(real(0.05, 0.3))
        theta = draw(real(-math.pi, math.pi))
        mass = draw(real(0.05, 1.0))
        along = draw(real(0.1, 0.9)) * length
        off = draw(st.sampled_from([0.0, None]))
        off = draw(real(-0.3, 0.3)) * length if off is None else 0.0
        izz = mass * length**2 * draw(real(0.01, 0.3))
        end = start + length * np.array([math.cos(theta), math.sin(theta)])
        links.append({"length": length, "theta": theta, "mass": mass, "cg": (along, off),
                      "izz": izz, "start": start, "end": end})
        start = end
    motor = draw(st.none() | st.tuples(st.integers(0, n - 1), real(0.05, 0.5),
                                       st.sampled_from([0.0, 1e-6, 2e-5])))
    tilt = draw(st.sampled_from([0.0, None]))
    tilt = draw(real(-1.0, 1.0)) if tilt is None else 0.0
    gravity = 9.81 * np.array([math.sin(tilt), -math.cos(tilt)])

    def pt(xy):
        return f"[{_f(xy[0] / lu)}, {_f(xy[1] / lu)}]"

    text = ['name = "{name}"', f"gravity = [{_f(gravity[0])}, {_f(gravity[1])}]", "",
            "[units]", f'length = "{unit["length"]}"', f'mass = "{unit["mass"]}"',
            f'inertia = "{unit["inertia"]}"', 'angle = "rad"', 'acceleration = "m/s^2"', "",
            "[ground]", "points = { O = [0.0, 0.0] }"]
    for i, ln in enumerate(links, 1):
        c, s = math.cos(ln["theta"]), math.sin(ln["theta"])
        a, b = ln["cg"]
        cg_world = (a * c - b * s, a * s + b * c)  # relative to CS1, world axes
        text += ["", "[[bodies]]", f'name = "link{i}"', f"mass = {_f(ln['mass'] / mu)}",
                 f"izz = {_f(ln['izz'] / iu)}", f"cg = {pt(cg_world)}", 'cg_from = "CS1"',
                 f"points = {{ CS1 = {pt(ln['start'])}, CS2 = {pt(ln['end'])} }}",
                 'frame = ["CS1", "CS2"]']
    if motor is not None:
        k, m_mass, m_izz = motor
        text += ["", "[[bodies]]", 'name = "motor"', f"mass = {_f(m_mass / mu)}",
                 f"izz = {_f(m_izz / iu)}", "cg = [0.0, 0.0]", 'cg_from = "CS1"',
                 f"points = {{ CS1 = {pt(links[k]['end'])} }}"]
    for i in range(1, n + 1):
        parent = "ground.O" if i == 1 else f"link{i - 1}.CS2"
        text += ["", "[[joints]]", f'name = "q{i}"', 'type = "revolute"', f'parent = "{parent}"',
                 f'child = "link{i}.CS1"', "actuated = true"]
    if motor is not None:
        text += ["", "[[joints]]", 'name = "weld_motor"', 'type = "weld"',
                 f'parent = "link{motor[0] + 1}.CS2"', 'child = "motor.CS1"']
    text += ["", "[task]", f'point = "link{n}.CS2"', ""]
    return "\n".join(text), {"links": links, "motor": motor, "gravity": gravity}


def independent_mass_and_gravity(model: dict, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """M(q) = sum m Jv^T Jv + I Jw^T Jw and g(q) = -sum m Jv^T g_vec, from the description.

    The coordinate of joint i is link i's angle minus link i-1's (drawn frames along the links),
    so link k's absolute angle is phi_k = sum_{j<=k} q_j; positions are sums of rotated
    link-frame vectors: r_cg,k = sum_{i<k} R(phi_i) (L_i, 0) + R(phi_k) c_k.
    """
    links, n = model["links"], len(model["links"])
    phi = np.cumsum(q)
    # the description rule: a body-frame coordinate under ZERO_SNAP_M (1e-12 m) is an exact
    # zero (the strategy can draw a 5e-13 m centre-of-gravity offset; dropping it moves M by
    # ~1e-12 relative, which is what this comparison measures)
    links = [{**ln, "cg": tuple(0.0 if abs(c) < ZERO_SNAP_M else c for c in ln["cg"])}
             for ln in links]

    def rot90(v, a):  # d/da of R(a) v
        return np.array([-math.sin(a) * v[0] - math.cos(a) * v[1],
                         math.cos(a) * v[0] - math.sin(a) * v[1]])

    def jac(vectors):  # vectors: [(link index, body-frame vector)], summed
        J = np.zeros((2, n))
        for k, v in vectors:
            d = rot90(v, phi[k])
            J[:, :k + 1] += d[:, None]
        return J

    M = np.zeros((n, n))
    g = np.zeros(n)
    bodies = [(k, ln["mass"], ln["izz"], [(i, (links[i]["length"], 0.0)) for i in range(k)]
               + [(k, ln["cg"])]) for k, ln in enumerate(links)]
    if model["motor"] is not None:
        k, m, izz = model["motor"]
        bodies.append((k, m, izz, [(i, (links[i]["length"], 0.0)) for i in range(k + 1)]))
    for k, m, izz, vectors in bodies:
        Jv = jac(vectors)
        Jw = np.zeros(n)
        Jw[:k + 1] = 1.0
        M += m * Jv.T @ Jv + izz * np.outer(Jw, Jw)
        g -= m * Jv.T @ model["gravity"]
    return M, g


def rel(a, b) -> float:
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


@pytest.fixture(scope="module")
def workshop(tmp_path_factory):
    """A folder for derived robots and a private compiled-library cache for this module."""
    return (tmp_path_factory.mktemp("hyp_robots"), tmp_path_factory.mktemp("hyp_cache"),
            itertools.count())


@pytest.mark.slow
@settings(max_examples=ROBOT_EXAMPLES, deadline=None, derandomize=False,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow,
                                 HealthCheck.data_too_large])
@given(robot=serial_robots(), seed=st.integers(0, 2**32 - 1))
def test_random_serial_robots(workshop, robot, seed):
    from derive.__main__ import main as derive_main

    out, cache, counter = workshop
    text, model = robot
    name = f"hyp{next(counter)}"
    toml = out / f"{name}.toml"
    toml.write_text(text.replace("{name}", name))
    assert derive_main([str(toml), "--out", str(out), "--quiet"]) == 0
    with pytest.MonkeyPatch.context() as mp:  # compiled into the private cache
        mp.setenv("PLANAR_SYM_CACHE", str(cache))
        fast = ps.load(out / name)
    assert fast.library.path.parent == cache
    exact = Robot(name, fast.library, exact=True)
    n = fast.n
    assert n == len(model["links"])
    rng = np.random.default_rng(seed)

    # M symmetric positive definite, and M, g equal the independent evaluation
    q = rng.uniform(-np.pi, np.pi, (20, n))
    for robot_ in (fast, exact):
        M = robot_.mass_matrix(q)
        assert np.max(np.abs(M - M.transpose(0, 2, 1))) <= 1e-14 * np.max(np.abs(M))
        assert np.all(np.linalg.eigvalsh(M)[:, 0] > 0)
        np.linalg.cholesky(M)
        G = robot_.gravity(q)
        for k in range(len(q)):
            M_ref, g_ref = independent_mass_and_gravity(model, q[k])
            assert rel(M[k], M_ref) < 1e-12, (k, M[k], M_ref)
            assert rel(G[k], g_ref) < 1e-12, (k, G[k], g_ref)

    # energy in a 1 s free swing
    q0, qd0 = rng.uniform(-np.pi, np.pi, n), rng.uniform(-2.0, 2.0, n)
    swing = ps.simulate(fast, q0, qd0, (0.0, 1.0))
    assert swing.energy_drift < 1e-8, swing.energy_drift

    # power balance along q(t) = c + a sin(w t + p)
    c, a = rng.uniform(-np.pi, np.pi, n), rng.uniform(0.2, 1.5, n)
    w, p = rng.uniform(0.5, 4.0, n), rng.uniform(0, 2 * np.pi, n)

    def motion(t):
        t = np.asarray(t, float)[:, None]
        return (c + a * np.sin(w * t + p), a * w * np.cos(w * t + p),
                -a * w**2 * np.sin(w * t + p))

    t = np.linspace(0.0, 1.0, 101)
    qt, qdt, qddt = motion(t)
    tau = fast.inverse_dynamics(qt, qdt, qddt)
    power = np.sum(tau * qdt, axis=1)
    h = 1e-3

    def energy(tt):
        kin, pot = fast.energy(*motion(tt)[:2])
        return kin + pot

    de = (-energy(t + 2 * h) + 8 * energy(t + h) - 8 * energy(t - h) + energy(t - 2 * h)) / (12 * h)
    scale = np.max(np.sum(np.abs(tau * qdt), axis=1))
    assert np.max(np.abs(power - de)) < 1e-7 * scale, np.max(np.abs(power - de)) / scale

    # forward(inverse) is the identity
    qd, qdd = rng.uniform(-3, 3, (50, n)), rng.uniform(-5, 5, (50, n))
    q = rng.uniform(-np.pi, np.pi, (50, n))
    for robot_ in (fast, exact):
        back = robot_.forward_dynamics(q, qd, robot_.inverse_dynamics(q, qd, qdd))
        assert np.max(np.abs(back - qdd) / np.max(np.abs(qdd), axis=1, keepdims=True)) < 1e-9


# -- 2. random runtime inputs to a built-in robot ---------------------------------------------------

METHODS = {  # name: number of per-sample arrays
    "serial_2dof": {"mass_matrix": 1, "bias": 2, "gravity": 1, "inverse_dynamics": 3,
                    "tree_inverse_dynamics": 3, "forward_dynamics": 3, "energy": 2, "task": 2,
                    "frames": 1},
    "five_bar_type1": {"mass_matrix": 1, "bias": 2, "gravity": 1, "tree_inverse_dynamics": 3,
                       "energy": 2, "frames": 1, "constraint": 1, "constraint_jacobian": 1,
                       "constraint_bias": 2},
}
_ROBOTS: dict[tuple[str, bool], Robot] = {}


def _robot(name: str, exact: bool) -> Robot:
    if (name, exact) not in _ROBOTS:
        base = ps.load(name)
        _ROBOTS[name, exact] = Robot(name, base.library, exact=exact) if exact else base
    return _ROBOTS[name, exact]


@st.composite
def array_arguments(draw, n: int, count: int):
    """``count`` arguments: (the object passed, its float64 value or None if not an array)."""
    # half the time well-shaped (one ndim, width n, one N), else each argument on its own
    N = draw(st.integers(0, 4))
    shaped = draw(st.booleans())
    common = draw(st.sampled_from([1, 2, 2]))
    args = []
    for _ in range(count):
        if shaped:
            ndim, width, rows = common, n, N
        else:
            ndim = draw(st.sampled_from([2, 2, 2, 1, 1, 0, 3]))
            width = n if draw(st.integers(0, 5)) else draw(st.integers(0, n + 2))
            rows = N if draw(st.integers(0, 6)) else draw(st.integers(0, 4))
        shape = {0: (), 1: (width,), 2: (rows, width), 3: (2, rows, width)}[ndim]
        size = int(np.prod(shape))
        values = draw(st.lists(st.floats(-10, 10, allow_nan=False, allow_subnormal=False),
                               min_size=size, max_size=size))
        arr = np.array(values, dtype=float).reshape(shape)
        if size and draw(st.integers(0, 4)) == 0:  # sprinkle NaN / inf
            for _ in range(draw(st.integers(1, 3))):
                idx = np.unravel_index(draw(st.integers(0, size - 1)), shape)
                arr[idx] = draw(st.sampled_from([np.nan, np.inf, -np.inf]))
        kind = draw(st.sampled_from(["f64", "f64", "f32", "int", "list", "int_list", "view",
                                     "fortran"] + ([] if shaped else ["scalar"])))
        if kind == "f32":
            obj = arr.astype(np.float32)
        elif kind == "int":
            obj = np.nan_to_num(arr, nan=1, posinf=2, neginf=-2).astype(np.int64)
        elif kind == "list":
            obj = arr.tolist()
        elif kind == "int_list":
            obj = np.nan_to_num(arr, nan=1, posinf=2, neginf=-2).astype(int).tolist()
        elif kind == "view" and arr.ndim >= 1:
            big = np.repeat(arr, 2, axis=-1)  # every other column: not contiguous
            obj = big[..., ::2]
        elif kind == "fortran":
            obj = np.asfortranarray(arr)
        elif kind == "scalar":
            obj = float(arr.flat[0]) if arr.size else 0.5
        else:
            obj = arr
        args.append(obj)
    return args


def _valid(args, n: int) -> bool | None:
    """True: well-formed (all (n,) or all (N, n) alike, finite); False: must be refused; None:
    either is fine (a mix of (n,) and (1, n), which the two paths treat differently)."""
    arrays = [np.asarray(a, dtype=float) for a in args]
    if any(a.ndim not in (1, 2) or a.shape[-1] != n for a in arrays):
        return False
    if len({a.shape[0] if a.ndim == 2 else 1 for a in arrays}) != 1:
        return False
    if not all(np.all(np.isfinite(a)) for a in arrays):
        return False
    if len({a.ndim for a in arrays}) != 1:
        return None
    return True


@settings(max_examples=INPUT_EXAMPLES, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(data=st.data())
def test_random_runtime_inputs(data):
    name = data.draw(st.sampled_from(sorted(METHODS)))
    exact = data.draw(st.booleans())
    robot = _robot(name, exact)
    method = data.draw(st.sampled_from(sorted(METHODS[name])))
    args = data.draw(array_arguments(robot.n, METHODS[name][method]))
    valid = _valid(args, robot.n)
    event({True: "well-formed", False: "must be refused", None: "(n,) mixed with (1, n)"}[valid])
    try:
        result = getattr(robot, method)(*args)
    except InputError as exc:
        assert valid is not True, f"refused well-formed input: {exc}"
        return
    except Exception as exc:  # the property: nothing else
        raise AssertionError(f"{type(exc).__name__} from {name}.{method} "
                             f"({'exact' if exact else 'fast'}): {exc}") from exc
    assert valid is not False, f"accepted bad input {args!r}"
    # the right result: each sample evaluated alone on clean float64 input, exact path
    clean = [np.ascontiguousarray(np.asarray(a, dtype=float)) for a in args]
    single = clean[0].ndim == 1 and all(a.ndim == 1 for a in clean)
    rows = [a if a.ndim == 2 else a[None] for a in clean]
    ref_robot = _robot(name, True)
    outs = result if isinstance(result, tuple) else (result,)
    for k in range(rows[0].shape[0]):
        ref = getattr(ref_robot, method)(*[r[k] for r in rows])
        refs = ref if isinstance(ref, tuple) else (ref,)
        for out, r in zip(outs, refs):
            got = np.asarray(out) if single else np.asarray(out)[k]
            np.testing.assert_allclose(got, r, rtol=1e-12, atol=1e-12)
    if rows[0].shape[0] == 0:
        assert all(np.asarray(o).shape[0] == 0 for o in outs)


# -- bugs found here and fixed: each test keeps the behaviour -----------------------------------------

@pytest.mark.parametrize("value", ["ab", [[1, 2], [3]], {"q": 1}, [10**400, 0]],
                         ids=["string", "ragged", "dict", "huge_int"])
def test_fixed_bug_exact_path_non_numeric_input(value):
    robot = Robot("serial_2dof", ps.load("serial_2dof").library, exact=True)
    try:
        robot.mass_matrix(value)
    except InputError:
        return
    except Exception as exc:
        raise AssertionError(f"{type(exc).__name__}: {exc}") from exc


def test_fixed_bug_fast_path_keyword_arguments():
    robot = ps.load("serial_2dof")
    z = np.zeros(2)
    exact = Robot("serial_2dof", robot.library, exact=True)
    # keywords work on both paths; fast and exact agree to rounding (fast math)
    np.testing.assert_allclose(robot.inverse_dynamics(q=z, qd=z, qdd=z),
                               exact.inverse_dynamics(q=z, qd=z, qdd=z), rtol=1e-12)


def test_fixed_bug_two_dimensional_parameters_accepted():
    base = ps.load("serial_2dof")
    p = np.vstack([base.p, 2 * base.p])
    try:
        Robot("serial_2dof", base.library, parameters=p)
    except InputError:
        return
    raise AssertionError("a (2, 11) parameter array was accepted")


def test_environment_is_unchanged():
    """The module fixture's private cache does not leak into later tests."""
    assert "hyp_cache" not in os.environ.get("PLANAR_SYM_CACHE", "")
    assert Path(ps.load("serial_2dof").library.path).exists()
