"""Keys and unsaved edits in the real window (xvfb): single-key shortcuts never type into
a cell or box nobody is editing, the keyboard returns to the 3D view after an edit, a
refusal goes once the cell is valid again, and unsaved edits are never dropped without
asking (Esc, closing, switching robots, Open…)."""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest

from test_window import app  # noqa: F401 - the QApplication fixture
from test_window_ux import planar  # noqa: F401 - a window on a copy of planar3.toml

from PyQt5.QtCore import QPoint, Qt, QTimer  # noqa: E402
from PyQt5.QtTest import QTest  # noqa: E402
from PyQt5.QtWidgets import QAbstractItemView, QAbstractSpinBox, QLineEdit, QMessageBox, QWidget  # noqa: E402

from robot_sim.viewer.dh_table import COLUMNS  # noqa: E402

pytestmark = pytest.mark.window


def key(app: Any, code: int, modifiers: Any = Qt.NoModifier) -> None:
    """A key press delivered to whatever has the keyboard focus, as the keyboard would."""
    QTest.keyClick(app.focusWidget(), code, modifiers)
    app.processEvents()


def open_cell(app: Any, win: Any, row: int, column: str) -> QLineEdit:
    """Start editing a DH cell as a user does (select it, F2) and return its editor."""
    table = win.dh_dock.table
    table.setFocus()
    table.setCurrentCell(row, COLUMNS.index(column))
    QTest.keyClick(table, Qt.Key_F2)
    editor = app.focusWidget()
    assert isinstance(editor, QLineEdit) and table.state() == QAbstractItemView.EditingState
    editor.selectAll()
    return editor


def commit_cell(app: Any, win: Any, row: int, column: str, text: str) -> None:
    editor = open_cell(app, win, row, column)
    QTest.keyClicks(editor, text)
    QTest.keyClick(editor, Qt.Key_Return)
    app.processEvents()


def cell(win: Any, row: int, column: str) -> Any:
    return win.dh_dock.table.item(row, COLUMNS.index(column))


def answering(app: Any, button: Any, asked: list[str]) -> None:
    """Answer the next modal question with ``button``, noting its text in ``asked``."""

    def answer() -> None:
        box = app.activeModalWidget()
        if isinstance(box, QMessageBox):
            asked.append(box.text())
            box.button(button).click()
        else:
            QTimer.singleShot(20, answer)  # not shown yet

    QTimer.singleShot(0, answer)


def with_answer(app: Any, button: Any, action: Callable[[], Any]) -> list[str]:
    """Run ``action`` answering the question it asks with ``button``; the questions asked."""
    asked: list[str] = []
    answering(app, button, asked)
    action()
    QTest.qWait(50)
    return asked


# ------------------------------------------------------------------ focus and shortcuts


def test_after_a_cell_edit_t_toggles_wireframe_and_types_nothing(app: Any, planar: Any) -> None:
    commit_cell(app, planar, 0, "d", "0.1")
    assert planar.session.robot.dh_d[0] == 0.1
    assert app.focusWidget() is planar.view
    key(app, Qt.Key_T)
    assert planar.session.options.wireframe
    table = planar.dh_dock.table
    assert table.state() != QAbstractItemView.EditingState
    assert cell(planar, 0, "type").text() == "revolute"
    QTest.mouseClick(planar.view, Qt.LeftButton, Qt.NoModifier, QPoint(20, 20))
    app.processEvents()
    assert "refused" not in planar.message_label.text() and planar.dh_dock.error_label.text() == ""


def test_keys_on_a_selected_row_are_shortcuts_not_typing(app: Any, planar: Any) -> None:
    table = planar.dh_dock.table
    rect = table.visualItemRect(cell(planar, 1, "type"))
    QTest.mouseClick(table.viewport(), Qt.LeftButton, Qt.NoModifier, rect.center())
    assert app.focusWidget() is table and planar.session.options.annotate_joint == 2
    key(app, Qt.Key_T)
    key(app, Qt.Key_0)
    assert planar.session.options.wireframe and all(planar.session.options.show_frames)
    assert table.state() != QAbstractItemView.EditingState
    assert [cell(planar, r, "type").text() for r in range(3)] == ["revolute"] * 3
    key(app, Qt.Key_D)  # the next joint's annotation, as from the view
    assert planar.session.options.annotate_joint == 3


def test_after_enter_in_a_joint_box_keys_are_shortcuts(app: Any, planar: Any) -> None:
    box = planar.joints.rows[0].box
    QTest.mouseClick(box.lineEdit(), Qt.LeftButton)
    assert app.focusWidget() in (box, box.lineEdit())
    box.selectAll()
    QTest.keyClicks(app.focusWidget(), "90")
    key(app, Qt.Key_Return)
    assert planar.session.state.q()[0] == pytest.approx(math.pi / 2)
    assert app.focusWidget() is planar.view
    key(app, Qt.Key_0)
    key(app, Qt.Key_T)
    assert box.text() == "90.0°"
    assert all(planar.session.options.show_frames) and planar.session.options.wireframe


def test_a_click_on_a_box_arrow_leaves_the_keys_to_the_shortcuts(app: Any, planar: Any) -> None:
    box = planar.joints.rows[1].box
    before = planar.session.state.q()[1]
    QTest.mouseClick(box, Qt.LeftButton, Qt.NoModifier, QPoint(box.width() - 6, 4))  # the up arrow
    assert planar.session.state.q()[1] > before
    assert app.focusWidget() is planar.view
    key(app, Qt.Key_T)
    assert planar.session.options.wireframe


def test_no_focusable_widget_swallows_a_shortcut(app: Any, planar: Any) -> None:
    """Every widget that can hold the keyboard without being a text entry passes T on."""
    planar.dh_dock.table.setCurrentCell(0, COLUMNS.index("type"))  # a current, editable cell
    takers = [w for w in planar.findChildren(QWidget)
              if w.isVisible() and w.focusPolicy() != Qt.NoFocus and w is not planar.view
              and not isinstance(w, (QLineEdit, QAbstractSpinBox))]
    assert planar.dh_dock.table in takers
    for widget in takers:
        widget.setFocus()
        app.processEvents()
        wire = planar.session.options.wireframe
        QTest.keyClick(widget, Qt.Key_T)
        assert planar.session.options.wireframe != wire, type(widget).__name__
    assert planar.dh_dock.table.state() != QAbstractItemView.EditingState
    assert cell(planar, 0, "type").text() == "revolute"


def test_escape_in_a_cell_cancels_the_edit_not_the_window(app: Any, planar: Any) -> None:
    robot = planar.session.robot
    editor = open_cell(app, planar, 1, "a")
    QTest.keyClicks(editor, "0.7")
    key(app, Qt.Key_Escape)
    assert planar.isVisible()
    assert planar.session.robot is robot and cell(planar, 1, "a").text() == "0.4"
    assert app.focusWidget() is planar.view


def test_escape_in_a_joint_box_restores_its_value(app: Any, planar: Any) -> None:
    box = planar.joints.rows[2].box
    q = planar.session.state.q().copy()
    QTest.mouseClick(box.lineEdit(), Qt.LeftButton)
    box.selectAll()
    QTest.keyClicks(app.focusWidget(), "45")
    key(app, Qt.Key_Escape)
    assert planar.isVisible() and app.focusWidget() is planar.view
    np.testing.assert_array_equal(planar.session.state.q(), q)
    assert box.text() == f"{math.degrees(q[2]):.1f}°"


def test_a_refusal_clears_once_the_cell_is_valid_again(app: Any, planar: Any) -> None:
    commit_cell(app, planar, 1, "limits", "100 .. 50")
    item = cell(planar, 1, "limits")
    assert planar.dh_dock.error_label.text().startswith("refused")
    assert planar.message_label.text().startswith("refused")
    commit_cell(app, planar, 1, "limits", "-170 .. 170°")  # the robot's value again
    item = cell(planar, 1, "limits")
    assert item.text() == "-170 .. 170°" and item.toolTip() == ""
    assert item.background().style() == Qt.NoBrush
    assert planar.dh_dock.error_label.text() == "" and planar.message_label.text() == ""
    # refused, then another valid value: the robot changes and the refusal goes too
    commit_cell(app, planar, 0, "alpha", "abc")
    assert planar.message_label.text() == "refused: joint 1 α: 'abc' is not a number"
    commit_cell(app, planar, 0, "alpha", "5")
    assert planar.session.robot.dh_alpha[0] == pytest.approx(math.radians(5))
    assert planar.dh_dock.error_label.text() == "" and planar.message_label.text() == ""


# ------------------------------------------------------------------ unsaved edits


def test_escape_with_unsaved_edits_asks_and_cancel_keeps_the_window(app: Any, planar: Any) -> None:
    commit_cell(app, planar, 0, "a", "0.55")
    assert "(edited)" in planar.windowTitle()
    asked = with_answer(app, QMessageBox.Cancel, lambda: key(app, Qt.Key_Escape))
    assert asked == ["Three-link planar arm has unsaved edits. Save them before closing?"]
    assert planar.isVisible() and planar.session.robot.dh_a[0] == 0.55 and "(edited)" in planar.windowTitle()
    asked = with_answer(app, QMessageBox.Discard, planar.close)
    assert len(asked) == 1 and not planar.isVisible()
    assert "a = 0.5\n" in Path(planar.dh_dock.path).read_text()  # the file was left alone


def test_save_on_close_writes_the_file(app: Any, planar: Any) -> None:
    path = Path(planar.dh_dock.path)
    commit_cell(app, planar, 0, "a", "0.55")
    asked = with_answer(app, QMessageBox.Save, planar.close)
    assert len(asked) == 1 and not planar.isVisible()
    text = path.read_text()
    assert "a = 0.55\n" in text and text.startswith("#")  # saved, comments kept


def test_no_question_without_edits(app: Any, planar: Any) -> None:
    asked = with_answer(app, QMessageBox.Cancel, lambda: key(app, Qt.Key_Escape))
    assert asked == [] and not planar.isVisible()


def test_switching_robots_with_unsaved_edits_asks(app: Any, planar: Any) -> None:
    commit_cell(app, planar, 0, "a", "0.55")
    combo = planar.robot_combo
    shown = combo.currentText()
    asked = with_answer(app, QMessageBox.Cancel, lambda: combo.setCurrentText("puma560"))
    assert asked == ["Three-link planar arm has unsaved edits. Save them before switching to puma560?"]
    assert combo.currentText() == shown and planar.session.robot.dh_a[0] == 0.55
    asked = with_answer(app, QMessageBox.Discard, lambda: combo.setCurrentText("puma560"))
    assert len(asked) == 1 and planar.session.robot.name == "PUMA 560" and combo.currentText() == "puma560"
    assert "(edited)" not in planar.windowTitle()


def test_open_with_unsaved_edits_asks_first(app: Any, planar: Any, monkeypatch: Any) -> None:
    from PyQt5.QtWidgets import QFileDialog

    opened: list[str] = []
    monkeypatch.setattr(QFileDialog, "getOpenFileName", lambda *a, **k: (opened.append("dialog"), ("", ""))[1])
    commit_cell(app, planar, 0, "a", "0.55")
    asked = with_answer(app, QMessageBox.Cancel, lambda: key(app, Qt.Key_O, Qt.ControlModifier))
    assert len(asked) == 1 and opened == []
    asked = with_answer(app, QMessageBox.Discard, lambda: key(app, Qt.Key_O, Qt.ControlModifier))
    assert len(asked) == 1 and opened == ["dialog"]


def test_a_reload_from_disk_keeps_unsaved_edits(app: Any, planar: Any) -> None:
    path = Path(planar.dh_dock.path)
    commit_cell(app, planar, 0, "a", "0.55")
    path.write_text(path.read_text().replace("a = 0.4\n", "a = 0.45\n"))
    QTest.qWait(600)  # past the reload delay
    assert planar.session.robot.dh_a[0] == 0.55 and planar.session.robot.dh_a[1] == 0.4
    assert "unsaved edits are kept" in planar.message_label.text()
