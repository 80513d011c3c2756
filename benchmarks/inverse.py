"""Section 1: inverse dynamics through the public API, per call and per sample over N samples.

Measured: ``Robot.inverse_dynamics`` (serial arms) and ``Robot.closed_chain_inverse_dynamics``
(closed chains: torques and loop forces, including its condition-number checks) exactly as a
user calls them, allocation of the result included. Baselines, each checked against planar_sym
to 1e-9 (worst per-sample normwise relative error) before it is timed:

* ``pinocchio.rnea`` and MuJoCo ``mj_inverse`` in a Python loop (serial arms): what a user of
  those libraries writes to get torques along a trajectory;
* SymPy ``lambdify`` (numpy, ``cse=True``) of ``M qdd + h``, vectorised over whole columns:
  the same equations, uncompiled (for closed chains: the tree part only);
* the plain-C floor: hand-written closed form, structure of arrays, ``-O3 -march=native
  -ffast-math`` (SIMD sin/cos), preallocated outputs, one ctypes call: what it costs at best.

For one sample, planar_sym's internal ``library.SingleCall`` (the same compiled function with
pointers bound once, as the integrators use it) is timed too: the difference to the public call
is the price of its input checks and ``ctypes`` argument conversion.

States: serial arms uniform random (q in [-pi, pi], qd and qdd in [-3, 3]); closed chains the
joint motion of their ``*_move_x`` scenario from the closed-form IK (N samples along the path;
above 1e5 samples, the 1e5-sample path repeated), so the loop constraints hold.
"""

from __future__ import annotations

import numpy as np

from planar_sym.model.library import SingleCall

from . import CLOSED, SERIAL, Config
from .report import Check, Section, Table
from .timing import interleaved, ratio

GATE = 1e-9
PS = "planar_sym"


def rel_err(a, b) -> float:
    """Worst per-sample normwise relative error (as tests/conftest.py's ``rel_err``)."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    return float(np.max(np.max(np.abs(a - b), axis=1) / np.maximum(np.max(np.abs(b), axis=1),
                                                                   1e-300)))


def serial_states(n: int, size: int, seed: int = 1):
    rng = np.random.default_rng(seed)
    return (rng.uniform(-np.pi, np.pi, (size, n)), rng.uniform(-3, 3, (size, n)),
            rng.uniform(-3, 3, (size, n)))


def closed_states(robot, size: int):
    from planar_sym.study.motion import joint_motion
    from planar_sym.study.run import load_study

    st = load_study(f"{robot.name}_move_x")
    base = min(size, 100_000)
    jt, _ = joint_motion(st, robot, t=np.linspace(0.0, st.motion.duration_s, base))
    reps = -(-size // base)
    return tuple(np.ascontiguousarray(np.tile(a, (reps, 1))[:size]) for a in (jt.q, jt.qd, jt.qdd))


def _fmt_n(n: int) -> str:
    return f"1e{int(np.log10(n))}" if n >= 1000 and 10 ** int(np.log10(n)) == n else str(n)


def exact_twin(robot):
    """The same robot on planar_sym's exact path (``exact=True``: CasADi's per-sample C, no
    fast math), or None where this planar_sym version has a single path."""
    import inspect

    from planar_sym.model.robot import Robot

    if "exact" not in inspect.signature(Robot).parameters:
        return None
    return Robot(robot.name, robot.library, exact=True)


class Serial:
    """One serial arm with every baseline built and checked."""

    def __init__(self, name: str, section: Section, symbolic):
        import pinocchio as pin

        from planar_sym import load
        from planar_sym.model import description

        from .baselines import cfloor, mujoco_model, pinocchio_model

        self.name, self.robot = name, load(name)
        self.exact = exact_twin(self.robot)
        desc = description.load(name)
        self.pin = pin
        self.pmodel, self.pdata = pinocchio_model.build(desc)
        self.mmodel, self.mdata = mujoco_model.build(desc)
        self.floor = cfloor.compile_floor(name, self.robot.parameters)
        self.sym = symbolic
        q, qd, qdd = serial_states(self.robot.n, 256, seed=99)
        ref = self.robot.inverse_dynamics(q, qd, qdd)
        got = {
            "pinocchio.rnea": pinocchio_model.rnea_loop(self.pmodel, self.pdata, q, qd, qdd),
            "MuJoCo mj_inverse": mujoco_model.inverse_loop(self.mmodel, self.mdata, q, qd, qdd),
            "C floor": self.floor(q, qd, qdd),
            "SymPy lambdify": self.sym.inverse_dynamics(q, qd, qdd),
        }
        self.ok = {}
        for what, tau in got.items():
            check = Check(f"{name}: {what} vs planar_sym inverse dynamics (256 random states)",
                          rel_err(tau, ref), GATE)
            section.checks.append(check)
            self.ok[what] = check.ok
        section.notes.append(
            f"{name} C floor: `{self.floor.command}`; vectorised with libmvec: "
            + (", ".join(f"`{s}`" for s in self.floor.vector_math) or "**no**"))

    def single(self) -> dict:
        """Callables for one sample with 1-D arrays."""
        import mujoco

        q, qd, qdd = (a[0] for a in serial_states(self.robot.n, 1, seed=5))
        m, d = self.mmodel, self.mdata
        qpos, qvel, qacc, frc = d.qpos, d.qvel, d.qacc, d.qfrc_inverse
        inverse = mujoco.mj_inverse

        def mj_one():
            qpos[:] = q
            qvel[:] = qd
            qacc[:] = qdd
            inverse(m, d)
            return frc.copy()

        cols, outs = self.floor.soa(q[None], qd[None], qdd[None]), self.floor.outputs(1)
        p = self.sym.p
        bound = SingleCall(self.robot.library.functions["inverse_dynamics"], self.robot.p)
        fns = {PS: lambda: self.robot.inverse_dynamics(q, qd, qdd),
               "exact": lambda: self.exact.inverse_dynamics(q, qd, qdd),
               "SingleCall": lambda: bound(q, qd, qdd)[0].copy(),
               "pinocchio.rnea": lambda: self.pin.rnea(self.pmodel, self.pdata, q, qd, qdd),
               "MuJoCo mj_inverse": mj_one,
               "SymPy lambdify": lambda: np.array(self.sym._tau(*q, *qd, *qdd, *p)),
               "C floor": self.floor.bind(cols, outs)}
        return {k: f for k, f in fns.items()
                if self.ok.get(k, True) and (k != "exact" or self.exact is not None)}

    def batch(self, size: int, loop_max_n: int) -> dict:
        from .baselines import mujoco_model, pinocchio_model

        q, qd, qdd = serial_states(self.robot.n, size)
        cols, outs = self.floor.soa(q, qd, qdd), self.floor.outputs(size)
        fns = {PS: lambda: self.robot.inverse_dynamics(q, qd, qdd),
               "exact": lambda: self.exact.inverse_dynamics(q, qd, qdd),
               "SymPy lambdify": lambda: self.sym.inverse_dynamics(q, qd, qdd),
               "C floor": self.floor.bind(cols, outs)}
        if size <= loop_max_n:
            fns["pinocchio.rnea"] = lambda: pinocchio_model.rnea_loop(
                self.pmodel, self.pdata, q, qd, qdd)
            fns["MuJoCo mj_inverse"] = lambda: mujoco_model.inverse_loop(
                self.mmodel, self.mdata, q, qd, qdd)
        return {k: f for k, f in fns.items()
                if self.ok.get(k, True) and (k != "exact" or self.exact is not None)}


LABELS = {PS: "planar_sym `inverse_dynamics`",
          "exact": "planar_sym `inverse_dynamics`, exact path (`exact=True`)",
          "SingleCall": "planar_sym internal `library.SingleCall` (pre-bound buffers)",
          "pinocchio.rnea": "`pinocchio.rnea`, Python loop",
          "MuJoCo mj_inverse": "MuJoCo `mj_inverse`, Python loop",
          "SymPy lambdify": "SymPy `lambdify` (numpy), vectorised",
          "C floor": "plain C floor (SoA, SIMD)"}


def run(cfg: Config) -> Section:
    from planar_sym import load

    from .baselines.lambdified import SymbolicRobot

    sec = Section("inverse", "1. Inverse dynamics", __doc__.split("\n\n", 1)[1])
    symbolic = {name: SymbolicRobot(load(name)) for name in SERIAL + CLOSED}
    arms = {name: Serial(name, sec, symbolic[name]) for name in SERIAL}
    single = Table("One sample, 1-D arrays: time per call; ratio = method time / planar_sym time",
                   ["robot", "method", "time per call", "ratio to planar_sym"])
    batch = Table("Batches of N samples: time per sample; ratio = method time / planar_sym "
                  "time (same N)", ["robot", "N", "method", "time per sample",
                                    "ratio to planar_sym"])
    results: dict = {}
    for name, arm in arms.items():
        st = interleaved(arm.single(), repeats=cfg.repeats, min_block_s=cfg.min_block_s)
        results[(name, 1)] = st
        for k, v in st.items():
            label = LABELS[k].replace(", Python loop", "").replace(", vectorised", "")
            single.add(name, label, v, ratio(v, st[PS]) if k != PS else "1")
    for name, arm in arms.items():
        for size in cfg.sizes:
            rep = cfg.big_repeats if size >= 1_000_000 else cfg.repeats
            st = interleaved(arm.batch(size, cfg.loop_max_n), repeats=rep, per=size,
                             min_block_s=cfg.min_block_s)
            results[(name, size)] = st
            for k, v in st.items():
                batch.add(name, _fmt_n(size), LABELS[k], v,
                          ratio(v, st[PS]) if k != PS else "1")
    if max(cfg.sizes) > cfg.loop_max_n:
        sec.notes.append(f"Python-loop baselines (Pinocchio, MuJoCo) are not run above N = "
                         f"{_fmt_n(cfg.loop_max_n)}: their per-sample cost does not depend on N.")
    closed = Table("Closed chains, batches of N samples: time per sample; ratio = method time / "
                   "time per sample of serial_2dof `inverse_dynamics` in the same rounds",
                   ["robot", "N", "method", "time per sample", "ratio to serial_2dof"])
    arm2 = load("serial_2dof")
    for name in CLOSED:
        robot, sym = load(name), symbolic[name]
        for size in cfg.sizes:
            q, qd, qdd = closed_states(robot, size)
            if size == cfg.sizes[0]:
                sec.checks.append(Check(f"{name}: SymPy lambdify tree part vs planar_sym",
                                        rel_err(sym.inverse_dynamics(q, qd, qdd),
                                                robot.tree_inverse_dynamics(q, qd, qdd)), GATE))
            a2, b2, c2 = serial_states(2, size)
            x, x2 = (q, qd, qdd), (a2, b2, c2)
            fns = {"serial_2dof": lambda x2=x2: arm2.inverse_dynamics(*x2),
                   PS: lambda r=robot, x=x: r.closed_chain_inverse_dynamics(*x),
                   "tree": lambda r=robot, x=x: r.tree_inverse_dynamics(*x),
                   "SymPy lambdify": lambda s=sym, x=x: s.inverse_dynamics(*x)}
            rep = cfg.big_repeats if size >= 1_000_000 else cfg.repeats
            st = interleaved(fns, repeats=rep, per=size, min_block_s=cfg.min_block_s)
            results[(name, size)] = st
            names = {"serial_2dof": "serial_2dof `inverse_dynamics` (reference)",
                     PS: "planar_sym `closed_chain_inverse_dynamics`",
                     "tree": "planar_sym `tree_inverse_dynamics` (M qdd + h only)",
                     "SymPy lambdify": "SymPy `lambdify` tree part (M qdd + h only)"}
            for k, v in st.items():
                closed.add(name, _fmt_n(size), names[k], v, ratio(v, st["serial_2dof"]))
    sec.tables += [single, batch, closed]
    _headlines(sec, cfg, results)
    return sec


def _headlines(sec: Section, cfg: Config, res: dict) -> None:
    n = 100_000 if 100_000 in cfg.sizes else max(s for s in cfg.sizes if s <= cfg.loop_max_n)
    st = res[("serial_2dof", n)]
    h = sec.headlines
    if "pinocchio.rnea" in st:
        r = ratio(st["pinocchio.rnea"], st[PS])
        h["id_vs_pin"] = (f"2-DOF inverse dynamics, N = {_fmt_n(n)} batch: planar_sym is "
                          f"**{r.median:.3g}x** [{r.min:.3g}-{r.max:.3g}] faster per sample than "
                          f"a `pinocchio.rnea` Python loop")
    if "MuJoCo mj_inverse" in st:
        r = ratio(st["MuJoCo mj_inverse"], st[PS])
        h["id_vs_mj"] = (f"2-DOF, N = {_fmt_n(n)}: **{r.median:.3g}x** [{r.min:.3g}-{r.max:.3g}]"
                         f" faster than a MuJoCo `mj_inverse` Python loop")
    if "C floor" in st:
        r = ratio(st[PS], st["C floor"])
        h["id_vs_floor"] = (f"2-DOF, N = {_fmt_n(n)}: planar_sym takes **{r.median:.3g}x** "
                            f"[{r.min:.3g}-{r.max:.3g}] the time of the hand-written SIMD C floor")
    if "SymPy lambdify" in st:
        r = ratio(st["SymPy lambdify"], st[PS])
        h["id_vs_lambdify"] = (f"2-DOF, N = {_fmt_n(n)}: vectorised SymPy `lambdify` (numpy) "
                               f"takes **{r.median:.3g}x** [{r.min:.3g}-{r.max:.3g}] the time of "
                               "planar_sym")
    nc = 100_000 if 100_000 in cfg.sizes else max(cfg.sizes)
    if ("parallel_3rrr", nc) in res:
        s3 = res[("parallel_3rrr", nc)]
        r = ratio(s3[PS], s3["serial_2dof"])
        h["id_3rrr"] = (f"3-RRR `closed_chain_inverse_dynamics`, N = {_fmt_n(nc)}: "
                        f"**{r.median:.3g}x** [{r.min:.3g}-{r.max:.3g}] the time per sample of "
                        "2-DOF `inverse_dynamics`")
    s1 = res[("serial_2dof", 1)]
    if "pinocchio.rnea" in s1:
        r = ratio(s1[PS], s1["pinocchio.rnea"])
        h["id_single"] = (f"One 2-DOF sample (1-D arrays): planar_sym takes **{r.median:.3g}x** "
                          f"[{r.min:.3g}-{r.max:.3g}] the time of one `pinocchio.rnea` call "
                          f"({s1[PS].median * 1e6:.3g} us vs "
                          f"{s1['pinocchio.rnea'].median * 1e6:.3g} us)")
