"""Physical motion modes in the real Qt window (``xvfb-run``): the chooser and its key,
computed torque following the dragged IK target, the Shift-drag pull, the dock's effort
bars and the status bar."""
from __future__ import annotations

from typing import Any, Iterator

import numpy as np
import pytest
from PyQt5.QtCore import QEvent, QPoint, Qt
from PyQt5.QtGui import QMouseEvent
from PyQt5.QtTest import QTest
from PyQt5.QtWidgets import QApplication

from robot_sim.graphics import defs as gd
from robot_sim.qt import settings as qs
from robot_sim.control.controllers import MOTION_LABELS, MOTION_MODES
from window_helpers import app, grab, open_window, press, project, wait_until  # noqa: F401 (app is a fixture)

from robot_sim.qt.overlays import help_lines  # noqa: E402


@pytest.fixture
def closing() -> Iterator[list[Any]]:
    windows: list[Any] = []
    yield windows
    for win in windows:
        win.close()
        win.deleteLater()


def _open(app: QApplication, closing: list[Any], *args: str) -> Any:
    win = open_window(app, *args)
    closing.append(win)
    return win


def _pixel(win: Any, point: np.ndarray) -> QPoint:
    x, y = project(win, point)
    return QPoint(int(round(x)), int(round(y)))


@pytest.mark.window
def test_shift_m_cycles_the_motion_modes_and_the_help_lists_it(app: QApplication, closing: list[Any]) -> None:
    win = _open(app, closing)
    assert win.motion_panel.combo.currentText() == "kinematic" and not win.session.physical
    assert not any(row.effort.isVisible() for row in win.joints.rows)
    seen = []
    for _ in MOTION_MODES:
        press(app, Qt.Key_M, Qt.ShiftModifier)
        seen.append(win.motion_panel.combo.currentData())
    assert seen == [*MOTION_MODES[1:], MOTION_MODES[0]]
    press(app, Qt.Key_M, Qt.ShiftModifier)
    assert win.session.motion.mode == "passive" and all(row.effort.isVisible() for row in win.joints.rows)
    assert win.motion_panel.combo.currentText() == MOTION_LABELS["passive"]
    assert any(line.startswith("Shift+M ") and "motion mode" in line for line in help_lines())


@pytest.mark.window
def test_computed_torque_and_dragging_the_target_moves_the_arm(app: QApplication, closing: list[Any]) -> None:
    win = _open(app, closing, "--robot", "humanoid7")
    win.motion_panel.combo.setCurrentIndex(MOTION_MODES.index("ct"))
    assert win.session.motion.mode == "ct" and win.timer.isActive()
    press(app, Qt.Key_G)  # the IK target appears at the endeffector
    ee_before = win.session.kin.endeff_tf.t().copy()
    start = _pixel(win, win.session.target_tf.t())
    QTest.mousePress(win.view, Qt.LeftButton, Qt.ControlModifier, start)
    app.sendEvent(win.view, QMouseEvent(QEvent.MouseMove, start + QPoint(60, 0), Qt.NoButton, Qt.LeftButton, Qt.ControlModifier))
    QTest.mouseRelease(win.view, Qt.LeftButton, Qt.ControlModifier, start + QPoint(60, 0))
    assert win.session.target_reachable
    goal = win.session.ghost.endeff_tf.t().copy()
    assert np.linalg.norm(goal - ee_before) > 0.05
    # the controller, not the animation, brings the arm there: simulated time passes
    wait_until(lambda: np.linalg.norm(win.session.kin.endeff_tf.t() - goal) < 2e-3, limit_ms=20000)
    assert win.session.motion.sim.time > 0.2
    grab(win)  # paints and refreshes the status bar
    status = win.status.text()
    assert "computed torque" in status and "t = " in status and "RTF" in status


@pytest.mark.window
def test_shift_drag_pulls_the_endeffector_and_draws_the_spring(app: QApplication, closing: list[Any]) -> None:
    win = _open(app, closing, "--robot", "humanoid7", "--motion", "pdg")
    ee0 = win.session.kin.endeff_tf.t().copy()
    start = _pixel(win, ee0)
    QTest.mousePress(win.view, Qt.LeftButton, Qt.ShiftModifier, start)
    app.sendEvent(win.view, QMouseEvent(QEvent.MouseMove, start + QPoint(80, 0), Qt.NoButton, Qt.LeftButton, Qt.ShiftModifier))
    anchor = win.session.motion.pull_point.copy()
    assert project(win, anchor)[0] == pytest.approx(start.x() + 80, abs=1.5)
    QTest.qWait(1500)
    ee = win.session.kin.endeff_tf.t()
    # the endeffector moved toward the anchor, rightward on the screen
    assert np.linalg.norm(anchor - ee) < np.linalg.norm(anchor - ee0) - 0.01
    assert project(win, ee)[0] > start.x() + 5
    # the spring is drawn from the endeffector to the anchor in PULL_COLOR
    image = grab(win).astype(int)
    mid = (project(win, ee) + project(win, anchor)) / 2
    x, y = int(round(mid[0])), int(round(mid[1]))
    patch = image[y - 3 : y + 4, x - 3 : x + 4, :3]
    pull = np.array(gd.PULL_COLOR[:3]) * 255
    assert np.any(np.abs(patch - pull).max(axis=-1) < 60)
    # the effort bars show the joints working against the spring
    assert np.any(win.joints.effort_fractions() != 0)
    QTest.mouseRelease(win.view, Qt.LeftButton, Qt.ShiftModifier, start + QPoint(80, 0))
    assert win.session.motion.pull_point is None
    wait_until(lambda: np.linalg.norm(win.session.kin.endeff_tf.t() - ee0) < 2e-3, limit_ms=20000)


@pytest.mark.window
def test_a_joint_hitting_its_limit_flashes_and_says_so(app: QApplication, closing: list[Any]) -> None:
    # humanoid7's elbow at -115 deg, 5 deg from its limit: a set point of -130 deg (past
    # the limit, as a program could set it) drives it into the stop
    win = _open(app, closing, "--robot", "humanoid7", "--q", "0,30,0,-115,0,45,0", "--motion", "pdg")
    label = win.joints.rows[3].name
    q_des = win.session.state.q_des()
    q_des[3] = np.radians(-130.0)
    win.session.set_q(q_des)
    wait_until(lambda: bool(win.session.motion.sim.at_limit[3]), limit_ms=10000)
    QTest.qWait(50)
    assert qs.LIMIT_FLASH_COLOR in label.styleSheet()
    assert "joint 4 hit its min limit" in win.message_label.text()


@pytest.mark.window
def test_under_osc_dragging_the_target_moves_the_tool_there_without_ik(
    app: QApplication, closing: list[Any], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Operational space: the dragged target is the tool's desired pose itself; IK is
    never called (it raises here), the ghost arm gives way to the target's pose, the tool
    arrives within 2 mm and the readout shows the Cartesian tracking error."""
    import robot_sim.viewer.target as target_module

    def no_ik(*args: Any, **kwargs: Any) -> Any:
        raise AssertionError("IK called under osc")

    monkeypatch.setattr(target_module, "solve_ik", no_ik)
    win = _open(app, closing, "--robot", "humanoid7")
    win.motion_panel.combo.setCurrentIndex(MOTION_MODES.index("osc"))
    assert win.session.motion.mode == "osc" and win.session.task_space
    press(app, Qt.Key_G)
    ee_before = win.session.kin.endeff_tf.t().copy()
    start = _pixel(win, win.session.target_tf.t())
    QTest.mousePress(win.view, Qt.LeftButton, Qt.ControlModifier, start)
    app.sendEvent(win.view, QMouseEvent(QEvent.MouseMove, start + QPoint(60, 0), Qt.NoButton, Qt.LeftButton, Qt.ControlModifier))
    QTest.mouseRelease(win.view, Qt.LeftButton, Qt.ControlModifier, start + QPoint(60, 0))
    goal = win.session.target_tf.t().copy()
    assert np.linalg.norm(goal - ee_before) > 0.05
    assert win.session.scene().ghost is None
    wait_until(lambda: np.linalg.norm(win.session.kin.endeff_tf.t() - goal) < 2e-3, limit_ms=30000)
    assert win.session.motion.sim.time > 0.2
    np.testing.assert_allclose(win.session.motion.sim.desired_pose, win.session.target_tf.mat)
    grab(win)
    assert "tracking error" in win.readout.text()
    assert "operational space" in win.status.text()
