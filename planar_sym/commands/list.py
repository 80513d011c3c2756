"""``planar-sym list``: the scenarios and the robots."""

from __future__ import annotations


def register(sub) -> None:
    sub.add_parser("list", help="list scenarios and robots").set_defaults(fn=run)


def run(args) -> int:
    from ..model.description import builtin_robots
    from ..study.scenarios import DEFAULT_SAMPLES, SCENARIOS

    print("Scenarios (planar-sym run NAME --out DIR):")
    for sc in SCENARIOS.values():
        print(f"  {sc.name:<30} {sc.summary}  [default {DEFAULT_SAMPLES[sc.kind]} samples]")
    print("\nRobots (planar-sym equations NAME):")
    for r in builtin_robots():
        print(f"  {r}")
    return 0
