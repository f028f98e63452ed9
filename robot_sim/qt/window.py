"""The Qt window of robot-sim: main window, GL view, docks, key and mouse input.

The widgets the window is built from have their own modules: the joint panel
(``robot_sim.qt.joints``), the DH table dock with Open…/Save as… and the file watch
(``robot_sim.qt.dh_dock``), the help overlay and the view's corner information
(``robot_sim.qt.overlays``).

PyQt5 is imported here, at the top, and this module is imported only when a window is
opened (``simulator.launch``), so ``--screenshot`` never loads Qt.  The window shows a
:class:`robot_sim.viewer.session.ViewerSession` and paints it with the one render path
``robot_sim.graphics.View``; keys are dispatched through ``KEY_BINDINGS``
(robot_sim.graphics.defs.py): one handler per action name, called with the row's argument.
"""
from __future__ import annotations

import copy
import functools
import math
import sys
import time
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np
from PyQt5 import QtCore, QtGui, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim.graphics import defs as gd
from robot_sim.qt import settings as qs
from robot_sim import graphics as go
from robot_sim.qt.guard import guarded, install_excepthook
from robot_sim.qt.pick_panel import PickPanel, PlotDock
from robot_sim.qt.dh_dock import DHTableDock, shown_path
from robot_sim.qt.joints import JointPanel
from robot_sim.qt.motion_panel import MotionPanel
from robot_sim.qt.overlays import HelpOverlay, ViewInfo, ViewInfoOverlay
from robot_sim.viewer.dh_table import carry_joint_values
from robot_sim.io.files import FileWriteError, write_atomic
from robot_sim.kinematics import manipulability
from robot_sim.viewer.pick_demo import plan_for
from robot_sim.viewer.readout import pose_readout
from robot_sim.control.controllers import MOTION_LABELS, MOTION_MODES
from robot_sim.model.params import RobotDefinitionError, RobotParams
from robot_sim.model.world import World
from robot_sim.io.robot_file import available_robots, resolve_robot_path
from robot_sim.viewer.trail import Trail
from robot_sim.qt.elided_label import ElidedLabel
from robot_sim.qt.robot_chooser import RobotChooser
from robot_sim.qt.shortcuts import ShortcutFilter
from robot_sim.viewer.session import ViewerSession, compute_workspace
from robot_sim.viewer.workspace_job import COMPUTING, FAILED, HIDDEN, IDLE, SHOWN, WorkspaceJob

#: The window's size when it opens, shrunk to the screen's free area if that is smaller
#: (``--size`` is the size of pictures: --screenshot, --record).
WINDOW_SIZE = (1280, 800)

_MODIFIER_FLAGS = {"Shift": Qt.ShiftModifier, "Ctrl": Qt.ControlModifier, "Alt": Qt.AltModifier}
_MODIFIER_MASK = int(functools.reduce(lambda a, b: a | b, _MODIFIER_FLAGS.values()))


def key_of(key: str, mods: str) -> tuple[int, int]:
    """(Qt key code, modifier bits) of a KEY_BINDINGS row's key name and modifiers."""
    bits = functools.reduce(lambda a, b: a | b, (_MODIFIER_FLAGS[m] for m in mods.split("+") if m), Qt.NoModifier)
    return int(getattr(Qt, f"Key_{key}")), int(bits)


#: The program's name, shown in the window title.
APP_NAME = "robot-sim"


@dataclass(frozen=True)
class WindowOptions:
    """How the window opens around its session: the robot chooser's entry (a shipped name or a
    file path, as given), the workspace cloud's point count (0: off),
    whether the circle demo runs, a first status message, the gain overrides the motion
    chooser keeps (``bandwidth``, ``damping``) and the world every robot shown stands in
    (None: the floor only)."""

    robot_arg: str
    workspace: int = 0
    circle_demo: bool = False
    message: str | None = None
    gains: dict[str, Any] = field(default_factory=dict)
    world: World | None = None


def opening_size() -> tuple[int, int]:
    """WINDOW_SIZE, no larger than the primary screen's available area (pixels)."""
    free = QtWidgets.QApplication.primaryScreen().availableGeometry()
    return min(WINDOW_SIZE[0], free.width()), min(WINDOW_SIZE[1], free.height())


def run_window(session: ViewerSession, options: WindowOptions) -> int:
    """Open the main window on ``session`` and run the Qt event loop; returns its exit status."""
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(sys.argv[:1])
    main_window = MainWindow(session, options)
    install_excepthook(main_window)  # the net under handlers that are not @guarded
    main_window.show()
    main_window.view.setFocus()
    return app.exec_()


class ColumnScroll(QtWidgets.QScrollArea):
    """A vertical scroll area never narrower than its content plus the scroll bar: its
    column scrolls up and down, and nothing is cut off on the right."""

    def setWidget(self, widget: QtWidgets.QWidget) -> None:  # noqa: N802 - Qt's name
        super().setWidget(widget)
        widget.installEventFilter(self)  # its layout changing changes this minimum

    def eventFilter(self, obj: QtCore.QObject, event: QtCore.QEvent) -> bool:  # noqa: N802 - Qt's name
        if obj is self.widget() and event.type() == QtCore.QEvent.LayoutRequest:
            self.updateGeometry()
        return super().eventFilter(obj, event)

    def minimumSizeHint(self) -> QtCore.QSize:  # noqa: N802 - Qt's name
        content = self.widget().minimumSizeHint() if self.widget() is not None else QtCore.QSize(0, 0)
        width = content.width() + self.verticalScrollBar().sizeHint().width() + 2 * self.frameWidth()
        return QtCore.QSize(width, super().minimumSizeHint().height())


class GLView(QtWidgets.QOpenGLWidget):
    """GL widget: paints the simulation with its :class:`graphics.View` (the scene's items
    and their GL objects, released when Qt destroys the widget's context), turns the
    mouse into camera and target moves, carries the view information overlay and
    measures the frame rate over actual paints.

    While the camera moves (orbit, pan, zoom, follow) frames are drawn without
    multisampling, which costs llvmpipe half of a frame; ``REFINE_AFTER_MS`` after the
    last move the still view is painted again with it.  Grabs of the picture
    (:meth:`grabFramebuffer`, the P screenshot) are always drawn with it."""

    def __init__(self, window: "MainWindow") -> None:
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
        scene = sim.scene()
        if self.window_.trail is not None:
            scene.trail = self.window_.trail.points()
        self.scene_view.render(sim.camera, scene, self.frame_options(width, height), width, height)  # errors: @guarded
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


class MainWindow(QtWidgets.QMainWindow):
    """Main window: GL view in the middle; on the right a dock with the robot chooser, the
    joint sliders and boxes, the endeffector readout and the frame list; below, the DH
    table dock; a status bar with one-off messages left of the permanent readout.  Keys
    are dispatched through KEY_BINDINGS."""

    workspace_ready = QtCore.pyqtSignal()

    def __init__(self, session: ViewerSession, options: WindowOptions) -> None:
        super().__init__()
        self.options = options
        self.session = session
        self.pick_panel: PickPanel | None = None
        self.plot_dock: PlotDock | None = None
        self.workspace = WorkspaceJob(compute_workspace, self.workspace_ready.emit)
        self.last_error = ""
        self.last_tick = 0.0
        self.trail: Trail | None = None
        self.following = False
        self.edited = False  # the shown robot differs from its file
        self.view = GLView(self)
        self.setCentralWidget(self.view)
        self.help = HelpOverlay(self.view)  # over the 3D view only, never over the docks
        self.timer = QtCore.QTimer(self)
        self.timer.setInterval(qs.ANIM_INTERVAL_MS)
        self.timer.timeout.connect(self.tick)
        self.workspace_ready.connect(self.on_workspace_ready, QtCore.Qt.QueuedConnection)
        self.message_label = ElidedLabel()  # long texts end in "…", never past the window's edge
        self.message_timer = QtCore.QTimer(self)
        self.message_timer.setSingleShot(True)
        self.message_timer.timeout.connect(lambda: self.message_label.setText(""))
        self.status = ElidedLabel()
        self.statusBar().addWidget(self.message_label, 1)
        self.statusBar().addPermanentWidget(self.status)
        self.build_dock()
        self.build_dh_dock()
        self.actions = self.build_actions()
        self.key_table = {key_of(key, mods): (action, arg) for key, mods, action, arg, _ in qs.KEY_BINDINGS}
        self.shortcuts = ShortcutFilter(self, self.is_bound, self.keyPressEvent)
        self.shortcuts.watch(self.dh_dock.table)
        self.resize(*opening_size())
        self.robot_changed()
        if options.workspace:
            self.act_toggle_workspace()
        if options.circle_demo:
            self.session.toggle_demo()
        if self.session.pick is not None:
            self.show_pick()
            if options.message is not None:
                self.message(options.message)
        self.start_motion()

    # ---- docks ----
    def build_dock(self) -> None:
        dock = QtWidgets.QDockWidget("Robot", self)
        dock.setObjectName("robot_dock")
        dock.setFeatures(QtWidgets.QDockWidget.NoDockWidgetFeatures)
        panel = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(panel)
        self.robot_choice = self.options.robot_arg  # what the chooser shows, kept on Cancel
        self.robot_combo = RobotChooser(available_robots(), self.robot_choice)  # long paths elided in the middle
        self.robot_combo.chosen.connect(self.choose_robot)
        layout.addWidget(self.robot_combo)
        self.motion_panel = MotionPanel()
        self.motion_panel.mode_chosen.connect(self.choose_motion)
        layout.addWidget(self.motion_panel)
        self.joints = JointPanel()
        self.joints.joint_moved.connect(self.joint_moved)
        self.joints.q_requested.connect(self.set_q)
        self.joints.edit_finished.connect(self.view.setFocus)  # Enter / Esc in a box: keys are shortcuts again
        self.readout = QtWidgets.QLabel()
        font = QtGui.QFont(qs.HELP_FONT_FAMILY, qs.READOUT_FONT_PT)
        font.setStyleHint(QtGui.QFont.TypeWriter)
        self.readout.setFont(font)
        self.readout.setTextInteractionFlags(Qt.TextSelectableByMouse)
        self.readout.setToolTip("endeffector pose in the world: position, roll-pitch-yaw (URDF), "
                                "quaternion; Yoshikawa's manipulability")
        self.frames_list = QtWidgets.QListWidget()
        self.frames_list.setVerticalScrollBarPolicy(Qt.ScrollBarAlwaysOff)  # as tall as its rows
        self.frames_list.itemChanged.connect(self.frame_item_changed)
        # one scroll area for all that grows with the joints: at 1024x768 a 7-joint arm
        # scrolls as a whole instead of squeezing its rows into nested scroll boxes
        body = QtWidgets.QWidget()
        column = QtWidgets.QVBoxLayout(body)
        column.setContentsMargins(0, 0, 0, 0)
        for widget in (self.joints, self.readout, QtWidgets.QLabel("Frames"), self.frames_list):
            column.addWidget(widget)
        column.addStretch(1)
        self.dock_scroll = ColumnScroll()
        self.dock_scroll.setWidgetResizable(True)
        self.dock_scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarAlwaysOff)
        self.dock_scroll.setFrameShape(QtWidgets.QFrame.NoFrame)
        self.dock_scroll.setWidget(body)
        layout.addWidget(self.dock_scroll, 1)
        for widget in (self.robot_combo, self.dock_scroll, self.frames_list):
            widget.setFocusPolicy(Qt.NoFocus)  # keys stay with the GL view
        dock.setWidget(panel)
        dock.setMinimumWidth(qs.DOCK_MIN_WIDTH)
        # the right dock runs the window's full height; the bottom docks sit under the view
        self.setCorner(Qt.TopRightCorner, Qt.RightDockWidgetArea)
        self.setCorner(Qt.BottomRightCorner, Qt.RightDockWidgetArea)
        self.addDockWidget(Qt.RightDockWidgetArea, dock)

    def build_dh_dock(self) -> None:
        self.dh_dock = DHTableDock(self)
        self.dh_dock.setFeatures(QtWidgets.QDockWidget.DockWidgetMovable | QtWidgets.QDockWidget.DockWidgetFloatable)
        self.dh_dock.may_drop = self.confirm_unsaved  # Open… asks before dropping unsaved edits
        self.dh_dock.unsaved = lambda: self.edited  # ... and a reload from disk keeps them
        self.dh_dock.robot_edited.connect(self.robot_edited)
        self.dh_dock.robot_loaded.connect(self.robot_loaded)
        self.dh_dock.joint_selected.connect(self.annotate)
        self.dh_dock.message.connect(self.message)
        self.dh_dock.message_void.connect(self.withdraw_message)
        self.dh_dock.edit_closed.connect(self.view.setFocus)  # a cell committed or cancelled: keys are shortcuts again
        self.dh_dock.file_changed.connect(self.file_changed)
        self.addDockWidget(Qt.BottomDockWidgetArea, self.dh_dock)
        try:
            path = resolve_robot_path(self.options.robot_arg)
            text = path.read_text(encoding="utf-8")
        except (RobotDefinitionError, OSError, UnicodeDecodeError):
            path, text = None, None  # loaded a moment ago; if it is gone now, edits stay unsaved
        self.dh_dock.set_file(path, text)

    def robot_changed(self) -> None:
        """Rebuild the joint rows, the DH table and the frame list for the session's robot."""
        robot = self.session.robot
        self.joints.set_robot(robot)
        self.show_motion_mode()
        self.dh_dock.set_robot(robot, self.session.state.q())
        annotated = self.session.options.annotate_joint  # --annotate J: its row selected
        if annotated is not None and self.dh_dock.selected_joint() != annotated - 1:
            self.dh_dock.table.selectRow(annotated - 1)
        self.frames_list.blockSignals(True)
        self.frames_list.clear()
        names = [f"frame {i}" + (" (base)" if i == 0 else "") for i in range(self.session.n_frames)]
        for name in names + ["endeffector"]:
            item = QtWidgets.QListWidgetItem(name)
            item.setFlags(Qt.ItemIsUserCheckable | Qt.ItemIsEnabled)
            self.frames_list.addItem(item)
        self.frames_list.blockSignals(False)
        rows = self.frames_list.count()
        self.frames_list.setFixedHeight(rows * self.frames_list.sizeHintForRow(0) + 2 * self.frames_list.frameWidth())
        self.dock_scroll.widget().ensurePolished()  # its real fonts and styles, so the dock is
        self.dock_scroll.updateGeometry()  # as wide as it needs before it is first shown
        self.update_title()
        self.sync_widgets()

    def update_title(self) -> None:
        """``robot — file [edited] — robot-sim``."""
        path = self.dh_dock.path
        where = shown_path(path) if path is not None else "not saved"
        mark = " (edited)" if self.edited else ""
        self.setWindowTitle(f"{self.session.robot.name} — {where}{mark} — {APP_NAME}")

    def sync_widgets(self) -> None:
        """Show the session's q, pose and frame options on the widgets; move the trail and
        the followed camera with the endeffector."""
        session = self.session
        q = session.state.q()
        endeff = session.kin.endeff_tf
        self.joints.show_q(session.state.q_des() if session.physical else q)  # physical: the set point
        self.dh_dock.show_q(q)
        try:
            measure = manipulability(session.robot, q, session.kin.jacobian)
        except ValueError:  # arms under 6 joints probe their range: an unlimited slider has none
            measure = math.nan
        collision = self.session.collision_readout()
        readout = pose_readout(endeff, measure, session.tracking_error())
        self.readout.setText(readout + ("" if collision is None else "\n" + collision))
        if self.trail is not None:
            self.trail.add(endeff.t())  # drawn by the view.update() below
        if self.following:
            session.camera.target = endeff.t().copy()
        self.frames_list.blockSignals(True)
        options = session.options
        for i, shown in enumerate(options.show_frames + [options.show_endeff_frame]):
            self.frames_list.item(i).setCheckState(Qt.Checked if shown else Qt.Unchecked)
        self.frames_list.blockSignals(False)
        self.sync_pick()
        self.sync_motion()
        self.update_view_info()
        self.view.update()

    def update_view_info(self) -> None:
        session = self.session
        step = go.FloorGrid.for_reach(go.robot_reach(session.robot)).step
        self.view.info.info = ViewInfo(step, session.camera.orthographic, self.following)
        self.view.info.update()

    @guarded
    def refresh_status(self) -> None:
        text = self.session.status_text(self.view.fps_text())
        if self.workspace.state != IDLE:
            text += qs.STATUS_WORKSPACE_FORMAT.format(state=self.workspace.state)
        self.status.setText(text)

    def report_error(self, text: str) -> None:
        """Show an error caught at the Qt boundary (robot_sim.qt.guard) in the status bar."""
        self.last_error = text
        self.message(text, qs.STATUS_ERROR_MS)

    def message(self, text: str, duration_ms: int | None = None) -> None:
        """Show ``text`` left of the permanent status for ``duration_ms`` (default
        STATUS_MESSAGE_MS)."""
        self.message_label.setText(text)
        self.message_timer.start(qs.STATUS_MESSAGE_MS if duration_ms is None else duration_ms)

    def withdraw_message(self, text: str) -> None:
        """``text`` no longer holds (a refused cell is valid again): clear it if shown."""
        if self.message_label.text() == text:
            self.message_label.setText("")

    # ---- robots: chooser, DH edits, files ----
    @guarded
    def choose_robot(self, name: str) -> None:
        """Switch to robot ``name`` (shipped name or file) without restarting; with unsaved
        edits only after Save or Discard (Cancel puts the chooser back)."""
        if not self.confirm_unsaved(f"switching to {name}"):
            self.show_robot_choice()
            return
        try:
            path = resolve_robot_path(name)
        except RobotDefinitionError as exc:
            self.message(str(exc))
            self.show_robot_choice()
            return
        if self.dh_dock.open_file(path):
            self.robot_choice = name
        self.show_robot_choice()
        self.view.setFocus()

    def show_robot_choice(self) -> None:
        """The chooser names the robot shown (without switching)."""
        self.robot_combo.show_choice(self.robot_choice)

    def confirm_unsaved(self, doing: str) -> bool:
        """True if the shown robot may be dropped for ``doing`` (e.g. "closing"): it has
        no unsaved edits, or the user saved or discarded them; False if they cancelled
        (or the save failed, which the status bar says)."""
        if not self.edited:
            return True
        box = QtWidgets.QMessageBox
        answer = box.question(
            self, APP_NAME, f"{self.session.robot.name} has unsaved edits. Save them before {doing}?",
            box.Save | box.Discard | box.Cancel, box.Save,
        )
        if answer == box.Save:
            return self.dh_dock.save()
        return answer == box.Discard

    @guarded
    def closeEvent(self, event: QtGui.QCloseEvent) -> None:
        """Closing (Esc, the title bar): with unsaved edits only after Save or Discard."""
        if self.confirm_unsaved("closing"):
            event.accept()
        else:
            event.ignore()

    @guarded
    def robot_loaded(self, robot: RobotParams, keep_q: bool) -> None:
        """A robot from Open…, the chooser or a reload of the file: keep the joint values
        (and the camera) on a reload when the number of joints is unchanged.  A reload
        while the shown robot has unsaved edits keeps the edits and says so."""
        if keep_q and self.edited:
            self.message(f"{self.dh_dock.path} changed on disk; your unsaved edits are kept "
                         "(Save as… writes them, Open… loads the file)")
            return
        self.edited = False
        self.replace_robot(robot, keep_q and robot.n_dofs == self.session.robot.n_dofs)

    @guarded
    def robot_edited(self, robot: RobotParams) -> None:
        """A DH table edit: the same arm with one value changed, at the same joint values."""
        self.edited = True
        self.replace_robot(robot, keep_q=True)

    @guarded
    def file_changed(self, _path: object) -> None:
        self.edited = False
        self.update_title()

    def replace_robot(self, robot: RobotParams, keep_q: bool) -> None:
        """Show ``robot`` in a new session; with ``keep_q`` the joint values (carried over
        joint by joint), the camera and the frame choice stay."""
        old = self.session
        self.timer.stop()
        # per-joint gains of the command line belong to the robot it named
        gains = {k: v for k, v in self.options.gains.items() if k in ("bandwidth", "damping")}
        self.session = ViewerSession(robot, aspect=self.view.width() / max(self.view.height(), 1), gain_overrides=gains,
                                     world=self.options.world)
        for flag in ("wireframe", "alpha", "show_vectors", "theme", "look", "show_collision"):
            setattr(self.session.options, flag, getattr(old.options, flag))
        self.session.camera.orthographic = old.camera.orthographic
        if keep_q:
            self.session.set_q(carry_joint_values(old.robot, old.state.q(), robot))
            self.session.camera = old.camera
            if robot.n_dofs == old.robot.n_dofs:
                self.session.options.show_frames = list(old.options.show_frames)
                self.session.options.show_endeff_frame = old.options.show_endeff_frame
                self.session.options.annotate_joint = old.options.annotate_joint
        self.workspace.reset()  # cancels a computation for the previous robot
        if self.trail is not None:
            self.trail.clear()
        self.robot_changed()
        if self.pick_panel is not None:
            self.start_pick()

    @guarded
    def joint_moved(self, joint: int, value: float) -> None:
        """A slider or box moved joint ``joint`` to ``value`` (rad or m); in a physical
        motion mode it sets the controller's desired value."""
        if self.session.physical:
            q_des = self.session.state.q_des()
            q_des[joint] = value
            self.session.set_q(q_des)
            self.start_motion()
        else:
            self.timer.stop()
            self.session.set_joint(joint, value)
        self.sync_widgets()

    @guarded
    def choose_motion(self, mode: str) -> None:
        """Motion chooser: switch the mode; a failure (e.g. dynamics refusing the robot)
        stays kinematic and says why."""
        try:
            self.session.set_motion(mode)
        except ValueError as exc:
            self.message(f"motion {MOTION_LABELS[mode]}: {exc}")
            if self.session.physical:
                self.session.set_motion("kinematic")
        else:
            motion = self.session.motion
            note = " (inertials estimated from the link geometry: the file has none)" if motion.estimated else ""
            self.message(f"motion: {motion.label}{note}")
        self.show_motion_mode()
        self.start_motion()
        self.sync_widgets()

    def show_motion_mode(self) -> None:
        """The chooser names the session's motion mode, or the mode of the simulated pick
        run being replayed; effort bars in physical modes."""
        session, pick = self.session, self.session.pick
        replayed = not session.physical and pick is not None and pick.effort is not None
        mode = session.motion.mode if session.physical else (pick.mode if replayed else "kinematic")
        self.motion_panel.show_mode(mode, replayed)
        self.joints.show_efforts(session.physical)

    def sync_motion(self) -> None:
        """Effort bars, and a flash and a message for each joint-limit arrival."""
        for event in self.session.limit_events:
            self.joints.flash(event.joint)
            self.message(f"joint {event.joint + 1} hit its {event.side} limit at t = {event.time:.3f} s")
        self.session.limit_events.clear()
        self.joints.sync_efforts(self.session.motion if self.session.physical else None)

    @guarded
    def set_q(self, q: np.ndarray) -> None:
        """Home or Zero: every joint at once (SI)."""
        self.timer.stop()
        self.session.set_q(q)
        self.sync_widgets()

    @guarded
    def annotate(self, row: int | None) -> None:
        """Draw the DH parameters of the joint of DH table row ``row`` (0-based) in the
        view, or none (``annotate_joint`` counts joints from 1)."""
        self.session.options.annotate_joint = None if row is None else row + 1
        self.view.update()

    @guarded
    def frame_item_changed(self, item: QtWidgets.QListWidgetItem) -> None:
        """A frame list checkbox: rows 0..n are DH frames, the last the endeffector frame."""
        row, shown = self.frames_list.row(item), item.checkState() == Qt.Checked
        if row < self.session.n_frames:
            self.session.options.show_frames[row] = shown
        else:
            self.session.options.show_endeff_frame = shown
        self.view.update()

    # ---- keys: one handler per KEY_BINDINGS action, called with the row's argument ----
    def is_bound(self, event: QtGui.QKeyEvent) -> bool:
        """True if ``event``'s key and modifiers are a KEY_BINDINGS shortcut."""
        return (int(event.key()), int(event.modifiers()) & _MODIFIER_MASK) in self.key_table

    @guarded
    def keyPressEvent(self, event: QtGui.QKeyEvent) -> None:
        binding = self.key_table.get((int(event.key()), int(event.modifiers()) & _MODIFIER_MASK))
        if binding is None:
            super().keyPressEvent(event)
            return
        action, argument = binding
        try:
            self.actions[action](argument)
        except Exception as exc:  # noqa: BLE001 - an exception escaping a Qt handler aborts PyQt
            self.message(f"{action} failed: {exc}")
        self.sync_widgets()

    def build_actions(self) -> dict[str, Callable[[Any], Any]]:
        """Action name (KEY_BINDINGS column 3) -> handler taking the row's argument (column
        4); every action of the table must have one."""
        actions: dict[str, Callable[[Any], Any]] = {
            "toggle_help": self.act_toggle_help,
            "quit": self.act_quit,
            "toggle_wireframe": self.act_toggle_wireframe,
            "cycle_look": self.act_cycle_look,
            "toggle_alpha": self.act_toggle_alpha,
            "toggle_all_frames": self.act_toggle_all_frames,
            "toggle_frame": self.act_toggle_frame,
            "zoom": self.act_zoom,
            "orbit": self.act_orbit,
            "reset_view": self.act_reset_view,
            "save_screenshot": self.act_save_screenshot,
            "toggle_workspace": self.act_toggle_workspace,
            "toggle_vectors": self.act_toggle_vectors,
            "toggle_labels": self.act_toggle_labels,
            "toggle_com": self.act_toggle_com,
            "toggle_demo": self.act_toggle_demo,
            "toggle_collision": self.act_toggle_collision,
            "toggle_pick": self.act_toggle_pick,
            "toggle_target": self.act_toggle_target,
            "move_target": self.act_move_target,
            "rotate_target": self.act_rotate_target,
            "view_preset": self.act_view_preset,
            "toggle_orthographic": self.act_toggle_orthographic,
            "toggle_follow": self.act_toggle_follow,
            "toggle_trail": self.act_toggle_trail,
            "annotate_next": self.act_annotate_next,
            "go_home": self.act_go_home,
            "cycle_motion": self.act_cycle_motion,
            "open_robot": lambda _: self.dh_dock.open_dialog(),
            "save_robot_as": lambda _: self.dh_dock.save_dialog(),
        }
        missing = {row[2] for row in qs.KEY_BINDINGS} - actions.keys()
        if missing:
            raise RuntimeError(f"KEY_BINDINGS actions without a handler: {sorted(missing)}")
        return actions

    def act_toggle_help(self, _: None) -> None:
        if self.help.isVisible():
            self.help.hide()
            return
        self.help.fit(self.view.rect())
        self.help.show()
        self.help.raise_()

    def act_quit(self, _: None) -> None:
        """Esc: close the help overlay if it is open, else the window."""
        if self.help.isVisible():
            self.help.hide()
        else:
            self.close()

    def act_view_preset(self, name: str) -> None:
        """Look from the front, side, top or iso direction (VIEW_PRESETS)."""
        self.session.camera.set_view(*qs.VIEW_PRESETS[name])
        self.message(f"view: {name}")

    def act_toggle_orthographic(self, _: None) -> None:
        camera = self.session.camera
        camera.orthographic = not camera.orthographic
        self.message("orthographic projection" if camera.orthographic else "perspective projection")

    def act_toggle_follow(self, _: None) -> None:
        """Keep the camera aimed at the endeffector (its target follows it) or stop."""
        self.following = not self.following
        self.message("camera follows the endeffector" if self.following else "camera stays put")

    def act_toggle_trail(self, _: None) -> None:
        """Start drawing the endeffector's path from here, or stop and forget it."""
        self.trail = Trail() if self.trail is None else None
        self.message("endeffector trail on" if self.trail is not None else "endeffector trail off")

    def act_annotate_next(self, _: None) -> None:
        """Annotate the next joint's DH parameters (selecting its DH table row); after the
        last joint, none."""
        current = self.session.options.annotate_joint  # 1..n or None
        following = 0 if current is None else current  # the next joint's 0-based row
        if following < self.session.robot.n_dofs:
            self.dh_dock.table.selectRow(following)
        else:
            self.dh_dock.table.clearSelection()

    def act_go_home(self, _: None) -> None:
        self.set_q(np.array(self.session.robot.q_home))

    def act_toggle_wireframe(self, _: None) -> None:
        self.session.options.toggle_wireframe()

    def act_cycle_look(self, _: None) -> None:
        """Draw the robot in its next look (``graphics.looks_of``: meshes, DH, both, solid)."""
        robot = self.session.robot
        look = self.session.options.cycle_look(go.looks_of(robot), go.look_for(robot, self.session.options.look))
        self.message(f"look: {look}")

    def act_toggle_alpha(self, _: None) -> None:
        self.session.options.toggle_alpha()

    def act_toggle_all_frames(self, _: None) -> None:
        self.session.options.toggle_all_frames()

    def act_toggle_frame(self, index: int) -> None:
        """Show or hide DH frame ``index``."""
        if not self.session.options.toggle_frame(index):
            self.message(f"{self.session.robot.name} has no frame {index} (frames 0..{self.session.n_frames - 1})")

    def act_zoom(self, steps: int) -> None:
        """Multiply the camera distance by KEY_ZOOM_FACTOR ** ``steps`` (< 0 zooms in)."""
        self.zoom(qs.KEY_ZOOM_FACTOR ** steps)

    def act_orbit(self, steps: tuple[int, int]) -> None:
        """Orbit by (azimuth, elevation) steps of KEY_ORBIT_STEP_DEG."""
        self.session.camera.orbit(steps[0] * qs.KEY_ORBIT_STEP_DEG, steps[1] * qs.KEY_ORBIT_STEP_DEG)

    def act_reset_view(self, _: None) -> None:
        self.session.fit_camera()

    def act_toggle_vectors(self, _: None) -> None:
        self.session.options.show_vectors = not self.session.options.show_vectors

    def act_toggle_labels(self, _: None) -> None:
        self.session.options.show_labels = not self.session.options.show_labels

    def act_toggle_com(self, _: None) -> None:
        self.session.options.show_com = not self.session.options.show_com

    def act_cycle_motion(self, _: None) -> None:
        """Next motion mode (through the chooser, which does the switching)."""
        combo = self.motion_panel.combo
        combo.setCurrentIndex((combo.currentIndex() + 1) % len(MOTION_MODES))

    def act_toggle_target(self, _: None) -> None:
        self.session.toggle_target()

    def act_move_target(self, axis_sign: tuple[int, int]) -> None:
        """Move the IK target by TARGET_STEP_M along world axis ``axis`` (0..2) times ``sign``."""
        axis, sign = axis_sign
        self.move_target_by(lambda: self.session.move_target(translation=sign * qs.TARGET_STEP_M * np.eye(3)[axis]))

    def act_rotate_target(self, axis_sign: tuple[int, int]) -> None:
        """Rotate the IK target by TARGET_STEP_DEG about world axis ``axis`` times ``sign``."""
        axis, sign = axis_sign
        step = sign * math.radians(qs.TARGET_STEP_DEG) * np.eye(3)[axis]
        self.move_target_by(lambda: self.session.move_target(rpy=step))

    def zoom(self, factor: float) -> None:
        """Multiply the camera distance by ``factor`` (< 1 zooms in)."""
        self.session.camera.zoom(factor)
        self.view.update()

    def drag(self, dx: int, dy: int, buttons: Qt.MouseButtons, modifiers: Qt.KeyboardModifiers) -> None:
        """Mouse drag of (dx, dy) pixels: left orbits, Ctrl+left moves the IK target,
        Shift+left moves the pull's anchor (physical modes), right or middle pans."""
        if buttons & Qt.LeftButton and self.session.physical and self.session.motion.pull_point is not None:
            self.session.move_pull_in_view(dx, dy, self.view.pixel_size()[1])
        elif buttons & Qt.LeftButton and modifiers & Qt.ControlModifier:
            self.move_target_by(lambda: self.session.move_target_in_view(dx, dy, self.view.pixel_size()[1]))
        elif buttons & Qt.LeftButton:
            self.session.camera.orbit(-dx * qs.MOUSE_ORBIT_DEG_PER_PX, dy * qs.MOUSE_ORBIT_DEG_PER_PX)
        elif buttons & (Qt.RightButton | Qt.MiddleButton):
            self.session.camera.pan(dx, dy, self.view.pixel_size()[1])
        self.view.update()

    def press(self, buttons: Qt.MouseButtons, modifiers: Qt.KeyboardModifiers) -> None:
        """Shift+left press in a physical mode starts pulling the endeffector."""
        if buttons & Qt.LeftButton and modifiers & Qt.ShiftModifier:
            if self.session.physical:
                self.session.start_pull()
                self.start_motion()
            else:
                self.message("pulling needs a physical motion mode: press Shift+M")

    def release(self) -> None:
        """Mouse released: let go of the endeffector."""
        if self.session.physical:
            self.session.motion.end_pull()
        self.view.update()

    # ---- IK target, animation, demo ----
    def move_target_by(self, move: Callable[[], bool]) -> None:
        if not move():
            self.message("IK target unreachable: the ghost stays at the last reachable pose")
        self.start_motion()

    def act_toggle_collision(self, _: None) -> None:
        shown = self.session.toggle_collision()
        self.message("collision display " + ("on: shapes, contacts in red, closest pair" if shown else "off"))
        self.view.update()

    def act_toggle_demo(self, _: None = None) -> None:
        self.message("circle demo " + ("started" if self.session.toggle_demo() else "stopped"))
        self.start_motion()

    def start_motion(self) -> None:
        """Run the timer while something moves; it stops itself when all has arrived."""
        if self.session.moving() and not self.timer.isActive():
            self.last_tick = time.monotonic()
            self.timer.start()

    @guarded
    def tick(self) -> None:
        now = time.monotonic()
        elapsed = now - self.last_tick
        # the simulation keeps wall-clock time itself (Simulation.advance caps a lag);
        # the kinematic animation takes bounded steps
        dt = elapsed if self.session.physical else min(max(elapsed, 1e-3), 4 * qs.ANIM_INTERVAL_MS / 1000.0)
        self.last_tick = now
        self.session.step(dt)
        if not self.session.moving():
            self.timer.stop()
            # once the last paints are older than the fps window the status says idle
            QtCore.QTimer.singleShot(round(qs.FPS_WINDOW_S * 1000) + 50, self.refresh_status)
        self.sync_widgets()

    # ---- pick demo: playback dock and plots ----
    def show_pick(self) -> None:
        """The pick demo's docks (made on first use) showing the session's plan."""
        if self.pick_panel is None:
            self.pick_panel = PickPanel(self, self.act_toggle_pick, self.seek_pick, self.set_pick_speed)
            self.plot_dock = PlotDock(self)
            # the timeline right under the view, the plots in a tab beside the DH table: each
            # gets the view's whole width (side by side at 1024x768 the plots were cut off)
            self.addDockWidget(Qt.BottomDockWidgetArea, self.pick_panel)
            self.splitDockWidget(self.pick_panel, self.dh_dock, Qt.Vertical)
            self.tabifyDockWidget(self.dh_dock, self.plot_dock)
            self.plot_dock.raise_()
            self.resizeDocks([self.plot_dock], [round(self.height() * qs.PLOT_DOCK_HEIGHT_FRACTION)], Qt.Vertical)
        self.plot_dock.show_trajectory(self.session.pick.plan.trajectory, self.session.pick.effort)
        self.show_motion_mode()
        self.sync_pick()
        self.start_motion()

    def sync_pick(self) -> None:
        """Timeline, label and plot cursors at the demo's time."""
        demo = self.session.pick
        if self.pick_panel is None or demo is None:
            return
        self.pick_panel.sync(demo.time, demo.duration, demo.playing, demo.state().phase)
        self.plot_dock.set_time(demo.time)

    def start_pick(self) -> None:
        """Plan the robot's default pick task and show it (a one-line message if it cannot)."""
        try:
            plan = plan_for(self.session.robot)
        except ValueError as exc:  # TaskError, TaskDefinitionError
            self.message(str(exc))
            return
        self.session.start_pick(plan)
        self.show_pick()

    def act_toggle_pick(self, _: None = None) -> None:
        """Start the pick demo, or play / pause it (also the Play button's handler)."""
        try:
            if self.session.pick is None:
                self.start_pick()
            else:
                self.session.pick.toggle()
                self.start_motion()
        except Exception as exc:  # noqa: BLE001 - an exception escaping a Qt handler aborts PyQt
            self.message(f"pick demo: {exc}")
        self.sync_widgets()

    def seek_pick(self, t: float) -> None:
        """Timeline slider: pause and show the task at ``t`` s."""
        try:
            self.session.pick.playing = False
            self.session.show_pick_at(t)
        except Exception as exc:  # noqa: BLE001 - an exception escaping a Qt handler aborts PyQt
            self.message(f"seek failed: {exc}")
        self.sync_widgets()

    @guarded
    def set_pick_speed(self, speed: float) -> None:
        """Speed box of the timeline: playback at ``speed`` × real time."""
        if self.session.pick is not None:
            self.session.pick.speed = speed

    # ---- screenshot and workspace ----
    def act_save_screenshot(self, _: None = None) -> None:
        """Save the view as a PNG in SCREENSHOT_DIR of the working directory (created if
        needed, written atomically); the status bar says where."""
        stamp = time.strftime("%Y%m%d-%H%M%S") + f"-{int(time.time() * 1000) % 1000:03d}"
        stem = self.dh_dock.path.stem if self.dh_dock.path is not None else "robot"
        folder = Path.cwd() / qs.SCREENSHOT_DIR
        path = folder / qs.SCREENSHOT_NAME_FORMAT.format(robot=stem, stamp=stamp)
        try:
            folder.mkdir(exist_ok=True)
        except OSError as exc:
            self.message(f"could not create {folder}: {exc.strerror or exc}")
            return
        buffer = QtCore.QBuffer()
        buffer.open(QtCore.QIODevice.WriteOnly)
        self.view.grabbing = True  # full quality even mid-orbit
        try:
            picture = self.view.grab().toImage()  # the GL picture with its corner information
        finally:
            self.view.grabbing = False
        picture.setText("Software", APP_NAME)
        picture.setText("Source", f"{APP_NAME} window: {self.windowTitle()}")  # what it shows, as it shows it
        picture.save(buffer, "PNG")
        try:
            write_atomic(path, bytes(buffer.data()))
        except FileWriteError as exc:
            self.message(f"could not save screenshot: {exc}")
            return
        self.message(f"screenshot saved to {path}")

    def act_toggle_workspace(self, _: None = None) -> None:
        """E: compute the cloud (in the background), cancel a computation, or show/hide
        the finished cloud (workspace_job.WorkspaceJob.toggle)."""
        self.workspace.toggle(self.session.robot, self.options.workspace or qs.WORKSPACE_DEFAULT_POINTS)
        self.show_workspace_state()

    @guarded
    def on_workspace_ready(self) -> None:
        """The worker ended (queued from its thread): take its outcome if still wanted; a
        cloud just computed is framed with the arm (it reaches well past the arm's pose)."""
        if self.workspace.collect():
            self.show_workspace_state()
            if self.workspace.state == SHOWN:
                self.session.fit_camera()
                self.view.update()

    def show_workspace_state(self) -> None:
        """Make the session, the status bar and the picture follow the job's state."""
        job = self.workspace
        self.session.workspace = job.cloud if job.state in (SHOWN, HIDDEN) else None
        self.session.options.show_workspace = job.state in (SHOWN, COMPUTING)
        if job.state == FAILED:
            self.report_error(job.message)
        elif job.message:
            self.message(job.message)
        self.refresh_status()
        self.view.update()
