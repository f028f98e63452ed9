"""The window's GL view: paints the session with the one render path
(``robot_sim.graphics.View``), turns the mouse into camera, target and pull moves (handed
to its host window), carries the view information overlay and measures the frame rate."""
from __future__ import annotations

import copy
import time
from collections import deque
from typing import Protocol

from PyQt5 import QtCore, QtGui, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim import graphics as go
from robot_sim.graphics import defs as gd
from robot_sim.qt import settings as qs
from robot_sim.qt.guard import guarded
from robot_sim.qt.overlays import HelpOverlay, ViewInfoOverlay
from robot_sim.viewer.session import ViewerSession


class ViewHost(Protocol):
    """What the view asks of the window it sits in."""

    session: ViewerSession
    help: HelpOverlay

    def refresh_status(self) -> None: ...

    def press(self, buttons: Qt.MouseButtons, modifiers: Qt.KeyboardModifiers) -> None: ...

    def release(self) -> None: ...

    def drag(self, dx: int, dy: int, buttons: Qt.MouseButtons, modifiers: Qt.KeyboardModifiers) -> None: ...

    def zoom(self, factor: float) -> None: ...


class GLView(QtWidgets.QOpenGLWidget):
    """GL widget: paints the simulation with its :class:`graphics.View` (the scene's items
    and their GL objects, released when Qt destroys the widget's context), turns the
    mouse into camera and target moves, carries the view information overlay and
    measures the frame rate over actual paints.

    While the camera moves (orbit, pan, zoom, follow) frames are drawn without
    multisampling, which costs llvmpipe half of a frame; ``REFINE_AFTER_MS`` after the
    last move the still view is painted again with it.  Grabs of the picture
    (:meth:`grabFramebuffer`, the P screenshot) are always drawn with it."""

    def __init__(self, window: ViewHost) -> None:
        super().__init__(window)
        # Qt's default surface has no depth buffer: without one every part would
        # paint over the others in drawing order
        surface = QtGui.QSurfaceFormat()
        surface.setDepthBufferSize(gd.DEPTH_BUFFER_BITS)
        self.setFormat(surface)
        self.window_ = window
        self.info = ViewInfoOverlay(self)
        self.paint_times: deque[float] = deque()
        self.drag_pos: QtCore.QPoint | None = None
        self.framed = False
        self.scene_view = go.View()
        self.last_view: bytes | None = None  # the camera of the last paint
        self.last_samples = 0  # the multisampling the last paint was drawn with
        self.grabbing = False  # a grab is painting: full quality
        self.refine = QtCore.QTimer(self)
        self.refine.setSingleShot(True)
        self.refine.setInterval(qs.REFINE_AFTER_MS)
        self.refine.timeout.connect(self.update)
        self.setFocusPolicy(Qt.StrongFocus)
        self.setMinimumSize(160, 120)

    def pixel_size(self) -> tuple[int, int]:
        """Framebuffer size (width, height) in device pixels."""
        ratio = self.devicePixelRatioF()
        return max(1, round(self.width() * ratio)), max(1, round(self.height() * ratio))

    def fps_text(self) -> str:
        """Frame rate over the paints of the last FPS_WINDOW_S seconds ("idle" if < 2)."""
        now = time.monotonic()
        while self.paint_times and now - self.paint_times[0] > qs.FPS_WINDOW_S:
            self.paint_times.popleft()
        span = self.paint_times[-1] - self.paint_times[0] if len(self.paint_times) >= 2 else 0.0
        if span <= 0.0:
            return qs.STATUS_FPS_IDLE
        return qs.STATUS_FPS_FORMAT.format(fps=(len(self.paint_times) - 1) / span)

    @guarded
    def initializeGL(self) -> None:
        self.scene_view.forget()  # a new context: none of the view's objects are in it
        self.context().aboutToBeDestroyed.connect(self.release_gl)

    @guarded
    def release_gl(self) -> None:
        """Delete the view's GL objects while their context still exists."""
        self.makeCurrent()
        self.scene_view.release()
        self.doneCurrent()

    @guarded
    def paintGL(self) -> None:
        sim = self.window_.session
        width, height = self.pixel_size()
        self.scene_view.render(sim.camera, sim.scene(), self.frame_options(width, height), width, height)  # errors: @guarded
        self.paint_times.append(time.monotonic())
        self.window_.refresh_status()

    def frame_options(self, width: int, height: int) -> go.GraphicsOptions:
        """The session's options, without multisampling while the camera moves (its view
        differs from the last paint's; the refine timer then paints the still view)."""
        camera, options = self.window_.session.camera, self.window_.session.options
        view = camera.view_matrix().tobytes() + camera.projection_matrix(width / max(height, 1)).tobytes()
        moving, self.last_view = view != self.last_view, view
        if not moving or options.samples <= 1 or self.grabbing:
            self.last_samples = options.samples
            return options
        self.refine.start()
        fast = copy.copy(options)
        fast.samples = self.last_samples = 0
        return fast

    def grabFramebuffer(self) -> QtGui.QImage:  # noqa: N802 - Qt's name
        """The picture, drawn now with the session's multisampling even while moving."""
        self.grabbing = True
        try:
            return super().grabFramebuffer()
        finally:
            self.grabbing = False

    @guarded
    def resizeGL(self, width: int, height: int) -> None:
        # frame the robot for the widget's real shape once it is known (the dock
        # takes part of the window); later resizes leave the user's camera alone
        sim = self.window_.session
        sim.aspect = width / max(height, 1)
        if not self.framed:
            sim.fit_camera()
            self.framed = True

    @guarded
    def resizeEvent(self, event: QtGui.QResizeEvent) -> None:
        super().resizeEvent(event)
        self.info.resize(self.size())
        if self.window_.help.isVisible():
            self.window_.help.fit(self.rect())

    @guarded
    def mousePressEvent(self, event: QtGui.QMouseEvent) -> None:
        self.drag_pos = event.pos()
        self.setFocus()
        self.window_.press(event.buttons(), event.modifiers())

    @guarded
    def mouseReleaseEvent(self, event: QtGui.QMouseEvent) -> None:
        self.drag_pos = None
        self.window_.release()

    @guarded
    def mouseMoveEvent(self, event: QtGui.QMouseEvent) -> None:
        if self.drag_pos is None:
            return
        delta = event.pos() - self.drag_pos
        self.drag_pos = event.pos()
        self.window_.drag(delta.x(), delta.y(), event.buttons(), event.modifiers())

    @guarded
    def wheelEvent(self, event: QtGui.QWheelEvent) -> None:
        notches = event.angleDelta().y() / 120.0  # > 0: wheel turned away, zoom in
        self.window_.zoom(qs.WHEEL_ZOOM_FACTOR ** -notches)
