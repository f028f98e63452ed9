"""Render docs/window.png: the window at 1280x800 on the PUMA 560 under computed torque
following the circle demo, joint 2 selected in the DH table and annotated in the view,
the endeffector trail on.  Needs a display: ``xvfb-run -a .venv/bin/python
docs/window_picture.py docs/window.png`` from the checkout's root (``make pictures``), so
that the window shows the robot file's path relative to it.  The PNG records what the
window showed (its title) in a text chunk named ``Source``.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.pop("PYOPENGL_PLATFORM", None)  # the window needs GLX

from PyQt5 import QtCore, QtWidgets  # noqa: E402
from PyQt5.QtCore import Qt  # noqa: E402
from PyQt5.QtTest import QTest  # noqa: E402

from robot_sim.app import output, prepare  # noqa: E402
from robot_sim.io.files import write_atomic  # noqa: E402
from robot_sim.qt.window import APP_NAME, MainWindow  # noqa: E402

ARGS = ["--robot", "puma560", "--motion", "ct", "--demo", "circle"]
SIZE = (1280, 800)
SECONDS = 5.0  # of the circle demo before the picture


def main(out: str) -> int:
    app = QtWidgets.QApplication.instance() or QtWidgets.QApplication(["robot-sim"])
    config = prepare.prepare(ARGS)
    window = MainWindow(prepare.session_from_config(config), output.window_options(config))
    window.resize(*SIZE)
    window.show()
    QTest.qWaitForWindowExposed(window)
    window.dh_dock.table.selectRow(1)  # joint 2: annotated in the view
    window.view.setFocus()
    QTest.keyClick(window.view, Qt.Key_F, Qt.ShiftModifier)  # the trail (the circle demo runs from --demo circle)
    QTest.qWait(round(1000 * SECONDS))
    app.processEvents()
    picture = window.grab().toImage()
    picture.setText("Software", APP_NAME)
    picture.setText("Source", f"docs/window_picture.py ({' '.join(ARGS)}): {APP_NAME} window: {window.windowTitle()}")
    buffer = QtCore.QBuffer()
    buffer.open(QtCore.QIODevice.WriteOnly)
    picture.save(buffer, "PNG")
    write_atomic(Path(out), bytes(buffer.data()))
    print(f"wrote {out}")
    window.close()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "docs/window.png"))
