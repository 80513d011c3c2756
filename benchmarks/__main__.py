"""``python -m benchmarks [--quick] [--out PATH] [--only SECTION ...]``

Runs the sections in order, printing each as it finishes, then writes the Markdown report
(default ``BENCHMARKS.md`` at the repository root). Exit status 1 if a correctness gate failed
(a baseline disagreeing with planar_sym is not timed), 0 otherwise.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from . import Config
from .machine import describe, load_now
from .report import markdown, print_section

SECTIONS = ("inverse", "ik", "forward", "build", "actuators", "growth", "imports", "control",
            "design", "identify", "optimal", "opty_peer")
DEFAULT_OUT = Path(__file__).resolve().parent.parent / "BENCHMARKS.md"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="tiny sizes and few repeats (seconds): a smoke test, not figures")
    ap.add_argument("--out", type=Path, default=DEFAULT_OUT,
                    help=f"Markdown report to write (default: {DEFAULT_OUT})")
    ap.add_argument("--only", nargs="+", choices=SECTIONS, default=list(SECTIONS),
                    help="run only these sections")
    args = ap.parse_args(argv)
    cfg = Config.quick_config() if args.quick else Config()
    t0 = time.perf_counter()
    machine = describe()
    print("planar-sym benchmarks" + (" (--quick)" if cfg.quick else ""))
    for k, v in machine.items():
        print(f"  {k}: {v}")
    sections = []
    for key in SECTIONS:
        if key not in args.only:
            continue
        module = __import__(f"benchmarks.{key}", fromlist=["run"])
        t1 = time.perf_counter()
        section = module.run(cfg)
        section.notes.append(f"section time {time.perf_counter() - t1:.0f} s")
        print_section(section)
        sections.append(section)
    machine["load average at end"] = load_now()
    command = "python -m benchmarks" + (" --quick" if args.quick else "")
    if set(args.only) != set(SECTIONS):
        command += " --only " + " ".join(args.only)
    text = markdown(machine, sections, quick=cfg.quick, command=command,
                    elapsed_s=time.perf_counter() - t0)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    tmp = args.out.with_name(args.out.name + ".tmp")
    tmp.write_text(text)
    tmp.replace(args.out)
    failed = [c for s in sections for c in s.checks if not c.ok]
    print(f"wrote {args.out} ({time.perf_counter() - t0:.0f} s)")
    for c in failed:
        print("FAILED " + c.text(), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
