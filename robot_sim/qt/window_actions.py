"""The window's key actions: the session's commands (robot_sim.viewer.commands) and the
few that need the window itself (help, quit, the DH table's next row, the motion chooser,
files, the P screenshot, the workspace job); a mixin of ``robot_sim.qt.window.MainWindow``."""
from __future__ import annotations

import time
from pathlib import Path
from typing import Any, Callable

from PyQt5 import QtCore, QtGui

from robot_sim.control.controllers import MOTION_MODES
from robot_sim.io.files import FileWriteError, write_atomic
from robot_sim.qt import settings as qs
from robot_sim.qt.guard import guarded
from robot_sim.qt.keys import binding
from robot_sim.qt.window_robots import APP_NAME
from robot_sim.viewer.commands import COMMANDS, STARTS_MOTION
from robot_sim.viewer.workspace_job import COMPUTING, FAILED, HIDDEN, SHOWN


class WindowActions:
    """Key dispatch and the window's own actions."""

    def build_actions(self) -> dict[str, Callable[[Any], Any]]:
        """Action name (KEY_BINDINGS column 3) -> handler taking the row's argument (column
        4): the session's commands, then the window's own; every action of the table must
        have one."""
        actions: dict[str, Callable[[Any], Any]] = {
            name: (lambda argument, name=name: self.run_command(name, argument)) for name in COMMANDS
        }
        actions.update({
            "toggle_help": self.act_toggle_help,
            "quit": self.act_quit,
            "save_screenshot": self.act_save_screenshot,
            "toggle_workspace": self.act_toggle_workspace,
            "toggle_pick": self.act_toggle_pick,
            "annotate_next": self.act_annotate_next,
            "cycle_motion": self.act_cycle_motion,
            "open_robot": lambda _: self.dh_dock.open_dialog(),
            "save_robot_as": lambda _: self.dh_dock.save_dialog(),
        })
        missing = {row[2] for row in qs.KEY_BINDINGS} - actions.keys()
        if missing:
            raise RuntimeError(f"KEY_BINDINGS actions without a handler: {sorted(missing)}")
        return actions

    def run_command(self, name: str, argument: Any) -> None:
        """Run the session command ``name``, show its message, and animate what it set moving."""
        message = COMMANDS[name](self.session, argument)
        if message is not None:
            self.message(message)
        if name in STARTS_MOTION:
            self.start_motion()

    def is_bound(self, event: QtGui.QKeyEvent) -> bool:
        """True if ``event``'s key and modifiers are a KEY_BINDINGS shortcut."""
        return binding(event) is not None

    @guarded
    def keyPressEvent(self, event: QtGui.QKeyEvent) -> None:  # noqa: N802 - Qt's name
        bound = binding(event)
        if bound is None:
            super().keyPressEvent(event)
            return
        action, argument = bound
        try:
            self.actions[action](argument)
        except Exception as exc:  # noqa: BLE001 - an exception escaping a Qt handler aborts PyQt
            self.message(f"{action} failed: {exc}")
        self.sync_widgets()

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

    def act_annotate_next(self, _: None) -> None:
        """Annotate the next joint's DH parameters (selecting its DH table row); after the
        last joint, none."""
        current = self.session.options.annotate_joint  # 1..n or None
        following = 0 if current is None else current  # the next joint's 0-based row
        if following < self.session.robot.n_dofs:
            self.dh_dock.table.selectRow(following)
        else:
            self.dh_dock.table.clearSelection()

    def act_cycle_motion(self, _: None) -> None:
        """Next motion mode (through the chooser, which does the switching)."""
        combo = self.motion_panel.combo
        combo.setCurrentIndex((combo.currentIndex() + 1) % len(MOTION_MODES))

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
