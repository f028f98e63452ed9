"""The window backend of ``rs.Visualizer``: the session shown in the program's main window,
with the script's loop owning time (MuJoCo's ``launch_passive`` and ``sync``, matplotlib's
interactive mode): every ``refresh`` and ``wait`` serves the window's events, so it stays
responsive between the script's calls, and the user can orbit, zoom and use its keys."""
from __future__ import annotations

import math
import sys
import time
import numpy as np
from numpy.typing import NDArray
from PyQt5 import QtCore, QtGui, QtWidgets

from robot_sim.qt.window import MainWindow, WindowOptions
from robot_sim.viewer.session import ViewerSession

#: How long one slice of :meth:`WindowBackend.wait` serves events before it checks whether
#: the window was closed [s].
WAIT_SLICE_S = 0.05


class WindowBackend:
    """Opens a main window on ``session`` whose view is ``size`` = (width, height) pixels
    (wider or taller where the docks need more room, e.g. the DH table of a 7-joint arm);
    ``robot_arg`` names the robot in the chooser (default: the robot's name)."""

    realtime = True

    def __init__(self, session: ViewerSession, *, size: tuple[int, int], robot_arg: str | None = None) -> None:
        self.app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
        self.window: MainWindow | None = MainWindow(session, WindowOptions(robot_arg=robot_arg or session.robot.name))
        self.window.show()
        self.app.processEvents()
        view = self.window.view.size()  # the docks take the rest of the window
        extra = self.window.size() - view
        self.window.resize(size[0] + extra.width(), size[1] + extra.height())
        self.window.view.setFocus()
        self.app.processEvents()

    @property
    def session(self) -> ViewerSession:
        """The session shown (a robot opened or edited in the window replaces it)."""
        return self._window().session

    def _window(self) -> MainWindow:
        if self.window is None:
            raise RuntimeError("the window backend is closed")
        return self.window

    def refresh(self) -> None:
        """Show the session now: widgets, picture and status follow it; events are served."""
        window = self._window()
        window.sync_widgets()
        window.start_motion()
        window.view.repaint()
        self.app.processEvents()

    def capture(self) -> NDArray[np.uint8]:
        """The view's picture (without its corner text), (H, W, 3) uint8 RGB."""
        image = self._window().view.grabFramebuffer().convertToFormat(QtGui.QImage.Format_RGB888)
        width, height = image.width(), image.height()
        bits = image.constBits()
        bits.setsize(image.byteCount())
        rows = np.frombuffer(bits, np.uint8).reshape(height, image.bytesPerLine())
        return rows[:, : width * 3].reshape(height, width, 3).copy()

    def wait(self, seconds: float) -> None:
        """Serve the window's events for ``seconds`` of wall time, or until the user closes
        the window (``math.inf``: until then)."""
        end = time.monotonic() + seconds if math.isfinite(seconds) else math.inf
        while self.window is not None and self.window.isVisible():
            left = end - time.monotonic()
            if left <= 0.0:
                break
            loop = QtCore.QEventLoop()
            QtCore.QTimer.singleShot(max(1, round(min(left, WAIT_SLICE_S) * 1000)), loop.quit)
            loop.exec_()
        self.app.processEvents()

    def close(self) -> None:
        """Close the window (asking first if a robot edit is unsaved)."""
        if self.window is not None:
            self.window.close()
            self.window.deleteLater()
            self.window = None
            self.app.processEvents()
