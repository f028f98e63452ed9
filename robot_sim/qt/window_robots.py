"""The window's robots: the DH table dock, the chooser, Open…/Save as…, edits of the table
and reloads of the file, and never dropping unsaved edits without asking (a mixin of
``robot_sim.qt.window.MainWindow``, whose session, docks and status it uses)."""
from __future__ import annotations

from PyQt5 import QtGui, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim.io.robot_file import resolve_robot_path
from robot_sim.model.params import RobotDefinitionError, RobotParams
from robot_sim.qt.dh_dock import DHTableDock, shown_path
from robot_sim.qt.guard import guarded

#: The program's name, shown in the window title and the dialogs.
APP_NAME = "robot-sim"


class RobotFiles:
    """Robot switching and file handling of the main window."""

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

    def update_title(self) -> None:
        """``robot — file [edited] — robot-sim``."""
        path = self.dh_dock.path
        where = shown_path(path) if path is not None else "not saved"
        mark = " (edited)" if self.edited else ""
        self.setWindowTitle(f"{self.session.robot.name} — {where}{mark} — {APP_NAME}")

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
        self.robot_combo.blockSignals(True)
        self.robot_combo.setCurrentText(self.robot_choice)
        self.robot_combo.blockSignals(False)

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
    def closeEvent(self, event: QtGui.QCloseEvent) -> None:  # noqa: N802 - Qt's name
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
        """Show ``robot`` in the session's place (ViewerSession.with_robot: options kept;
        with ``keep_q`` the joint values, the camera and the frame choice too); a pick
        task shown is planned again for it."""
        self.timer.stop()
        self.session.aspect = self.view.width() / max(self.view.height(), 1)
        self.session = self.session.with_robot(robot, keep_q)
        self.workspace.reset()  # cancels a computation for the previous robot
        self.robot_changed()
        if self.pick_panel is not None:
            self.start_pick()
