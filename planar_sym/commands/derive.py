"""``planar-sym derive ROBOT.toml [...] --out DIR``: your own robot, from description to library.

Every description is validated first and every problem of every file is reported at once;
then nothing is written (exit code 2). Otherwise each robot is derived in memory (SymPy),
written atomically to ``DIR/<name>/`` (the generated C, header, manifest, equations, plus a copy
of the description as ``description.toml`` so the folder is self-contained, e.g. for
``planar-sym validate``; not for built-in robots, whose folders stay exactly what ``make derive``
writes), and compiled into the cache. Load it with
``planar_sym.load("DIR/<name>")``.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import DescriptionError, LibraryError, PlanarSymError
from ..model.derived import DESCRIPTION_COPY
from ..model.deriving import derive_modules


def register(sub) -> None:
    p = sub.add_parser("derive", help="derive, generate and compile robots from TOML descriptions")
    p.add_argument("robots", nargs="+", metavar="ROBOT",
                   help="description files (path/to/robot.toml) or built-in robot names")
    p.add_argument("--out", type=Path, required=True,
                   help="output folder; each robot goes to OUT/<name>/")
    p.add_argument("--no-build", action="store_true", help="write the C, do not compile it")
    p.add_argument("--equations", choices=("auto", "closed", "structure"), default="auto", type=str.lower,
                   help="equations.txt/.tex/.md: the expanded closed forms up to 4 moving joints "
                        "in a chain and 9 coordinates (auto), always (closed: minutes past "
                        "about 6 links), or the structure they are computed from")
    p.set_defaults(fn=run)


def validate_all(robots: list[str]) -> list:
    """Every description, validated; one DescriptionError listing every problem of every file."""
    from ..model.description import load

    descs, problems = [], []
    for robot in robots:
        try:
            descs.append(load(robot))
        except DescriptionError as exc:
            problems += exc.problems
    names = [d.name for d in descs]
    for name in sorted({n for n in names if names.count(n) > 1}):
        files = ", ".join(str(d.path) for d in descs if d.name == name)
        problems.append(f"{files}: name: {name!r} is used by several descriptions")
    if problems:
        raise DescriptionError(problems)
    return descs


def run(args) -> int:
    from ..model.description import robots_dir
    from ..model.library import Library
    from ..progress import Progress

    if args.out.exists() and not args.out.is_dir():
        raise PlanarSymError(f"--out {args.out} is a file, not a folder")
    derive_main = derive_modules()
    descs = validate_all(args.robots)  # raises before anything is derived or written
    for desc in descs:  # a user's own file or folder there is never replaced
        folder = args.out / desc.name
        if folder.exists():
            _check_replaceable(folder)
    progress = Progress(len(descs) * (1 if args.no_build else 2), quiet=args.quiet)
    rendered = []
    for desc in descs:
        progress.step(f"deriving {desc.name} ({desc.path})")
        name, files = derive_main.derive_robot(desc.path, args.equations,
                                               lambda what: progress.note(f"{what} ..."))
        if desc.path.resolve().parent != robots_dir():  # a built-in comes out as `make derive`
            files = {**files, DESCRIPTION_COPY: desc.path.read_bytes()}
        rendered.append((name, files))
    for name, files in rendered:
        folder = args.out / name
        derive_main.write_atomically(files, folder)
        if args.no_build:
            message = f"{name}: wrote {folder}/"
        else:
            progress.step(f"compiling {name}")
            try:
                lib = Library(name, folder)
                if not lib.compiled:
                    message = (f"{name}: wrote {folder}/, not compiled (no C compiler: it runs "
                               "on CasADi's evaluator, slower; with a compiler, `planar-sym "
                               f"build {folder}`)")
                elif len(lib.groups) > 1:  # a big robot: each function when first called
                    message = (f"{name}: wrote {folder}/; its {len(lib.groups)} functions "
                               "compile each when first called (all of them now: `planar-sym "
                               f"build {folder}`)")
                else:
                    message = f"{name}: wrote {folder}/, compiled {lib.path}"
            except LibraryError as exc:
                raise LibraryError(f"{name}: wrote {folder}/, but compiling it failed (the "
                                   f"generated C stays there; fix the compiler and run "
                                   f"`planar-sym build {folder}`): {exc}") from None
        if not args.quiet:
            print(f"{message}\n  load it with planar_sym.load({str(folder)!r})")
    progress.done()
    return 0


def _check_replaceable(folder: Path) -> None:
    """Only a folder this command wrote is replaced: one with a manifest and nothing else but
    the files the manifest lists (and the description copy)."""
    import json

    try:
        listed = set(json.loads((folder / "manifest.json").read_text())["files"])
    except (OSError, ValueError, KeyError, TypeError):
        raise PlanarSymError(f"{folder} exists and is not a generated robot folder (no readable "
                             "manifest.json): it is not replaced; choose another --out") from None
    foreign = sorted(p.name for p in folder.iterdir()
                     if p.name not in listed | {"manifest.json", DESCRIPTION_COPY})
    if foreign:
        raise PlanarSymError(f"{folder} holds files planar-sym did not write ({', '.join(foreign)}"
                             "): it is not replaced; move them or choose another --out")
