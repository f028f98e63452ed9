"""The pick demo in the real window (xvfb): the plot dock shows the trajectory, the
timeline slider scrubs the scene, play advances time."""
from __future__ import annotations

import numpy as np
import pytest

from robot_sim.qt import settings as qs
from window_helpers import app, open_window  # noqa: F401 - the QApplication fixture
from robot_sim.control.controllers import MOTION_LABELS

from PyQt5.QtGui import QColor, QImage  # noqa: E402
from PyQt5.QtTest import QTest  # noqa: E402

pytestmark = pytest.mark.window


@pytest.mark.parametrize("robot", ["scara", "humanoid7"])
def test_the_pick_view_frames_table_object_and_arm_with_nothing_hidden(app, robot):  # noqa: F811
    from robot_sim.viewer.pick_view import arm_points, hidden_by_box, table_box

    win = open_window(app, "--robot", robot, "--demo", "pick", size=(1024, 768))
    try:
        win.timer.stop()
        plan, camera = win.session.pick.plan, win.session.camera
        assert not hidden_by_box(camera.eye(), arm_points(plan), *table_box(plan)).any()  # the table hides no arm
        lo, hi = table_box(plan)
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        width, height = win.view.pixel_size()
        for what, points in (("table", corners), ("arm", arm_points(plan)), ("object", plan.spec.object_pose[None, :3, 3])):
            pixels = camera.project(points, width, height)
            assert np.all((pixels >= 0) & (pixels < [width, height])), what
        assert win.motion_panel.combo.currentText() == MOTION_LABELS["kinematic"]
        assert not win.motion_panel.replay_note.isVisible()
    finally:
        win.close()
        win.deleteLater()


@pytest.fixture
def pick_window(app):  # noqa: F811
    win = open_window(app, "--robot", "ur5", "--demo", "pick")
    yield win
    win.close()
    win.deleteLater()


def test_plot_dock_shows_the_trajectory(pick_window):
    win = pick_window
    traj = win.session.pick.plan.trajectory
    dock = win.plot_dock
    assert dock.isVisible()
    assert not dock.plots["effort"].isVisible() and not dock.curves["effort"]  # kinematic: no effort
    for key in ("q", "qd", "qdd"):
        curves = dock.curves[key]
        assert len(curves) == traj.n_dofs
        for j, curve in enumerate(curves):
            np.testing.assert_array_equal(curve.xData, traj.t)
            np.testing.assert_array_equal(curve.yData, getattr(traj, key)[:, j])
    # the legend row names each joint next to its curve's pen
    assert [label.text for _, label in dock.legend.items] == [f"joint {j + 1}" for j in range(traj.n_dofs)]
    assert [sample.item is curve for (sample, _), curve in zip(dock.legend.items, dock.curves["q"])] == [True] * traj.n_dofs
    # only the lowest plot shown carries the time axis
    assert [dock.plots[k].getAxis("bottom").isVisible() for k in ("q", "qd", "qdd")] == [False, False, True]
    # the plot widget really painted the curves: pixels of each joint's colour
    image = dock.graphics.grab().toImage().convertToFormat(QImage.Format_RGB888)
    pixels = np.frombuffer(image.constBits().asstring(image.byteCount()), np.uint8)
    pixels = pixels.reshape(image.height(), image.bytesPerLine())[:, : 3 * image.width()].reshape(image.height(), -1, 3)
    for j in range(traj.n_dofs):
        rgb = QColor(qs.PLOT_JOINT_COLORS[j]).getRgb()[:3]
        assert np.count_nonzero(np.all(np.abs(pixels.astype(int) - rgb) <= 40, axis=2)) > 20, f"joint {j + 1}"


def test_slider_scrubs_the_scene_and_moves_the_cursor(pick_window):
    win = pick_window
    demo = win.session.pick
    win.timer.stop()
    demo.playing = False
    t = demo.plan.phase_times()["transport"] + 0.3
    win.pick_panel.slider.setValue(round(t * qs.PICK_SLIDER_TICKS_PER_S))
    assert demo.time == pytest.approx(t, abs=1e-3)
    np.testing.assert_allclose(win.session.state.q(), demo.plan.state_at(demo.time).q, atol=1e-12)
    assert win.plot_dock.cursors["q"].value() == pytest.approx(demo.time)
    assert "transport" in win.pick_panel.label.text()


def test_play_advances_time(pick_window):
    win = pick_window
    demo = win.session.pick
    assert demo.playing
    start = demo.time
    QTest.qWait(300)
    assert demo.time > start
    win.pick_panel.play.click()  # pause
    assert not demo.playing
    paused = demo.time
    QTest.qWait(200)
    assert demo.time == paused


def test_simulated_pick_plots_effort(app):  # noqa: F811
    win = open_window(app, "--robot", "ur5", "--demo", "pick", "--motion", "ct")
    try:
        demo = win.session.pick
        assert demo.effort is not None
        assert win.plot_dock.plots["effort"].isVisible()
        curves = win.plot_dock.curves["effort"]
        assert len(curves) == 6
        np.testing.assert_array_equal(curves[0].yData, demo.effort[:, 0])
        np.testing.assert_array_equal(curves[0].xData, demo.plan.trajectory.t)
        # the chooser names the replayed run's mode, not "kinematic"
        assert win.motion_panel.combo.currentText() == MOTION_LABELS["ct"] and not win.session.physical
        assert win.motion_panel.replay_note.isVisible()
        assert "computed torque" in win.motion_panel.replay_note.text()
    finally:
        win.close()
        win.deleteLater()
