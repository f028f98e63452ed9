"""The workspace job in the real window (xvfb-run): E computes in the background, E again
while computing cancels, switching robot cancels, a failure is shown in the status bar."""
from __future__ import annotations

import dataclasses

import os
import time
from typing import Any, Callable

import pytest

from robot_sim.app import output, prepare
import simulator

if "OpenGL.platform" not in __import__("sys").modules:
    os.environ.pop("PYOPENGL_PLATFORM", None)  # the window needs GLX, not OSMesa

from PyQt5.QtCore import Qt  # noqa: E402
from PyQt5.QtTest import QTest  # noqa: E402
from PyQt5.QtWidgets import QApplication  # noqa: E402

from robot_sim.qt import window as viewer_window  # noqa: E402
from robot_sim.viewer.workspace_job import CANCELLED, COMPUTING, FAILED, IDLE, SHOWN  # noqa: E402

BIG = 3_000_000  # points: seconds of work, so a second key press lands while computing


@pytest.fixture(scope="module")
def app() -> QApplication:
    if not os.environ.get("DISPLAY"):
        pytest.fail("window tests need an X display: run them with xvfb-run (make test)")
    return QApplication.instance() or QApplication(["robot-sim-test"])


def open_window(*args: str) -> Any:
    config = prepare.prepare(list(args))
    win = viewer_window.MainWindow(prepare.session_from_config(config), output.window_options(config))
    win.resize(800, 600)
    win.show()
    win.view.setFocus()
    assert QTest.qWaitForWindowExposed(win)
    return win


def wait_until(condition: Callable[[], bool], seconds: float = 60.0) -> None:
    end = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < end, "timed out"
        QTest.qWait(20)


def press_e(win: Any) -> None:
    QTest.keyClick(win.view, Qt.Key_E)


@pytest.mark.window
def test_e_twice_while_computing_cancels(app: QApplication) -> None:
    win = open_window()
    try:
        win.options = dataclasses.replace(win.options, workspace=BIG)
        press_e(win)
        assert win.workspace.state == COMPUTING
        assert "workspace: computing" in win.status.text()
        press_e(win)
        assert win.workspace.state == CANCELLED
        assert win.message_label.text() == "workspace computation cancelled"
        assert win.session.workspace is None and not win.session.options.show_workspace
        assert win.workspace.wait(30)  # the worker stops at its next chunk
        QTest.qWait(50)
        assert win.workspace.state == CANCELLED and win.session.workspace is None
        assert "workspace: cancelled" in win.status.text()
        win.options = dataclasses.replace(win.options, workspace=5000)
        press_e(win)  # a third press starts afresh
        wait_until(lambda: win.workspace.state == SHOWN)
        assert len(win.session.workspace.points) == 5000 and win.session.options.show_workspace
    finally:
        win.close()


@pytest.mark.window
def test_switching_robot_cancels_the_computation(app: QApplication) -> None:
    win = open_window()
    try:
        win.options = dataclasses.replace(win.options, workspace=BIG)
        press_e(win)
        thread = win.workspace._thread
        win.choose_robot("puma560")
        assert win.workspace.state == IDLE and win.session.workspace is None
        thread.join(30)
        assert not thread.is_alive()
        QTest.qWait(50)
        assert win.workspace.state == IDLE and win.session.workspace is None
    finally:
        win.close()


@pytest.mark.window
def test_failure_is_shown_in_the_status_bar(app: QApplication, tmp_path) -> None:
    robot = tmp_path / "slider.toml"
    robot.write_text(
        'name = "slider"\nunits = "deg"\n[[joints]]\ntype = "prismatic"\na = 0.0\nalpha = 0.0\nd = 0.0\ntheta = 0.0\n'
    )
    win = open_window("--robot", str(robot))
    try:
        press_e(win)
        wait_until(lambda: win.workspace.state == FAILED)
        message = "workspace failed: slider: prismatic joint 1 has no limits; cannot sample its range"
        assert win.message_label.text() == message
        assert "workspace: failed" in win.status.text()
        assert win.isVisible()
    finally:
        win.close()
