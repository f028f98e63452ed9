"""The look key in the real window (xvfb): Shift+T cycles the robot's looks (meshes,
DH, both, solid for a robot with visuals; DH, solid without), the picture changes with
each, the help lists the key, and --theme / --look reach the window."""
from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from geometry_helpers import boxed_arm
from window_helpers import app, changed_pixels, grab, open_window, press  # noqa: F401 (app is a fixture)

from PyQt5.QtCore import Qt  # noqa: E402

from robot_sim.qt.overlays import help_lines  # noqa: E402

pytestmark = pytest.mark.window


def _cycle(app: Any, win: Any, presses: int) -> tuple[list[str], list[np.ndarray]]:
    looks, pictures = [], [grab(win)]
    for _ in range(presses):
        press(app, Qt.Key_T, Qt.ShiftModifier)
        looks.append(win.session.options.look)
        pictures.append(grab(win))
    return looks, pictures


def test_shift_t_cycles_the_looks_of_a_robot_with_visuals(app: Any, tmp_path: Path) -> None:  # noqa: F811
    win = open_window(app, "--robot", str(boxed_arm(tmp_path)))
    try:
        looks, pictures = _cycle(app, win, 4)
        assert looks == ["dh", "both", "solid", "mesh"]  # from the default, meshes
        for before, after in zip(pictures, pictures[1:]):
            assert changed_pixels(before, after) > 200
        assert changed_pixels(pictures[0], pictures[-1]) == 0  # back to the first look, same picture
        assert win.message_label.text() == "look: mesh"
    finally:
        win.close()
        win.deleteLater()


def test_shift_t_without_visuals_and_theme_from_the_command_line(app: Any) -> None:  # noqa: F811
    win = open_window(app, "--theme", "light", "--look", "solid")
    try:
        assert grab(win)[2, 2, :3].min() > 230  # the light theme's background
        looks, pictures = _cycle(app, win, 2)
        assert looks == ["dh", "solid"]
        assert changed_pixels(pictures[0], pictures[1]) > 200 and changed_pixels(pictures[0], pictures[2]) == 0
        assert any(line.startswith("Shift+T ") and "look" in line for line in help_lines())
    finally:
        win.close()
        win.deleteLater()


def test_a_moving_camera_draws_without_msaa_and_the_still_view_with_it(app: Any) -> None:  # noqa: F811
    from PyQt5.QtTest import QTest

    win = open_window(app, "--robot", "planar3", "--q", "30,30,30")
    try:
        still = grab(win)
        refine = win.view.refine
        refine.setInterval(60_000)  # not due while the moving frame is checked, however slow the machine
        press(app, Qt.Key_Left)  # the camera orbits
        app.processEvents()  # its paint
        assert win.view.last_samples == 0 and refine.isActive()
        refine.start(1)  # the camera has not moved since: the refine's paint is the still view
        QTest.qWait(50)
        app.processEvents()
        assert win.view.last_samples == win.session.options.samples > 1  # the still view, and the session keeps MSAA
        press(app, Qt.Key_Right)  # back where it was; a grab now is drawn with MSAA at once
        assert changed_pixels(grab(win), still) == 0 and win.view.last_samples > 1
    finally:
        win.close()
        win.deleteLater()
