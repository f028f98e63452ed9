"""Pixels of the new look: the light theme, the key light's shadow, multisampling.

Every expected position comes from forward kinematics, ``Camera.project`` and the key
light's direction (``lighting.key_light``)."""
from __future__ import annotations

import numpy as np

from robot_sim import graphics as go

go.require_osmesa_platform()

from render_helpers import DEG, framed, key_points, options_for, posed, project, render  # noqa: E402,F401
from robot_sim.graphics.lighting import key_light  # noqa: E402
from robot_sim.transforms import HomogeneousTransform  # noqa: E402


def test_light_theme_background_is_light(render) -> None:
    kin = posed("ur5")
    options = options_for(kin)
    options.theme = "light"
    image = render(framed(key_points(kin)), go.Scene(kin), options)
    corner = image[:5, :5, :3].astype(float).mean(axis=(0, 1))
    assert corner.min() > 0.85 * 255, f"light theme background {corner}"
    options.theme = "dark"
    dark = render(framed(key_points(kin)), go.Scene(kin), options)
    assert dark[:5, :5, :3].astype(float).mean() < 0.3 * 255


def test_the_shadow_falls_on_the_floor_away_from_the_light(render) -> None:
    """The endeffector's shadow lies where the ray from it away from the key light meets
    the floor: that pixel darkens when shadows are on; the point as far towards the
    light does not."""
    kin = posed("planar3", [0.0, 0.0, 0.0], HomogeneousTransform.from_rt(t=[0.0, 0.0, 0.3]))  # 0.3 m up
    tip = kin.endeff_tf.t()
    key = key_light()
    shadow = tip - key * (tip[2] / key[2])
    towards = tip + key * (tip[2] / key[2]) * np.array([1.0, 1.0, -1.0])  # mirrored towards the light, on the floor
    camera = go.Camera(elevation_deg=70.0)
    camera.fit(np.vstack([key_points(kin), shadow, towards, shadow * (1, 1, 0)]))
    options = options_for(kin)
    lit = render(camera, go.Scene(kin), options)
    options.shadows = False
    unlit = render(camera, go.Scene(kin), options)
    at, away = project(camera, [shadow, towards])
    darker = unlit[..., :3].astype(int).sum(axis=-1) - lit[..., :3].astype(int).sum(axis=-1)
    y, x = int(round(at[1])), int(round(at[0]))
    assert darker[y - 2:y + 3, x - 2:x + 3].max() > 30, f"no shadow at {at.round(1)}"
    y, x = int(round(away[1])), int(round(away[0]))
    assert darker[y - 2:y + 3, x - 2:x + 3].max() <= 3, f"a shadow towards the light at {away.round(1)}"


def test_msaa_gives_intermediate_colours_on_an_edge(render) -> None:
    """The red endeffector sphere against the floor: without multisampling its rim pixels
    are red or floor; with it some are mixtures between the two."""
    kin = posed("planar3", [30 * DEG, 30 * DEG, 30 * DEG])
    camera = framed(key_points(kin))
    options = options_for(kin)
    options.shadows = False

    def mixed(image: np.ndarray) -> int:
        xy = project(camera, kin.endeff_tf.t())[0]
        y, x = int(round(xy[1])), int(round(xy[0]))
        patch = image[max(y - 40, 0):y + 40, max(x - 40, 0):x + 40, :3].astype(int)
        red = patch[..., 0] - np.maximum(patch[..., 1], patch[..., 2])
        return int(np.count_nonzero((red > 25) & (red < 90)))  # partly red: neither sphere nor floor

    options.samples = 0
    hard = mixed(render(camera, go.Scene(kin), options))
    options.samples = 4
    smooth = mixed(render(camera, go.Scene(kin), options))
    assert smooth > hard + 10, f"partly red rim pixels: {smooth} with MSAA, {hard} without"


def test_a_translucent_material_leaves_the_picture_opaque(render) -> None:
    """A visual whose colour has alpha 0.8 (as rtb-data's URDF materials) is drawn in its
    colour, and every pixel of the picture keeps alpha 255."""
    import dataclasses

    from robot_sim.model.shapes import Box

    base = posed("planar3", [20 * DEG, 40 * DEG, -30 * DEG]).robot
    robot = dataclasses.replace(base, visuals=((), (Box((0.3, 0.1, 0.1), color=(0.0, 0.0, 0.9, 0.8)),), ()))
    kin = posed(robot, [20 * DEG, 40 * DEG, -30 * DEG])
    image = render(framed(key_points(kin)), go.Scene(kin), options_for(kin))
    blue = (image[..., 2] > 120) & (image[..., 2] > 2 * image[..., :2].max(axis=-1).astype(int) + 30)
    assert blue.sum() > 200, "the box is not drawn"
    assert image[..., 3].min() == 255, f"{np.count_nonzero(image[..., 3] < 255)} pixels are not opaque"


def test_a_mesh_renders_where_its_vertices_project(render) -> None:
    """A magenta tetrahedron mesh on link 2 of the planar arm, in the mesh look: its
    centroid's pixel (from forward kinematics and the link pose) is magenta, and the
    pixels there are not magenta in the DH look."""
    import dataclasses

    from robot_sim.model.shapes import Mesh
    from render_helpers import MAGENTA, color_mask

    vertices = 0.06 * np.array([[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]])
    faces = np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
    offset = np.eye(4)
    offset[:3, 3] = [-0.1, 0.0, 0.05]
    base = posed("planar3", [20 * DEG, 40 * DEG, -30 * DEG]).robot
    shapes = ((), (Mesh((vertices, faces), pose=offset, color=MAGENTA),), ())
    robot = dataclasses.replace(base, visuals=shapes)
    kin = posed(robot, [20 * DEG, 40 * DEG, -30 * DEG])
    world = (kin.frames[2] @ offset @ np.c_[vertices, np.ones(4)].T).T[:, :3]
    camera = framed(np.vstack([key_points(kin), world]))
    options = options_for(kin)
    options.shadows = False
    meshes = render(camera, go.Scene(kin), options)
    options.look = "dh"
    plain = render(camera, go.Scene(kin), options)
    xy = project(camera, world.mean(axis=0))[0]
    y, x = int(round(xy[1])), int(round(xy[0]))
    assert color_mask(meshes, MAGENTA)[y - 1:y + 2, x - 1:x + 2].any(), f"no mesh at {xy.round(1)}"
    assert not color_mask(plain, MAGENTA)[y - 1:y + 2, x - 1:x + 2].any()
    corners = project(camera, world)
    lo, hi = corners.min(axis=0) - 2, corners.max(axis=0) + 2
    ys, xs = np.nonzero(color_mask(meshes, MAGENTA))
    assert len(xs) and xs.min() >= lo[0] and xs.max() <= hi[0] and ys.min() >= lo[1] and ys.max() <= hi[1]
