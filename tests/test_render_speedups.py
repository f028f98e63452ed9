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


# ------------------------------------------------------------ back-face culling


def _lat_long_sphere(rings: int) -> tuple[np.ndarray, np.ndarray]:
    """A latitude-longitude unit sphere with a seam and poles of repeated vertices (as
    mesh files often have), faces counter-clockwise seen from outside."""
    theta, phi = np.meshgrid(np.linspace(0.0, np.pi, rings + 1), np.linspace(0.0, 2 * np.pi, 2 * rings + 1), indexing="ij")
    vertices = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1)
    index = np.arange(vertices.shape[0] * vertices.shape[1]).reshape(vertices.shape[:2])
    a, b, c, d = index[:-1, :-1], index[:-1, 1:], index[1:, 1:], index[1:, :-1]
    faces = np.concatenate([np.stack([a, c, b], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    return vertices.reshape(-1, 3), faces


def test_closed_winding_tells_closed_meshes_and_their_winding() -> None:
    from robot_sim.graphics.buffers import StaticMesh, closed_winding
    from robot_sim.graphics.meshes import unit_meshes

    windings = {name: StaticMesh.from_triangles(v, n).winding for name, (v, n) in unit_meshes().items()}
    assert windings == {"cylinder": 0, "joint": 1, "cone": 1, "sphere": 1, "box": 1}
    vertices, faces = _lat_long_sphere(12)
    assert closed_winding(vertices, faces) == 1
    assert closed_winding(vertices, faces[:, ::-1]) == -1  # wound inwards
    middle = len(faces) // 2  # a face away from the poles' degenerate ones
    assert closed_winding(vertices, np.delete(faces, middle, axis=0)) == 0  # a hole
    flipped = faces.copy()
    flipped[middle] = flipped[middle, ::-1]
    assert closed_winding(vertices, flipped) == 0  # one face wound against its neighbours
    assert closed_winding(vertices, np.zeros((0, 3), dtype=int)) == 0


@pytest.mark.parametrize("look", ["solid", "dh", "mesh"])
def test_culled_back_faces_leave_the_picture_as_drawn_with_them(render: Frames, look: str,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    """Closed meshes drawn without their back faces (opaque layer and shadow map): the
    picture of every mesh drawn whole, but for samples on cracks of the meshes' seams
    (vertices that close a mesh only to round-off): a few pixels at silhouettes."""
    import dataclasses

    from robot_sim.graphics.buffers import StaticMesh
    from robot_sim.model.shapes import Mesh

    kin = posed("puma560", [0.4, -0.6, 0.9, 0.3, 0.7, -0.2])
    if look == "mesh":  # spheres wound inwards: their front faces are the ones culled
        vertices, faces = _lat_long_sphere(24)
        robot = dataclasses.replace(kin.robot, visuals=tuple(
            (Mesh((0.08 * vertices, faces[:, ::-1]), color=(0.7, 0.7, 0.75, 1.0)),) for _ in range(kin.robot.n_dofs)))
        kin = posed(robot, [0.4, -0.6, 0.9, 0.3, 0.7, -0.2])
    options = go.GraphicsOptions(kin.robot.n_dofs + 1)
    options.look = look
    for azimuth in (0.0, 150.0):
        camera = framed(key_points(kin))
        camera.orbit(azimuth, 15.0)
        culled = render(camera, go.Scene(kin), options)
        with monkeypatch.context() as patch:
            patch.setattr(StaticMesh, "winding", property(lambda self: 0))
            whole = render(camera, go.Scene(kin), options)
        differ = np.abs(culled.astype(int) - whole.astype(int)).max(-1)
        assert (differ > 0).sum() <= 20 and (differ > 48).sum() == 0, (
            f"{look}, camera at {azimuth} deg: {(differ > 0).sum()} pixels differ, by up to {differ.max()}")
