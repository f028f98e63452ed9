"""Pixels of the offscreen renderer (OSMesa): parts land where ``Camera.project`` says.

Every expected position comes from forward kinematics and ``Camera.project`` (the matrices
the render path loads), every expected colour from ``graphics_defs``.  Lighting changes
the exact values, so colours are compared by which channels dominate, not by value.
"Robot pixels" are pixels that differ from a reference render of the same scene with the
robot moved a kilometre below the ground (past the far plane; the ground, which follows
only the base's x and y, stays where it was).

PyOpenGL fixes its platform at first import.  This module asks for OSMesa at import and
again just before importing ``OpenGL.GL`` in the renderer fixture: the window tests,
collected after this module, drop ``PYOPENGL_PLATFORM`` when OpenGL is not imported yet,
and importing it here at collection time would force OSMesa on their (GLX) run.
"""
from __future__ import annotations

import math
import struct
import zlib
from pathlib import Path

import numpy as np
import pytest

from robot_sim import graphics as go

go.require_osmesa_platform()

from robot_sim.graphics import defs as gd  # noqa: E402
from robot_sim.kinematics import Kinematics  # noqa: E402
from robot_sim.model.params import RobotParams
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.transforms import HomogeneousTransform  # noqa: E402

W, H = 320, 240
from render_helpers import (  # noqa: F401 - fixtures and helpers
    P_,
    R_,
    DEG,
    BACKGROUND_PX,
    MAGENTA,
    Frames,
    render,
    posed,
    sunk,
    key_points,
    framed,
    options_for,
    project,
    color_mask,
    robot_mask,
    window,
    pixel,
    along,
    assert_drawn_along,
    assert_sane,
    POSES,
)


@pytest.mark.parametrize("name,q", POSES)
def test_endeffector_sphere_is_where_forward_kinematics_puts_it(render: Frames, name: str, q: list[float] | None) -> None:
    kin = posed(name, q)
    camera = framed(key_points(kin))
    image, empty = render.pair(camera, kin, options_for(kin))
    assert_sane(image, empty)

    red = color_mask(image, gd.ENDEFF_COLOR)
    xy = project(camera, kin.endeff_tf.t())[0]
    assert window(red, xy).any(), f"{name} q={q}: no endeffector red within 2 px of {xy.round(1)}"
    # The red blob is centred on the projection (the sphere is the only red part).
    radius = go.robot_look(kin.robot).endeff_radius
    right, _ = camera.view_plane_axes()
    radius_px = float(np.linalg.norm(np.diff(project(camera, [kin.endeff_tf.t(), kin.endeff_tf.t() + radius * right]), axis=0)))
    ys, xs = np.nonzero(red)
    centroid = np.array([xs.mean(), ys.mean()])
    # (Perspective stretches a sphere near the image edge outwards, and links entering it
    # hide a sliver: a tenth of its radius on top of 1.5 px covers both.)
    assert np.linalg.norm(centroid - xy) <= 1.5 + 0.1 * radius_px, (
        f"{name} q={q}: red blob centred at {centroid.round(1)}, endeffector projects to {xy.round(1)}"
    )
    assert 0.5 * radius_px**2 <= red.sum() <= math.pi * (radius_px + 1.5) ** 2, f"{name}: {red.sum()} red pixels for a {radius_px:.1f} px sphere"


# ---------------------------------------------------------------- 2. wireframe


def test_wireframe_draws_fewer_robot_pixels_inside_the_solid_silhouette(render: Frames) -> None:
    kin = posed("planar3")
    start, end = kin.h_tf[0].t(), kin.h_tf[1].t()
    camera = framed(key_points(kin))
    camera.target, camera.distance = 0.5 * (start + end), 0.4  # the first link fills the view
    options = options_for(kin)
    # pixel counts of exact coverage: anti-aliasing would smear the lines' edges, and the
    # shadow on the floor would show between them
    options.samples, options.shadows = 0, False
    solid, empty = render.pair(camera, kin, options)
    assert options.toggle_wireframe() is True
    wire = render(camera, go.Scene(kin), options)

    solid_px, wire_px = robot_mask(solid, empty), robot_mask(wire, empty)
    assert solid_px.sum() > 0.05 * W * H, f"zoomed link covers only {solid_px.sum()} pixels"
    assert 0 < wire_px.sum() < 0.8 * solid_px.sum(), f"wireframe {wire_px.sum()} px vs solid {solid_px.sum()} px"
    # The lines are edges of the same meshes: inside the solid silhouette (grown by a pixel).
    grown = solid_px.copy()
    for axis, shift in ((0, 1), (0, -1), (1, 1), (1, -1)):
        grown |= np.roll(solid_px, shift, axis=axis)
    outside = wire_px & ~grown
    assert outside.sum() <= 0.02 * wire_px.sum(), f"{outside.sum()} wireframe pixels outside the solid robot"
    assert options.toggle_wireframe() is False
    assert np.array_equal(render(camera, go.Scene(kin), options), solid)


# -------------------------------------------------------------------- 3. frames


def axes_camera(tf: HomogeneousTransform, length: float) -> go.Camera:
    """A camera framing the axes of ``tf`` from along its (1, 1, 1) diagonal, so the three
    axes project equally long, 120 degrees apart."""
    d = tf.R() @ np.ones(3) / math.sqrt(3.0)
    camera = go.Camera(azimuth_deg=math.degrees(math.atan2(d[1], d[0])), elevation_deg=math.degrees(math.asin(d[2])))
    camera.fit(np.vstack([tf.t(), tf.t() + length * tf.R().T]))
    camera.target = tf.t()
    return camera


def assert_axes_drawn(on: np.ndarray, off: np.ndarray, camera: go.Camera, tf: HomogeneousTransform,
                      length: float, what: str) -> None:
    """Red, green and blue pixels, new in ``on``, along the projected x, y, z axes of ``tf``."""
    for column, rgba, name in zip(range(3), (gd.AXIS_X_COLOR, gd.AXIS_Y_COLOR, gd.AXIS_Z_COLOR), "xyz"):
        tip = tf.t() + length * tf.R()[:, column]
        ends = project(camera, [tf.t(), tip])
        assert np.linalg.norm(ends[1] - ends[0]) > 30, f"{what} {name} axis is foreshortened to {ends}"
        assert_drawn_along(on, off, rgba, camera, tf.t(), tip, f"{what} {name} axis")


def assert_frame_axes_drawn(render: Frames, kin: Kinematics, i: int, options: go.GraphicsOptions) -> None:
    """Frame ``i`` off in ``options``: turning it on puts RGB pixels along its axes."""
    tf = kin.h_tf[i]
    length = go.robot_look(kin.robot).frame_length
    camera = axes_camera(tf, length)
    assert not options.show_frames[i]
    off = render(camera, go.Scene(kin), options)
    assert options.toggle_frame(i) is True
    on = render(camera, go.Scene(kin), options)
    assert options.toggle_frame(i) is True  # back off
    assert_axes_drawn(on, off, camera, tf, length, f"frame {i}")


@pytest.mark.parametrize("name,i", [("planar3", 2), ("spherical", 3), ("anthropomorphic", 1), ("anthropomorphic", 0)])
def test_frame_toggle_draws_rgb_axes(render: Frames, name: str, i: int) -> None:
    kin = posed(name)
    assert_frame_axes_drawn(render, kin, i, options_for(kin))


def test_endeffector_frame_toggle_draws_rgb_axes(render: Frames) -> None:
    kin = posed("anthropomorphic", [30 * DEG, 60 * DEG, -45 * DEG])
    length = go.robot_look(kin.robot).frame_length
    camera = axes_camera(kin.endeff_tf, length)
    options = options_for(kin)
    off = render(camera, go.Scene(kin), options)
    assert options.toggle_endeff_frame() is True
    on = render(camera, go.Scene(kin), options)
    assert_axes_drawn(on, off, camera, kin.endeff_tf, length, "endeffector frame")


# ------------------------------------------------------------- 4. transparency


def test_translucent_robot_mixes_link_and_ground(render: Frames) -> None:
    kin = posed("planar3")
    camera = framed(key_points(kin))
    options = options_for(kin)
    options.shadows = False  # the arm lies on the floor: its shadow would darken the ground it is mixed with
    opaque, empty = render.pair(camera, kin, options)
    assert options.toggle_alpha() == pytest.approx(gd.TRANSLUCENT_ALPHA)
    translucent = render(camera, go.Scene(kin), options)
    origins = key_points(kin)
    # Links 1 and 3 at 30 % and 45 %: clear of the joints and of the COM spheres, which sit
    # at the inertial COMs about 60 % along (link 2 runs towards the camera, so on screen
    # its joints cover most of it).
    for link in (0, 2):
        for xy in project(camera, along(origins[link], origins[link + 1], (0.3, 0.45))):
            o, t, e = pixel(opaque, xy), pixel(translucent, xy), pixel(empty, xy)
            assert o.min() > e.max() + 40 and o.max() - o.min() < 15, f"{xy.round(1)}: {o} is not the lit grey link"
            assert np.abs(t - o).max() > 20, f"{xy.round(1)}: translucent {t} equals opaque {o}"
            assert np.abs(t - e).max() > 10, f"{xy.round(1)}: translucent {t} equals the ground {e}"
            lo, hi = np.minimum(o, e) - 6, np.maximum(o, e) + 6
            assert np.all((lo <= t) & (t <= hi)), f"{xy.round(1)}: translucent {t} is not between link {o} and ground {e}"
    changed = robot_mask(translucent, opaque)
    assert changed.sum() > 0.5 * robot_mask(opaque, empty).sum(), "most robot pixels should change when translucent"
    assert options.toggle_alpha() == 1.0
    assert np.array_equal(render(camera, go.Scene(kin), options), opaque)


# ------------------------------------------------------- 5. link pointing down


def assert_link_drawn_downward(render: Frames, kin: Kinematics, joint: np.ndarray, tip: np.ndarray,
                               azimuth_deg: float) -> None:
    """Robot pixels along the projected segment from ``joint`` down to ``tip``, below the
    joint on screen; none along its mirror image above the joint (a link drawn the wrong
    way up).  The camera looks horizontally across the offset between the link and the
    pedestal under the base, so the two do not overlap on screen."""
    mirror = 2 * joint - tip
    camera = framed(np.vstack([key_points(kin), mirror]), azimuth_deg=azimuth_deg)
    image, empty = render.pair(camera, kin, options_for(kin))
    robot = robot_mask(image, empty)
    joint_xy = project(camera, joint)[0]
    for xy in project(camera, along(joint, tip, (0.3, 0.45, 0.6, 0.75))):
        assert xy[1] > joint_xy[1] + 10, f"{xy} is not below the joint {joint_xy} on screen"
        assert window(robot, xy, 1).any(), f"no robot pixel at {xy.round(1)} on the downward link"
    for xy in project(camera, along(joint, mirror, (0.4, 0.6, 0.8))):
        assert not window(robot, xy, 2).any(), f"robot pixels at {xy.round(1)}, above the joint where nothing is"


def test_spherical_prismatic_link_pointing_down_is_a_rod_below_a_sleeve_above(render: Frames) -> None:
    """The prismatic joint (limits 0.1..0.9 m, at 0.5 m) points straight down: its rod,
    as long as the stroke (0.8 m), reaches from the tip 0.5 m below the joint to 0.3 m
    above it; the sleeve, as long too, ends 0.1 m below the joint where the travel
    starts, so it reaches 0.7 m above the joint; nothing is farther up."""
    kin = posed("spherical", [0.0, math.pi, 0.5])
    joint, tip = kin.h_tf[2].t(), kin.endeff_tf.t()
    np.testing.assert_allclose(joint, [0.0, 0.2, 0.6], atol=1e-9)
    np.testing.assert_allclose(tip - joint, [0.0, 0.0, -0.5], atol=1e-9)  # straight down, 0.5 m
    up = np.array([0.0, 0.0, 1.0])
    camera = framed(np.vstack([key_points(kin), joint + up]), azimuth_deg=0.0)  # y across the screen
    image, empty = render.pair(camera, kin, options_for(kin))
    robot = robot_mask(image, empty)
    for xy in project(camera, along(joint, tip, (0.3, 0.45, 0.6, 0.75))):
        assert window(robot, xy, 1).any(), f"no robot pixel at {xy.round(1)} on the downward rod"
    for height in (0.2, 0.4, 0.6):
        xy = project(camera, joint + height * up)[0]
        assert window(robot, xy, 1).any(), f"no sleeve {height} m above the joint at {xy.round(1)}"
    for height in (0.8, 0.95):
        xy = project(camera, joint + height * up)[0]
        assert not window(robot, xy, 2).any(), f"robot pixels {height} m above the joint, past the sleeve"
    assert window(color_mask(image, gd.ENDEFF_COLOR), project(camera, tip)[0]).any(), "endeffector hidden"


# -------------------------------------------------------------------- 6. ghost


def ghost_mask(image: np.ndarray) -> np.ndarray:
    """The translucent ghost's hue: green and blue clearly above red."""
    return color_mask(image, gd.GHOST_COLOR, margin=25, ratio=1.0)


def test_ghost_is_drawn_in_ghost_colour_at_its_endeffector(render: Frames) -> None:
    kin = posed("planar3")
    ghost = posed("planar3", [-60 * DEG, -30 * DEG, 0.0])
    camera = framed(np.vstack([key_points(kin), key_points(ghost)]))
    options = options_for(kin)
    plain, empty = render.pair(camera, kin, options)
    with_ghost = render(camera, go.Scene(kin, ghost=ghost), options)
    xy = project(camera, ghost.endeff_tf.t())[0]
    assert not window(robot_mask(plain, empty), xy, 3).any(), "the current robot is at the ghost's endeffector"
    assert window(ghost_mask(with_ghost), xy, 1).any(), f"no ghost colour at {xy.round(1)}: {pixel(with_ghost, xy)}"
    assert not window(ghost_mask(plain), xy, 3).any()
    g, p = pixel(with_ghost, xy), pixel(plain, xy)
    assert g[2] - g[0] > p[2] - p[0] + 20 and g[1] - g[0] > p[1] - p[0] + 20, f"ghost {g} over ground {p}"
    # The ghost's links show too, midway along its first link.
    mid = project(camera, along(ghost.h_tf[0].t(), ghost.h_tf[1].t(), (0.7,)))[0]
    assert window(ghost_mask(with_ghost), mid, 1).any(), f"no ghost colour on its first link at {mid.round(1)}"

    options.show_ghost = False
    assert np.array_equal(render(camera, go.Scene(kin, ghost=ghost), options), plain)


# ---------------------------------------------------------------- 7. IK target


def test_ik_target_marker_colour_follows_reachability(render: Frames) -> None:
    kin = posed("planar3")
    target = HomogeneousTransform.from_rt(t=[0.1, -0.5, 0.4])
    camera = framed(np.vstack([key_points(kin), target.t()]))
    options = options_for(kin)
    plain = render(camera, go.Scene(kin), options)
    reachable = render(camera, go.Scene(kin, target_tf=target), options)
    unreachable = render(camera, go.Scene(kin, target_tf=target, target_reachable=False), options)
    xy = project(camera, target.t())[0]
    yellow = lambda img: window(color_mask(img, gd.TARGET_COLOR), xy, 1).any()  # noqa: E731
    magenta = lambda img: window(color_mask(img, gd.TARGET_UNREACHABLE_COLOR), xy, 1).any()  # noqa: E731
    assert yellow(reachable) and not magenta(reachable), f"reachable target pixel {pixel(reachable, xy)}"
    assert magenta(unreachable) and not yellow(unreachable), f"unreachable target pixel {pixel(unreachable, xy)}"
    assert not yellow(plain) and not magenta(plain)
    # The target's small frame: its x axis (red) sticks out of the marker.
    length = go.robot_reach(kin.robot) * gd.TARGET_FRAME_LENGTH_FRAC
    assert_drawn_along(reachable, plain, gd.AXIS_X_COLOR, camera, target.t(), target.t() + [length, 0, 0],
                       "target x axis", fractions=(0.5, 0.7))

    options.show_target = False
    assert np.array_equal(render(camera, go.Scene(kin, target_tf=target), options), plain)


# -------------------------------------------------------------------- 8. vectors


@pytest.mark.parametrize("vec", [(0.0, 0.0, 0.4), (0.0, 0.0, -0.4), (0.3, -0.3, 0.0), (-0.2, 0.1, 0.3)])
def test_vector_arrow_is_drawn_from_origin_to_tip(render: Frames, vec: tuple[float, float, float]) -> None:
    kin = posed("spherical")
    origin = kin.endeff_tf.t()
    tip = origin + np.asarray(vec)
    camera = framed(np.vstack([key_points(kin), tip]))
    options = options_for(kin)
    plain = render(camera, go.Scene(kin), options)
    scene = go.Scene(kin, vectors=[(origin, np.asarray(vec), MAGENTA), (origin, np.zeros(3), MAGENTA)])
    arrows = render(camera, scene, options)
    assert_drawn_along(arrows, plain, MAGENTA, camera, origin, tip, f"vector {vec}", (0.2, 0.4, 0.6, 0.8))
    assert not color_mask(plain, MAGENTA).any()
    # Nothing magenta beyond the tip or behind the origin.
    for xy in project(camera, along(origin, tip, (-0.4, 1.4))):
        if 0 <= xy[0] < W and 0 <= xy[1] < H:
            assert not window(color_mask(arrows, MAGENTA), xy, 1).any(), f"magenta at {xy.round(1)}, off the arrow"

    options.show_vectors = False
    hidden = render(camera, scene, options)
    assert not color_mask(hidden, MAGENTA).any()
    assert np.array_equal(hidden, plain)


# ------------------------------------------------------------- 9. workspace cloud


def colormap_distance(colours: np.ndarray) -> np.ndarray:
    """For RGB(A) colours (N, 3|4), the largest channel difference to the nearest colour of
    the colormap (sampled finely enough that neighbours differ by at most 1)."""
    curve = go.colormap(np.linspace(0.0, 1.0, 1025))[:, :3].astype(np.int16)
    unique, inverse = np.unique(colours[:, :3], axis=0, return_inverse=True)
    best = np.abs(unique.astype(np.int16)[:, None] - curve).max(axis=-1).min(axis=1)
    return best[inverse.ravel()]


def test_workspace_cloud_colours_land_on_their_points(render: Frames) -> None:
    kin = posed("spherical")
    centres = np.array([[0.7, 0.0, 0.2], [0.0, 0.7, 0.4], [0.7, 0.5, 0.5], [-0.3, 0.4, 1.2], [0.4, -0.5, 0.05]])
    rng = np.random.default_rng(7)
    points = np.repeat(centres, 50, axis=0) + rng.normal(scale=0.004, size=(250, 3))
    values = np.repeat(np.arange(len(centres), dtype=float), 50)
    cloud = go.WorkspaceCloud(points, values)
    expected = go.colormap(values)[::50, :3].astype(int)
    stops = np.round(255.0 * np.asarray(gd.WORKSPACE_COLORMAP)[:, 1:]).astype(int)
    np.testing.assert_array_equal(expected, stops)  # values 0..4 land on the five stops

    camera = framed(np.vstack([key_points(kin), centres]))
    options = options_for(kin)
    plain, empty = render.pair(camera, kin, options)
    hidden = render(camera, go.Scene(kin, workspace=cloud), options)
    assert np.array_equal(hidden, plain), "the cloud is drawn with show_workspace False"
    options.show_workspace = True
    # Repeated frames of one view (the renderer may reuse a picture of the points) agree.
    frames = [render(camera, go.Scene(kin, workspace=cloud), options) for _ in range(4)]
    for k, later in enumerate(frames[1:], 2):
        assert np.array_equal(later, frames[0]), f"frame {k} of the same view differs from the first"
    shown = frames[-1]

    robot = robot_mask(plain, empty)
    for centre, colour, xy in zip(centres, expected, project(camera, centres)):
        assert not window(robot, xy, 3).any(), f"the robot covers {centre}"
        near = window(np.abs(shown[..., :3].astype(int) - colour).max(axis=-1) <= 3, xy, 2)
        assert near.any(), f"no colormap colour {colour} near {xy.round(1)} (cloud at {centre}): {pixel(shown, xy)}"
        before = window(np.abs(plain[..., :3].astype(int) - colour).max(axis=-1) <= 30, xy, 2)
        assert not before.any(), f"colour {colour} was already near {xy.round(1)} without the cloud"


def test_cloud_frames_equal_drawing_the_cloud_afresh(render: Frames) -> None:
    """After several frames of one view (the renderer may keep a picture of the points),
    moving the robot or the camera gives the frame that an identical new cloud gives."""
    robot = load_robot("spherical")
    before, after = posed(robot, [0.0, 45 * DEG, 0.5]), posed(robot, [70 * DEG, 100 * DEG, 0.8])
    rng = np.random.default_rng(11)
    points = rng.uniform([-0.8, -0.8, 0.0], [0.8, 0.8, 1.4], size=(20_000, 3))
    cloud = go.WorkspaceCloud(points, points[:, 2])
    camera = framed(np.vstack([key_points(before), key_points(after)]))
    options = options_for(before)
    options.show_workspace = True

    def assert_as_fresh(kin: Kinematics, what: str) -> None:
        kept = render(camera, go.Scene(kin, workspace=cloud), options)
        fresh = render(camera, go.Scene(kin, workspace=go.WorkspaceCloud(points, points[:, 2])), options)
        assert robot_mask(fresh, render(camera, go.Scene(kin), options)).sum() > 1000, "the cloud hardly shows"
        differ = robot_mask(kept, fresh, tol=0)
        assert differ.sum() == 0, f"{what}: {differ.sum()} pixels differ from a fresh cloud, e.g. (y, x) {np.argwhere(differ)[:3].tolist()}"

    for _ in range(3):
        render(camera, go.Scene(before, workspace=cloud), options)
    assert_as_fresh(after, "robot moved")
    for _ in range(3):
        render(camera, go.Scene(after, workspace=cloud), options)
    camera.orbit(40.0, 10.0)
    assert_as_fresh(after, "camera orbited")
    for _ in range(3):
        render(camera, go.Scene(after, workspace=cloud), options)
    camera.zoom(0.8)
    assert_as_fresh(after, "camera zoomed")


def test_cloud_from_the_background_picture_equals_the_cloud_drawn_in_the_frame(render: Frames) -> None:
    """The cloud drawn once into the background picture and copied into each frame gives
    the frame that drawing it among the other opaque items gives, pixel for pixel."""
    from robot_sim.graphics.items.cloud import CloudItem

    kin = posed("spherical")
    rng = np.random.default_rng(5)
    points = rng.uniform([-0.8, -0.8, 0.0], [0.8, 0.8, 1.4], size=(20_000, 3))
    scene = go.Scene(kin, workspace=go.WorkspaceCloud(points, points[:, 2]))
    camera = framed(key_points(kin))
    options = options_for(kin)
    options.show_workspace = True
    item = render.renderer.view.item(CloudItem)
    cached = [render(camera, scene, options) for _ in range(2)]
    item.cached = False  # type: ignore[misc] - this one instance draws in the frame
    try:
        direct = render(camera, scene, options)
    finally:
        del item.cached
    assert robot_mask(direct, render(camera, go.Scene(kin), options)).sum() > 1000, "the cloud hardly shows"
    for k, picture in enumerate(cached):
        assert np.array_equal(picture, direct), f"frame {k}: {np.count_nonzero(np.any(picture != direct, axis=2))} pixels differ"


def test_large_workspace_cloud_renders(render: Frames) -> None:
    kin = posed("spherical")
    rng = np.random.default_rng(0)
    points = rng.uniform([-1.0, -1.0, 0.0], [1.0, 1.0, 1.5], size=(200_000, 3))
    cloud = go.WorkspaceCloud(points, points[:, 2])
    camera = framed(key_points(kin))
    options = options_for(kin)
    options.show_workspace = True
    options.samples = 0  # exact colours: anti-aliasing mixes the points' edges with what is behind
    plain = render(camera, go.Scene(kin), options)
    for _ in range(3):  # drawn three times: the same buffer, uploaded once
        shown = render(camera, go.Scene(kin, workspace=cloud), options)
    changed = robot_mask(shown, plain, tol=0)
    assert changed.mean() > 0.3, f"a 200 000-point cloud changed only {changed.mean():.1%} of the frame"
    scale = go.color_scale_layout(float(points[:, 2].min()), float(points[:, 2].max()), W, H)
    for left, top, right, bottom in np.round(scale.boxes()).astype(int):  # the colour scale's texts and frame
        changed[max(top - 2, 0):bottom + 3, max(left - 2, 0):right + 3] = False
    # Points are unlit and opaque: every pixel they change takes a colormap colour.
    off_curve = int((colormap_distance(shown[changed]) > 3).sum())
    assert off_curve <= 0.01 * changed.sum(), f"{off_curve} of {changed.sum()} cloud pixels are not colormap colours"


# ---------------------------------------------------------- 10. degenerate robots


def chain_12(rng: np.random.Generator) -> RobotParams:
    n = 12
    return RobotParams.from_arrays(
        "chain12", rng.uniform(0.05, 0.15, n), rng.uniform(-math.pi, math.pi, n), rng.uniform(0.0, 0.1, n),
        np.zeros(n), [R_] * 11 + [P_], q_home=np.r_[rng.uniform(-1.0, 1.0, 11), 0.05],
        base_tf=HomogeneousTransform.from_rt(t=[0.0, 0.0, 1.0]),
    )


DEGENERATE = {
    "zero_links": RobotParams.from_arrays("zero", [0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0], [R_, R_, P_]),
    "down_link": RobotParams.from_arrays(  # out 0.4 m along x, then 0.5 m straight down
        "down", [0.4, 0.0], [0.0, 0.0], [0.0, -0.5], [0.0, 0.0], [R_, R_],
        base_tf=HomogeneousTransform.from_rt(t=[0.0, 0.0, 1.0]),
    ),
    "chain12": chain_12(np.random.default_rng(3)),
}


@pytest.mark.parametrize("name", list(DEGENERATE))
def test_degenerate_robots_render_cleanly(render: Frames, name: str) -> None:
    kin = posed(DEGENERATE[name])
    camera = framed(key_points(kin))
    options = options_for(kin)
    image, empty = render.pair(camera, kin, options)
    assert_sane(image, empty)
    options.toggle_all_frames()
    assert all(options.show_frames) and options.show_endeff_frame
    options.toggle_wireframe()
    options.toggle_alpha()
    image = render(camera, go.Scene(kin, ghost=kin, target_tf=kin.endeff_tf), options)
    assert_sane(image, empty)
    for rgba in (gd.AXIS_X_COLOR, gd.AXIS_Y_COLOR, gd.AXIS_Z_COLOR):
        assert color_mask(image, rgba).sum() > 10, f"{name}: no {rgba} frame axes with all frames shown"


def test_link_along_minus_z_is_drawn_below_its_joint(render: Frames) -> None:
    kin = posed(DEGENERATE["down_link"])
    joint, elbow = kin.h_tf[1].t(), kin.h_tf[2].t()
    np.testing.assert_allclose(joint, [0.4, 0.0, 1.0], atol=1e-12)
    np.testing.assert_allclose(elbow - joint, [0.0, 0.0, -0.5], atol=1e-12)
    assert_link_drawn_downward(render, kin, joint, elbow, azimuth_deg=90.0)  # x across the screen


def test_frame_twelve_of_a_twelve_joint_chain(render: Frames) -> None:
    kin = posed(DEGENERATE["chain12"])
    options = go.GraphicsOptions(13)
    assert options.n_frames == 13
    for bad in (13, -1, 100, 2.0, "3"):
        assert options.toggle_frame(bad) is False  # type: ignore[arg-type]
    assert options.show_frames == [True] + [False] * 12
    assert options.toggle_frame(np.int64(0)) is True  # numpy indices count too
    assert_frame_axes_drawn(render, kin, 12, options)


# ------------------------------------------------------------------- 11. PNG


def decode_png(data: bytes) -> np.ndarray:
    """A minimal 8-bit RGB/RGBA non-interlaced PNG decoder (all five filter types)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "bad PNG signature"
    pos, chunks = 8, []
    while pos < len(data):
        (length,), kind = struct.unpack(">I", data[pos:pos + 4]), data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        assert crc == zlib.crc32(kind + body) & 0xFFFFFFFF, f"bad CRC in {kind!r}"
        chunks.append((kind, body))
        pos += 12 + length
    assert chunks[0][0] == b"IHDR" and chunks[-1][0] == b"IEND"
    width, height, depth, color_type, compression, filtering, interlace = struct.unpack(">IIBBBBB", chunks[0][1])
    assert (depth, compression, filtering, interlace) == (8, 0, 0, 0) and color_type in (2, 6)
    channels = 4 if color_type == 6 else 3
    raw = zlib.decompress(b"".join(body for kind, body in chunks if kind == b"IDAT"))
    stride = width * channels
    assert len(raw) == height * (1 + stride), f"IDAT holds {len(raw)} bytes for {width}x{height}x{channels}"
    out = np.zeros((height, stride), dtype=np.int32)
    prev = np.zeros(stride, dtype=np.int32)
    for y in range(height):
        ftype, line = raw[y * (1 + stride)], np.frombuffer(raw, np.uint8, stride, y * (1 + stride) + 1).astype(np.int32)
        if ftype in (0, 2):
            cur = (line + (prev if ftype == 2 else 0)) % 256
        else:
            cur = np.zeros(stride, dtype=np.int32)
            for x in range(stride):
                a = cur[x - channels] if x >= channels else 0
                b, c = prev[x], prev[x - channels] if x >= channels else 0
                if ftype == 1:
                    pred = a
                elif ftype == 3:
                    pred = (a + b) // 2
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[x] = (line[x] + pred) % 256
        out[y], prev = cur, cur
    return out.astype(np.uint8).reshape(height, width, channels)


def test_save_png_round_trips_a_rendered_frame(render: Frames, tmp_path: Path) -> None:
    kin = posed("anthropomorphic")
    image = render(framed(key_points(kin)), go.Scene(kin), options_for(kin, base_frame=True))
    rgba_path, rgb_path = tmp_path / "frame.png", tmp_path / "frame_rgb.png"
    go.save_png(rgba_path, image)
    go.save_png(str(rgb_path), image[..., :3])  # a strided view, written as RGB
    decoded = decode_png(rgba_path.read_bytes())
    assert decoded.shape == (H, W, 4)
    np.testing.assert_array_equal(decoded, image)
    np.testing.assert_array_equal(decode_png(rgb_path.read_bytes()), image[..., :3])


def test_save_png_unwritable_path_names_it(render: Frames, tmp_path: Path) -> None:
    image = np.zeros((4, 5, 4), dtype=np.uint8)
    for path in (tmp_path / "no_such_dir" / "x.png", tmp_path):  # missing folder; a directory
        with pytest.raises(OSError) as info:
            go.save_png(path, image)
        assert str(path) in str(info.value), f"{info.value!r} does not name {path}"
    assert not (tmp_path / "no_such_dir").exists()


# ------------------------------------------------- 12. camera and renderer agree


def test_projection_agrees_with_the_rendered_ground(render: Frames) -> None:
    kin = posed("planar3")
    empty_kin = sunk(kin)
    ground = go.FloorGrid.for_reach(go.robot_reach(kin.robot), kin.h_tf[0].t()[:2])
    h = ground.half_extent
    corners = np.array([[sx * h, sy * h, 0.0] for sx in (-1, 1) for sy in (-1, 1)])
    camera = framed(corners, azimuth_deg=30.0, elevation_deg=40.0)
    image = render(camera, go.Scene(empty_kin), options_for(kin))

    def is_background(xy: np.ndarray) -> bool:
        return bool(np.abs(pixel(image, xy) - BACKGROUND_PX).max() <= 2)

    def is_ground(xy: np.ndarray) -> bool:
        px = pixel(image, xy)
        return bool(np.abs(px - BACKGROUND_PX).max() > 15 and px.max() - px.min() < 25)  # lit grey, not sky

    origin_xy = project(camera, [0.0, 0.0, 0.0])[0]
    assert is_ground(origin_xy), f"world origin projects to {origin_xy.round(1)}: {pixel(image, origin_xy)}"
    solid = 0.95 * gd.FLOOR_FADE_START  # the floor fades out from there to its edge
    for corner, inside, outside in zip(corners, project(camera, solid * corners), project(camera, 1.05 * corners)):
        assert is_ground(inside), f"inside corner {corner}: {inside.round(1)} is {pixel(image, inside)}"
        if 1 <= outside[0] < W - 1 and 1 <= outside[1] < H - 1:
            assert is_background(outside), f"outside corner {corner}: {outside.round(1)} is {pixel(image, outside)}"
    # Towards the far edge: the midpoints of its four sides land on ground inside the fade.
    for mid in ([h, 0, 0], [-h, 0, 0], [0, h, 0], [0, -h, 0]):
        assert is_ground(project(camera, solid * np.asarray(mid, dtype=float))[0]), f"side midpoint {mid}"


def test_points_behind_the_eye_project_to_nan() -> None:
    camera = go.Camera(distance=2.0, azimuth_deg=10.0, elevation_deg=20.0, target=[0.1, 0.2, 0.3])
    eye = camera.eye()
    back = (eye - camera.target) / np.linalg.norm(eye - camera.target)
    pts = np.array([eye + 0.5 * back, eye + 3.0 * back + [0.1, 0.0, 0.0], camera.target])
    xy = camera.project(pts, W, H)
    assert np.all(np.isnan(xy[:2]))
    np.testing.assert_allclose(xy[2], [(W - 1) / 2, (H - 1) / 2], atol=1e-9)  # the target is at the centre


def test_a_second_renderer_agrees_and_refuses_after_close(render: Frames) -> None:
    """Two OSMesa contexts in one process: each draws the same scene at its own size, and
    a closed renderer raises instead of drawing."""
    kin = posed("anthropomorphic")
    camera = framed(key_points(kin))
    options = options_for(kin)
    first = render(camera, go.Scene(kin), options)
    w2, h2 = 200, 150
    with go.OffscreenRenderer(w2, h2) as other:
        small = other.render(camera, go.Scene(kin), options)
        assert small.shape == (h2, w2, 4)
        xy = camera.project(kin.endeff_tf.t()[None], w2, h2)[0]
        x, y = int(round(xy[0])), int(round(xy[1]))
        assert color_mask(small, gd.ENDEFF_COLOR)[y - 2:y + 3, x - 2:x + 3].any(), f"no red at {xy.round(1)} in {w2}x{h2}"
    with pytest.raises(RuntimeError, match="after close"):
        other.render(camera, go.Scene(kin), options)
    assert np.array_equal(render(camera, go.Scene(kin), options), first)


@pytest.mark.parametrize("aspect", [0.4, 1.0, 2.5])
def test_fit_keeps_every_point_in_a_viewport_of_any_shape(aspect: float) -> None:
    rng = np.random.default_rng(17)
    points = rng.normal(size=(200, 3)) * [1.5, 0.3, 0.8] + [0.2, -0.1, 0.9]
    width, height = round(300 * aspect), 300
    camera = go.Camera()
    camera.fit(points, aspect)
    px = camera.project(points, width, height)
    assert np.all((px[:, 0] >= 0) & (px[:, 0] < width) & (px[:, 1] >= 0) & (px[:, 1] < height))
    # and it is a fit, not a zoom-out: the cloud spans a good part of the narrower side
    span = np.ptp(px, axis=0) / [width, height]
    assert span.max() > 0.4
