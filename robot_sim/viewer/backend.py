"""The contract between :class:`robot_sim.viewer.visualizer.Visualizer` and the things that
show a :class:`~robot_sim.viewer.session.ViewerSession`: an offscreen renderer, a Qt
window, a browser.

A backend is built from a session and a picture size in pixels (width, height); the
session is the one source of what is shown (robot, joint values, options, trail, camera,
world).  ``Visualizer`` changes the session and then calls :meth:`Backend.refresh`; it
paces a trajectory with :meth:`Backend.wait` when :attr:`Backend.realtime` is true.

Backends are named in :data:`BACKENDS` as ``"module:Class"`` and imported only when asked
for, so ``import robot_sim`` never loads Qt, OpenGL or a web server.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

import numpy as np

if TYPE_CHECKING:
    from robot_sim.viewer.session import ViewerSession

#: Backend name -> "module:Class", imported on request by Visualizer.
BACKENDS = {
    "offscreen": "robot_sim.viewer.offscreen_backend:OffscreenBackend",
    "window": "robot_sim.qt.backend:WindowBackend",
    "web": "robot_sim.web.backend:WebBackend",
}


@runtime_checkable
class Backend(Protocol):
    """What shows a session.  ``size`` is (width, height) in pixels; ``options`` are the
    backend's own keywords (e.g. a web server's host and port)."""

    #: True when :meth:`wait` lets wall time pass (a window, a browser): ``Visualizer.play``
    #: then shows each sample at its time.  False offscreen: every sample is rendered at
    #: once, one frame per sample.
    realtime: bool

    def __init__(self, session: ViewerSession, *, size: tuple[int, int], **options: Any) -> None: ...

    def refresh(self) -> None:
        """The session changed (q, options, robot, trail, ...): show it now."""

    def capture(self) -> np.ndarray:
        """The picture shown, (H, W, 3) uint8 RGB, top row first."""

    def wait(self, seconds: float) -> None:
        """Let ``seconds`` of wall time pass while serving the backend's events (a window's
        input, a browser's requests); offscreen, return at once."""

    def close(self) -> None:
        """Release the backend (close the window, stop the server, free the GL context).
        Calling it twice is harmless."""
