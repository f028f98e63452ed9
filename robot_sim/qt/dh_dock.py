"""The DH table dock: the robot's Denavit–Hartenberg table, editable live, with Open…,
Save as… and a watch on the robot file.

Cells come from :mod:`dh_table` (display units: degrees and metres).  An accepted edit
emits ``robot_edited`` with a new immutable RobotParams built through the loader; a
refused one stays in its cell, tinted, with the reason in the cell's tooltip and under
the table, and the robot is unchanged.  Save as… writes through
:func:`robot_sim.io.robot_writer.save_robot` with the opened file's text as template, so its comments
and citations are kept (or a URDF through :func:`urdf.to_urdf` for a ``.urdf`` name).  The opened (or saved) file is watched: when it changes on disk
it is reloaded and ``robot_loaded(robot, True)`` asks the window to keep the joint values.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

import numpy as np
from numpy.typing import NDArray
from PyQt5 import QtCore, QtGui, QtWidgets
from PyQt5.QtCore import Qt

from robot_sim.qt import settings as qs
from robot_sim.qt.elided_label import ElidedLabel
from robot_sim.qt.guard import guarded
from robot_sim.viewer.dh_table import COLUMNS, HEADERS, cell_text, edit_cell, is_editable, variable_column
from robot_sim.model.params import RobotDefinitionError, RobotParams
from robot_sim.io.robot_file import load_robot
from robot_sim.viewer.units import display_range, display_scale
from robot_sim.io.files import write_atomic
from robot_sim.io.robot_writer import save_robot
from robot_sim.io.urdf_out import to_urdf

_CONVENTION_TEXT = {
    "standard": "standard DH: A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i), joint i about z_{i-1}",
    "modified": "modified DH (Craig): A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i), joint i about z_i",
}
_FILE_FILTER = "Robot files (*.toml *.urdf);;TOML (*.toml);;URDF (*.urdf);;All files (*)"


def shown_path(path: Path) -> str:
    """``path`` as the window writes it: relative to the working directory when it lies
    inside it (``robots/puma560.toml``), else as it is."""
    try:
        return str(Path(path).resolve().relative_to(Path.cwd().resolve()))
    except (ValueError, OSError):
        return str(path)


class DHTableDock(QtWidgets.QDockWidget):
    """Dock with the DH table of the shown robot and its file actions.

    Signals: ``robot_edited(robot)`` after an accepted cell edit, ``robot_loaded(robot,
    keep_q)`` after Open… (False) or a reload from disk (True), ``joint_selected(index or
    None)`` when the selected row changes, ``message(text)`` for the status bar,
    ``file_changed(path or None)`` when another file becomes the current one (Open…,
    Save as…), ``message_void(text)`` when a message said earlier no longer holds (a
    refused cell holds a valid value again), ``edit_closed()`` when a cell editor closes
    (committed or cancelled).
    """

    robot_edited = QtCore.pyqtSignal(object)
    robot_loaded = QtCore.pyqtSignal(object, bool)
    joint_selected = QtCore.pyqtSignal(object)
    message = QtCore.pyqtSignal(str)
    message_void = QtCore.pyqtSignal(str)
    file_changed = QtCore.pyqtSignal(object)
    edit_closed = QtCore.pyqtSignal()

    def __init__(self, parent: QtWidgets.QWidget | None = None) -> None:
        super().__init__("DH parameters", parent)
        self.setObjectName("dh_dock")
        self.robot: RobotParams | None = None
        self.q = np.zeros(0)
        self.path: Path | None = None
        self.text: str | None = None  # the file's text when last read or written: the template
        self._filling = False
        self.refused: dict[tuple[int, int], str] = {}  # (row, column) -> "refused: reason"
        # asked before Open… replaces the shown robot, with what is about to happen
        # ("opening another robot"); the window asks about unsaved edits
        self.may_drop: Callable[[str], bool] = lambda _doing: True
        self.unsaved: Callable[[], bool] = lambda: False  # True: a reload from disk must not replace the robot
        panel = QtWidgets.QWidget()
        layout = QtWidgets.QVBoxLayout(panel)
        layout.setContentsMargins(4, 2, 4, 2)
        bar = QtWidgets.QHBoxLayout()
        self.open_button = QtWidgets.QPushButton("Open…")
        self.save_button = QtWidgets.QPushButton("Save as…")
        self.file_label = ElidedLabel(mode=Qt.ElideMiddle)  # a long path must not widen the window
        for button in (self.open_button, self.save_button):
            button.setFocusPolicy(Qt.NoFocus)
            bar.addWidget(button)
        bar.addWidget(self.file_label, 1)
        layout.addLayout(bar)
        self.convention_label = QtWidgets.QLabel()
        layout.addWidget(self.convention_label)
        self.table = QtWidgets.QTableWidget(0, len(COLUMNS))
        self.table.setHorizontalHeaderLabels(HEADERS)
        self.table.setSelectionBehavior(QtWidgets.QAbstractItemView.SelectRows)
        self.table.setSelectionMode(QtWidgets.QAbstractItemView.SingleSelection)
        # editing starts by a double click or F2 only: any other key is the window's
        # shortcut (route_keys), never text typed into a cell nobody opened
        self.table.setEditTriggers(
            QtWidgets.QAbstractItemView.DoubleClicked | QtWidgets.QAbstractItemView.EditKeyPressed
        )
        self.table.verticalHeader().setDefaultSectionSize(self.table.fontMetrics().height() + qs.DH_ROW_PADDING_PX)
        self.table.setSizeAdjustPolicy(QtWidgets.QAbstractScrollArea.AdjustToContents)
        self.table.setSizePolicy(QtWidgets.QSizePolicy.Expanding, QtWidgets.QSizePolicy.Maximum)
        layout.addWidget(self.table)
        self.error_label = QtWidgets.QLabel()
        self.error_label.setStyleSheet(qs.DH_ERROR_STYLE)
        self.error_label.setWordWrap(True)
        layout.addWidget(self.error_label)
        self.setWidget(panel)
        self.watcher = QtCore.QFileSystemWatcher(self)
        self.reload_timer = QtCore.QTimer(self)
        self.reload_timer.setSingleShot(True)
        self.reload_timer.setInterval(qs.DH_RELOAD_DELAY_MS)
        self.open_button.clicked.connect(lambda _checked: self.open_dialog())
        self.save_button.clicked.connect(lambda _checked: self.save_dialog())
        self.table.itemChanged.connect(self.cell_changed)
        self.table.itemDelegate().closeEditor.connect(lambda *_: self.edit_closed.emit())
        self.table.itemSelectionChanged.connect(self.selection_changed)
        self.watcher.fileChanged.connect(lambda _path: self.reload_timer.start())
        self.reload_timer.timeout.connect(self.reload)

    # ---- what is shown ----
    def set_robot(self, robot: RobotParams, q: NDArray[np.float64]) -> None:
        """Show ``robot`` at joint values ``q`` (SI); the selected row is kept if it exists."""
        selected = self.selected_joint()
        self.robot, self.q = robot, np.array(q, dtype=float)
        self._filling = True
        self.table.setRowCount(robot.n_dofs)
        self.table.setVerticalHeaderLabels([str(i + 1) for i in range(robot.n_dofs)])
        for row in range(robot.n_dofs):
            for col, column in enumerate(COLUMNS):
                item = QtWidgets.QTableWidgetItem(cell_text(robot, self.q, row, column))
                if not is_editable(robot, row, column):
                    item.setFlags(item.flags() & ~Qt.ItemIsEditable)
                    item.setBackground(QtGui.QColor(*qs.DH_VARIABLE_CELL_RGB))
                    item.setToolTip(f"joint variable q{row + 1}: move it with the joint slider or box")
                self.table.setItem(row, col, item)
        self._size_columns()
        self._filling = False
        self._clear_refusals()
        self.convention_label.setText(_CONVENTION_TEXT[robot.convention])
        if selected is not None and selected < robot.n_dofs:
            self.table.selectRow(selected)

    def _size_columns(self) -> None:
        """Columns as wide as their texts, the joint-variable cells' at their widest: each
        is measured holding the value at the end of the joint's range that reads longer,
        so moving a joint never elides its θ or d ("-112.72 …")."""
        robot = self.robot
        lo, hi = (np.asarray(v) / display_scale(robot) for v in display_range(robot))  # the sliders' range, SI
        for row in range(robot.n_dofs):
            column = variable_column(robot, row)
            texts = [cell_text(robot, np.where(np.arange(robot.n_dofs) == row, end, self.q), row, column)
                     for end in (lo[row], hi[row])]
            self.table.item(row, COLUMNS.index(column)).setText(max(texts, key=len))
        self.table.resizeColumnsToContents()
        self.show_q(self.q)

    def show_q(self, q: NDArray[np.float64]) -> None:
        """Update the joint-variable cells for joint values ``q`` (SI)."""
        self.q = np.array(q, dtype=float)
        self._filling = True
        for row in range(self.robot.n_dofs):
            column = variable_column(self.robot, row)
            self.table.item(row, COLUMNS.index(column)).setText(cell_text(self.robot, self.q, row, column))
        self._filling = False

    def selected_joint(self) -> int | None:
        """Index of the selected row (0-based joint), or None."""
        rows = self.table.selectionModel().selectedRows()
        return rows[0].row() if rows else None

    def set_file(self, path: Path | None, text: str | None) -> None:
        """Make ``path`` (with its contents ``text``) the current, watched file."""
        if self.watcher.files():
            self.watcher.removePaths(self.watcher.files())
        self.path, self.text = path, text
        if path is not None:
            self.watcher.addPath(str(path))
        self.file_label.setText(shown_path(path) if path is not None else "(not saved)")
        self.file_changed.emit(path)

    # ---- edits ----
    @guarded
    def cell_changed(self, item: QtWidgets.QTableWidgetItem) -> None:
        if self._filling or self.robot is None:
            return
        row, col = item.row(), item.column()
        column = COLUMNS[col]
        if item.text() == cell_text(self.robot, self.q, row, column):
            self._accept_cell(item)  # typed back to the robot's value: nothing refused here now
            return
        try:
            edited = edit_cell(self.robot, row, column, item.text())
        except ValueError as exc:
            self._refuse_cell(item, f"refused: {exc}")
            return
        self.robot_edited.emit(edited)  # the table is rebuilt for the new robot

    def _refuse_cell(self, item: QtWidgets.QTableWidgetItem, reason: str) -> None:
        """Tint ``item``, put ``reason`` in its tooltip, under the table and in the status bar."""
        self._filling = True
        item.setBackground(QtGui.QColor(*qs.DH_INVALID_CELL_RGB))
        item.setToolTip(reason)
        self._filling = False
        self.refused[(item.row(), item.column())] = reason
        self.error_label.setText(reason)
        self.message.emit(reason)

    def _accept_cell(self, item: QtWidgets.QTableWidgetItem) -> None:
        """``item`` holds a valid value again: untint it and withdraw its refusal."""
        reason = self.refused.pop((item.row(), item.column()), None)
        if reason is None:
            return
        self._filling = True
        item.setBackground(QtGui.QBrush())
        item.setToolTip("")
        self._filling = False
        self.error_label.setText(next(iter(self.refused.values()), ""))  # another refused cell's reason, if any
        self.message_void.emit(reason)

    def _clear_refusals(self) -> None:
        """A new table: no cell is refused (the status bar forgets the reasons too)."""
        for reason in self.refused.values():
            self.message_void.emit(reason)
        self.refused.clear()
        self.error_label.clear()

    @guarded
    def selection_changed(self) -> None:
        self.joint_selected.emit(self.selected_joint())

    def report_error(self, text: str) -> None:
        """Where guarded slots report an unexpected exception (see robot_sim.qt.guard)."""
        self.message.emit(text)

    # ---- files ----
    def open_file(self, path: str | Path) -> bool:
        """Load the robot file ``path``, watch it and emit ``robot_loaded(robot, False)``;
        on failure say why and keep the current robot.  Returns whether it loaded."""
        path = Path(path)
        try:
            robot = load_robot(path)
            text = path.read_text(encoding="utf-8")
        except (RobotDefinitionError, OSError, UnicodeDecodeError) as exc:
            self.message.emit(f"cannot open {path}: {exc}")
            return False
        self.set_file(path, text)
        self.robot_loaded.emit(robot, False)
        return True

    def save_to(self, path: str | Path) -> bool:
        """Write the shown robot to ``path`` and watch that file: URDF for a ``.urdf``
        name, else TOML keeping the comments of the current file when it is a TOML file.
        Returns whether it was written."""
        path = Path(path)
        try:
            if path.suffix.lower() == ".urdf":
                write_atomic(path, to_urdf(self.robot, path=path))
            else:
                toml_template = self.path is not None and self.path.suffix.lower() == ".toml"
                save_robot(self.robot, path, template=self.text if toml_template else None)
            text = path.read_text(encoding="utf-8")
        except (OSError, ValueError) as exc:
            self.message.emit(f"cannot save: {exc}")
            return False
        self.set_file(path, text)
        self.message.emit(f"saved {self.robot.name} to {path}")
        return True

    @guarded
    def reload(self) -> None:
        """Reload the watched file after it changed on disk (ignored if its text is what
        was last read or written; a file that fails to load is reported and skipped; with
        unsaved edits shown they are kept and the status bar says so)."""
        path = self.path
        if path is None:
            return
        if str(path) not in self.watcher.files() and path.exists():
            self.watcher.addPath(str(path))  # an editor's save-by-rename drops the watch
        try:
            text = path.read_text(encoding="utf-8")
            if text == self.text:
                return
            robot = load_robot(path)
        except (RobotDefinitionError, OSError, UnicodeDecodeError) as exc:
            self.message.emit(f"{path} changed but was not reloaded: {exc}")
            return
        if self.unsaved():
            self.message.emit(f"{path} changed on disk; your unsaved edits are kept "
                              "(Save as… writes them, Open… loads the file)")
            return
        self.text = text
        self.robot_loaded.emit(robot, True)
        self.message.emit(f"reloaded {path}")

    @guarded
    def open_dialog(self) -> None:
        if not self.may_drop("opening another robot"):
            return
        start = str(self.path.parent) if self.path is not None else str(Path.cwd())
        path, _ = QtWidgets.QFileDialog.getOpenFileName(self, "Open robot file", start, _FILE_FILTER)
        if path:
            self.open_file(path)

    @guarded
    def save_dialog(self) -> bool:
        """Ask for a file name and save there; False if cancelled or not written."""
        start = str(self.path) if self.path is not None else str(Path.cwd() / "robot.toml")
        path, _ = QtWidgets.QFileDialog.getSaveFileName(self, "Save robot file as", start, _FILE_FILTER)
        return bool(path) and self.save_to(path)

    def save(self) -> bool:
        """Save the shown robot to its current file (comments kept), or ask for a name
        when it has none; returns whether it was written."""
        return self.save_to(self.path) if self.path is not None else bool(self.save_dialog())
