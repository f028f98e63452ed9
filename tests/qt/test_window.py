"""The real Qt window under an X server (``xvfb-run``): keys, sliders, dock, mouse.

Each test creates the main window, sends input with QTest to the widget that has the
keyboard focus (as a user's key press would go), grabs the GL framebuffer before and after
and checks that the picture changed the way the input says.  Pixel positions come from
``Camera.project`` with the GL widget's size.
"""
from __future__ import annotations

import dataclasses

import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from robot_sim.graphics import defs as gd
from robot_sim.qt import settings as qs
from robot_sim.viewer import settings as vs
from robot_sim import graphics as graphics_objects

if "OpenGL.platform" not in __import__("sys").modules:
    os.environ.pop("PYOPENGL_PLATFORM", None)  # the window needs GLX, not OSMesa

from PyQt5.QtCore import QPoint, Qt  # noqa: E402
from PyQt5.QtGui import QWheelEvent  # noqa: E402
from PyQt5.QtTest import QTest  # noqa: E402
from PyQt5.QtWidgets import QApplication, QSlider  # noqa: E402

from robot_sim.qt.overlays import help_lines  # noqa: E402

from window_helpers import (  # noqa: F401 - fixtures and helpers
    ROOT,
    app,
    open_window,
    window,
    grab,
    grab_window,
    press,
    project,
    near,
    dominant,
    robot_pixels,
    changed_pixels,
    cyan_pixels,
    is_red,
    drag,
    wait_until,
)


@pytest.mark.window
def test_gl_view_has_focus_and_window_is_idle(app: QApplication, window: Any) -> None:
    assert app.focusWidget() is window.view
    assert not window.timer.isActive()  # nothing moves, so nothing redraws
    assert window.session.robot.name in window.status.text()


@pytest.mark.window
def test_gl_context_has_a_depth_buffer(app: QApplication, window: Any) -> None:
    # Qt's default surface has none, and then parts paint over each other in drawing order
    grab(window)
    assert window.view.context().format().depthBufferSize() >= 24


def close_up_on_link(win: Any, link: int = 2) -> None:
    """Aim the camera closely at the middle of ``link`` so its mesh lines are pixels apart."""
    frames = win.session.kin.h_tf
    win.session.camera.target = 0.5 * (frames[link - 1].t() + frames[link].t())
    win.session.camera.distance = 0.4


@pytest.mark.window
def test_t_toggles_wireframe(app: QApplication, window: Any) -> None:
    close_up_on_link(window)
    before = grab(window)
    press(app, Qt.Key_T)
    after = grab(window)
    assert window.session.options.wireframe
    assert robot_pixels(after) < 0.7 * robot_pixels(before)


@pytest.mark.window
def test_digit_toggles_frame_axes_at_its_origin(app: QApplication, window: Any) -> None:
    origin = project(window, window.session.kin.h_tf[2].t())  # the elbow (frame 1 sits on frame 0)
    reach = graphics_objects.robot_reach(window.session.robot)
    radius = int(0.6 * gd.FRAME_LENGTH_FRAC * reach / window.session.camera.world_per_pixel(window.view.pixel_size()[1]))
    before = near(grab(window), origin, radius)
    press(app, Qt.Key_2)
    after = near(grab(window), origin, radius)
    assert window.session.options.show_frames[2]
    for channel in range(3):  # x red, y green, z blue
        assert dominant(after, channel) > dominant(before, channel) + 10, channel


@pytest.mark.window
def test_zero_toggles_all_frames(app: QApplication, window: Any) -> None:
    before = grab(window)
    press(app, Qt.Key_0)
    after = grab(window)
    assert all(window.session.options.show_frames)
    for i in range(1, window.session.n_frames):
        assert window.frames_list.item(i).checkState() == Qt.Checked
    assert dominant(after[..., :3].astype(int), 1) > dominant(before[..., :3].astype(int), 1) + 30


@pytest.mark.window
def test_arrow_key_orbits_camera(app: QApplication, window: Any) -> None:
    azimuth = window.session.camera.azimuth_deg
    before = grab(window)
    press(app, Qt.Key_Left)
    after = grab(window)
    assert window.session.camera.azimuth_deg == pytest.approx(azimuth - qs.KEY_ORBIT_STEP_DEG)
    assert changed_pixels(before, after) > 1000


@pytest.mark.window
def test_w_and_s_zoom(app: QApplication, window: Any) -> None:
    distance = window.session.camera.distance
    press(app, Qt.Key_W)
    assert window.session.camera.distance == pytest.approx(distance / qs.KEY_ZOOM_FACTOR)
    press(app, Qt.Key_S)
    press(app, Qt.Key_S)
    assert window.session.camera.distance == pytest.approx(distance * qs.KEY_ZOOM_FACTOR)


@pytest.mark.window
def test_slider_moves_the_red_endeffector(app: QApplication, window: Any) -> None:
    old_xy = project(window, window.session.kin.endeff_tf.t())
    before = grab(window)
    assert is_red(before, old_xy)
    slider = window.joints.rows[0].slider
    slider.setValue(slider.value() + 60 * qs.SLIDER_TICKS_PER_DEG)  # joint 1 by +60 deg
    assert window.session.state.q()[0] == pytest.approx(math.radians(60.0))
    assert window.joints.rows[0].box.value() == pytest.approx(60.0)  # the box follows
    new_xy = project(window, window.session.kin.endeff_tf.t())
    after = grab(window)
    assert np.linalg.norm(new_xy - old_xy) > 20
    assert is_red(after, new_xy)
    assert not is_red(after, old_xy)


@pytest.mark.window
def test_keys_work_after_clicking_a_slider(app: QApplication, window: Any) -> None:
    slider = window.joints.rows[1].slider
    QTest.mouseClick(slider, Qt.LeftButton, Qt.NoModifier, slider.rect().center() + slider.rect().topLeft())
    assert not isinstance(app.focusWidget(), QSlider)
    close_up_on_link(window)
    before = grab(window)
    press(app, Qt.Key_T)
    assert window.session.options.wireframe
    assert robot_pixels(grab(window)) < 0.7 * robot_pixels(before)


@pytest.mark.window
def test_target_keys_move_the_ghost_and_robot_follows(app: QApplication, window: Any) -> None:
    press(app, Qt.Key_G)
    before = grab(window)
    ghost_before = window.session.ghost.endeff_tf.t().copy()
    xy_before = project(window, ghost_before)
    for _ in range(8):
        press(app, Qt.Key_I)  # +x, TARGET_STEP_M each
    assert window.session.target_reachable
    ghost_after = window.session.ghost.endeff_tf.t()
    np.testing.assert_allclose(ghost_after - ghost_before, [8 * qs.TARGET_STEP_M, 0, 0], atol=1e-4)
    xy_after = project(window, ghost_after)
    assert np.linalg.norm(xy_after - xy_before) > 10
    # the current robot has not moved yet: around the yellow target marker only the
    # ghost's endeffector sphere (cyan, translucent) is new
    endeff_radius = graphics_objects.robot_look(window.session.robot).endeff_radius
    radius = int(endeff_radius / window.session.camera.world_per_pixel(window.view.pixel_size()[1]))
    assert cyan_pixels(near(grab(window), xy_after, radius)) > cyan_pixels(near(before, xy_after, radius)) + 10
    assert window.timer.isActive()
    wait_until(lambda: not window.timer.isActive())
    np.testing.assert_allclose(window.session.kin.endeff_tf.t(), ghost_after, atol=1e-6)
    # the red endeffector sphere now shows around the (smaller) yellow target marker
    assert dominant(near(grab(window), xy_after, radius), 0) > dominant(near(before, xy_after, radius), 0) + 10


@pytest.mark.window
def test_unreachable_target_keeps_ghost_and_says_so(app: QApplication, window: Any) -> None:
    press(app, Qt.Key_G)
    for _ in range(150):
        press(app, Qt.Key_U)  # 3 m up: out of reach
    assert not window.session.target_reachable
    ghost = window.session.ghost.endeff_tf.t().copy()
    press(app, Qt.Key_U)
    np.testing.assert_array_equal(window.session.ghost.endeff_tf.t(), ghost)
    grab(window)  # paints and refreshes the status bar
    assert "UNREACHABLE" in window.status.text()


@pytest.mark.window
def test_shift_target_key_rotates_target(app: QApplication, window: Any) -> None:
    press(app, Qt.Key_G)
    rot = window.session.target_tf.R().copy()
    press(app, Qt.Key_U, Qt.ShiftModifier)
    step = math.radians(qs.TARGET_STEP_DEG)
    rz = np.array([[math.cos(step), -math.sin(step), 0], [math.sin(step), math.cos(step), 0], [0, 0, 1]])
    np.testing.assert_allclose(window.session.target_tf.R(), rz @ rot, atol=1e-9)


@pytest.mark.window
def test_help_overlay_lists_bindings(app: QApplication, window: Any) -> None:
    press(app, Qt.Key_G)  # more GL state to live with: ghost, target
    before = grab_window(window)
    press(app, Qt.Key_H)
    grab_window(window)
    after = grab_window(window)  # still there on a later paint
    corner = after[qs.HELP_MARGIN_PX + 2: 200, qs.HELP_MARGIN_PX + 2: 200, :3].astype(int)
    text = np.all(np.abs(corner - np.array(qs.HELP_TEXT_RGB)) < 40, axis=-1)
    assert np.count_nonzero(text) > 100
    assert changed_pixels(before, after) > 5000
    lines = help_lines()
    for _key, _mods, _action, _arg, text in qs.KEY_BINDINGS:  # rows with one description share a line
        assert any(text in line for line in lines), text
    assert any(line.startswith("1 .. 9 ") for line in lines)
    assert any(line.startswith("Shift+I / Shift+K ") for line in lines)
    for gesture, text in qs.MOUSE_BINDINGS:
        assert any(line.startswith(gesture) and text in line for line in lines)


@pytest.mark.window
def test_robot_chooser_switches_robot(app: QApplication, window: Any) -> None:
    before = grab(window)
    window.robot_combo.setCurrentText("puma560")
    assert window.session.robot.n_dofs == 6
    assert len(window.joints.rows) == 6 and window.dh_dock.table.rowCount() == 6
    assert window.frames_list.count() == 6 + 2  # frames 0..6 and the endeffector
    assert changed_pixels(before, grab(window)) > 1000
    assert window.session.robot.name in window.status.text()
    assert app.focusWidget() is window.view
    press(app, Qt.Key_T)
    assert window.session.options.wireframe


@pytest.mark.window
def test_frames_past_nine_reachable_in_dock(app: QApplication, tmp_path: Path) -> None:
    joints = "".join(
        '[[joints]]\ntype = "revolute"\na = 0.12\nalpha = 0.0\nd = 0.0\ntheta = 0.0\nhome = 20.0\n'
        "limits = [-170.0, 170.0]\n\n"
        for _ in range(12)
    )
    robot_file = tmp_path / "snake12.toml"  # planar 12-link snake above the ground
    robot_file.write_text(f'name = "snake12"\nunits = "deg"\n\n[base]\nxyz = [0.0, 0.0, 0.3]\n\n{joints}')
    win = open_window(app, "--robot", str(robot_file))
    try:
        assert win.frames_list.count() == 13 + 1
        origin = project(win, win.session.kin.h_tf[12].t())
        before = near(grab(win), origin, 25)
        item = win.frames_list.item(12)
        win.frames_list.scrollToItem(item)
        rect = win.frames_list.visualItemRect(item)
        checkbox = QPoint(rect.left() + rect.height() // 2 + 2, rect.center().y())
        QTest.mouseClick(win.frames_list.viewport(), Qt.LeftButton, Qt.NoModifier, checkbox)
        assert win.session.options.show_frames[12]
        after = near(grab(win), origin, 25)
        assert dominant(after, 1) > dominant(before, 1) + 10  # its green y axis (red x covers the red endeffector)
        press(app, Qt.Key_9)
        assert win.session.options.show_frames[9]
    finally:
        win.close()


@pytest.mark.window
def test_workspace_cloud_computed_in_background(app: QApplication, window: Any) -> None:
    before = grab(window)
    window.options = dataclasses.replace(window.options, workspace=20000)
    press(app, Qt.Key_E)
    assert window.session.options.show_workspace
    wait_until(lambda: window.session.workspace is not None)
    with_cloud = grab(window)
    assert len(window.session.workspace) == 20000
    assert changed_pixels(before, with_cloud) > 1000
    press(app, Qt.Key_E)
    assert not window.session.options.show_workspace
    hidden = grab(window)  # the cloud framed the view: compare with the same view, no cloud at all
    window.session.workspace = None
    assert changed_pixels(hidden, grab(window)) == 0


@pytest.mark.window
def test_circle_demo_and_velocity_vectors(app: QApplication) -> None:
    win = open_window(app, "--demo", "circle")
    try:
        demo = win.session.demo
        assert win.timer.isActive()
        QTest.qWait(400)
        distance = np.linalg.norm((win.session.kin.endeff_tf.t() - demo.center)[:2])
        assert distance == pytest.approx(vs.DEMO_CIRCLE_RADIUS_M, abs=0.01)
        assert np.linalg.norm(win.session.kin.endeff_twist[:3]) > 0.01
        win.timer.stop()  # freeze the motion, arrows still show the last velocity
        with_vectors = grab(win)
        press(app, Qt.Key_V)
        assert not win.session.options.show_vectors
        assert changed_pixels(with_vectors, grab(win)) > 50
        press(app, Qt.Key_C, Qt.ShiftModifier)
        assert win.session.demo is None and not win.timer.isActive()
    finally:
        win.close()


@pytest.mark.window
def test_mouse_drag_orbits_and_ctrl_drag_moves_target(app: QApplication, window: Any) -> None:
    view = window.view
    centre = view.rect().center()
    azimuth, distance = window.session.camera.azimuth_deg, window.session.camera.distance
    drag(app, view, centre, QPoint(25, 0), Qt.LeftButton)
    assert window.session.camera.azimuth_deg == pytest.approx(azimuth - 25 * qs.MOUSE_ORBIT_DEG_PER_PX)
    camera_target = window.session.camera.target.copy()
    drag(app, view, centre, QPoint(0, 40), Qt.RightButton)
    assert np.linalg.norm(window.session.camera.target - camera_target) > 0
    QTest.mouseClick(view, Qt.LeftButton)  # focus stays with the view
    wheel = QWheelEvent(QPoint(centre), view.mapToGlobal(centre), QPoint(), QPoint(0, 120), Qt.NoButton, Qt.NoModifier, Qt.NoScrollPhase, False)
    app.sendEvent(view, wheel)  # one notch away from the user: zoom in
    assert window.session.camera.distance == pytest.approx(distance / qs.WHEEL_ZOOM_FACTOR)
    press(app, Qt.Key_G)
    target = window.session.target_tf.t().copy()
    drag(app, view, centre, QPoint(30, 0), Qt.LeftButton, Qt.ControlModifier)
    right, _up = window.session.camera.view_plane_axes()
    step = window.session.target_tf.t() - target
    assert np.dot(step, right) == pytest.approx(30 * window.session.camera.world_per_pixel(view.pixel_size()[1]))


@pytest.mark.window
def test_escape_closes_window(app: QApplication, window: Any) -> None:
    press(app, Qt.Key_Escape)
    assert not window.isVisible()


@pytest.mark.window
def test_n_toggles_frame_labels_and_m_centres_of_mass(app: QApplication, window: Any) -> None:
    before = grab(window)
    press(app, Qt.Key_N)
    assert not window.session.options.show_labels
    without_labels = grab(window)
    origin = project(window, window.session.kin.h_tf[0].t())
    assert changed_pixels(near(before, origin, 40), near(without_labels, origin, 40)) > 10  # the "0" is gone
    press(app, Qt.Key_N)
    assert window.session.options.show_labels
    assert changed_pixels(before, grab(window)) == 0
    press(app, Qt.Key_M)
    assert window.session.options.show_com
    assert changed_pixels(before, grab(window)) > 10
