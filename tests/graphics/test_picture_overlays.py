"""What the picture shows besides the scene, offscreen: the workspace cloud's colour scale
in a ``--screenshot``, no arrow shorter than its head (a disc on a resting tool), arrows
shortened to the view, and status texts that quote only errors that mean something."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from robot_sim import graphics as go

go.require_osmesa_platform()

from cli_helpers import read_png, run  # noqa: E402
from robot_sim.graphics import defs as gd  # noqa: E402
from robot_sim.graphics.items.color_scale import color_scale_layout, value_texts  # noqa: E402
from robot_sim.graphics.label_layout import boxes_overlap  # noqa: E402
from robot_sim.graphics.vector_clip import VIEW_MARGIN, shown_vectors, visible_fraction  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.viewer.session import ViewerSession  # noqa: E402
from robot_sim.viewer.workspace_job import compute_workspace  # noqa: E402

W, H = 480, 360


def stop_pixels_found(image: np.ndarray, bar: np.ndarray) -> list[bool]:
    left, top, right, bottom = bar
    y = int(round(0.5 * (top + bottom)))
    found = []
    for stop, r, g, b in gd.WORKSPACE_COLORMAP:
        x = int(round(left + 2 + stop * (right - left - 4)))
        found.append(bool(np.all(np.abs(image[y, x, :3].astype(int) - np.round(255 * np.array([r, g, b]))) < 24)))
    return found


def test_a_workspace_screenshot_draws_the_colour_scale(tmp_path: Path) -> None:
    out = tmp_path / "cloud.png"
    result = run("--robot", "planar3", "--workspace", "3000", "--size", f"{W}x{H}", "--screenshot", str(out))
    assert result.returncode == 0, result.stderr
    image = read_png(out)
    values = compute_workspace(load_robot("planar3"), 3000).values  # the same seeded cloud
    scale = color_scale_layout(float(values.min()), float(values.max()), W, H)
    assert all(stop_pixels_found(image, scale.bar))
    for text, box in scale.texts:  # each text is written, in its box, inside the picture
        left, top, right, bottom = np.round(box).astype(int)
        assert 0 <= left and right <= W and 0 <= top and bottom <= H
        patch = image[top:bottom + 1, left:right + 1, :3].astype(int)
        assert np.count_nonzero(np.all(patch > 200, axis=-1)) >= 4 * len(text), text
    plain = tmp_path / "plain.png"
    assert run("--robot", "planar3", "--size", f"{W}x{H}", "--screenshot", str(plain)).returncode == 0
    assert not any(stop_pixels_found(read_png(plain), scale.bar))


def test_scale_texts_never_touch() -> None:
    for lo, hi in ((2.17e-08, 0.118), (0.0, 1234.5), (-0.5, 0.5), (0.3, 0.3)):
        scale = color_scale_layout(lo, hi, W, H)
        boxes = np.array([box for _, box in scale.texts])
        for i in range(len(boxes)):
            assert not np.any(boxes_overlap(boxes[i], boxes[i + 1:])), (lo, hi)
        assert np.all(boxes[:, 0] >= 0) and np.all(boxes[:, 2] <= W)
    assert value_texts(2.17e-08, 0.118) == ("0.000", "0.118")


@pytest.fixture(scope="module")
def renderer() -> go.OffscreenRenderer:
    with go.OffscreenRenderer(W, H) as r:
        yield r


def orange(image: np.ndarray) -> int:
    rgb = np.round(255 * np.asarray(gd.LINEAR_VELOCITY_COLOR[:3]))
    return int(np.count_nonzero(np.all(np.abs(image[..., :3].astype(int) - rgb) <= 60, axis=-1)))


def test_an_arrow_shorter_than_its_head_is_not_drawn(renderer: go.OffscreenRenderer) -> None:
    session = ViewerSession(load_robot("puma560"), aspect=W / H)
    reach = go.robot_reach(session.robot)
    head = reach * gd.VECTOR_HEAD_LENGTH_FRAC
    tool = session.kin.endeff_tf.t()
    plain = renderer.render(session.camera, session.scene(), session.options)
    for length, drawn in ((0.04 * head, False), (0.9 * head, False), (2.5 * head, True)):
        scene = session.scene()
        scene.vectors = [(tool, np.array([0.0, length, 0.0]), gd.LINEAR_VELOCITY_COLOR)]
        image = renderer.render(session.camera, scene, session.options)
        assert (orange(image) > orange(plain) + 20) == drawn, length
        if not drawn:
            np.testing.assert_array_equal(image, plain)


def test_a_long_arrow_ends_inside_the_view(renderer: go.OffscreenRenderer) -> None:
    session = ViewerSession(load_robot("puma560"), aspect=W / H)
    camera, tool = session.camera, session.kin.endeff_tf.t()
    right, _ = camera.view_plane_axes()
    vector = 40.0 * right  # metres: far past the picture's right edge
    t = visible_fraction(camera, W, H, tool, vector)
    assert 0.0 < t < 0.2
    tip = camera.project(tool + t * vector, W, H)[0]
    assert tip[0] == pytest.approx((1.0 - VIEW_MARGIN) * 0.5 * W + 0.5 * W - 0.5, abs=1.0)  # on the margin
    head = go.robot_reach(session.robot) * gd.VECTOR_HEAD_LENGTH_FRAC
    (_, shown, _), = shown_vectors([(tool, vector, gd.LINEAR_VELOCITY_COLOR)], camera, W, H, head)
    np.testing.assert_allclose(shown, t * vector)
    scene = session.scene()
    scene.vectors = [(tool, vector, gd.LINEAR_VELOCITY_COLOR)]
    image = renderer.render(camera, scene, session.options)
    x, y = np.round(camera.project(tool + (t * 0.98) * vector, W, H)[0]).astype(int)
    patch = image[y - 3:y + 4, x - 6:x + 1, :3].astype(int)  # the head, just inside the edge
    assert np.any(np.all(np.abs(patch - np.round(255 * np.asarray(gd.LINEAR_VELOCITY_COLOR[:3]))) <= 70, axis=-1))
    inside = [(tool, 0.1 * right, gd.LINEAR_VELOCITY_COLOR)]  # already in view: unchanged
    np.testing.assert_array_equal(shown_vectors(inside, camera, W, H, 0.01)[0][1], 0.1 * right)


def test_a_position_only_arm_quotes_no_rotation_error() -> None:
    planar = ViewerSession(load_robot("planar3"))
    planar.toggle_target()
    planar.move_target(translation=np.array([2.0, 0.0, 0.0]))  # far past its 1.2 m reach
    assert not planar.target_reachable
    text = planar.status_text("idle")
    assert f"pos err {planar.ik_result.pos_err:.3f} m" in text and "rot err" not in text
    puma = ViewerSession(load_robot("puma560"))
    puma.toggle_target()
    puma.move_target(translation=np.array([2.0, 0.0, 0.0]))
    assert not puma.target_reachable
    assert f"rot err {math.degrees(puma.ik_result.rot_err):.1f} deg" in puma.status_text("idle")
