"""``planar-sym demo``: every built-in study, animation and robot drawing, with an index README.md
and a page index.html (``outputs.html_index``) that shows them all, offline."""

from __future__ import annotations

import sys
import time
from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("demo", help="every built-in study (CSV, plots, animation), every robot "
                                    "drawn, and DIR/README.md indexing them")
    p.add_argument("--out", type=Path, default=Path("results"), help="output folder")
    p.add_argument("--samples", type=int, default=None,
                   help="samples per study (default 201 inverse, 1001 forward dynamics)")
    p.add_argument("--frames", type=int, default=40, help="frames per animation (default 40)")
    p.add_argument("--fps", type=float, default=15.0, help="animation frames per second (default 15)")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..files import atomic_files
    from ..model.description import builtin_robots
    from ..outputs.animation import check_frames, writer_for
    from ..outputs.results import write
    from ..study.builtin import names
    from ..study.run import load_study
    from ..study.run import run as run_study
    from .draw import save_drawing
    from .run import animate_study, check_out, check_samples

    check_samples(args.samples)
    check_frames(args.frames, 80)
    check_out(args.out)
    writer_for(Path("check.gif"), args.fps)  # a bad --fps fails before anything is written
    out, robots = Path(args.out), builtin_robots()
    studies = [load_study(name) for name in names()]
    total = 2 * len(studies) + len(robots) + 1
    progress = Progress(total, args.quiet)
    results = []
    for st in studies:
        name = st.name
        result = run_study(st, args.samples)
        results.append(result)
        progress(f"{name}: {', '.join(p.name for p in write(result, out, split=True))}")
        gif = animate_study(st, out / f"{name}.gif", frames=args.frames, fps=args.fps,
                            dpi=80, figsize=(5.0, 4.2), quiet=args.quiet)
        progress(f"{name}: {gif.name} ({args.frames} frames)")
    for robot in robots:
        save_drawing(robot, out / f"{robot}.png")
        progress(f"{robot}: {robot}.png")
    from ..outputs.html_index import index_html

    index, page = out / "README.md", out / "index.html"
    with atomic_files([index, page]) as (tmp, tmp_page):  # both indexes or neither
        tmp.write_text(index_text(results, robots))
        tmp_page.write_text(index_html(results, robots, out), encoding="utf-8")
    progress(f"index: {index}, {page.name}")
    return 0


class Progress:
    """One line per finished item on stderr: ``[k/total] what (seconds for it)``."""

    def __init__(self, total: int, quiet: bool):
        self.total, self.quiet, self.done, self.last = total, quiet, 0, time.perf_counter()

    def __call__(self, what: str) -> None:
        now = time.perf_counter()
        self.done += 1
        if not self.quiet:
            print(f"[{self.done}/{self.total}] {what} ({now - self.last:.2f} s)",
                  file=sys.stderr, flush=True)
        self.last = now


def peaks_text(result) -> str:
    """Peak |torque| per actuated joint (N*m), or why there is none."""
    peaks = result.peak_torques()
    if not peaks:
        return "none (forward dynamics, zero torque)"
    return ", ".join(f"{k} = {v:.6g}" for k, v in peaks.items())


def index_text(results, robots: list[str]) -> str:
    """``README.md`` of a demo folder: every study with its files, every robot drawn."""
    from ..model.description import load as load_description

    about = ("Made by `planar-sym demo`: every built-in study: the seed chapter's scenarios (CSV, the seed-like "
             "plot, the torque split into inertial `M qdd`, velocity `C qd` and gravity `g` "
             "parts, and an animation), and every robot in its drawn configuration. "
             "Column units are in the CSV headers (`t_s`, `q1_rad`, `qd1_rad_s`, `tau1_n_m`, ...).")
    lines = ["# planar-sym demo results", "", about, "", "## Studies", "",
             "| study | what | peak abs(torque) per joint (N*m; N for a slider) | files |",
             "|---|---|---|---|"]
    for r in results:
        files = " · ".join(f"[{label}]({r.name}{suffix})" for label, suffix in (
            ("CSV", ".csv"), ("plot", ".png"), ("split", "_split.png"),
            ("animation", ".gif")))
        lines.append(f"| `{r.name}` | {r.summary} | {peaks_text(r)} | {files} |")
    from ..dynamics.sizing import table

    sized = [r for r in results if r.sizing]
    if sized:
        lines += ["", "## Actuator sizing", "",
                  ("What each actuator delivers over each inverse-dynamics study: torque (force "
                   "for a prismatic joint) at the joint and at the motor (through the gear "
                   "ratio; 1 where the robot gives no actuator), speed, power and net energy; a "
                   "limit the robot's actuator gives is checked, and the first time it is "
                   "exceeded named.")]
        for r in sized:
            lines += ["", f"### {r.name}", "", table(r.sizing, r.events)]
    lines += ["", "## Robots", "", "| robot | what | drawing |", "|---|---|---|"]
    for robot in robots:
        lines.append(f"| `{robot}` | {load_description(robot).title} | "
                     f"[{robot}.png]({robot}.png) |")
    for robot in robots:
        lines += ["", f"### {robot}", "", f"![{robot} in its drawn configuration]({robot}.png)"]
    return "\n".join(lines) + "\n"
