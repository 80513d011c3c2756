"""planar-sym benchmarks: ``python -m benchmarks [--quick] [--out BENCHMARKS.md]``.

Every figure is measured together with a baseline in the same run (interleaved repeats) and
reported as median [min-max] and as a ratio to that baseline; see ``timing.py``. Sections:
``inverse`` (inverse dynamics vs Pinocchio, MuJoCo, lambdify, a hand-written C floor),
``forward`` (work-precision of forward dynamics), ``build`` (derive and compile times),
``actuators`` (what actuator models add to derivation, generated C and compiled evaluation),
``growth`` (derive, compile, code size and run time of n-link chains and a three-loop linkage
against the number of links, fitted exponents, native Pinocchio as the run-time baseline),
``imports`` (import and first-torque latency).
"""

from __future__ import annotations

from dataclasses import dataclass

SERIAL = ("serial_2dof", "serial_3dof")
CLOSED = ("five_bar_type1", "five_bar_type2", "parallel_3rrr")
ROBOTS = SERIAL + CLOSED


@dataclass(frozen=True)
class Config:
    """Sizes and repeats of one run; ``quick()`` is the seconds-long smoke-test version."""

    quick: bool = False
    repeats: int = 7  # interleaved rounds for in-process timings
    min_block_s: float = 0.02  # each timed block lasts at least this long
    sizes: tuple[int, ...] = (1_000, 100_000, 1_000_000)
    loop_max_n: int = 100_000  # Python-loop baselines (Pinocchio, MuJoCo) stop here
    big_repeats: int = 3  # rounds for N >= 1e6
    rtols: tuple[float, ...] = (1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 3e-10, 1e-10,
                                3e-11, 1e-11, 3e-12, 1e-12, 3e-13, 1e-13)
    numpy_rtols: tuple[float, ...] = (1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12)
    mujoco_dts: tuple[float, ...] = (3e-3, 1e-3, 3e-4, 1e-4, 3e-5)
    sim_repeats: int = 7
    radau_check: bool = True  # cross-check each forward reference with Radau (10 s: 5-bar)
    derive_robots: tuple[str, ...] = ROBOTS
    build_robots: tuple[str, ...] = ROBOTS
    build_repeats: int = 3
    import_repeats: int = 10
    actuator_pairs: tuple[str, ...] = ("tree", "closed")  # plain vs actuated 2-DOF, five-bar
    actuator_rounds: int = 5  # interleaved derivations and compilations per robot
    actuator_samples: int = 10_000
    growth_sizes: tuple[int, ...] = (2, 4, 6, 8, 10, 12, 16, 20)  # links of the n-link pendulums
    growth_jansen: bool = True  # also the three-loop Jansen linkage (7 coordinates)
    growth_build_repeats: int = 3  # rounds of derive + first compile per robot
    growth_samples: int = 100_000  # states per call for the per-sample times
    growth_pin_samples: int = 100_000  # of those, the ones native Pinocchio runs
    growth_rounds: int = 5  # rounds of per-sample timing (each: best of growth_best_of)
    growth_best_of: int = 3
    growth_pinocchio: bool = True  # build and time native Pinocchio (about 45 s, once, cached)
    growth_fit_from: int = 4  # fit the growth exponents over the chains from this size on

    @classmethod
    def quick_config(cls) -> Config:
        return cls(quick=True, repeats=3, min_block_s=0.003, sizes=(1_000,), loop_max_n=1_000,
                   big_repeats=1, rtols=(1e-7, 1e-10), numpy_rtols=(1e-7,),
                   mujoco_dts=(1e-3, 1e-4), sim_repeats=1, radau_check=False,
                   derive_robots=("serial_2dof",),
                   build_robots=("serial_2dof",), build_repeats=1, import_repeats=2,
                   actuator_pairs=("tree",), actuator_rounds=1,
                   growth_sizes=(2, 4), growth_jansen=False, growth_build_repeats=1,
                   growth_samples=10_000, growth_pin_samples=10_000, growth_rounds=2,
                   growth_best_of=2, growth_pinocchio=False)
