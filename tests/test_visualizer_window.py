"""rs.Visualizer on the window backend (xvfb-run, ``-m window``): the script's loop owns
time, so display() shows the pose at once and wait() serves the window's events (a key
press reaches it), play() paces the samples in wall time, and wait(inf) returns when the
user closes the window."""
from __future__ import annotations

import math
import os
import time

import numpy as np
import pytest

if "OpenGL.platform" not in __import__("sys").modules:
    os.environ.pop("PYOPENGL_PLATFORM", None)  # the window needs GLX, not OSMesa

from PyQt5 import QtCore, QtGui  # noqa: E402
from PyQt5.QtCore import Qt  # noqa: E402
from PyQt5.QtWidgets import QApplication  # noqa: E402

import robot_sim as rs  # noqa: E402

pytestmark = pytest.mark.window


@pytest.fixture(scope="module")
def app() -> QApplication:
    if not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        pytest.fail("window tests need an X display: run them with xvfb-run (make test)")
    return QApplication.instance() or QApplication(["robot-sim-test"])


def test_display_shows_the_pose_and_wait_serves_the_windows_keys(app: QApplication) -> None:
    robot = rs.load_robot("ur5")
    with rs.Visualizer(robot, backend="window", size=(480, 360)) as viz:
        window = viz.backend.window
        options = viz.session.options
        options.show_frames = [False] * len(options.show_frames)
        options.show_labels = options.show_vectors = False
        q_a = np.array(robot.q_home, dtype=float)
        q_b = q_a + np.r_[0.8, np.zeros(robot.n_dofs - 1)]
        viz.display(q_a)
        image_a = viz.capture()
        viz.display(q_b)
        image_b = viz.capture()
        height, width = image_a.shape[:2]
        assert (width, height) == window.view.pixel_size()
        assert abs(width - 480) <= 2 and abs(height - 360) <= 2  # the view got the size asked
        assert viz.session is window.session
        frames = rs.forward_kinematics(robot, q_b, all_frames=True)[2:, :3, 3]
        pixels = viz.session.camera.project(frames, width, height)
        changed = np.any(np.abs(image_a.astype(int) - image_b.astype(int)) > 24, axis=2)
        assert all(changed[max(0, round(y) - 2):round(y) + 3, max(0, round(x) - 2):round(x) + 3].any()
                   for x, y in pixels)
        # a key pressed while the script waits is served: T turns the wireframe on
        assert not options.wireframe
        for kind in (QtCore.QEvent.KeyPress, QtCore.QEvent.KeyRelease):
            app.postEvent(window.view, QtGui.QKeyEvent(kind, Qt.Key_T, Qt.NoModifier, "t"))
        viz.backend.wait(0.2)
        assert viz.session.options.wireframe


def test_play_paces_the_samples_in_wall_time(app: QApplication) -> None:
    robot = rs.load_robot("puma560")
    t = np.linspace(0.0, 0.6, 61)
    q = np.asarray(robot.q_home) + np.outer(t, np.full(robot.n_dofs, 0.5))
    with rs.Visualizer(robot, backend="window", size=(320, 240)) as viz:
        for speed, least in ((1.0, 0.6), (3.0, 0.2)):
            start = time.monotonic()
            viz.play((t, q), speed=speed)
            assert time.monotonic() - start >= least - 1e-3  # never ahead of the trajectory
            np.testing.assert_allclose(viz.session.state.q(), q[-1])


def test_wait_forever_returns_when_the_user_closes_the_window(app: QApplication) -> None:
    robot = rs.load_robot("puma560")
    viz = rs.Visualizer(robot, backend="window", size=(320, 240))
    QtCore.QTimer.singleShot(300, viz.backend.window.close)
    viz.backend.wait(math.inf)
    assert not viz.backend.window.isVisible()
    viz.close()
    viz.close()  # harmless twice


def test_a_trail_played_in_real_time_keeps_the_samples_it_skipped(app: QApplication) -> None:
    robot = rs.load_robot("puma560")
    t = np.linspace(0.0, 0.2, 201)  # 1 kHz: far more samples than frames
    q = np.asarray(robot.q_home) + np.outer(t / 0.2, np.r_[1.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    with rs.Visualizer(robot, backend="window", size=(320, 240)) as viz:
        viz.session.toggle_trail()
        viz.play((t, q))
        points = viz.session.trail.points()
    tool = rs.forward_kinematics(robot, q)[:, :3, 3]
    sample_step = np.linalg.norm(np.diff(tool, axis=0), axis=1).max()  # 3.8 mm, above the trail's 2 mm
    # every sample's tool position, not the few chords between the frames drawn
    assert len(points) == len(t)
    assert np.linalg.norm(np.diff(points, axis=0), axis=1).max() <= sample_step + 1e-12
    np.testing.assert_allclose(points, tool, atol=1e-12)
