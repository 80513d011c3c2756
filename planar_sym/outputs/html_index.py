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
"""

from __future__ import annotations

import base64
import html
from pathlib import Path
from urllib.parse import quote

from ..errors import PlanarSymError
from ..files import atomic_files
from ..study.result import Result

#: picture kinds of a study, in page order: (file suffix, caption)
STUDY_PICTURES = ((".png", "plot"), ("_split.png", "torque split into M qdd, C qd and g"),
                  (".gif", "animation"))
MIME = {".png": "image/png", ".gif": "image/gif", ".svg": "image/svg+xml"}

_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:1.5em auto;
max-width:1400px;padding:0 1em;color:#222;background:#fff}
h1{margin-bottom:0.2em}h2{border-bottom:2px solid #ddd;padding-bottom:0.2em;margin-top:2em}
table{border-collapse:collapse;font-size:0.9em}td,th{border:1px solid #ccc;padding:3px 8px;
text-align:left;vertical-align:top}th{background:#f3f3f3}
.pictures{display:flex;flex-wrap:wrap;gap:12px;align-items:flex-start}
figure{margin:0;flex:1 1 360px;max-width:460px}figcaption{font-size:0.8em;color:#555}
img{max-width:100%;height:auto;border:1px solid #eee}
.warning{color:#8a4b00;background:#fff4e0;padding:2px 6px}
pre{background:#f7f7f7;padding:0.8em;overflow-x:auto;font-size:0.8em;line-height:1.35}
.peaks{font-family:ui-monospace,monospace;font-size:0.9em}
nav a{margin-right:0.6em}
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


def _picture(src: str, caption: str, alt: str) -> str:
    return (f'<figure><img src="{_e(src)}" alt="{_e(alt)}" loading="eager">'
            f"<figcaption>{_e(caption)}</figcaption></figure>")


def peak_lines(result: Result) -> list[str]:
    """``tau<k> = <peak>`` with the unit (N*m, or N for a slider) per actuated joint; one line
    saying why when there is none (forward dynamics under zero torque)."""
    lines = [f"peak |{k}| = {v:.6g} {unit}"
             for k, (v, unit) in result.peak_torques_with_units().items()]
    return lines or ["no torque (forward dynamics, zero torque)"]


def study_section(result: Result, folder: Path, embed: bool) -> str:
    """One study: title, what it is, peak torques, its pictures found in ``folder``, CSV link."""
    t = result.get("t").values
    rows = [("robot", f'<a href="#robot-{_e(result.robot)}">{_e(result.robot)}</a>'),
            ("duration", f"{t[-1] - t[0]:.6g} s, {len(t)} samples"),
            ("peaks", '<span class="peaks">' + "<br>".join(map(_e, peak_lines(result)))
             + "</span>")]
    if result.solver:
        rows.append(("inverse kinematics", _e(result.solver)))
    csv = _source(folder, f"{result.name}.csv", embed=False)
    if csv is not None:
        link = f'<a href="{_e(csv)}">{_e(result.name)}.csv</a>'
        rows.append(("table", f"{link} (units in the column names)"))
    table = "<table>" + "".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in rows) + "</table>"
    pictures = []
    for suffix, caption in STUDY_PICTURES:
        src = _source(folder, f"{result.name}{suffix}", embed)
        if src is not None:
            pictures.append(_picture(src, caption, f"{result.name} {caption}"))
    note = f"<p><small>{_e(result.note)}</small></p>" if result.note else ""
    note += "".join(f'<p class="warning">warning: {_e(w)}</p>' for w in result.warnings)
    return (f'<section id="study-{_e(result.name)}"><h3>{_e(result.name)}</h3>'
            f"<p>{_e(result.summary)}</p>{table}{note}"
            f'<div class="pictures">{"".join(pictures)}</div></section>')


def robot_section(robot: str, folder: Path, embed: bool) -> str:
    """One robot: its drawing (``<robot>.png`` in ``folder``) and its equations as text."""
    from ..model.description import load as load_description
    from .equations import equations

    try:
        title = load_description(robot).title
    except PlanarSymError as exc:
        title = f"(description not readable: {exc})"
    src = _source(folder, f"{robot}.png", embed)
    drawing = _picture(src, "drawn configuration", f"{robot} drawn") if src else ""
    try:
        text = equations(robot).text
        eqs = (f"<details><summary>equations of motion (text form of "
               f"<code>planar-sym equations {_e(robot)}</code>)</summary>"
               f"<pre>{_e(text)}</pre></details>")
    except PlanarSymError as exc:  # said on the page, not skipped silently
        eqs = f"<p>equations not available: {_e(exc)}</p>"
    return (f'<section id="robot-{_e(robot)}"><h3>{_e(robot)}</h3><p>{_e(title)}</p>'
            f'<div class="pictures">{drawing}</div>{eqs}</section>')


def index_html(results: list[Result], robots: list[str], folder: Path,
               embed: bool = False) -> str:
    """The whole page for the studies ``results`` and the robots ``robots`` in ``folder``.

    Parameters
    ----------
    results : list of Result
        Studies, in page order; their pictures ``<name>.png``, ``<name>_split.png`` and
        ``<name>.gif`` and table ``<name>.csv`` are linked where present in ``folder``.
    robots : list of str
        Robot names: each gets its drawing ``<robot>.png`` (where present) and its equations.
        The robots of the studies are added if missing, so every study's robot link resolves.
    folder : Path
        Where the page and its pictures are (``index.html`` is written there).
    embed : bool
        Inline the pictures as data URIs (one self-contained file, several MB for a full demo)
        instead of relative references.

    Returns
    -------
    str
        A complete HTML5 document, UTF-8, with no reference outside ``folder``.
    """
    folder = Path(folder)
    robots = list(dict.fromkeys([*robots, *(r.robot for r in results if r.robot)]))
    toc = "".join(f'<tr><td><a href="#study-{_e(r.name)}">{_e(r.name)}</a></td>'
                  f"<td>{_e(r.summary)}</td><td class=\"peaks\">"
                  + "<br>".join(map(_e, peak_lines(r))) + "</td></tr>" for r in results)
    nav = " ".join(f'<a href="#robot-{_e(r)}">{_e(r)}</a>' for r in robots)
    intro = (f"<h1>planar-sym results</h1><p>Made by <code>planar-sym demo</code>: "
             f"{len(results)} studies and {len(robots)} robots. Column units are in the CSV "
             "headers (<code>t_s</code>, <code>q1_rad</code>, <code>tau1_n_m</code>, ...); "
             "this page needs no network.</p>")
    studies = ("<h2>Studies</h2><table><tr><th>study</th><th>what</th><th>peak |torque| "
               f"(N*m; N for a slider)</th></tr>{toc}</table>")
    body = [intro, f"<nav>robots: {nav}</nav>", studies,
            *(study_section(r, folder, embed) for r in results),
            "<h2>Robots</h2>", *(robot_section(r, folder, embed) for r in robots)]
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<title>planar-sym results</title><style>{_CSS}</style></head><body>"
            + "\n".join(body) + "</body></html>\n")


def write_index(results: list[Result], robots: list[str], folder: Path,
                embed: bool = False) -> Path:
    """Write ``folder/index.html`` (``index_html``), whole or not at all; returns its path."""
    path = Path(folder) / "index.html"
    page = index_html(results, robots, folder, embed)
    with atomic_files([path]) as (tmp,):
        tmp.write_text(page, encoding="utf-8")
    return path
