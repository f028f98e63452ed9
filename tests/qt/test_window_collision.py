"""The collision key in the real window (xvfb): C shows the collision display (shapes,
contacts in red, closest pair) and the readout gains the minimum distance; the status
bar flags the pose --q put into collision; C again hides the display; Shift+C runs the
circle demo; the help lists both keys."""
from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from window_helpers import app, changed_pixels, grab, open_window, press  # noqa: F401 (app is a fixture)

from PyQt5.QtCore import Qt  # noqa: E402
from PyQt5.QtTest import QTest  # noqa: E402

from robot_sim.qt.overlays import help_lines  # noqa: E402

pytestmark = pytest.mark.window

TABLE = '[[obstacles]]\nname = "table"\nshape = "box"\nsize = [0.6, 0.6, 0.1]\nxyz = [-0.55, -0.1, 0.05]\n'


def test_c_toggles_the_collision_display(app: Any, tmp_path: Path) -> None:  # noqa: F811
    world = tmp_path / "world.toml"
    world.write_text(TABLE)
    win = open_window(app, "--robot", "ur5", "--world", str(world), "--q", "0,-30,60,-120,0,0")
    try:
        before = grab(win)
        win.refresh_status()  # --q set the joints into the table: flagged without the display
        assert "IN COLLISION: link3 - table" in win.status.text() and "min distance" not in win.readout.text()
        press(app, Qt.Key_C)
        assert win.session.options.show_collision and win.session.demo is None
        assert "min distance -" in win.readout.text() and "(link3 - table)" in win.readout.text()
        shown = grab(win)
        assert changed_pixels(before, shown) > 2000
        press(app, Qt.Key_C)
        win.refresh_status()
        assert not win.session.options.show_collision and "min distance" not in win.readout.text()
        assert changed_pixels(before, grab(win)) == 0
        press(app, Qt.Key_C, Qt.ShiftModifier)
        assert win.session.demo is not None
        QTest.qWait(50)
        press(app, Qt.Key_C, Qt.ShiftModifier)
        assert win.session.demo is None
        text = "\n".join(help_lines())
        assert "collision shapes, contacts and closest distance" in text and "circle demo" in text
    finally:
        win.close()
