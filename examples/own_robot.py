"""Your own robot, from a description to torques and equations: the four-bar linkage.

    python examples/own_robot.py [ROBOT.toml] [--out DIR] [--samples N]

1. describe it: examples/four_bar.toml (bodies, points in the drawn pose, joints, one loop cut);
2. derive it: ``planar-sym derive four_bar.toml --out DIR`` (SymPy -> CasADi C -> compiled),
   here called in-process; DIR defaults to a temporary folder, removed at the end;
3. load it: ``planar_sym.load(DIR / "four_bar")``;
4. move the crank one turn at 1 rev/s and solve the passive joints from the loop closure
   (``closure.from_actuated``);
5. torques: the crank torque and the reaction force at the cut joint
   (``closed_chain_inverse_dynamics``);
6. the equations it was derived with: ``DIR/four_bar/equations.txt``.

A serial robot (e.g. examples/heavy_motor_2dof.toml) gets a joint-space swing instead of 4.-5.
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np
from _lectures import equation_lines

import planar_sym as ps
from planar_sym.cli import main as planar_sym_cli
from planar_sym.model.description import load as load_description
from planar_sym.motion.closure import from_actuated

HERE = Path(__file__).resolve().parent


def derive_and_load(toml: Path, out: Path) -> ps.Robot:
    print(f"$ planar-sym derive {toml} --out {out}")
    if planar_sym_cli(["derive", str(toml), "--out", str(out)]) != 0:
        raise SystemExit(2)  # the description's problems are printed already
    name = load_description(toml).name  # the folder is named after the robot
    return ps.load(out / name)


def crank_turn(robot: ps.Robot, samples: int):
    """One turn of the actuated joint(s) at 1 rev/s from the drawn pose; all joints follow."""
    t = np.linspace(0.0, 1.0, samples)
    act = list(robot.actuated)
    q_act = robot.q_drawn[act] + 2 * np.pi * t[:, None]
    rate = np.full_like(q_act, 2 * np.pi)
    return from_actuated(robot, t, q_act, rate, np.zeros_like(q_act))


def closed_chain_lesson(robot: ps.Robot, samples: int) -> None:
    motion = crank_turn(robot, samples)
    tau, lam = robot.closed_chain_inverse_dynamics(motion.q, motion.qd, motion.qdd, t=motion.t_s)
    for k, i in enumerate(robot.actuated):
        print(f"peak |tau{k + 1}| = {np.max(np.abs(tau[:, k])):.12g} N*m  "
              f"(joint {robot.coordinates[i]}, one turn at 1 rev/s)")
    for i in (i for i in range(robot.n) if i not in robot.actuated):
        lo, hi = np.degrees(motion.q[:, i].min()), np.degrees(motion.q[:, i].max())
        print(f"passive joint {robot.coordinates[i]} (relative to its parent body): "
              f"{lo:.3f} .. {hi:.3f} deg")
    for k, loop in enumerate(robot.loops):
        f = np.hypot(lam[:, 2 * k], lam[:, 2 * k + 1])
        print(f"peak |reaction force at cut joint {loop}| = {f.max():.6g} N")
    # energy comes back after a full turn at constant speed, so the mean crank power is ~0
    power = np.sum(tau * motion.qd[:, list(robot.actuated)], axis=1)
    print(f"crank power: peak {np.max(np.abs(power)):.4g} W, mean over the turn "
          f"{np.mean(power[:-1]):.2e} W")
    print(f"loop residual max |Phi| = {np.max(np.abs(robot.constraint(motion.q))):.2g} m")


def serial_lesson(robot: ps.Robot, samples: int) -> None:
    w = 2 * np.pi * np.linspace(0.0, 1.0, samples)[:, None] * np.ones(robot.n)  # 1 Hz, all joints
    q, qd, qdd = robot.q_drawn + 0.5 * np.sin(w), np.pi * np.cos(w), -2 * np.pi ** 2 * np.sin(w)
    tau = robot.inverse_dynamics(q, qd, qdd)
    for k in range(robot.n):
        print(f"peak |tau{k + 1}| = {np.max(np.abs(tau[:, k])):.12g} N*m  "
              f"(joint {robot.coordinates[k]}, 0.5 rad swing at 1 Hz)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("toml", nargs="?", type=Path, default=HERE / "four_bar.toml")
    ap.add_argument("--out", type=Path, default=None, help="keep the generated folder here")
    ap.add_argument("--samples", type=int, default=181)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="own_robot.") as tmp:
        out = args.out or Path(tmp)
        robot = derive_and_load(args.toml, out)
        print(f"\n{robot.title}: coordinates {robot.coordinates}, actuated "
              f"{[robot.coordinates[i] for i in robot.actuated]}, {len(robot.p)} parameters\n")
        (closed_chain_lesson if robot.is_closed_chain else serial_lesson)(robot, args.samples)
        equations = robot.library.folder / "equations.txt"
        print(f"\nEquations ({equations}):")
        for line in equation_lines(equations.read_text(), ("M11", "M12", "g1", "Phi1", "Phi2")):
            print(f"  {line}")


if __name__ == "__main__":
    main()
