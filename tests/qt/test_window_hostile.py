"""Issue 31 (xvfb): a robot named by a long path keeps the Robot dock inside a 1280 px
window: the chooser elides the name in the middle, and the joint boxes, the upper limits,
the Zero button and the status bar stay visible.  The window's pick demo (Space) plans
among the --world obstacles."""
from __future__ import annotations

import shutil
from typing import Any

import pytest

from test_window import app  # noqa: F401 - the QApplication fixture
from test_window_layout import cut_off, opened  # noqa: F401 - the window fixture

from PyQt5.QtCore import QRect  # noqa: E402

from robot_sim.io.robot_file import ROBOTS_DIR  # noqa: E402

pytestmark = pytest.mark.window


def _visible_in(widget: Any, win: Any) -> bool:
    rect = QRect(widget.mapTo(win, widget.rect().topLeft()), widget.size())
    return win.rect().contains(rect) and not widget.visibleRegion().isEmpty()


def test_a_long_robot_path_keeps_the_robot_dock_inside_the_window(opened, tmp_path) -> None:  # noqa: F811
    folder = tmp_path / ("a_rather_long_folder_name_" * 6) / ("and_another_one_below_it_" * 6)
    folder.mkdir(parents=True)
    path = folder / ("puma560_with_a_long_descriptive_name_" * 3 + ".toml")
    shutil.copy(ROBOTS_DIR / "puma560.toml", path)
    win = opened("--robot", str(path), size=(1280, 800))
    assert win.width() == 1280
    assert cut_off(win) == []
    combo = win.robot_combo
    shown = combo.itemText(combo.currentIndex())
    assert "…" in shown and shown.startswith("puma560") and shown.endswith("_.toml")  # the file name, middle cut
    assert combo.currentData() == str(path) and combo.toolTip() == str(path)
    for row in win.joints.rows:
        win.dock_scroll.ensureWidgetVisible(row.slider)
        for widget in (row.box, row.slider, row.high):
            assert _visible_in(widget, win), type(widget).__name__
    win.dock_scroll.ensureWidgetVisible(win.joints.zero_button)
    assert _visible_in(win.joints.zero_button, win)
    assert _visible_in(win.statusBar(), win)


def test_the_window_pick_demo_plans_among_the_world_obstacles(opened, tmp_path) -> None:  # noqa: F811
    from robot_sim.io.robot_file import load_robot
    from robot_sim.planning.pick_task import default_task

    x, y, _ = default_task(load_robot("ur5")).place[:3, 3]
    world = tmp_path / "world.toml"
    world.write_text(f'[[obstacles]]\nname = "post"\nshape = "box"\nsize = [0.1, 0.1, 1.0]\nxyz = [{x}, {y}, 0.0]\n')
    win = opened("--robot", "ur5", "--world", str(world), size=(1280, 800))
    win.start_pick()
    assert win.session.pick is None
    assert "place: the place pose at" in win.message_label.text()
    assert "is inside obstacle 'post'" in win.message_label.text()
