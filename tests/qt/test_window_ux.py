"""The window's DH table dock, joint panel, readout, status messages, view presets, help,
screenshots, trail and legend, in the real Qt window under Xvfb (marker ``window``).

Expected values come from closed forms (moving a link length moves the endeffector along
that frame's x axis) and from ``Camera.project`` for pixels, as in test_window.py, whose
helpers this module shares.
"""
from __future__ import annotations

import dataclasses

import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from paths import ROOT
from robot_sim.graphics import defs as gd
from robot_sim.qt import settings as qs
from window_helpers import app, changed_pixels, grab, is_red, open_window, press, project, wait_until  # noqa: F401

from PyQt5.QtCore import Qt  # noqa: E402
from PyQt5.QtTest import QTest  # noqa: E402

from robot_sim.viewer.dh_table import COLUMNS  # noqa: E402
from robot_sim.viewer.readout import pose_readout  # noqa: E402
from robot_sim.kinematics import manipulability  # noqa: E402

pytestmark = pytest.mark.window


@pytest.fixture
def planar(app: Any, tmp_path: Path) -> Any:
    """A window on a copy of planar3.toml (so tests may rewrite it), joints at 10, 20, 30 deg."""
    path = tmp_path / "planar3.toml"
    path.write_text((ROOT / "robots" / "planar3.toml").read_text())
    win = open_window(app, "--robot", str(path), "--q", "10,20,30")
    yield win
    win.edited = False  # tests that edit leave nothing to ask about at teardown
    win.close()


def type_into_cell(app: Any, win: Any, row: int, column: str, text: str) -> None:
    """Type ``text`` into a DH table cell and press Enter, as a user would."""
    table = win.dh_dock.table
    table.setFocus()
    table.setCurrentCell(row, COLUMNS.index(column))
    QTest.keyClick(table, Qt.Key_F2)  # open the cell's editor (as a double click does)
    editor = app.focusWidget()
    assert editor is not table
    editor.selectAll()
    QTest.keyClicks(editor, text)
    QTest.keyClick(editor, Qt.Key_Return)
    app.processEvents()


def readout_xyz(win: Any) -> np.ndarray:
    return np.array([float(v) for v in win.readout.text().splitlines()[0].split()[2:5]])


# ------------------------------------------------------------------ DH table dock


def test_editing_a_link_length_moves_the_endeffector_along_that_frames_x(app: Any, planar: Any) -> None:
    session = planar.session
    q = session.state.q().copy()
    x3 = session.kin.h_tf[3].R()[:, 0].copy()  # a_3 runs along x of frame 3
    before = session.kin.endeff_tf.t().copy()
    np.testing.assert_allclose(readout_xyz(planar), before, atol=5e-5)
    type_into_cell(app, planar, 2, "a", "0.45")
    session = planar.session
    assert session.robot.dh_a[2] == 0.45
    np.testing.assert_array_equal(session.state.q(), q)  # joint values kept
    expected = before + 0.15 * x3
    np.testing.assert_allclose(session.kin.endeff_tf.t(), expected, atol=1e-12)
    np.testing.assert_allclose(readout_xyz(planar), expected, atol=5e-5)
    assert planar.readout.text() == pose_readout(session.kin.endeff_tf, manipulability(session.robot, q))
    assert "(edited)" in planar.windowTitle()


def test_an_invalid_value_is_refused_in_place_with_the_reason(app: Any, planar: Any) -> None:
    robot = planar.session.robot
    type_into_cell(app, planar, 1, "limits", "100 .. 50")
    assert planar.session.robot is robot  # nothing changed
    item = planar.dh_dock.table.item(1, COLUMNS.index("limits"))
    assert item.text() == "100 .. 50"  # the refused text stays where it was typed ...
    assert item.background().color().getRgb()[:3] == qs.DH_INVALID_CELL_RGB  # ... tinted
    reason = "joint 2 limits: min 100.0 > max 50.0"
    assert item.toolTip() == f"refused: {reason}"
    assert planar.dh_dock.error_label.text() == f"refused: {reason}"
    assert planar.message_label.text() == f"refused: {reason}"
    type_into_cell(app, planar, 1, "alpha", "abc")
    assert planar.dh_dock.error_label.text() == "refused: joint 2 α: 'abc' is not a number"


def test_the_joint_variable_cell_is_read_only_and_follows_the_joint(app: Any, planar: Any) -> None:
    item = planar.dh_dock.table.item(0, COLUMNS.index("theta"))
    assert not item.flags() & Qt.ItemIsEditable
    assert item.text() == "10.00 (q1)"
    planar.joints.rows[0].slider.setValue(45 * qs.SLIDER_TICKS_PER_DEG)
    assert item.text() == "45.00 (q1)"


def rewrite(path: Path, text: str) -> None:
    """Replace the file the way editors do (write a new file, rename it over the old)."""
    tmp = path.with_suffix(".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def test_the_file_is_reloaded_when_it_changes_on_disk(app: Any, planar: Any) -> None:
    path = Path(planar.dh_dock.path)
    q = planar.session.state.q().copy()
    robot = planar.session.robot
    rewrite(path, path.read_text().replace("a = 0.3\n", "a = 0.35\n"))
    wait_until(lambda: planar.session.robot is not robot, 5000)
    assert planar.session.robot.dh_a[2] == 0.35
    np.testing.assert_array_equal(planar.session.state.q(), q)  # same DOF: joint values kept
    assert planar.message_label.text() == f"reloaded {path}"
    # a broken file is reported and the shown robot stays
    robot = planar.session.robot
    rewrite(path, path.read_text().replace("a = 0.35\n", "a = \"long\"\n"))
    wait_until(lambda: "not reloaded" in planar.message_label.text(), 5000)
    assert planar.session.robot is robot
    assert "joints[2].a: expected a number, got 'long'" in planar.message_label.text()
    # another number of joints: home values
    rewrite(path, (ROOT / "robots" / "scara.toml").read_text())
    wait_until(lambda: planar.session.robot.n_dofs == 4, 5000)
    np.testing.assert_array_equal(planar.session.state.q(), planar.session.robot.q_home)


def test_save_as_keeps_the_comments_and_watches_the_new_file(app: Any, planar: Any, tmp_path: Path) -> None:
    original = Path(planar.dh_dock.path).read_text()
    type_into_cell(app, planar, 0, "d", "0.1")
    target = tmp_path / "saved.toml"
    assert planar.dh_dock.save_to(target)
    saved = target.read_text()
    comments = [line for line in original.splitlines() if line.startswith("#")]
    assert comments and comments == [line for line in saved.splitlines() if line.startswith("#")]
    assert "d = 0.1" in saved.split("[[joints]]")[1]
    assert planar.windowTitle() == f"Three-link planar arm — {target} — robot-sim"
    assert planar.message_label.text() == f"saved Three-link planar arm to {target}"
    robot = planar.session.robot
    rewrite(target, saved.replace("a = 0.5\n", "a = 0.55\n"))
    wait_until(lambda: planar.session.robot is not robot, 5000)
    assert planar.session.robot.dh_a[0] == 0.55


def test_save_as_urdf_and_back_to_toml(app: Any, planar: Any, tmp_path: Path) -> None:
    from robot_sim.io.robot_file import load_robot

    urdf = tmp_path / "planar3.urdf"
    assert planar.dh_dock.save_to(urdf)
    assert urdf.read_text().lstrip().startswith("<")
    assert planar.dh_dock.open_file(urdf)
    assert planar.session.robot.n_dofs == 3
    toml = tmp_path / "from_urdf.toml"
    assert planar.dh_dock.save_to(toml)  # a URDF is no TOML template: a fresh file
    again = load_robot(toml)
    np.testing.assert_array_equal(again.dh_a, planar.session.robot.dh_a)
    np.testing.assert_array_equal(again.dh_alpha, planar.session.robot.dh_alpha)


def test_open_loads_another_robot_at_home(app: Any, planar: Any, monkeypatch: Any) -> None:
    monkeypatch.chdir(ROOT)  # the title names files inside the working folder relative to it
    assert planar.dh_dock.open_file(ROOT / "robots" / "puma560.toml")
    assert planar.session.robot.name == "PUMA 560"
    np.testing.assert_array_equal(planar.session.state.q(), planar.session.robot.q_home)
    assert planar.windowTitle() == "PUMA 560 — robots/puma560.toml — robot-sim"  # relative to the working folder
    assert not planar.dh_dock.open_file(ROOT / "robots" / "nosuch.toml")
    assert planar.session.robot.name == "PUMA 560"
    assert "cannot open" in planar.message_label.text()


def test_selecting_a_row_or_pressing_d_annotates_that_joint(app: Any, planar: Any) -> None:
    planar.dh_dock.table.selectRow(1)  # joint 2 (annotate_joint counts from 1)
    assert planar.session.options.annotate_joint == 2
    planar.view.setFocus()
    press(app, Qt.Key_D)
    assert planar.session.options.annotate_joint == 3
    press(app, Qt.Key_D)
    assert planar.session.options.annotate_joint is None and planar.dh_dock.selected_joint() is None
    press(app, Qt.Key_D)
    assert planar.session.options.annotate_joint == 1
    assert planar.dh_dock.selected_joint() == 0


def test_annotate_option_selects_its_dh_row(app: Any) -> None:
    win = open_window(app, "--robot", "puma560", "--annotate", "3")
    try:
        assert win.dh_dock.selected_joint() == 2 and win.session.options.annotate_joint == 3
    finally:
        win.close()


# ------------------------------------------------------------------ joint panel


def test_typed_joint_values_home_zero_and_limit_labels(app: Any, planar: Any) -> None:
    row = planar.joints.rows[1]
    assert (row.low.text(), row.high.text()) == ("-170°", "170°")
    row.box.setFocus()
    row.box.selectAll()
    QTest.keyClicks(row.box, "-35.5")
    QTest.keyClick(row.box, Qt.Key_Return)
    assert planar.session.state.q()[1] == pytest.approx(math.radians(-35.5))
    assert row.slider.value() == -355
    QTest.mouseClick(planar.joints.zero_button, Qt.LeftButton)
    np.testing.assert_array_equal(planar.session.state.q(), [0.0, 0.0, 0.0])
    QTest.mouseClick(planar.joints.home_button, Qt.LeftButton)
    np.testing.assert_array_equal(planar.session.state.q(), planar.session.robot.q_home)


# ------------------------------------------------------------------ status bar and title


def test_one_off_messages_show_beside_the_permanent_status_and_go(app: Any, planar: Any, monkeypatch: Any) -> None:
    monkeypatch.setattr(qs, "STATUS_MESSAGE_MS", 300)
    planar.message("a message the user must see")
    label, status = planar.message_label, planar.status
    assert label.isVisible() and label.text() == "a message the user must see"
    assert label.width() >= label.sizeHint().width()  # not clipped
    assert label.geometry().right() < status.geometry().left()  # beside, not under
    assert planar.session.robot.name in status.text()
    wait_until(lambda: label.text() == "", 3000)


def test_title_names_robot_and_file(app: Any, planar: Any) -> None:
    assert planar.windowTitle() == f"Three-link planar arm — {planar.dh_dock.path} — robot-sim"


# ------------------------------------------------------------------ view


@pytest.mark.parametrize(
    "key, direction",
    [(Qt.Key_1, (1.0, 0.0, 0.0)), (Qt.Key_2, (0.0, -1.0, 0.0)), (Qt.Key_4, (1.0, 1.0, 1.0))],
)
def test_view_preset_keys_move_the_camera_and_the_picture(app: Any, planar: Any, key: int, direction: Any) -> None:
    camera = planar.session.camera
    target, distance = camera.target.copy(), camera.distance
    before = grab(planar)
    press(app, key, Qt.ControlModifier)
    expected = np.asarray(direction) / np.linalg.norm(direction)
    np.testing.assert_allclose((camera.eye() - camera.target) / camera.distance, expected, atol=1e-9)
    np.testing.assert_array_equal(camera.target, target)
    assert camera.distance == distance
    after = grab(planar)
    assert changed_pixels(before, after) > 1000
    if key != Qt.Key_2:  # from the side the planar arm's tip can hide behind its links
        assert is_red(after, project(planar, planar.session.kin.endeff_tf.t()))


def test_top_view_and_orthographic_toggle(app: Any, planar: Any) -> None:
    press(app, Qt.Key_3, Qt.ControlModifier)
    camera = planar.session.camera
    assert camera.elevation_deg == gd.CAMERA_MAX_ELEVATION_DEG
    press(app, Qt.Key_5, Qt.ControlModifier)
    assert camera.orthographic
    assert "orthographic" in planar.view.info.status_text()
    image = grab(planar)
    assert is_red(image, project(planar, planar.session.kin.endeff_tf.t()))
    press(app, Qt.Key_5, Qt.ControlModifier)
    assert not camera.orthographic and "perspective" in planar.view.info.status_text()


def test_grid_scale_is_shown(app: Any, planar: Any) -> None:
    from robot_sim import graphics as go

    step = go.FloorGrid.for_reach(go.robot_reach(planar.session.robot)).step
    assert planar.view.info.status_text().startswith(f"grid {step:g} m")


def test_follow_keeps_the_camera_on_the_endeffector(app: Any, planar: Any) -> None:
    press(app, Qt.Key_F)
    planar.joints.rows[0].slider.setValue(60 * qs.SLIDER_TICKS_PER_DEG)
    np.testing.assert_array_equal(planar.session.camera.target, planar.session.kin.endeff_tf.t())
    centre = (np.array(planar.view.pixel_size()) - 1) / 2.0
    np.testing.assert_allclose(project(planar, planar.session.kin.endeff_tf.t()), centre, atol=1e-6)
    press(app, Qt.Key_F)
    target = planar.session.camera.target.copy()
    planar.joints.rows[0].slider.setValue(0)
    np.testing.assert_array_equal(planar.session.camera.target, target)


def test_trail_draws_the_endeffector_path(app: Any, planar: Any) -> None:
    press(app, Qt.Key_F, Qt.ShiftModifier)
    slider = planar.joints.rows[0].slider
    start = planar.session.kin.endeff_tf.t().copy()
    for deg in range(10, 71, 2):
        slider.setValue(deg * qs.SLIDER_TICKS_PER_DEG)
    points = planar.session.trail.points()
    assert len(points) >= 25
    np.testing.assert_allclose(points[0], start)
    width, height = planar.view.pixel_size()
    planar.session.camera.fit(np.vstack([points, planar.session.kin.endeff_tf.t()]), width / height)
    image = grab(planar)
    trail_rgb = np.round(255 * np.asarray(gd.TRAIL_COLOR[:3])).astype(int)
    middle = points[len(points) // 2]  # on the arc swept by the tip, now left behind
    x, y = np.round(project(planar, middle)).astype(int)
    assert 2 <= x < width - 2 and 2 <= y < height - 2
    window = image[y - 2:y + 3, x - 2:x + 3, :3].astype(int)
    assert np.any(np.all(np.abs(window - trail_rgb) <= 3, axis=-1))
    press(app, Qt.Key_F, Qt.ShiftModifier)
    assert planar.session.trail is None
    window = grab(planar)[y - 2:y + 3, x - 2:x + 3, :3].astype(int)
    assert not np.any(np.all(np.abs(window - trail_rgb) <= 3, axis=-1))


def scale_colours(image: np.ndarray, scale: Any) -> list[bool]:
    """Whether the picture shows each second colour stop inside the scale's bar."""
    left, top, right, bottom = scale.bar
    y = int(round(0.5 * (top + bottom)))
    hits = []
    for stop, r, g, b in gd.WORKSPACE_COLORMAP[::2]:
        x = int(round(left + 2 + stop * (right - left - 4)))
        hits.append(bool(np.all(np.abs(image[y, x, :3].astype(int) - np.round(255 * np.array([r, g, b]))) < 20)))
    return hits


def test_e_shows_the_colour_scale_at_once(app: Any, planar: Any) -> None:
    from robot_sim.graphics.items.color_scale import color_scale_layout

    planar.options = dataclasses.replace(planar.options, workspace=5000)
    press(app, Qt.Key_E)
    wait_until(lambda: planar.session.workspace is not None)  # no widget sync asked for
    values = planar.session.workspace.values
    scale = color_scale_layout(float(values.min()), float(values.max()), *planar.view.pixel_size())
    assert all(scale_colours(grab(planar), scale))
    press(app, Qt.Key_E)
    assert not any(scale_colours(grab(planar), scale))


def test_e_frames_the_cloud(app: Any) -> None:
    win = open_window(app, "--robot", "ur5", "--q", "0,-60,90,-120,-90,0")
    try:
        win.options = dataclasses.replace(win.options, workspace=4000)
        press(app, Qt.Key_E)
        wait_until(lambda: win.session.workspace is not None)
        points = np.asarray(win.session.workspace.points)
        camera = win.session.camera
        eye = camera.eye()
        assert np.any(eye < points.min(axis=0)) or np.any(eye > points.max(axis=0))  # outside the cloud
        pixels = camera.project(points, *win.view.pixel_size())
        width, height = win.view.pixel_size()
        inside = (pixels[:, 0] >= 0) & (pixels[:, 0] < width) & (pixels[:, 1] >= 0) & (pixels[:, 1] < height)
        assert inside.all()
    finally:
        win.close()


# ------------------------------------------------------------------ help, Esc, screenshots


def test_escape_closes_the_help_before_the_window(app: Any, planar: Any) -> None:
    press(app, Qt.Key_H)
    assert planar.help.isVisible()
    press(app, Qt.Key_Escape)
    assert not planar.help.isVisible() and planar.isVisible()
    press(app, Qt.Key_Escape)
    assert not planar.isVisible()


@pytest.mark.parametrize("size", [(640, 480), (1024, 768), (1280, 960)])
def test_help_fits_the_view(app: Any, size: tuple[int, int]) -> None:
    """The help covers the 3D view only (never the docks), cuts no line and scrolls the rest."""
    from PyQt5.QtCore import QRect
    from PyQt5.QtWidgets import QDockWidget

    win = open_window(app, "--robot", "puma560", size=size)
    try:
        press(app, Qt.Key_H)
        help_ = win.help
        assert help_.parentWidget() is win.view and win.view.rect().contains(help_.geometry())
        on_window = QRect(help_.mapTo(win, help_.rect().topLeft()), help_.size())
        for dock in win.findChildren(QDockWidget):
            assert not dock.isVisible() or not on_window.intersects(dock.geometry()), dock.windowTitle()
        viewport = help_.viewport()
        wide = help_.label.sizeHint().width() - viewport.width()
        assert wide <= 0 or help_.horizontalScrollBar().maximum() >= wide  # a narrow view scrolls sideways
        if size != (640, 480):
            assert wide <= 0  # no line cut on the right
        hidden = help_.label.sizeHint().height() - viewport.height()
        assert hidden <= 0 or help_.verticalScrollBar().maximum() >= hidden  # the rest scrolls
    finally:
        win.close()


def test_p_saves_into_the_screenshots_folder_and_says_where(app: Any, planar: Any, tmp_path: Path,
                                                         monkeypatch: Any) -> None:
    monkeypatch.chdir(tmp_path)
    press(app, Qt.Key_P)
    saved = list((tmp_path / qs.SCREENSHOT_DIR).glob("robot-sim-planar3-*.png"))
    assert len(saved) == 1
    assert planar.message_label.text() == f"screenshot saved to {saved[0]}"
    assert planar.message_label.isVisible()
    assert (ROOT / ".gitignore").read_text().splitlines().count(f"{qs.SCREENSHOT_DIR}/") == 1


def test_keys_b_and_shift_b_show_the_ik_branches(app: Any) -> None:
    win = open_window(app, "--robot", "puma560", "--q", "30,50,-100,20,30,-20")
    session = win.session
    before = grab(win)
    press(app, Qt.Key_B)
    sols = session.branches.solutions
    assert win.message_label.text() == f"IK branch 1 of {len(sols)}: {sols.branch[0]}"
    np.testing.assert_array_equal(session.state.q_des(), sols.q[0])
    press(app, Qt.Key_B)
    np.testing.assert_array_equal(session.state.q_des(), sols.q[1])
    press(app, Qt.Key_B, Qt.ShiftModifier)
    assert win.message_label.text() == f"all {len(sols)} IK branches shown"
    assert len(session.scene().branches) == len(sols) >= 2
    assert np.count_nonzero(np.any(grab(win) != before, axis=2)) > 200
    press(app, Qt.Key_B, Qt.ShiftModifier)
    assert win.message_label.text() == "IK branches hidden" and session.scene().branches == []
    win.close()
