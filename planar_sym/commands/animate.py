"""``planar-sym animate``: a study's mechanism moving, as a GIF (or MP4 with ffmpeg)."""

from __future__ import annotations

from pathlib import Path


def register(sub) -> None:
    p = sub.add_parser("animate", help="animate a study's motion into a GIF (or MP4)")
    p.add_argument("study", help="built-in study name (see `list`) or a study file (.toml)")
    p.add_argument("--out", type=Path, default=None,
                   help="animation file, .gif (or .mp4 where ffmpeg is installed); "
                        "default STUDY.gif")
    p.add_argument("--frames", type=int, default=60,
                   help="frames, evenly spaced in time (2 to 2000, default 60)")
    p.add_argument("--fps", type=float, default=20.0, help="frames per second of playback (default 20)")
    p.add_argument("--dpi", type=int, default=80, help="pixels per inch; frames are 5.6 x 4.6 in (default 80)")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..study.run import load_study
    from .run import animate_study

    st = load_study(args.study)
    out = args.out or Path(f"{st.name}.gif")
    animate_study(st, out, frames=args.frames, fps=args.fps, dpi=args.dpi, quiet=args.quiet)
    if not args.quiet:
        print(f"{st.name}: wrote {out} ({args.frames} frames at {args.fps:g} fps)")
    return 0
