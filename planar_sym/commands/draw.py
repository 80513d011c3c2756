"""``planar-sym draw``: a robot in its drawn configuration, as a labelled picture."""

from __future__ import annotations

from pathlib import Path

from ..errors import InputError

#: picture formats ``draw`` writes (matplotlib picks the writer from the suffix)
FORMATS = (".png", ".svg", ".pdf")


def register(sub) -> None:
    p = sub.add_parser("draw", help="draw a robot in its drawn configuration (PNG)")
    p.add_argument("robot", help="built-in robot name (see `list`) or a description file (.toml)")
    p.add_argument("--out", type=Path, default=None,
                   help="image file, .png (or .svg, .pdf); default ROBOT.png")
    p.add_argument("--dpi", type=int, default=100, help="pixels per inch; the figure is 8 x 6 in (default 100)")
    p.set_defaults(fn=run)


def run(args) -> int:
    out = args.out or Path(f"{args.robot}.png")
    save_drawing(args.robot, out, dpi=args.dpi)
    if not args.quiet:
        print(f"{args.robot}: wrote {out}")
        if str(args.robot).endswith(".toml"):  # say what assembling the loops changed
            from ..model.description import load as load_description

            assembly = load_description(args.robot).assembly
            if assembly is not None:
                print(assembly.report())
    return 0


def save_drawing(robot_name: str, path: Path, dpi: int = 100) -> Path:
    """Write ``drawing.drawing_figure(robot_name)`` to ``path``, whole or not at all.

    Parameters
    ----------
    robot_name : str
    path : Path
        ``.png``, ``.svg`` or ``.pdf``; the figure is 8 x 6 in, so 800 x 600 pixels at
        ``dpi = 100``.
    dpi : int
        Pixels per inch.
    """
    from ..files import atomic_files
    from ..outputs.drawing import drawing_figure
    from ..outputs.resolution import check_dpi

    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        raise InputError(f"--out must end in {', '.join(FORMATS)} (got {path.name!r})")
    check_dpi(dpi)
    fig = drawing_figure(robot_name)
    with atomic_files([path]) as (tmp,):
        fig.savefig(tmp, dpi=dpi, format=path.suffix[1:].lower())
    return path
