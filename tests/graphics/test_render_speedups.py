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

from render_helpers import MAGENTA, Frames, framed, key_points, posed, render, robot_mask, sunk  # noqa: E402,F401


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


# ---------------------------------------------- coarse meshes (detail, shadow casters)


def test_clustering_moves_vertices_less_than_a_cell_and_keeps_sharp_edges() -> None:
    from robot_sim.graphics.buffers import StaticMesh, clustered
    from robot_sim.graphics.visuals import vertex_normals

    vertices, faces = _lat_long_sphere(60)
    mesh = StaticMesh(vertices, vertex_normals(vertices, faces), faces)
    cell = 0.125
    positions, normals, tri = clustered(mesh.vertices, mesh.normals, mesh.indices, cell)
    assert len(tri) < 0.5 * mesh.n_triangles
    # every vertex has a clustered vertex within a cell's diagonal; the clustered ones lie
    # within the sphere (means of points on it) and near it
    nearest = np.sqrt(((mesh.vertices[:, None, :] - positions[None, :, :]) ** 2).sum(-1)).min(axis=1)
    assert nearest.max() < np.sqrt(3.0) * cell
    radii = np.linalg.norm(positions, axis=1)
    assert np.all(radii <= 1.0 + 1e-6) and np.all(radii >= 1.0 - np.sqrt(3.0) * cell)
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0)
    assert tri.max() < len(positions)
    # two finely tessellated flat faces meeting at a 10 degree crease (flat shaded: the
    # crease's vertices repeated with either face's normal): every clustered normal is
    # one of the faces', none a mean of both (that streaks flat faces)
    u, v = np.meshgrid(np.linspace(0.0, 1.0, 41), np.linspace(0.0, 1.0, 41), indexing="ij")
    tilt = np.radians(10.0)
    flat = np.stack([-u, v, np.zeros_like(u)], -1).reshape(-1, 3)
    tilted = np.stack([u * np.cos(tilt), v, u * np.sin(tilt)], -1).reshape(-1, 3)
    grid = np.arange(41 * 41).reshape(41, 41)
    quads = np.concatenate([np.stack([grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:]], -1).reshape(-1, 3),
                            np.stack([grid[:-1, :-1], grid[1:, 1:], grid[:-1, 1:]], -1).reshape(-1, 3)])
    face_normals = np.array([[0.0, 0.0, 1.0], [-np.sin(tilt), 0.0, np.cos(tilt)]])
    crease = StaticMesh(np.vstack([flat, tilted]), np.repeat(face_normals, len(flat), axis=0),
                        np.vstack([quads, quads + len(flat)]))
    _, crease_normals, crease_tri = clustered(crease.vertices, crease.normals, crease.indices, 0.1)
    assert len(crease_tri) < 0.5 * crease.n_triangles
    assert np.all(np.abs(crease_normals @ face_normals.T).max(axis=1) > 1.0 - 1e-6)


def test_a_coarse_mesh_is_built_once_per_grid_and_only_when_it_saves() -> None:
    from robot_sim.graphics.buffers import StaticMesh
    from robot_sim.graphics.visuals import vertex_normals

    vertices, faces = _lat_long_sphere(60)
    mesh = StaticMesh(vertices, vertex_normals(vertices, faces), faces)
    coarse = mesh.coarse(0.2)
    assert coarse is not mesh and coarse.n_triangles <= 0.5 * mesh.n_triangles
    assert mesh.coarse(0.15) is coarse  # the same power-of-two grid (1/8 m)
    assert mesh.coarse(0.001) is mesh and mesh.coarse(0.0) is mesh


def test_pixel_size_is_what_a_pixel_spans_in_the_picture() -> None:
    camera = framed(np.array([[0.0, 0.0, 0.0], [0.5, 0.5, 0.8]]))
    eye, target = camera.eye(), camera.target
    forward = (target - eye) / np.linalg.norm(target - eye)
    right, _ = camera.view_plane_axes()
    for depth in (0.5 * camera.distance, camera.distance, 2.0 * camera.distance):
        point = eye + depth * forward
        size = camera.pixel_size(depth, 240)
        pixels = camera.project(np.array([point, point + 10.0 * size * right]), 320, 240)
        assert np.isclose(pixels[1, 0] - pixels[0, 0], 10.0, atol=1e-6)


def _sphere_arm(rings: int, radius: float) -> go.Scene:
    """The puma560 carrying a fine sphere mesh on every link."""
    import dataclasses

    from robot_sim.model.shapes import Mesh

    kin = posed("puma560")
    vertices, faces = _lat_long_sphere(rings)
    visuals = tuple((Mesh((radius * vertices, faces), color=(0.7, 0.7, 0.75, 1.0)),) for _ in range(kin.robot.n_dofs))
    return go.Scene(posed(dataclasses.replace(kin.robot, visuals=visuals), [0.4, -0.6, 0.9, 0.3, 0.7, -0.2]))


def _far(mask: np.ndarray, other: np.ndarray, pixels: int) -> int:
    """How many pixels of ``mask`` lie farther than ``pixels`` (square) from ``other``'s."""
    grown = other.copy()
    for axis in (0, 1):
        for shift in range(1, pixels + 1):
            grown |= np.roll(other, shift, axis) | np.roll(other, -shift, axis)
    return int((mask & ~grown).sum())


def test_fine_meshes_drawn_coarse_keep_their_silhouette_and_shadow(render: Frames,
                                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    """A mesh finer than the pixels (about 60 000 triangles a sphere, with a seam of
    repeated vertices) drawn through its coarse stand-ins, and casting its shadow from
    them: silhouettes and shadow outlines within 2 pixels of the full mesh's (but for a
    few pixels at the threshold), and no seam opening (few pixels much changed)."""
    from robot_sim.graphics import defs as gd
    from robot_sim.graphics.buffers import StaticMesh

    scene = _sphere_arm(170, 0.07)
    options = go.GraphicsOptions(scene.kinematics.robot.n_dofs + 1)
    camera = framed(key_points(scene.kinematics))
    built: list[int] = []
    coarse = StaticMesh.coarse

    def counted(self: StaticMesh, cell: float) -> StaticMesh:
        stand_in = coarse(self, cell)
        built.append(stand_in.n_triangles)
        return stand_in

    with monkeypatch.context() as patch:
        patch.setattr(StaticMesh, "coarse", counted)
        drawn = render(camera, scene, options)
    with monkeypatch.context() as patch:
        patch.setattr(gd, "MESH_DETAIL_PX", 0.0)
        patch.setattr(gd, "SHADOW_CASTER_CELL_TEXELS", 0.0)
        full = render(camera, scene, options)
    assert max(built) < 0.5 * 2 * 170 * 170 * 2, "no coarse stand-in was drawn"
    background = render(camera, go.Scene(sunk(scene.kinematics)), options)
    for what, drawn_mask, full_mask in (
            ("silhouette", robot_mask(drawn, background), robot_mask(full, background)),
            ("shadow", _dark(drawn, background), _dark(full, background))):
        assert full_mask.sum() > 200, f"no {what} to compare"
        far = _far(drawn_mask, full_mask, 2) + _far(full_mask, drawn_mask, 2)
        assert far <= 3, f"{what}: {far} pixels moved by more than 2 pixels"
        assert abs(int(drawn_mask.sum()) - int(full_mask.sum())) <= 0.03 * full_mask.sum(), what
    changed = int((np.abs(drawn.astype(int) - full.astype(int)).max(axis=-1) > 30).sum())
    assert changed <= 20, f"{changed} pixels changed by more than 30 levels (a seam opened?)"


def _dark(image: np.ndarray, background: np.ndarray) -> np.ndarray:
    """Pixels (H, W) at least 20 levels darker than the same view without the robot."""
    return (background[..., :3].astype(int) - image[..., :3].astype(int)).min(axis=-1) >= 20


# ------------------------------------------------------- the floor's shadow patch


@pytest.mark.parametrize("name, q", [("stanford", [0.3, 0.9, 0.4, 0.0, 0.8, 0.0]),  # its base housing crosses the floor
                                     ("puma560", [0.4, -0.6, 0.9, 0.3, 0.7, -0.2]),
                                     ("humanoid7", [0.3, -0.5, 0.8, 1.1, -0.4, 0.6, 0.2])])
@pytest.mark.parametrize("theme", ["dark", "light"])
def test_shadow_patch_shaded_only_over_the_casters_footprint_equals_the_whole_patch(
        render: Frames, name: str, q: list[float], theme: str, monkeypatch: pytest.MonkeyPatch) -> None:
    kin = posed(name, q)
    options = go.GraphicsOptions(kin.robot.n_dofs + 1)
    options.theme = theme
    for azimuth in (0.0, 100.0, 200.0):
        camera = framed(key_points(kin))
        camera.orbit(azimuth, 0.0)
        footprinted = render(camera, go.Scene(kin), options)
        behind_eye = np.tile(camera.eye() + 2.0 * (camera.eye() - camera.target), (4, 1))  # scissor: everything
        with monkeypatch.context() as patch:
            patch.setattr(render_module, "shadow_footprint", lambda *args: behind_eye)
            whole = render(camera, go.Scene(kin), options)
        assert np.array_equal(footprinted, whole), (
            f"{name}, camera at {azimuth} deg: {int((footprinted != whole).any(-1).sum())} pixels differ")
