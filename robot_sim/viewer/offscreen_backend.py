"""The offscreen backend of ``rs.Visualizer``: the session rendered through OSMesa into an
image, no display, no Qt.  Not real time: ``play`` renders one frame per sample at once."""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from robot_sim import graphics as go
from robot_sim.viewer.session import ViewerSession


class OffscreenBackend:
    """Renders ``session`` at ``size`` = (width, height) pixels on every :meth:`refresh`;
    :attr:`frames` counts the frames rendered.  Takes no options."""

    realtime = False

    def __init__(self, session: ViewerSession, *, size: tuple[int, int], **options: Any) -> None:
        if options:
            raise TypeError(f"the offscreen backend takes no options, got {', '.join(sorted(options))}")
        self.session = session
        self.frames = 0
        self._renderer: go.OffscreenRenderer | None = go.OffscreenRenderer(*size)
        self._image: NDArray[np.uint8] | None = None

    def refresh(self) -> None:
        """Render the session now."""
        if self._renderer is None:
            raise RuntimeError("the offscreen backend is closed")
        session = self.session
        self._image = self._renderer.render(session.camera, session.scene(), session.options)[..., :3]
        self.frames += 1

    def capture(self) -> NDArray[np.uint8]:
        """The last picture rendered (rendered now if none), (H, W, 3) uint8 RGB."""
        if self._image is None:
            self.refresh()
        return self._image.copy()

    def wait(self, seconds: float) -> None:
        """Offscreen nothing is served: returns at once."""

    def close(self) -> None:
        """Free the GL context."""
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None
