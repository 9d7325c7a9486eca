"""A real browser for the replay's tests: Debian's Chromium driven by Playwright, with software
WebGL (SwiftShader through ANGLE: with `--use-gl=swiftshader` WebGL fails and the page stays
white). A machine without Chromium or Playwright skips these tests and says why; CI installs
both (`.ci/run` and the test extra)."""

from __future__ import annotations

import contextlib
import dataclasses
import os
from collections.abc import Iterator
from pathlib import Path

import cv2
import numpy as np
import pytest

CHROMIUM = Path(os.environ.get("HSR_HANDOVER_CHROMIUM", "/usr/bin/chromium"))
SOFTWARE_WEBGL = ("--use-angle=swiftshader", "--enable-unsafe-swiftshader")
NO_WEBGL = ("--disable-3d-apis",)
# Root in a container needs no sandbox; the rest keeps Chromium off the (closed) network.
QUIET = ("--no-sandbox", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--disable-quic")  # fmt: skip
VIEWPORT = {"width": 640, "height": 480}
LOAD_TIMEOUT_MS = 120_000  # a 10 MB replay decodes in a few seconds; CI machines are slower
DRAWN_MS = 400  # ms given to the viewer to draw after a seek


def require_browser():
    """Playwright's sync API, or skip the test with the reason."""
    if not CHROMIUM.exists():
        pytest.skip(f"no Chromium at {CHROMIUM}: install Debian's chromium (.ci/run does)")
    return pytest.importorskip(
        "playwright.sync_api", reason="Playwright is not installed: pip install -e '.[test]'"
    )


@dataclasses.dataclass
class ReplayPage:
    """An open replay: the page, its console errors and uncaught exceptions, and every URL
    it requested."""

    page: object
    errors: list[str]
    requests: list[str]

    def wait_for_viewer(self) -> None:
        """Until Meshcat's viewer has loaded the recording's animation."""
        self.page.wait_for_function(
            "typeof viewer !== 'undefined' && viewer.animator.actions.length > 0",
            timeout=LOAD_TIMEOUT_MS,
        )

    def frame(self, time: float) -> np.ndarray:
        """The canvas (BGR) with the recording paused at `time` (s)."""
        self.page.evaluate(f"viewer.animator.pause(); viewer.animator.seek({float(time)})")
        self.page.wait_for_timeout(DRAWN_MS)
        png = self.page.locator("canvas").first.screenshot()
        return cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)

    def set_visible(self, path: str, visible: bool) -> None:
        """Switch a Meshcat path on or off, as the viewer's controls do."""
        command = {"type": "set_property", "path": path, "property": "visible", "value": visible}
        self.page.evaluate("command => viewer.handle_command(command)", command)

    def click_checkbox(self, path: str) -> bool:
        """Click the visibility checkbox of `path` in the viewer's controls, as a user does;
        returns whether it is ticked afterwards."""
        script = _walk(
            "const box = last.vis_controller.domElement.querySelector('input');"
            "box.click(); return box.checked;"
        )
        return bool(self.page.evaluate(script, path))

    def ticked(self, path: str) -> bool:
        """Whether the checkbox of `path` in the viewer's controls is ticked."""
        script = _walk("return last.vis_controller.domElement.querySelector('input').checked;")
        return bool(self.page.evaluate(script, path))

    def play(self, seconds: float) -> None:
        """Play the recording from where it is for `seconds` of wall time, then pause."""
        self.page.evaluate("viewer.animator.play()")
        self.page.wait_for_timeout(int(1000 * seconds))
        self.page.evaluate("viewer.animator.pause()")

    def shown(self, path: str) -> bool:
        """Whether the object at `path` is drawn: it and every parent visible."""
        return bool(self.page.evaluate(_walk("return nodes.every(n => n.object.visible);"), path))

    def visible(self, path: str) -> bool:
        """The `visible` property of the object at `path` alone."""
        return bool(self.page.evaluate(_walk("return last.object.visible;"), path))

    def world_position(self, path: str) -> np.ndarray:
        """Where the object at `path` is in the world (m; Meshcat's world is Drake's, z up)."""
        script = _walk(
            "const p = last.object.getWorldPosition(new MeshCat.THREE.Vector3());"
            "return [p.x, p.y, p.z];"
        )
        return np.array(self.page.evaluate(script, path))

    def evaluate(self, script: str, argument=None):
        return self.page.evaluate(script, argument)

    def duration(self) -> float:
        """The recording's length (s)."""
        return float(self.page.evaluate("viewer.animator.duration"))

    def network_requests(self) -> list[str]:
        """Requests that would leave the machine (the page itself and its data: URLs do not)."""
        return [url for url in self.requests if not url.startswith(("file:", "data:"))]


def _walk(body: str) -> str:
    """A script of one argument, a Meshcat path, running `body` with `nodes`, the scene tree's
    nodes from the root to that path (none created on the way), and `last`, the path's."""
    return (
        "path => { const nodes = [viewer.scene_tree];"
        " for (const name of path.split('/').filter(part => part.length > 0)) {"
        "  const next = nodes[nodes.length - 1].children[name];"
        "  if (next === undefined) { throw new Error('no ' + name + ' in ' + path); }"
        "  nodes.push(next); }"
        f" const last = nodes[nodes.length - 1]; {body} }}"
    )


@contextlib.contextmanager
def open_replay(path: Path, webgl: bool = True) -> Iterator[ReplayPage]:
    """`path` opened from a file:// URL in headless Chromium (with no WebGL if not `webgl`)."""
    sync_api = require_browser()
    args = [*QUIET, *(SOFTWARE_WEBGL if webgl else NO_WEBGL)]
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), args=args)
        try:
            page = browser.new_page(viewport=VIEWPORT)
            errors: list[str] = []
            requests: list[str] = []
            page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
            page.on("pageerror", lambda error: errors.append(str(error)))
            page.on("request", lambda request: requests.append(request.url))
            page.goto(Path(path).resolve().as_uri(), timeout=LOAD_TIMEOUT_MS)
            yield ReplayPage(page, errors, requests)
        finally:
            browser.close()


def red_mask(image: np.ndarray) -> np.ndarray:
    """Where the image (BGR) is a strong red (the mutual area's colour)."""
    blue, green, red = (image[..., k].astype(int) for k in range(3))
    return (red > 150) & (green < 80) & (blue < 80)


def red_pixels(image: np.ndarray) -> int:
    return int(red_mask(image).sum())


def distinct_colours(image: np.ndarray) -> int:
    return len(np.unique(image.reshape(-1, 3), axis=0))


def changed_pixels(a: np.ndarray, b: np.ndarray, threshold: int = 30) -> int:
    """Pixels whose colour differs by more than `threshold` (summed over B, G, R)."""
    return int((np.abs(a.astype(int) - b.astype(int)).sum(axis=2) > threshold).sum())
