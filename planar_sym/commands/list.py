"""``planar-sym list [FOLDER]``: the built-in robots and studies, and a folder's own."""

from __future__ import annotations

import tomllib
from pathlib import Path

from ..errors import InputError


def register(sub) -> None:
    p = sub.add_parser("list", help="list the built-in robots and studies (and those in FOLDER)")
    p.add_argument("folder", nargs="?", type=Path, default=None,
                   help="also list the robot descriptions, generated robots and study files "
                        "found in this folder")
    p.set_defaults(fn=run)


def run(args) -> int:
    from ..model.description import builtin_robots, load
    from ..study.builtin import find, names
    from ..study.spec import load as load_study

    print("Built-in robots (planar-sym draw|equations|validate NAME):")
    for r in builtin_robots():
        print(f"  {r:<30} {load(r).title}")
    print("\nBuilt-in studies (planar-sym run NAME --out DIR):")
    for name in names():
        st = load_study(find(name))
        samples = (st.control.samples if st.control else st.motion.samples if st.motion
                   else st.simulation.samples)
        print(f"  {name:<30} {st.title}  [{st.kind}, {samples} samples]")
    if args.folder is not None:
        list_folder(args.folder)
    return 0


def classify(path: Path) -> str | None:
    """'robot', 'study' or None for a TOML file, by its top-level keys."""
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError):
        return None
    if "bodies" in data or "joints" in data:
        return "robot"
    if "kind" in data and "robot" in data:
        return "study"
    return None


def list_folder(folder: Path) -> None:
    if not folder.is_dir():
        raise InputError(f"{folder} is not a folder")
    files = sorted(folder.glob("*.toml"))
    kinds = {p: classify(p) for p in files}
    generated = sorted(p for p in folder.iterdir() if (p / "manifest.json").is_file())
    print(f"\nIn {folder}:")
    robots = [p for p in files if kinds[p] == "robot"]
    studies = [p for p in files if kinds[p] == "study"]
    for title, items in (("robot descriptions (planar-sym draw FILE)", robots),
                         ("generated robots (planar-sym validate DIR)", generated),
                         ("studies (planar-sym run FILE)", studies)):
        print(f"  {title}:")
        for p in items:
            print(f"    {p}")
        if not items:
            print("    (none)")
