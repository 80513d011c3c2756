"""``index.html`` of a results folder: every study's plots and animation, and every robot's
drawing and equations, on one page that opens with no network.

Nothing is fetched: no script, font or stylesheet from elsewhere, and no JavaScript at all.
Pictures are the folder's own files, referenced relative to the page (``embed=False``: the page
stays small and the folder is the unit to copy) or inlined as ``data:`` URIs (``embed=True``: one
file to send). Animations are the GIFs ``planar-sym demo`` writes: a browser plays them by
itself. Equations are the plain-text closed forms of ``planar-sym equations ROBOT`` (SymPy
syntax, as the terminal shows them) in ``<pre>`` blocks: rendering the LaTeX form would need a
math renderer (MathJax from a network, or a LaTeX-to-MathML converter), and the text form is
exact, searchable and can be pasted into Python.

Made by ``planar-sym demo`` (the built-in studies and robots) and ``planar-sym report`` (the
user's own, robots given by their description files). Besides the studies given, the page
shows the atlas maps (``planar-sym atlas``) and sweep tables (``planar-sym sweep``) it finds in
the folder.
"""

from __future__ import annotations

import base64
import csv
import html
from collections.abc import Mapping
from pathlib import Path
from urllib.parse import quote

import numpy as np

from ..errors import PlanarSymError
from ..files import atomic_files
from ..study.result import Result

#: picture kinds of a study, in page order: (file suffix, caption)
STUDY_PICTURES = ((".png", "plot"), ("_split.png", "torque split into M qdd, C qd, g (and friction, rotors)"),
                  (".gif", "animation"))
MIME = {".png": "image/png", ".gif": "image/gif", ".svg": "image/svg+xml"}

_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:1.5em auto;
max-width:1600px;padding:0 1em;color:#222;background:#fff}
h1{margin-bottom:0.2em}h2{border-bottom:2px solid #ddd;padding-bottom:0.2em;margin-top:2em}
table{border-collapse:collapse;font-size:0.9em}td,th{border:1px solid #ccc;padding:3px 8px;
text-align:left;vertical-align:top}th{background:#f3f3f3}
.pictures{display:grid;grid-template-columns:repeat(auto-fill,minmax(min(100%,720px),1fr));
gap:12px;align-items:start}
figure{margin:0}figcaption{font-size:0.8em;color:#555}
img{display:block;max-width:100%;height:auto;border:1px solid #eee}
.warning{color:#8a4b00;background:#fff4e0;padding:2px 6px}
pre{background:#f7f7f7;padding:0.8em;overflow-x:auto;font-size:0.8em;line-height:1.35}
.peaks{font-family:ui-monospace,monospace;font-size:0.9em}
nav a{margin-right:0.6em}.scroll{overflow-x:auto}
"""


def _e(text) -> str:
    return html.escape(str(text))


def _source(folder: Path, name: str, embed: bool) -> str | None:
    """The ``src`` of a picture file in ``folder``: relative, or a data URI; None if absent."""
    path = folder / name
    if not path.is_file():
        return None
    if not embed:
        return quote(name)
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return f"data:{MIME[path.suffix.lower()]};base64,{data}"


def _picture(src: str, caption: str, alt: str, href: str | None = None) -> str:
    """A captioned picture; with ``href``, the picture is a link to it (the full-size file)."""
    img = f'<img src="{_e(src)}" alt="{_e(alt)}" loading="eager">'
    if href is not None:
        img = f'<a href="{_e(href)}">{img}</a>'
    return f"<figure>{img}<figcaption>{_e(caption)}</figcaption></figure>"


def _pictures(folder: Path, names, embed: bool, link: bool) -> str:
    """``(file name, caption, alt)`` of ``names`` present in ``folder``, as a grid of pictures,
    each linked to its file when ``link`` (never when ``embed``: the page is then alone)."""
    out = []
    for name, caption, alt in names:
        src = _source(folder, name, embed)
        if src is not None:
            href = quote(name) if link and not embed else None
            out.append(_picture(src, caption, alt, href))
    return f'<div class="pictures">{"".join(out)}</div>'


def _table(header: list[str], rows: list[list[str]]) -> str:
    """An HTML table of plain text cells (escaped here), scrolled sideways on its own when it
    is wider than the page (a sweep's many columns), not the page with it."""
    head = "".join(f"<th>{_e(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{_e(c)}</td>" for c in row) + "</tr>" for row in rows)
    return f'<div class="scroll"><table><tr>{head}</tr>{body}</table></div>'


def sizing_table(result: Result) -> str:
    """The actuator sizing (peak and RMS torque at the joint and the motor, speed, power,
    energy, limits) as an HTML table: the rows of ``dynamics.sizing.table``, the Markdown that
    ``planar-sym demo``'s README shows, so both print the same numbers; "" without sizing."""
    from ..dynamics.sizing import table

    lines = [ln.strip().strip("|").split("|")
             for ln in table(result.sizing, result.events).splitlines()
             if not ln.startswith("|---")]
    if not lines:
        return ""
    return _table([c.strip() for c in lines[0]], [[c.strip() for c in r] for r in lines[1:]])


def tracking_errors(result: Result) -> list[tuple[str, float, float, str]]:
    """A control study's tracking errors: (name, largest |e|, |e| at the end, unit) for each
    coordinate's ``e<k>`` and the tool point's distance; [] for another study."""
    if result.kind != "control":
        return []
    errors = [(f"e{s.index + 1}", s) for s in result.series("e")]
    errors += [("tool point", s) for s in result.series("e_task")]
    return [(k, float(np.abs(s.values).max()), float(abs(s.values[-1])), s.unit)
            for k, s in errors]


def peak_lines(result: Result) -> list[str]:
    """``tau<k> = <peak>`` with the unit (N*m, or N for a slider) per actuated joint; one line
    saying why when there is none (forward dynamics under zero torque)."""
    lines = [f"peak |{k}| = {v:.6g} {unit}"
             for k, (v, unit) in result.peak_torques_with_units().items()]
    return lines or ["no torque (forward dynamics, zero torque)"]


def study_section(result: Result, folder: Path, embed: bool, link: bool = False) -> str:
    """One study: title, what it is, peak torques, its pictures found in ``folder`` (each a link
    to its file with ``link``), CSV link, actuator sizing and tracking errors where it has them."""
    t = result.get("t").values
    rows = [("robot", f'<a href="#robot-{_e(result.robot)}">{_e(result.robot)}</a>'),
            ("duration", f"{t[-1] - t[0]:.6g} s, {len(t)} samples"),
            ("peaks", '<span class="peaks">' + "<br>".join(map(_e, peak_lines(result)))
             + "</span>")]
    if result.solver:
        rows.append(("inverse kinematics", _e(result.solver)))
    if result.timing:
        rows.append(("timing", _e(result.timing)))
    if result.events:
        rows.append(("events", "<br>".join(_e(e) for e in result.events)))
    csv = _source(folder, f"{result.name}.csv", embed=False)
    if csv is not None:
        anchor = f'<a href="{_e(csv)}">{_e(result.name)}.csv</a>'
        rows.append(("table", f"{anchor} (units in the column names)"))
    table = "<table>" + "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in rows) + "</table>"
    sizing = sizing_table(result)
    if sizing:
        table += f"<h4>actuator sizing</h4>{sizing}"
    errors = tracking_errors(result)
    if errors:  # as `planar-sym run` prints them: 3 significant digits
        table += "<h4>tracking error</h4>" + _table(
            ["error", "largest |e|", "|e| at the end"],
            [[k, f"{big:.3g} {unit}", f"{end:.3g} {unit}"] for k, big, end, unit in errors])
    pictures = _pictures(folder, [(f"{result.name}{suffix}", caption,
                                   f"{result.name} {caption}")
                                  for suffix, caption in STUDY_PICTURES], embed, link)
    note = f"<p><small>{_e(result.note)}</small></p>" if result.note else ""
    note += "".join(f'<p class="warning">warning: {_e(w)}</p>' for w in result.warnings)
    return (f'<section id="study-{_e(result.name)}"><h3>{_e(result.name)}</h3>'
            f"<p>{_e(result.summary)}</p>{table}{note}{pictures}</section>")


def robot_section(robot: str, folder: Path, embed: bool, source: str | None = None,
                  link: bool = False) -> str:
    """One robot: its drawing (``<robot>.png`` in ``folder``) and its equations as text.

    ``robot`` is the robot's name (the section's anchor and the drawing's file name);
    ``source`` what to read it from: a description file or generated folder for a robot of
    the user's own, which its name alone does not find (default: ``robot``, a built-in name).
    """
    from ..model.description import load as load_description
    from .equations import equations

    source = str(source or robot)
    described = Path(source, "description.toml")  # a generated folder keeps its description
    try:
        title = load_description(described if Path(source).name != source  # a path
                                 and described.is_file() else source).title
    except PlanarSymError as exc:
        title = f"(description not readable: {exc})"
    drawing = _pictures(folder, [(f"{robot}.png", "drawn configuration", f"{robot} drawn")],
                        embed, link)
    try:
        text = equations(source).text
        eqs = (f"<details><summary>equations of motion (text form of "
               f"<code>planar-sym equations {_e(source)}</code>)</summary>"
               f"<pre>{_e(text)}</pre></details>")
    except PlanarSymError as exc:  # said on the page, not skipped silently
        eqs = f"<p>equations not available: {_e(exc)}</p>"
    return (f'<section id="robot-{_e(robot)}"><h3>{_e(robot)}</h3><p>{_e(title)}</p>'
            f"{drawing}{eqs}</section>")


#: rows of a sweep table shown on the page (the CSV link has them all)
SWEEP_ROWS = 50


def _sweep_section(folder: Path, csv_name: str, embed: bool, link: bool) -> str:
    """A ``planar-sym sweep`` result: its plot and its table (numbers to 6 digits)."""
    with open(folder / csv_name, newline="", encoding="utf-8") as f:
        header, *rows = list(csv.reader(f)) or [[]]

    def cell(text: str) -> str:
        try:
            return f"{float(text):.6g}"
        except ValueError:  # the error column of a failed design, or an empty figure
            return text

    shown = [[cell(c) for c in row] for row in rows[:SWEEP_ROWS]]
    more = (f" (the first {SWEEP_ROWS} of {len(rows)} designs)" if len(rows) > SWEEP_ROWS
            else "")
    stem = csv_name[:-len(".csv")]
    return (f'<section id="sweep-{_e(stem)}"><h3>{_e(stem)}</h3>'
            f'<p>table: <a href="{_e(quote(csv_name))}">{_e(csv_name)}</a>{_e(more)}</p>'
            + _pictures(folder, [(f"{stem}.png", "sweep", stem)], embed, link)
            + _table(header, shown) + "</section>")


def _atlas_section(folder: Path, sub: str, embed: bool, link: bool) -> str:
    """A ``planar-sym atlas`` result in ``folder/sub`` ("" for ``folder`` itself): its maps
    and links to its tables."""
    where = folder / sub
    maps = sorted(p.name for p in where.glob("atlas*.png"))
    maps += [n for n in ("envelope_along.png",) if (where / n).is_file()]
    pictures = _pictures(folder, [(f"{sub}/{n}" if sub else n, n[:-4].replace("_", " "),
                                   f"{sub or 'atlas'} {n}") for n in maps], embed, link)
    tables = [f"{sub}/{n}" if sub else n for n in ("atlas.csv", "atlas.npz", "envelope_along.csv")
              if (where / n).is_file()]
    files = ", ".join(f'<a href="{_e(quote(n))}">{_e(n)}</a>' for n in tables)
    title = f"atlas of {sub}" if sub else "atlas"
    return (f'<section id="atlas-{_e(sub or "atlas")}"><h3>{_e(title)}</h3>'
            f"<p>tables: {files or 'none'}</p>{pictures}</section>")


def other_results(folder: Path, results: list[Result], embed: bool = False,
                  link: bool = False) -> str:
    """The atlas maps and sweep tables found in ``folder`` (written there by ``planar-sym
    atlas --out`` and ``planar-sym sweep --out``, which run no study file of their own), as
    page sections; "" when there are none. A study's own files are not taken for a sweep's."""
    folder = Path(folder)
    own = {f"{r.name}.csv" for r in results}
    sweeps = sorted(p.name for p in folder.glob("*_sweep.csv") if p.name not in own)
    atlases = [""] if any(folder.glob("atlas*.png")) else []
    atlases += sorted({p.parent.name for p in folder.glob("*/atlas*.png")})  # atlas A B
    parts = []
    if atlases:
        compare = _pictures(folder, [("compare.png", "the robots' atlases side by side",
                                      "atlas comparison")], embed, link)
        parts += ["<h2>Atlases</h2>", compare,
                  *(_atlas_section(folder, a, embed, link) for a in atlases)]
    if sweeps:
        parts += ["<h2>Sweeps</h2>", *(_sweep_section(folder, s, embed, link) for s in sweeps)]
    return "\n".join(parts)


def index_html(results: list[Result], robots: list[str] | Mapping[str, str], folder: Path,
               embed: bool = False, *, made_by: str = "planar-sym demo",
               link: bool = False) -> str:
    """The whole page for the studies ``results`` and the robots ``robots`` in ``folder``.

    Parameters
    ----------
    results : list of Result
        Studies, in page order; their pictures ``<name>.png``, ``<name>_split.png`` and
        ``<name>.gif`` and table ``<name>.csv`` are linked where present in ``folder``.
    robots : list of str, or mapping of str to str
        Robot names: each gets its drawing ``<robot>.png`` (where present) and its equations;
        or {name: description file or generated folder} for robots that are not built in.
        The robots of the studies are added if missing, so every study's robot link resolves.
    folder : Path
        Where the page and its pictures are (``index.html`` is written there).
    embed : bool
        Inline the pictures as data URIs (one self-contained file, several MB for a full demo)
        instead of relative references.
    made_by : str
        The command said to have made the page.
    link : bool
        Make each picture a link to its file, to open it at full size (not with ``embed``).

    Returns
    -------
    str
        A complete HTML5 document, UTF-8, with no reference outside ``folder``.
    """
    folder = Path(folder)
    robots = dict(robots) if isinstance(robots, Mapping) else {r: r for r in robots}
    for r in results:
        if r.robot:
            robots.setdefault(r.robot, r.robot)
    toc = "".join(f'<tr><td><a href="#study-{_e(r.name)}">{_e(r.name)}</a></td>'
                  f"<td>{_e(r.summary)}</td><td class=\"peaks\">"
                  + "<br>".join(map(_e, peak_lines(r))) + "</td></tr>" for r in results)
    nav = " ".join(f'<a href="#robot-{_e(r)}">{_e(r)}</a>' for r in robots)
    intro = (f"<h1>planar-sym results</h1><p>Made by <code>{_e(made_by)}</code>: "
             f"{len(results)} studies and {len(robots)} robots. Column units are in the CSV "
             "headers (<code>t_s</code>, <code>q1_rad</code>, <code>tau1_n_m</code>, ...); "
             "this page needs no network.</p>")
    studies = ("<h2>Studies</h2><table><tr><th>study</th><th>what</th><th>peak |torque| "
               f"(N*m; N for a slider)</th></tr>{toc}</table>")
    body = [intro, f"<nav>robots: {nav}</nav>", studies,
            *(study_section(r, folder, embed, link) for r in results),
            "<h2>Robots</h2>",
            *(robot_section(name, folder, embed, source, link) for name, source in robots.items()),
            other_results(folder, results, embed, link)]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>planar-sym results</title><style>{_CSS}</style></head><body>"
            + "\n".join(body) + "</body></html>\n")


def write_index(results: list[Result], robots: list[str] | Mapping[str, str], folder: Path,
                embed: bool = False, **options) -> Path:
    """Write ``folder/index.html`` (``index_html``, with its keyword ``options``), whole or not
    at all; returns its path."""
    path = Path(folder) / "index.html"
    page = index_html(results, robots, folder, embed, **options)
    with atomic_files([path]) as (tmp,):
        tmp.write_text(page, encoding="utf-8")
    return path
