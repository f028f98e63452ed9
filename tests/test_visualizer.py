"""rs.Visualizer offscreen: the picture shows the arm where the camera projects its joints,
play() renders one frame per sample, bad arguments are refused before anything opens, and
the trail drawn is the path the tool took (OSMesa; no display)."""
from __future__ import annotations

import math

import numpy as np
import pytest

import robot_sim as rs
from robot_sim import graphics as go

go.require_osmesa_platform()

W, H = 320, 240


def _plain(viz: rs.Visualizer) -> None:
    """No frames, labels or arrows: what changes between two poses is the arm (and its shadow)."""
    options = viz.session.options
    options.show_frames = [False] * len(options.show_frames)
    options.show_labels = options.show_vectors = False


def test_the_arm_is_drawn_where_the_camera_projects_its_joints() -> None:
    robot = rs.load_robot("ur5")
    q_a = np.array(robot.q_home, dtype=float)
    q_b = q_a + np.r_[0.8, np.zeros(robot.n_dofs - 1)]  # the base joint turns: the whole arm moves
    with rs.Visualizer(robot, size=(W, H)) as viz:
        _plain(viz)
        viz.display(q_a)
        image_a = viz.capture()
        viz.display(q_b)
        image_b = viz.capture()
        camera = viz.session.camera
        frames_a = rs.forward_kinematics(robot, q_a, all_frames=True)
        frames_b = rs.forward_kinematics(robot, q_b, all_frames=True)
    assert image_a.shape == (H, W, 3) and image_a.dtype == np.uint8
    changed = np.any(np.abs(image_a.astype(int) - image_b.astype(int)) > 24, axis=2)
    assert 0.005 < changed.mean() < 0.25  # the arm moved, the floor and sky stayed
    # the joint origins that moved more than 5 cm, in both poses
    moved = np.linalg.norm(frames_a[:, :3, 3] - frames_b[:, :3, 3], axis=1) > 0.05
    points = np.vstack([frames_a[moved, :3, 3], frames_b[moved, :3, 3]])
    assert len(points) >= 6
    pixels = camera.project(points, W, H)
    near = [changed[max(0, round(y) - 2):round(y) + 3, max(0, round(x) - 2):round(x) + 3].any() for x, y in pixels]
    assert all(near), f"joints drawn away from their projection: {pixels[~np.array(near)]}"
    # the same points mirrored top to bottom mostly miss the arm (the check can fail)
    mirrored = [changed[H - 1 - round(y), round(x)] for x, y in pixels]
    assert sum(mirrored) < len(mirrored) // 2


def test_play_renders_one_frame_per_sample_and_ends_at_the_last() -> None:
    robot = rs.load_robot("puma560")
    t = np.linspace(0.0, 2.0, 9)  # 8 Hz: offscreen ignores wall time
    q = np.asarray(robot.q_home) + np.outer(np.sin(t), np.linspace(0.2, 0.6, robot.n_dofs))
    with rs.Visualizer(robot, size=(W, H)) as viz:
        before = viz.backend.frames
        viz.play((t, q), speed=0.5)
        assert viz.backend.frames - before == len(t)
        np.testing.assert_allclose(viz.session.state.q(), q[-1])
        last = viz.capture()
        trajectory = rs.Trajectory(t, q, np.zeros_like(q), np.zeros_like(q))
        viz.play(trajectory)
        assert viz.backend.frames - before == 2 * len(t)
        np.testing.assert_array_equal(viz.capture(), last)


def test_the_trail_drawn_is_the_tool_path_played() -> None:
    robot = rs.load_robot("ur5")
    t = np.linspace(0.0, 1.0, 41)
    q = np.asarray(robot.q_home) + np.outer(t, np.r_[1.2, 0.4, np.zeros(robot.n_dofs - 2)])
    with rs.Visualizer(robot, size=(W, H)) as viz:
        _plain(viz)
        viz.play((t, q))
        without = viz.capture()
        viz.session.toggle_trail()
        viz.play((t, q))
        with_trail = viz.capture()
        trail = viz.session.trail.points()
        pixels = viz.session.camera.project(trail, W, H)
    tool = rs.forward_kinematics(robot, q)[:, :3, 3]
    # the trail holds the tool's positions: each played sample is within a step of it
    assert len(trail) > 10
    assert max(np.min(np.linalg.norm(trail - p, axis=1)) for p in tool) < 0.003
    changed = np.any(np.abs(with_trail.astype(int) - without.astype(int)) > 24, axis=2)
    assert changed.any()
    inside = [(x, y) for x, y in pixels if 2 <= x < W - 2 and 2 <= y < H - 2]
    hits = [changed[round(y) - 2:round(y) + 3, round(x) - 2:round(x) + 3].any() for x, y in inside]
    assert np.mean(hits) > 0.6  # most of the line shows (the arm hides some of it)


def test_show_offscreen_returns_the_picture_of_a_visualizer() -> None:
    robot = rs.load_robot("puma560")
    q = np.asarray(robot.q_home) + 0.3
    picture = rs.show(robot, q, backend="offscreen", size=(W, H), theme="light")
    with rs.Visualizer(robot, size=(W, H), theme="light") as viz:
        viz.display(q)
        np.testing.assert_array_equal(picture, viz.capture())
        assert viz.session.options.theme == "light"


@pytest.mark.parametrize("kwargs, message", [
    ({"backend": "vr"}, "backend: expected one of offscreen, window, web, got 'vr'"),
    ({"size": (0, 600)}, "size: expected (width, height) in pixels, each 1..8192, got (0, 600)"),
    ({"size": (800.5, 600)}, "size: expected (width, height) in pixels, each 1..8192, got (800.5, 600)"),
    ({"theme": "neon"}, "theme: expected one of dark, light, got 'neon'"),
    ({"look": "mesh"}, "look: robot 'PUMA 560' can be drawn as dh, solid; got 'mesh'"),
])
def test_bad_arguments_are_refused_before_anything_opens(kwargs: dict, message: str) -> None:
    robot = rs.load_robot("puma560")
    with pytest.raises(ValueError) as err:
        rs.Visualizer(robot, **kwargs)
    assert str(err.value) == message


def test_bad_joint_values_and_trajectories_change_nothing() -> None:
    robot = rs.load_robot("puma560")
    with rs.Visualizer(robot, size=(W, H)) as viz:
        q0 = viz.session.state.q()
        with pytest.raises(ValueError):
            viz.display(np.zeros(robot.n_dofs + 1))
        with pytest.raises(ValueError, match=r"trajectory: q must have shape \(3, 6\)"):
            viz.play((np.arange(3.0), np.zeros((3, 5))))
        with pytest.raises(ValueError, match="speed: expected a positive finite number, got 0"):
            viz.play((np.arange(3.0), np.zeros((3, 6))), speed=0)
        with pytest.raises(ValueError, match="t must be strictly increasing"):
            viz.play((np.array([0.0, 0.0, 1.0]), np.zeros((3, 6))))
        np.testing.assert_array_equal(viz.session.state.q(), q0)
        assert not math.isnan(viz.capture().mean())


def test_backend_attributes_are_read_through_the_visualizer() -> None:
    robot = rs.load_robot("planar3")
    with rs.Visualizer(robot, size=(64, 48)) as viz:
        viz.display()
        assert viz.frames == viz.backend.frames == 1  # the offscreen backend's own attribute
        with pytest.raises(AttributeError):
            viz.no_such_attribute
        with pytest.raises(AttributeError):
            viz._renderer  # private names are not delegated
    with pytest.raises(TypeError, match="the offscreen backend takes no options, got port"):
        rs.Visualizer(robot, size=(64, 48), port=8080)
