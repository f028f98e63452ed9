"""``robot-sim --web``: serve the interactive viewer in the browser until Ctrl+C.

One loop in the main thread moves the session in wall-clock time (the simulation, the
demos, the pick playback, the animation toward the IK solution) and streams its poses at
``STREAM_HZ``; the page's events change the session from viser's threads under the
backend's lock (robot_sim.web.panel).  Every tab sees the same session.
"""
from __future__ import annotations

import sys
import threading
import time
from typing import Any, TextIO

from robot_sim.web.backend import WebBackend
from robot_sim.web.panel import WebPanel

#: Pose updates sent per second while something moves.
STREAM_HZ = 50.0
#: Widget updates (sliders, readout, timeline) per second.
PANEL_HZ = 8.0
#: The longest step the loop takes at once [s] (after a stall, time jumps no further).
MAX_STEP_S = 0.1


class WebViewer:
    """The served viewer: ``backend`` (the server and the scene) and ``panel`` (the page's
    controls) on ``session``; :meth:`run` loops until ``stop`` is set or Ctrl+C."""

    def __init__(self, session: Any, robot_arg: str, *, host: str, port: int | None,
                 size: tuple[int, int] = (960, 720)) -> None:
        self.backend = WebBackend(session, size=size, host=host, port=port)
        self.panel = WebPanel(self.backend, robot_arg)
        self.stop = threading.Event()
        self.frames_sent = 0  # loop passes that sent the session (for the benchmark)

    @property
    def url(self) -> str:
        return self.backend.url

    def run(self) -> None:
        """Move and stream the session until :attr:`stop` is set."""
        backend, period = self.backend, 1.0 / STREAM_HZ
        last = last_panel = time.perf_counter()
        while not self.stop.is_set():
            now = time.perf_counter()
            dt, last = min(now - last, MAX_STEP_S), now
            with backend.lock:
                session = backend.session
                if session.moving():
                    session.step(dt)
                backend.refresh()
                self.frames_sent += 1
            if now - last_panel >= 1.0 / PANEL_HZ:
                self.panel.tick()
                last_panel = now
            self.stop.wait(max(0.0, period - (time.perf_counter() - now)))

    def close(self) -> None:
        self.stop.set()
        self.backend.close()


def serve(session: Any, robot_arg: str, host: str, port: int | None, out: TextIO = sys.stdout) -> int:
    """Serve ``session`` at ``host``:``port`` until Ctrl+C; returns the exit status (0).
    Raises robot_sim.web.server.WebServerError before serving when the server cannot start."""
    viewer = WebViewer(session, robot_arg, host=host, port=port)
    print(f"robot-sim: serving the viewer at {viewer.url} (Ctrl+C stops)", file=out, flush=True)
    try:
        viewer.run()
    except KeyboardInterrupt:
        pass
    finally:
        viewer.close()
    return 0
