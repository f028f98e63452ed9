"""The Qt window of robot-sim: the main window around a viewer session.

``robot_sim.app.main.launch`` opens it (and only then is PyQt5 imported: ``--screenshot``
never loads Qt); ``rs.Visualizer(robot, backend="window")`` opens it from a script
(robot_sim.qt.backend).  It shows a :class:`robot_sim.viewer.session.ViewerSession`,
painted by its GL view (``robot_sim.qt.gl_view``); the widgets it is built from have their
own modules: the right dock (``robot_dock``), the joint panel (``joints``), the DH table
dock (``dh_dock``), the overlays (``overlays``), the pick playback docks (``pick_panel``).
Its methods by job: robots and files (``window_robots``), key actions, the screenshot
and the workspace job (``window_actions``; the key bindings are ``KEY_BINDINGS`` in
robot_sim.qt.settings and the actions that only change the session are
robot_sim.viewer.commands), the pick demo (``window_pick``).
"""
from __future__ import annotations

import sys
import time
from dataclasses import dataclass
from typing import Callable

import numpy as np
from PyQt5 import QtCore, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim import graphics as go
from robot_sim.control.controllers import MOTION_LABELS
from robot_sim.qt import settings as qs
from robot_sim.qt.elided_label import ElidedLabel
from robot_sim.qt.gl_view import GLView
from robot_sim.qt.guard import guarded, install_excepthook
from robot_sim.qt.overlays import HelpOverlay, ViewInfo
from robot_sim.qt.pick_panel import PickPanel, PlotDock
from robot_sim.qt.robot_dock import RobotDock
from robot_sim.qt.shortcuts import ShortcutFilter
from robot_sim.qt.window_actions import WindowActions
from robot_sim.qt.window_pick import PickControls
from robot_sim.qt.window_robots import APP_NAME, RobotFiles
from robot_sim.viewer.commands import UNREACHABLE
from robot_sim.viewer.readout import session_readout
from robot_sim.viewer.session import ViewerSession
from robot_sim.viewer.workspace_job import IDLE, WorkspaceJob, compute_workspace

__all__ = ["APP_NAME", "MainWindow", "WINDOW_SIZE", "WindowOptions", "opening_size", "run_window"]

#: The window's size when it opens, shrunk to the screen's free area if that is smaller
#: (``--size`` is the size of pictures: --screenshot, --record).
WINDOW_SIZE = (1280, 800)


@dataclass(frozen=True)
class WindowOptions:
    """How the window opens around its session: the robot chooser's entry (a shipped name
    or a file path, as given), the workspace cloud's point count (0: off) and a first
    status message."""

    robot_arg: str
    workspace: int = 0
    message: str | None = None


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


class MainWindow(RobotFiles, PickControls, WindowActions, QtWidgets.QMainWindow):
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
        self.build_robot_dock()
        self.build_dh_dock()
        self.actions = self.build_actions()
        self.shortcuts = ShortcutFilter(self, self.is_bound, self.keyPressEvent)
        self.shortcuts.watch(self.dh_dock.table)
        self.resize(*opening_size())
        self.robot_changed()
        if options.workspace:
            self.act_toggle_workspace()
        if self.session.pick is not None:
            self.show_pick()
            if options.message is not None:
                self.message(options.message)
        self.start_motion()

    def build_robot_dock(self) -> None:
        """The right dock, its widgets named on the window and connected to it."""
        dock = self.robot_dock = RobotDock(self, self.options.robot_arg)
        self.robot_combo, self.motion_panel, self.joints = dock.robot_combo, dock.motion_panel, dock.joints
        self.readout, self.frames_list, self.dock_scroll = dock.readout, dock.frames_list, dock.dock_scroll
        self.robot_choice = self.options.robot_arg  # what the chooser shows, kept on Cancel
        self.robot_combo.chosen.connect(self.choose_robot)
        self.motion_panel.mode_chosen.connect(self.choose_motion)
        self.joints.joint_moved.connect(self.joint_moved)
        self.joints.q_requested.connect(self.set_q)
        self.joints.edit_finished.connect(self.view.setFocus)  # Enter / Esc in a box: keys are shortcuts again
        self.frames_list.itemChanged.connect(self.frame_item_changed)
        # the right dock runs the window's full height; the bottom docks sit under the view
        self.setCorner(Qt.TopRightCorner, Qt.RightDockWidgetArea)
        self.setCorner(Qt.BottomRightCorner, Qt.RightDockWidgetArea)
        self.addDockWidget(Qt.RightDockWidgetArea, dock)

    def robot_changed(self) -> None:
        """Rebuild the joint rows, the DH table and the frame list for the session's robot."""
        robot = self.session.robot
        self.joints.set_robot(robot)
        self.show_motion_mode()
        self.dh_dock.set_robot(robot, self.session.state.q())
        annotated = self.session.options.annotate_joint  # --annotate J: its row selected
        if annotated is not None and self.dh_dock.selected_joint() != annotated - 1:
            self.dh_dock.table.selectRow(annotated - 1)
        self.robot_dock.set_frames(self.session.n_frames)
        self.update_title()
        self.sync_widgets()

    def sync_widgets(self) -> None:
        """Show the session's q, pose and frame options on the widgets, and paint."""
        session = self.session
        self.joints.show_q(session.q_set_point())  # physical: the controller's set point
        self.dh_dock.show_q(session.state.q())
        self.readout.setText(session_readout(session))
        self.robot_dock.show_frames(session.options)
        self.sync_pick()
        self.sync_motion()
        self.update_view_info()
        self.view.update()

    def update_view_info(self) -> None:
        session = self.session
        step = go.FloorGrid.for_reach(go.robot_reach(session.robot)).step
        self.view.info.info = ViewInfo(step, session.camera.orthographic, session.follow)
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

    @guarded
    def joint_moved(self, joint: int, value: float) -> None:
        """A slider or box moved joint ``joint`` to ``value`` (rad or m); in a physical
        motion mode it sets the controller's desired value (ViewerSession.q_set_point)."""
        self.session.set_joint(joint, value)
        if self.session.moving():
            self.start_motion()
        else:
            self.timer.stop()
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
        driver = self.session.driver
        replayed = driver.replayed_mode
        self.motion_panel.show_mode(driver.mode if replayed is None else replayed, replayed is not None)
        self.joints.show_efforts(driver.physical)

    def sync_motion(self) -> None:
        """Effort bars, and a flash and a message for each joint-limit arrival."""
        for event in self.session.limit_events:
            self.joints.flash(event.joint)
            self.message(f"joint {event.joint + 1} hit its {event.side} limit at t = {event.time:.3f} s")
        self.session.limit_events.clear()
        self.joints.sync_efforts(self.session.driver.motion)

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

    def zoom(self, factor: float) -> None:
        """Multiply the camera distance by ``factor`` (< 1 zooms in)."""
        self.session.camera.zoom(factor)
        self.view.update()

    def drag(self, dx: int, dy: int, buttons: Qt.MouseButtons, modifiers: Qt.KeyboardModifiers) -> None:
        """Mouse drag of (dx, dy) pixels: left orbits, Ctrl+left moves the IK target,
        Shift+left moves the pull's anchor (physical modes), right or middle pans."""
        if buttons & Qt.LeftButton and self.session.pulling:
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
            try:
                self.session.start_pull()
            except ValueError as exc:  # the still arm: nothing to pull
                self.message(str(exc))
            else:
                self.start_motion()

    def release(self) -> None:
        """Mouse released: let go of the endeffector."""
        self.session.end_pull()
        self.view.update()

    def move_target_by(self, move: Callable[[], bool]) -> None:
        """Move the IK target by ``move`` (False: unreachable, which the status bar says)."""
        if not move():
            self.message(UNREACHABLE)
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
        dt = self.session.driver.wall_step(elapsed, 4 * qs.ANIM_INTERVAL_MS / 1000.0)
        self.last_tick = now
        self.session.step(dt)
        if not self.session.moving():
            self.timer.stop()
            # once the last paints are older than the fps window the status says idle
            QtCore.QTimer.singleShot(round(qs.FPS_WINDOW_S * 1000) + 50, self.refresh_status)
        self.sync_widgets()
