"""A real browser for the web view's tests: Debian's chromium (installed by the Makefile
with the other system packages), driven by Playwright without Playwright's own browser
download, headless, with a fresh profile and every host but 127.0.0.1 blocked twice
over: the resolver maps every other name to nothing, and every request leaving the
machine is aborted and recorded (tests assert that none was made)."""
from __future__ import annotations

import re
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterator
from urllib.parse import urlsplit

import numpy as np
import pytest

CHROMIUM = Path("/usr/bin/chromium")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run",
         "--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1"]
#: Screenshots for the closing note (outside the repository).
SHOTS = Path("/work/wt/web-shots")
#: The page's size in the tests.
VIEWPORT = {"width": 1200, "height": 800}
#: Servers being stopped (Served.close), waited for when the test's browser has closed.
STOPPING: list[threading.Thread] = []


@dataclass
class Traffic:
    """Every request a page made, and those aborted because they would leave the machine."""

    requests: list[str] = field(default_factory=list)
    blocked: list[str] = field(default_factory=list)


def is_local(url: str) -> bool:
    """True for a request that stays on this machine: 127.0.0.1, a file, a blob, data."""
    parts = urlsplit(url)
    if parts.scheme in ("file", "blob", "data", "about"):
        return True
    return parts.hostname == "127.0.0.1"


@pytest.fixture(scope="module")
def playwright_driver() -> Iterator[Any]:
    from playwright.sync_api import sync_playwright

    assert CHROMIUM.exists(), "the browser tests need Debian's chromium (make setup installs it)"
    with sync_playwright() as playwright:
        yield playwright


@pytest.fixture()
def browser(playwright_driver: Any, tmp_path: Path) -> Iterator[Any]:
    """Chromium with a fresh profile for each test (nothing a page stored carries over)."""
    context = playwright_driver.chromium.launch_persistent_context(
        str(tmp_path / "chromium-profile"), executable_path=str(CHROMIUM), headless=True, args=FLAGS,
        viewport=VIEWPORT)
    yield context
    context.close()
    while STOPPING:
        STOPPING.pop().join(timeout=10)


def open_page(browser: Any, url: str, traffic: Traffic) -> Any:
    """A new tab at ``url``: requests recorded in ``traffic``, those leaving the machine aborted."""
    page = browser.new_page()

    def route(request_route: Any) -> None:
        url = request_route.request.url
        traffic.requests.append(url)
        if is_local(url):
            request_route.continue_()
        else:
            traffic.blocked.append(url)
            request_route.abort()

    page.route("**/*", route)
    page.goto(url)
    return page


def wait_until(condition: Callable[[], bool], timeout: float = 300.0, what: str = "condition") -> None:
    """Return once ``condition()`` holds; fail after ``timeout`` seconds.  Generous: a page's
    event can be the first to need a compiled kernel (IK, collision, the pick task), which
    on a fresh clone another process of the suite may be compiling (tests/compile_lock.py):
    tens of seconds each on a loaded machine."""
    end = time.monotonic() + timeout
    while not condition():
        assert time.monotonic() < end, f"timed out waiting for {what}"
        time.sleep(0.05)


class Served:
    """A WebViewer (robot-sim --web's loop) running in a thread for one test."""

    def __init__(self, session: Any, robot_arg: str) -> None:
        from robot_sim.web.serve import WebViewer

        self.viewer = WebViewer(session, robot_arg, host="127.0.0.1", port=None)
        self.thread = threading.Thread(target=self.viewer.run, daemon=True)
        self.thread.start()

    @property
    def session(self) -> Any:
        return self.viewer.backend.session

    def close(self) -> None:
        """Stop the loop now and the server in the background: viser's stop waits 6 s for
        the connections a browser still holds, and the test's browser closes only after the
        test (the ``browser`` fixture then waits for the stop to end)."""
        stopping = threading.Thread(target=self.viewer.close, daemon=True)
        stopping.start()
        STOPPING.append(stopping)
        self.thread.join(timeout=10)


#: Every label's box on the page (JavaScript): the panel's layout.
LABEL_BOXES = "() => Array.from(document.querySelectorAll('label'), l => { const b = l.getBoundingClientRect(); " \
              "return [b.x, b.y, b.width, b.height]; })"


def connected(page: Any, backend: Any) -> None:
    """Wait until ``page`` is connected to ``backend``'s server (robot-sim --web's), draws,
    shows the panel's first update, and its controls have stopped moving (a render asked
    for while the page is still starting can be lost; a control clicked while the panel
    grows can move away from the click)."""
    wait_until(lambda: bool(backend.server.get_clients()), what="the page to connect")
    wait_until(lambda: page.locator("canvas").count() > 0, what="the page's canvas")
    page.get_by_text("manipulability", exact=False).first.wait_for()  # the panel's first update is in
    laid_out = [None]

    def settled() -> bool:  # the controls stayed where they are over the last 0.3 s
        now = page.evaluate(LABEL_BOXES)
        if now != laid_out[0]:
            laid_out[:] = [now]
            return False
        laid_out.append(now)
        return len(laid_out) > 6

    wait_until(settled, what="the panel's layout to settle")


def canvas_box(page: Any) -> dict[str, float]:
    """The 3D view's canvas in page pixels (x, y, width, height)."""
    box = page.locator("canvas").first.bounding_box()
    assert box is not None
    return box


def settled_capture(backend: Any, frames: int = 3) -> np.ndarray:
    """The browser's picture once two captures in a row agree (the page has drawn the
    last update)."""
    last = backend.capture()
    for _ in range(frames * 10):
        time.sleep(0.15)
        image = backend.capture()
        if np.array_equal(image, last):
            return image
        last = image
    return last


def control(page: Any, label: str) -> Any:
    """The panel's control labelled ``label`` (a slider, a text box, a checkbox): the
    element its <label for=...> names (a slider is a div, which get_by_label skips)."""
    tag = page.locator("label").filter(has_text=re.compile(f"^{re.escape(label)}$")).first
    tag.wait_for(state="attached")
    named = page.locator(f'[id="{tag.get_attribute("for")}"]')
    if named.count():
        return named.first
    # a text box carries the id of its own input library: the one input of the label's row
    return tag.locator("xpath=ancestor::div[contains(@class,'mantine-Flex-root')][1]"
                       "//input[not(@type='hidden')]").first


def click_at_fraction(page: Any, label: str, fraction: float) -> None:
    """Click the slider labelled ``label`` at ``fraction`` (0..1) of its track, scrolled
    into view first: a mouse click at page coordinates below the viewport lands nowhere,
    and the panel's readout above the joints can grow while the page runs."""
    track = control(page, label).locator(".mantine-Slider-track").first
    track.scroll_into_view_if_needed()
    box = track.bounding_box()
    assert box is not None, f"no slider {label!r} on the page"
    page.mouse.click(box["x"] + fraction * box["width"], box["y"] + box["height"] / 2)
