"""The browser view's numbers (a benchmark, not a test; needs Debian's chromium):

1. streaming: a UR5 under computed torque following the circle demo, served by
   ``robot-sim --web``'s loop to a connected headless Chromium: the simulation's
   real-time factor, the pose updates sent per second, and the frame rate the page draws
   at (software WebGL);
2. start-up: from starting ``robot-sim --web`` to the first arm drawn in the browser
   (the numba cache filled by a first run, which is not counted);
3. export: the size of ``--export-html`` of the UR5 pick task (25 frames a second) beside
   the size of viser's client page it embeds.

Run: ``PYTHONPATH=. .venv/bin/python benchmarks/web_bench.py``.  Medians of ``--repeats``.
"""
from __future__ import annotations

import argparse
import socket
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))

from browser_helpers import CHROMIUM, FLAGS, VIEWPORT  # noqa: E402

#: JavaScript measuring the page's frame rate over ``ms`` milliseconds (requestAnimationFrame).
FPS_JS = """ms => new Promise(done => { let n = 0; const t0 = performance.now();
  function frame() { n++; if (performance.now() - t0 < ms) requestAnimationFrame(frame);
                     else done(n / (performance.now() - t0) * 1000); }
  requestAnimationFrame(frame); })"""


def streaming(playwright, seconds: float, moving: bool = True) -> dict[str, float]:
    """The served UR5 under computed torque, following the circle demo (``moving``) or
    resting: real-time factor, updates sent per second, the page's frame rate."""
    from robot_sim.io.robot_file import load_robot
    from robot_sim.viewer.session import ViewerSession
    from robot_sim.web.serve import WebViewer

    session = ViewerSession(load_robot("ur5"), aspect=1.5)
    session.set_motion("ct")
    if moving:
        session.toggle_demo()
    viewer = WebViewer(session, "ur5", host="127.0.0.1", port=None)
    thread = threading.Thread(target=viewer.run, daemon=True)
    with tempfile.TemporaryDirectory() as profile:
        browser = playwright.chromium.launch_persistent_context(profile, executable_path=str(CHROMIUM), headless=True,
                                                               args=FLAGS, viewport=VIEWPORT)
        try:
            page = browser.new_page()
            page.goto(viewer.url)
            while not viewer.backend.server.get_clients():
                time.sleep(0.05)
            thread.start()
            time.sleep(2.0)  # the simulation and the page settle
            sim = viewer.backend.session.motion.sim
            sim_t0, frames0, wall0 = sim.time, viewer.frames_sent, time.perf_counter()
            fps = page.evaluate(FPS_JS, int(seconds * 1000))
            wall = time.perf_counter() - wall0
            result = {"rtf": (sim.time - sim_t0) / wall, "updates_per_s": (viewer.frames_sent - frames0) / wall,
                      "page_fps": float(fps)}
        finally:
            viewer.close()
            browser.close()
    return result


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def startup(playwright) -> float:
    """Seconds from starting ``robot-sim --web`` to the arm's pixels in the browser."""
    port = _free_port()
    with tempfile.TemporaryDirectory() as profile:
        browser = playwright.chromium.launch_persistent_context(profile, executable_path=str(CHROMIUM), headless=True,
                                                               args=FLAGS, viewport=VIEWPORT)
        page = browser.new_page()
        start = time.perf_counter()
        server = subprocess.Popen([sys.executable, str(ROOT / "simulator.py"), "--robot", "ur5", "--web", "--port", str(port)],
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=ROOT)
        try:
            while True:
                try:
                    page.goto(f"http://127.0.0.1:{port}/", timeout=2000)
                    break
                except Exception:  # noqa: BLE001 - not listening yet
                    time.sleep(0.02)
            while True:  # the arm: light grey pixels (the dark theme's floor and grid are darker)
                shot = page.screenshot(clip={"x": 0, "y": 0, "width": 800, "height": 800}, type="png")
                from io import BytesIO

                from PIL import Image

                image = np.asarray(Image.open(BytesIO(shot)).convert("RGB")).astype(int)
                if (image.min(axis=-1) > 170).sum() > 500:
                    return time.perf_counter() - start
                assert time.perf_counter() - start < 60, "no arm after 60 s"
        finally:
            server.terminate()
            server.wait(10)
            browser.close()


def export_size(out: Path) -> tuple[int, int, float]:
    """(bytes of the exported pick page, bytes of viser's client page, seconds of motion)."""
    import viser

    done = subprocess.run([sys.executable, str(ROOT / "simulator.py"), "--robot", "ur5", "--demo", "pick",
                           "--export-html", str(out)], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert done.returncode == 0, done.stderr
    client = Path(viser.__file__).parent / "client" / "build" / "index.html"
    from robot_sim.io.robot_file import load_robot
    from robot_sim.viewer.pick_demo import plan_for

    return out.stat().st_size, client.stat().st_size, plan_for(load_robot("ur5"), None).duration


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=8.0, help="length of each streaming measurement")
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        startup(playwright)  # fills the numba cache; not counted
        starts, streams, idle = [], [], []
        for _ in range(args.repeats):  # alternated, so the machine's load falls on all alike
            starts.append(startup(playwright))
            streams.append(streaming(playwright, args.seconds))
            idle.append(streaming(playwright, args.seconds, moving=False)["page_fps"])
    print(f"start to first drawn arm: median {statistics.median(starts):.2f} s  (runs {', '.join(f'{s:.2f}' for s in starts)})")
    for key, label in (("rtf", "real-time factor"), ("updates_per_s", "pose updates sent per second"),
                       ("page_fps", "page frames per second (software WebGL)")):
        values = [s[key] for s in streams]
        print(f"UR5 ct, circle demo, streamed: {label}: median {statistics.median(values):.2f} "
              f"(runs {', '.join(f'{v:.2f}' for v in values)})")
    print(f"the same page, the arm at rest: page frames per second: median {statistics.median(idle):.2f} "
          f"(runs {', '.join(f'{v:.2f}' for v in idle)})")
    with tempfile.TemporaryDirectory() as folder:
        size, client, duration = export_size(Path(folder) / "pick.html")
    print(f"export of the UR5 pick task ({duration:.1f} s at 25 fps): {size / 1e6:.2f} MB, of which viser's client "
          f"{client / 1e6:.2f} MB; the motion {(size - client) / 1e6:.2f} MB")


if __name__ == "__main__":
    main()
