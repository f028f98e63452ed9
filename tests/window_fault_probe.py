"""Run as a script under an X server: open the main window, make one handler raise, send
the event that calls it, and print JSON with what survived.  A separate process, because
an exception escaping a Qt handler aborts PyQt5's process (exit 134).

Usage: python window_fault_probe.py CASE   (CASE: key, wheel, paint, slider, timer)
"""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
os.environ.pop("PYOPENGL_PLATFORM", None)  # the window needs GLX

from PyQt5.QtCore import QPoint, QPointF, Qt  # noqa: E402
from PyQt5.QtGui import QWheelEvent  # noqa: E402
from PyQt5.QtTest import QTest  # noqa: E402
from PyQt5.QtWidgets import QApplication  # noqa: E402

from robot_sim.app import output, prepare
import simulator  # noqa: E402
from robot_sim.qt import window as viewer_window  # noqa: E402


class Boom(Exception):
    pass


def raiser(*args, **kwargs):
    raise Boom("injected failure")


def main(case: str) -> None:
    app = QApplication(["probe"])
    config = prepare.prepare([])
    win = viewer_window.MainWindow(prepare.session_from_config(config), output.window_options(config))
    win.resize(640, 480)
    win.show()
    QTest.qWaitForWindowExposed(win)
    app.processEvents()
    if case == "key":  # a key whose handler fails after its action (widget sync)
        win.sync_widgets = raiser
        QTest.keyClick(win.view, Qt.Key_T)
    elif case == "wheel":
        win.session.camera.zoom = raiser
        event = QWheelEvent(QPointF(100, 100), QPointF(100, 100), QPoint(0, 0), QPoint(0, 120),
                            Qt.NoButton, Qt.NoModifier, Qt.NoScrollPhase, False)
        QApplication.sendEvent(win.view, event)
    elif case == "paint":
        win.session.scene = raiser
        win.view.repaint()
    elif case == "slider":
        win.session.set_joint = raiser
        slider = win.joints.rows[0].slider
        slider.setValue(slider.value() + 50)
    elif case == "timer":
        win.session.step = raiser
        win.session.toggle_demo()
        win.start_motion()
        QTest.qWait(300)
    app.processEvents()
    QTest.qWait(50)
    print(json.dumps({"alive": win.isVisible(), "message": win.message_label.text()}))
    win.close()


if __name__ == "__main__":
    main(sys.argv[1])
