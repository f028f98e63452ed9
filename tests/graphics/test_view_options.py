"""View presets, the orthographic projection and the endeffector trail, rendered offscreen
(OSMesa): camera maths checked against closed forms, pixels at Camera.project's points."""
from __future__ import annotations

import math
from typing import Iterator

import numpy as np
import pytest

from robot_sim import graphics as go

go.require_osmesa_platform()

from robot_sim.graphics import defs as gd  # noqa: E402
from robot_sim.kinematics import Kinematics  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.model.state import RobotState  # noqa: E402
from robot_sim.qt import settings as qs

W, H = 320, 240


@pytest.fixture(scope="module")
def renderer() -> Iterator[go.OffscreenRenderer]:
    with go.OffscreenRenderer(W, H) as r:
        yield r


def planar_kinematics() -> Kinematics:
    robot = load_robot("planar3")
    state = RobotState(robot)
    state.set_q(np.radians([20.0, 30.0, -40.0]))
    kin = Kinematics(robot)
    kin.update(state.joint_state)
    return kin


@pytest.mark.parametrize(
    "preset, direction",
    [
        ("front", (1.0, 0.0, 0.0)),
        ("side", (0.0, -1.0, 0.0)),
        ("iso", (1.0, 1.0, 1.0)),
    ],
)
def test_view_presets_put_the_eye_on_the_named_side(preset, direction):
    camera = go.Camera(distance=2.0, azimuth_deg=10.0, elevation_deg=20.0, target=[0.1, 0.2, 0.3])
    camera.set_view(*qs.VIEW_PRESETS[preset])
    expected = np.asarray(direction) / np.linalg.norm(direction)
    np.testing.assert_allclose((camera.eye() - camera.target) / camera.distance, expected, atol=1e-9)
    np.testing.assert_array_equal(camera.target, [0.1, 0.2, 0.3])
    assert camera.distance == 2.0


def test_top_view_looks_down_with_x_right_and_y_up():
    camera = go.Camera()
    camera.set_view(*qs.VIEW_PRESETS["top"])
    view_dir = (camera.target - camera.eye()) / camera.distance
    assert math.degrees(math.acos(-view_dir[2])) <= 90.0 - gd.CAMERA_MAX_ELEVATION_DEG + 1e-9
    right, up = camera.view_plane_axes()
    np.testing.assert_allclose(right, [1.0, 0.0, 0.0], atol=1e-12)
    assert up[1] > 0.999


def test_orthographic_projection_is_parallel_at_the_scale_of_the_target_plane():
    camera = go.Camera(distance=2.0, azimuth_deg=30.0, elevation_deg=20.0)
    right, _ = camera.view_plane_axes()
    towards_eye = (camera.eye() - camera.target) / camera.distance
    beside = camera.target + 0.1 * right
    pair = np.array([beside, beside + 0.5 * towards_eye])
    centre_x = (W - 1) / 2.0
    perspective = camera.project(pair, W, H)
    expected = 0.1 / camera.world_per_pixel(H)  # px: 0.1 m in the plane through the target
    # perspective: the point 0.5 m nearer (1.5 m from the eye instead of 2) lies farther out
    np.testing.assert_allclose(perspective[1, 0] - centre_x, expected * 2.0 / 1.5, rtol=1e-9)
    camera.orthographic = True
    ortho = camera.project(pair, W, H)
    np.testing.assert_allclose(ortho[1], ortho[0], atol=1e-9)  # same ray, same pixel
    # both put a point of the target plane at the same place
    np.testing.assert_allclose([ortho[0, 0] - centre_x, perspective[0, 0] - centre_x], expected, rtol=1e-9)


def test_orthographic_render_draws_the_endeffector_where_project_puts_it(renderer):
    kin = planar_kinematics()
    camera = go.Camera(orthographic=True)
    camera.set_view(*qs.VIEW_PRESETS["top"])
    camera.fit(np.vstack([[tf.t() for tf in kin.h_tf], kin.endeff_tf.t()]), W / H)
    image = renderer.render(camera, go.Scene(kin), go.GraphicsOptions(kin.robot.n_dofs + 1))
    x, y = np.round(camera.project(kin.endeff_tf.t()[None], W, H)[0]).astype(int)
    r, g, b = image[y, x, :3].astype(int)
    assert r > 120 and r > 2 * g and r > 2 * b, f"endeffector pixel {(r, g, b)} at {(x, y)}"


def test_trail_is_drawn_as_a_line_of_its_colour_through_its_points(renderer):
    kin = planar_kinematics()
    camera = go.Camera()
    camera.set_view(*qs.VIEW_PRESETS["iso"])
    reach = go.robot_reach(kin.robot)
    # a square path beside the arm, 0.2 reach above the ground
    corners = reach * np.array([[0.5, -0.8, 0.2], [0.9, -0.8, 0.2], [0.9, -0.4, 0.2], [0.5, -0.4, 0.2], [0.5, -0.8, 0.2]])
    path = np.vstack([np.linspace(a, b, 20) for a, b in zip(corners[:-1], corners[1:])])
    camera.fit(np.vstack([path, kin.endeff_tf.t()]), W / H)
    options = go.GraphicsOptions(kin.robot.n_dofs + 1)
    with_trail = renderer.render(camera, go.Scene(kin, trail=path), options)
    without = renderer.render(camera, go.Scene(kin), options)
    trail_rgb = np.round(255 * np.asarray(gd.TRAIL_COLOR[:3])).astype(int)
    for a, b in zip(corners[:-1], corners[1:]):
        x, y = np.round(camera.project(((a + b) / 2)[None], W, H)[0]).astype(int)
        window = with_trail[y - 1:y + 2, x - 1:x + 2, :3].astype(int)
        assert np.any(np.all(np.abs(window - trail_rgb) <= 3, axis=-1)), f"no trail pixel near {(x, y)}"
        assert not np.any(np.all(np.abs(without[y - 1:y + 2, x - 1:x + 2, :3].astype(int) - trail_rgb) <= 3, axis=-1))


def test_fit_on_annotation_frames_the_annotated_joint() -> None:
    """`--annotate J` frames joint J's annotation (its dimensions, arcs, labels and its two
    frames) rather than the whole arm: every annotation point is in the picture, and the
    annotation spans at least 1.5 times as many pixels as when the whole arm is framed
    (about 2× for PUMA 560's joint 3)."""
    from robot_sim.viewer.session import ViewerSession

    session = ViewerSession(load_robot("puma560"), aspect=800 / 600)
    session.set_q(np.radians([0.0, 45.0, -135.0, 0.0, 45.0, 0.0]))
    session.options.annotate_joint = 3
    points = go.annotation_points(session.scene(), session.options)

    def extent() -> tuple[float, np.ndarray]:
        px = session.camera.project(points, 800, 600)
        return float(np.ptp(px, axis=0).max()), px

    session.fit_camera()
    whole, _ = extent()
    session.fit_camera(on_annotation=True)
    close, px = extent()
    assert np.all((px >= 0.0) & (px <= [800.0, 600.0]))
    assert close >= 1.5 * whole
    session.options.annotate_joint = None  # nothing annotated: the usual framing
    assert go.annotation_points(session.scene(), session.options) is None
    session.fit_camera(on_annotation=True)
    focused = session.camera.distance
    session.fit_camera()
    assert focused == pytest.approx(session.camera.distance, rel=1e-12)


def test_framing_includes_the_ghost_when_it_is_drawn() -> None:
    """PUMA 560 falls for 1.5 s (passive) while its desired state stays at home: the ghost
    is drawn apart from the arm, and fit_camera keeps every corner of its parts in view
    (it used to frame the arm alone and cut the ghost off at the top)."""
    from robot_sim.viewer.session import ViewerSession

    session = ViewerSession(load_robot("puma560"), aspect=1024 / 768)
    session.set_motion("passive")
    session.motion.simulate(1.5)
    session.update_kinematics()
    scene = session.scene()
    assert scene.ghost is not None and session.options.show_ghost
    session.fit_camera()
    ghost = scene.ghost
    corners = go.part_corners(go.robot_parts(ghost.robot, ghost.frames, ghost.endeff_tf.mat, None))
    px = session.camera.project(corners, 1024, 768)
    assert np.all((px >= 0.0) & (px <= [1024.0, 768.0]))
