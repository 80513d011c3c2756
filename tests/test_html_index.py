"""``results/index.html`` (``outputs.html_index``): its content, the demo's hook, and a real
headless Chromium that opens it with no network.

The browser is driven through the DevTools protocol over a pipe (``--remote-debugging-pipe``:
file descriptors 3 and 4, NUL-separated JSON), so no WebSocket package is needed (POSIX only,
as Debian's Chromium is). It records
every request (none may leave the folder), every console message and failed load, checks each
picture decoded, that a GIF animation plays (two screenshots of it differ), and takes a
screenshot whose plot region must not be blank.

Chromium is Debian's package (``.ci/install-browser``). Without it the browser tests skip,
unless ``PLANAR_SYM_REQUIRE_BROWSER=1`` (the Makefile's test set-up), where they fail.
"""

from __future__ import annotations

import base64
import fcntl
import io
import json
import os
import re
import select
import shutil
import signal
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import planar_sym as ps
from planar_sym.commands.draw import save_drawing
from planar_sym.commands.run import animate_study
from planar_sym.outputs.html_index import index_html, write_index
from planar_sym.outputs.results import write
from planar_sym.study.run import load_study

#: studies of the page under test: an inverse-dynamics move of a tree and of a closed chain,
#: and a forward run (no torque)
STUDIES = ("serial_2dof_joint_move", "five_bar_type1_move_x", "serial_2dof_free_swing")
SAMPLES = 41
SHOT = (1280, 2000)  # screenshot size, pixels
SRC = re.compile(r'\b(?:src|href)="([^"]*)"')


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> tuple[Path, list]:
    """A results folder as ``planar-sym demo`` leaves it, for three studies and two robots
    (pictures at small sizes), without its index."""
    out = tmp_path_factory.mktemp("results")
    results = []
    for name in STUDIES:
        result = ps.run_study(name, SAMPLES)
        write(result, out, split=bool(result.split))
        animate_study(load_study(name), out / f"{name}.gif", frames=8, fps=10.0, dpi=40,
                      figsize=(5.0, 4.2))
        results.append(result)
    for robot in ("serial_2dof", "five_bar_type1"):
        save_drawing(robot, out / f"{robot}.png", dpi=50)
    return out, results


# -- the page's content ----------------------------------------------------------------

def test_page_shows_every_study_and_robot_with_its_numbers(folder):
    out, results = folder
    page = index_html(results, ["serial_2dof"], out)
    for r in results:
        assert f'id="study-{r.name}"' in page and r.summary in page
        for key, value in r.peak_torques().items():
            assert f"peak |{key}| = {value:.6g} N*m" in page  # this process's own peaks
    assert "no torque (forward dynamics, zero torque)" in page  # the free swing
    # the studies' robots are added: five_bar_type1 was not asked for, its study needs it
    for robot in ("serial_2dof", "five_bar_type1"):
        eq = ps.equations(robot).text
        assert f"<pre>{eq.replace('&', '&amp;').replace('<', '&lt;').replace('>', '&gt;')}" \
               "</pre>" in page.replace("&#x27;", "'").replace("&quot;", '"')
    refs = SRC.findall(page)
    local = [r for r in refs if not r.startswith("#")]
    # every picture and table written, and nothing else: all relative, all present
    assert sorted(local) == sorted(p.name for p in out.iterdir())
    assert not [r for r in refs if re.match(r"[a-z]+:", r)], "a reference leaves the folder"


def test_embedded_page_carries_the_files_themselves(folder):
    out, results = folder
    page = index_html(results[:1], [], out, embed=True)
    name = results[0].name
    uris = re.findall(r'src="data:image/(png|gif);base64,([^"]+)"', page)
    assert len(uris) == 4  # plot, split, animation, drawing
    blobs = {base64.b64decode(data) for _, data in uris}
    for suffix in (".png", "_split.png", ".gif"):
        assert (out / f"{name}{suffix}").read_bytes() in blobs
    assert (out / "serial_2dof.png").read_bytes() in blobs
    assert f'href="{name}.csv"' in page  # the table stays a link


def test_write_index_is_whole_or_nothing(folder, tmp_path, monkeypatch):
    out, results = folder
    target = tmp_path / "res"
    shutil.copytree(out, target)
    path = write_index(results, [], target)
    assert path == target / "index.html" and path.read_text().endswith("</html>\n")
    from planar_sym.outputs import html_index

    def broken(*args, **kwargs):
        raise ps.PlanarSymError("simulated failure")

    monkeypatch.setattr(html_index, "index_html", broken)
    path.unlink()
    with pytest.raises(ps.PlanarSymError):
        write_index(results, [], target)
    assert not (target / "index.html").exists()
    assert not [p for p in target.iterdir() if p.name.startswith(".")]


def test_demo_writes_index_html_beside_readme(tmp_path, monkeypatch):
    """The demo's hook, on two studies and one robot (the whole demo is tested elsewhere)."""
    from planar_sym.cli import main
    from planar_sym.model import description
    from planar_sym.study import builtin

    monkeypatch.setattr(builtin, "names", lambda: ["serial_2dof_joint_move",
                                                   "five_bar_type2_move_y"])
    monkeypatch.setattr(description, "builtin_robots", lambda: ["five_bar_type2"])
    out = tmp_path / "demo"
    assert main(["--quiet", "demo", "--out", str(out), "--samples", "7", "--frames", "2"]) == 0
    page = (out / "index.html").read_text()
    assert (out / "README.md").is_file()
    local = {r for r in SRC.findall(page) if not r.startswith("#")}
    assert local == {p.name for p in out.iterdir()} - {"index.html", "README.md"}
    peak = ps.run_study("five_bar_type2_move_y", 7).peak_torques()["tau3"]
    assert f"peak |tau3| = {peak:.6g} N*m" in page


# -- a real browser --------------------------------------------------------------------

class DevTools:
    """Chromium driven through the DevTools protocol on a pipe (fd 3: commands in, fd 4:
    replies and events out), headless and with no network."""

    def __init__(self, exe: str, profile: Path):
        # pipe ends numbered 10 and up, so that placing them at 3 and 4 cannot overwrite one
        # another; posix_spawn places them (no Python runs between fork and exec)
        to_browser, self._write = (_high(fd) for fd in os.pipe())
        self._read, from_browser = (_high(fd) for fd in os.pipe())
        argv = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                "--no-first-run", "--disable-background-networking",
                "--disable-component-update", "--disable-sync", "--disable-extensions",
                "--host-resolver-rules=MAP * ~NOTFOUND", f"--user-data-dir={profile}",
                f"--window-size={SHOT[0]},{SHOT[1]}", "--remote-debugging-pipe", "about:blank"]
        actions = [(os.POSIX_SPAWN_OPEN, fd, os.devnull, os.O_RDWR, 0) for fd in (0, 1, 2)]
        actions += [(os.POSIX_SPAWN_DUP2, to_browser, 3), (os.POSIX_SPAWN_DUP2, from_browser, 4)]
        # its own process group: the browser's helper processes end with it
        self.pid = os.posix_spawn(exe, argv, os.environ, file_actions=actions, setpgroup=0)
        os.close(to_browser)
        os.close(from_browser)
        self._buffer, self._id, self.events = b"", 0, []
        target = self.call("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.call("Target.attachToTarget", targetId=target,
                                 flatten=True)["sessionId"]
        for domain in ("Page", "Runtime", "Log", "Network"):
            self.call(f"{domain}.enable", page=True)
        self.call("Emulation.setDeviceMetricsOverride", page=True, width=SHOT[0],
                  height=SHOT[1], deviceScaleFactor=1, mobile=False)

    def call(self, method: str, page: bool = False, timeout: float = 60.0, **params) -> dict:
        """Send one command (to the page's session if ``page``); events meanwhile are kept."""
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params}
        if page:
            msg["sessionId"] = self.session
        os.write(self._write, json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + timeout
        while True:
            reply = self._next(deadline)
            if reply.get("id") == self._id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]
            self.events.append(reply)

    def wait_for(self, event: str, timeout: float = 60.0) -> dict:
        deadline = time.monotonic() + timeout
        for seen in self.events:
            if seen.get("method") == event:
                return seen
        while True:
            msg = self._next(deadline)
            self.events.append(msg)
            if msg.get("method") == event:
                return msg

    def _next(self, deadline: float) -> dict:
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0 or not select.select([self._read], [], [], left)[0]:
                raise TimeoutError("Chromium did not answer in time")
            chunk = os.read(self._read, 1 << 20)
            if not chunk:
                raise EOFError("Chromium closed the DevTools pipe")
            self._buffer += chunk
        raw, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(raw)

    def open(self, url: str) -> None:
        self.events.clear()
        self.call("Page.navigate", page=True, url=url)
        self.wait_for("Page.loadEventFired")

    def js(self, expression: str):
        out = self.call("Runtime.evaluate", page=True, expression=expression,
                        returnByValue=True, awaitPromise=True)
        assert "exceptionDetails" not in out, out["exceptionDetails"]
        return out["result"]["value"]

    def screenshot(self, clip: dict | None = None) -> Image.Image:
        params = {"format": "png"}
        if clip:
            params["clip"] = {**clip, "scale": 1}
        data = self.call("Page.captureScreenshot", page=True, **params)["data"]
        return Image.open(io.BytesIO(base64.b64decode(data))).convert("RGB")

    def problems(self) -> list[str]:
        """Console errors and warnings, uncaught exceptions, failed loads, and any request
        that is not for a local file or a data URI, since the last ``open``."""
        found = []
        for e in self.events:
            method, p = e.get("method"), e.get("params", {})
            if method == "Runtime.consoleAPICalled" and p["type"] in ("error", "warning",
                                                                       "assert"):
                found.append(f"console {p['type']}: {p['args']}")
            elif method == "Runtime.exceptionThrown":
                found.append(f"exception: {p['exceptionDetails']}")
            elif method == "Log.entryAdded" and p["entry"]["level"] in ("error", "warning"):
                found.append(f"log {p['entry']['level']}: {p['entry']['text']} "
                             f"({p['entry'].get('url', '')})")
            elif method == "Network.loadingFailed":
                found.append(f"failed load: {p['errorText']}")
            elif method == "Network.requestWillBeSent":
                url = p["request"]["url"]
                if not url.startswith(("file://", "data:")):
                    found.append(f"request leaves the folder: {url}")
        return found

    def close(self) -> None:
        try:
            self.call("Browser.close", timeout=10)
        except (RuntimeError, TimeoutError, EOFError, OSError):
            pass
        deadline = time.monotonic() + 15
        while os.waitpid(self.pid, os.WNOHANG) == (0, 0):
            if time.monotonic() > deadline:  # not closed: end the group this test started
                os.killpg(self.pid, signal.SIGKILL)
                os.waitpid(self.pid, 0)
                break
            time.sleep(0.05)
        os.close(self._read)
        os.close(self._write)


def _high(fd: int) -> int:
    """``fd`` moved to a descriptor numbered 10 or more (close-on-exec, as ``os.pipe`` made it)."""
    moved = fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10)
    os.close(fd)
    return moved


def chromium() -> str:
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        why = "Chromium is not installed: run .ci/install-browser (as root) to install it"
        if os.environ.get("PLANAR_SYM_REQUIRE_BROWSER") == "1":
            pytest.fail(f"PLANAR_SYM_REQUIRE_BROWSER=1 but {why}")
        pytest.skip(why)
    return exe


def test_a_missing_browser_skips_or_fails(monkeypatch):
    """Skipped with how to install it; failed where the browser is required (the Makefile)."""
    monkeypatch.setattr(shutil, "which", lambda name: None)
    monkeypatch.delenv("PLANAR_SYM_REQUIRE_BROWSER", raising=False)
    with pytest.raises(pytest.skip.Exception, match=r"run \.ci/install-browser"):
        chromium()
    monkeypatch.setenv("PLANAR_SYM_REQUIRE_BROWSER", "1")
    with pytest.raises(pytest.fail.Exception, match=r"REQUIRE_BROWSER=1 .*install-browser"):
        chromium()


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    tools = DevTools(chromium(), tmp_path_factory.mktemp("chromium-profile"))
    yield tools
    tools.close()


IMAGES = """[...document.images].map(i => ({src: i.getAttribute('src').slice(0, 60),
  ok: i.complete && i.naturalWidth > 0, w: i.naturalWidth, h: i.naturalHeight}))"""
RECT = """(() => {{ const i = [...document.images].find(i => i.getAttribute('src')
  .{test}); i.scrollIntoView(); const r = i.getBoundingClientRect();
  return {{x: r.x, y: r.y, width: r.width, height: r.height}}; }})()"""


def _box(browser: DevTools, test: str) -> dict:
    """Bounding box (CSS pixels, after scrolling it into view) of the first image whose src
    passes the JavaScript string test ``test`` (e.g. ``endsWith('.gif')``)."""
    box = browser.js(RECT.format(test=test))
    box["y"] += browser.js("window.scrollY")  # screenshot clips are in page coordinates
    return box


def test_index_opens_offline_in_chromium(browser, folder, tmp_path):
    out, results = folder
    path = write_index(results, ["serial_2dof"], out)
    browser.open(path.as_uri())
    assert browser.problems() == []
    images = browser.js(IMAGES)
    pictures = sorted(p.name for p in out.iterdir() if p.suffix in (".png", ".gif"))
    assert len(images) == len(pictures) == 3 * 3 + 2  # plot, split, GIF of 3 studies; 2 drawings
    assert all(i["ok"] for i in images), [i for i in images if not i["ok"]]
    # the sizes decoded are the files' own
    on_disk = {p: Image.open(out / p).size for p in pictures}
    assert sorted((i["w"], i["h"]) for i in images) == sorted(on_disk.values())
    # the numbers a reader sees are this process's
    text = browser.js("document.body.innerText")
    peak = ps.run_study("five_bar_type1_move_x", SAMPLES).peak_torques()["tau3"]
    assert f"peak |tau3| = {peak:.6g} N*m" in text
    # the equations are on the page, whole
    pre = browser.js("document.querySelector('#robot-serial_2dof pre').textContent")
    assert pre == ps.equations("serial_2dof").text

    shot = browser.screenshot()
    shot.save(tmp_path / "index.png")
    assert shot.size == SHOT
    pixels = np.asarray(shot)
    assert len(np.unique(pixels.reshape(-1, 3), axis=0)) > 200, "a flat page"
    # the first study's plot, where the page put it: drawn, with matplotlib's blue line
    box = _box(browser, "endsWith('serial_2dof_joint_move.png')")
    plot = np.asarray(browser.screenshot(box)).astype(int)
    assert (np.abs(plot - 255).sum(axis=2) > 60).mean() > 0.03, "the plot region is blank"
    blue = (np.abs(plot - (31, 119, 180)).sum(axis=2) < 60).sum()  # tab:blue, the torques
    assert blue > 200, f"only {blue} pixels of the torque lines"


def test_animation_plays_in_chromium(browser, folder):
    out, results = folder
    path = write_index(results[:1], [], out)
    browser.open(path.as_uri())
    assert browser.problems() == []
    box = _box(browser, "endsWith('.gif')")
    assert box["width"] > 50 and box["height"] > 50
    first = np.asarray(browser.screenshot(box)).astype(int)
    frames = [first]
    for _ in range(5):  # 8 frames at 10 fps: a different one within a few tenths of a second
        time.sleep(0.3)
        frames.append(np.asarray(browser.screenshot(box)).astype(int))
        if np.abs(frames[-1] - first).sum() > 0:
            break
    assert np.abs(frames[-1] - first).sum() > 0, "the GIF does not move"


def test_embedded_index_opens_alone(browser, folder, tmp_path):
    """The embed=True page, moved away from its pictures, still shows them all."""
    out, results = folder
    page = tmp_path / "alone.html"
    page.write_text(index_html(results, [], out, embed=True))
    browser.open(page.as_uri())
    assert browser.problems() == []
    images = browser.js(IMAGES)
    assert len(images) == 3 * 3 + 2 and all(i["ok"] for i in images)
