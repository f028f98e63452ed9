"""The browser backend of ``rs.Visualizer(robot, backend="web")``: a viser server showing
one viewer session (robot_sim.viewer.backend.Backend).

The server binds 127.0.0.1 unless ``host`` says otherwise (robot_sim.web.server);
:attr:`WebBackend.url` is the page to open.  :meth:`refresh` sends the session's state
(poses only once the meshes are there); :meth:`capture` returns what a connected browser
drew.  Every change to the session from the page or from the script happens under
:attr:`WebBackend.lock`, so a browser event never sees half an update.
"""
from __future__ import annotations

import html
import threading
import time
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robot_sim.web.camera import aim_initial_camera, point_camera
from robot_sim.web.scene import WebScene
from robot_sim.web.server import DEFAULT_HOST, server_url, start_server, stop_server

#: Seconds capture() waits for the browser's picture.
CAPTURE_TIMEOUT_S = 8.0
#: Height of the page embedded in a notebook (pixels).
NOTEBOOK_HEIGHT_PX = 520


class StaticPage:
    """A self-contained page shown inline by Jupyter (``_repr_html_``: an iframe holding
    the page itself, so the notebook needs no server to show it later)."""

    def __init__(self, page: str) -> None:
        self.page = page

    def _repr_html_(self) -> str:
        return (f'<iframe srcdoc="{html.escape(self.page, quote=True)}" width="100%" '
                f'height="{NOTEBOOK_HEIGHT_PX}" style="border:none"></iframe>')


class WebBackend:
    """A viser server showing ``session``; ``size`` (width, height) in pixels is the size of
    :meth:`capture`'s picture.  ``host``/``port``: where the server listens (None: a free
    port)."""

    realtime = True

    def __init__(self, session: Any, *, size: tuple[int, int] = (960, 720), host: str = DEFAULT_HOST,
                 port: int | None = None) -> None:
        width, height = (int(v) for v in size)
        if width < 1 or height < 1:
            raise ValueError(f"size: expected a positive width and height in pixels, got {size!r}")
        self.session = session
        self.size = (width, height)
        self.lock = threading.RLock()
        self.server = start_server(host, port, dark=session.options.theme == "dark")
        self.view = WebScene(self.server.scene)
        self._closed = False
        self.server.on_client_connect(self._on_connect)
        self.refresh()
        self.reset_cameras()

    @property
    def url(self) -> str:
        """The page showing the session (on this machine)."""
        return server_url(self.server)

    def _on_connect(self, client: Any) -> None:
        with self.lock:
            point_camera(client.camera, self.session.camera)

    def reset_cameras(self) -> None:
        """Every page (and pages still to come) looks from the session's camera."""
        with self.lock:
            aim_initial_camera(self.server, self.session.camera)
            for client in self.server.get_clients().values():
                point_camera(client.camera, self.session.camera)

    def set_session(self, session: Any) -> None:
        """Show ``session`` instead (e.g. another robot)."""
        with self.lock:
            self.session = session
            self.refresh()

    # ---- the Backend protocol ----
    def refresh(self) -> None:
        """Send the session's current state to every page."""
        with self.lock, self.server.atomic():
            self.view.sync(self.session)

    def capture(self) -> NDArray[np.uint8]:
        """(H, W, 3) uint8 RGB of what the first connected browser draws from the session's
        camera, at :attr:`size`.  RuntimeError when no browser is connected."""
        clients = self.server.get_clients()
        if not clients:
            raise RuntimeError(f"capture: no browser is connected; open {self.url} first")
        client = clients[min(clients)]
        width, height = self.size
        with self.lock:
            point_camera(client.camera, self.session.camera)
        image = client.get_render(height=height, width=width, transport_format="png", timeout=CAPTURE_TIMEOUT_S)
        return np.ascontiguousarray(np.asarray(image)[..., :3], dtype=np.uint8)

    def wait(self, seconds: float) -> None:
        """Let ``seconds`` of wall time pass (the server answers the page meanwhile); with
        ``math.inf``, until Ctrl+C or :meth:`close`."""
        end = time.monotonic() + seconds
        while not self._closed and (left := end - time.monotonic()) > 0.0:
            time.sleep(min(left, 1.0))

    def wait_for_browser(self, timeout: float = 30.0) -> bool:
        """Wait until a page is connected (at most ``timeout`` s); returns whether one is."""
        end = time.monotonic() + timeout
        while not self.server.get_clients():
            if time.monotonic() >= end:
                return False
            time.sleep(0.05)
        return True

    def close(self) -> None:
        """Stop the server (twice is harmless)."""
        if not self._closed:
            self._closed = True
            stop_server(self.server)

    # ---- notebooks and files ----
    def _repr_html_(self) -> str:
        """The live page in a notebook cell (while the server runs)."""
        return (f'<iframe src="{html.escape(self.url)}" width="100%" height="{NOTEBOOK_HEIGHT_PX}" '
                'style="border:none"></iframe>')

    def embed(self, trajectory: Any = None, fps: float | None = None) -> StaticPage:
        """The session (or ``trajectory`` played on it) as a self-contained page for a
        notebook cell: it stays in the saved notebook and needs no server."""
        from robot_sim.web.export import export_page

        with self.lock:
            return StaticPage(export_page(self.session, trajectory=trajectory, fps=fps))

    def export_html(self, path: str | Path, trajectory: Any = None, fps: float | None = None) -> Path:
        """Write the session (or ``trajectory`` played on it) as a self-contained page; see
        :func:`robot_sim.web.export.export_html`."""
        from robot_sim.web.export import export_html

        with self.lock:
            return export_html(self.session, path, trajectory=trajectory, fps=fps)
