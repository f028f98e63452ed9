"""The render path's shortcuts draw the pictures of the plain path they replace, pixel for
pixel: the overlay's depth cleared only under its items' bounds (against a full clear).

Each test renders through the shortcut and through the plain way (put back for the test
with monkeypatch) and compares the images exactly."""
from __future__ import annotations

import numpy as np
import pytest

from robot_sim import graphics as go

go.require_osmesa_platform()

from robot_sim.graphics import render as render_module  # noqa: E402
from robot_sim.graphics.gl import GL  # noqa: E402
from robot_sim.transforms import HomogeneousTransform  # noqa: E402

from render_helpers import MAGENTA, Frames, framed, key_points, posed, render  # noqa: E402,F401


def _full_clear(frame: object, overlay: object) -> None:
    """The plain overlay start: every depth sample cleared."""
    GL.glClear(GL.GL_DEPTH_BUFFER_BIT)


def _overlay_scene() -> tuple[go.Scene, go.GraphicsOptions, list[go.Camera]]:
    """humanoid7 with every frame, an IK target and two arrows, and cameras around it,
    one of them with its eye among the frames (some bounds behind the eye)."""
    kin = posed("humanoid7", [0.3, -0.5, 0.8, 1.1, -0.4, 0.6, 0.2])
    target = HomogeneousTransform.from_rt(t=kin.endeff_tf.t() + [0.1, 0.1, -0.2])
    origin = kin.endeff_tf.t()
    scene = go.Scene(kin, target_tf=target, vectors=[(origin, np.array([0.0, 0.3, 0.2]), MAGENTA),
                                                   (origin, np.array([-0.2, 0.0, -0.3]), MAGENTA)])
    options = go.GraphicsOptions(kin.robot.n_dofs + 1)
    options.toggle_all_frames()
    options.show_target = options.show_vectors = True
    cameras = []
    for azimuth in (0.0, 120.0, 240.0):
        camera = framed(key_points(kin))
        camera.orbit(azimuth, 10.0)
        cameras.append(camera)
    inside = framed(key_points(kin))
    inside.zoom(0.02)  # the eye among the frames
    cameras.append(inside)
    return scene, options, cameras


@pytest.mark.parametrize("theme", ["dark", "light"])
def test_overlay_depth_cleared_under_its_bounds_equals_a_full_clear(render: Frames, theme: str,
                                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    scene, options, cameras = _overlay_scene()
    options.theme = theme
    for camera in cameras:
        boxed = render(camera, scene, options)
        with monkeypatch.context() as patch:
            patch.setattr(render_module, "_clear_overlay_depth", _full_clear)
            full = render(camera, scene, options)
        assert np.array_equal(boxed, full), (
            f"camera {camera.azimuth_deg:.0f} deg: {int((boxed != full).any(-1).sum())} pixels differ from a full clear")
