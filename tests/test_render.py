"""Pixels of the one render path, through OSMesa: things appear where the camera projects them.

Every check projects world points with ``Camera.project`` (the matrices ``render_scene``
loads) and looks at the rendered image there.  A "reference" image renders the same view
with the robot moved far out of sight, so robot pixels are those that differ from it.
"""
from __future__ import annotations

import struct
import zlib
from pathlib import Path

import numpy as np
import pytest

import graphics_objects as go

go.require_osmesa_platform()  # before anything imports OpenGL

import graphics_defs as gd  # noqa: E402
from kinematics import Kinematics, forward_kinematics, random_configurations  # noqa: E402
from robot_defs import JTYPE_PRISMATIC, RobotParams, load_robot  # noqa: E402
from robot_state import RobotState  # noqa: E402
from transforms import HomogeneousTransform, rot_x  # noqa: E402

W, H = 320, 240
# far below the ground, out of the view; the ground (centred under the base) stays put
FAR_AWAY = HomogeneousTransform.from_rt(np.eye(3), [0.0, 0.0, -1000.0])


@pytest.fixture(scope="module")
def renderer() -> go.OffscreenRenderer:
    with go.OffscreenRenderer(W, H) as r:
        yield r


def gl_error() -> int:
    from OpenGL import GL

    return int(GL.glGetError())


def posed(robot: RobotParams, q: np.ndarray, base_tf: HomogeneousTransform | None = None) -> Kinematics:
    state = RobotState(robot)
    state.set_q(q)
    kin = Kinematics(robot)
    kin.update(state.joint_state, base_tf)
    return kin


def framing_camera(*kins: Kinematics) -> go.Camera:
    camera = go.Camera()
    camera.fit(np.vstack([np.vstack([k.frames[:, :3, 3], k.endeff_tf.t()]) for k in kins]))
    return camera


def pixel(image: np.ndarray, point_px: np.ndarray) -> np.ndarray:
    x, y = np.round(point_px).astype(int)
    assert 0 <= x < W and 0 <= y < H, f"projected point {point_px} is off the image"
    return image[y, x, :3].astype(int)


def window(image: np.ndarray, point_px: np.ndarray, radius: int = 2) -> np.ndarray:
    """Pixels (k, 3) within ``radius`` of a projected point."""
    x, y = np.round(point_px).astype(int)
    return image[max(y - radius, 0) : y + radius + 1, max(x - radius, 0) : x + radius + 1, :3].reshape(-1, 3).astype(int)


def dominated_by(rgb: np.ndarray, channel: int, margin: int = 60) -> np.ndarray:
    """Mask of pixels whose ``channel`` exceeds both others by ``margin``."""
    others = [c for c in range(3) if c != channel]
    return (rgb[..., channel] > 120) & np.all(rgb[..., [channel]] > rgb[..., others] + margin, axis=-1)


def robot_mask(image: np.ndarray, reference: np.ndarray) -> np.ndarray:
    return np.any(np.abs(image[..., :3].astype(int) - reference[..., :3].astype(int)) > 30, axis=-1)


def render(renderer: go.OffscreenRenderer, camera: go.Camera, options: go.GraphicsOptions, **scene) -> np.ndarray:
    image = renderer.render(camera, go.Scene(**scene), options)
    assert gl_error() == 0
    return image


TUTORIAL_ARMS = ["planar3", "spherical", "anthropomorphic"]


@pytest.mark.parametrize("name", TUTORIAL_ARMS)
@pytest.mark.parametrize("seed", [None, 1, 2, 3])
def test_endeffector_sphere_is_red_where_it_projects(renderer, name, seed) -> None:
    robot = load_robot(name)
    q = robot.q_home if seed is None else random_configurations(robot, 1, np.random.default_rng(seed))[0]
    kin = posed(robot, q)
    camera = framing_camera(kin)
    image = render(renderer, camera, go.GraphicsOptions(robot.n_dofs + 1), kinematics=kin)
    at = camera.project(kin.endeff_tf.t()[None], W, H)[0]
    assert dominated_by(window(image, at), 0).any(), f"no red at {at} for q = {q}"
    # the picture is a real frame: ground, background and robot all present
    assert len(np.unique(image.reshape(-1, 4), axis=0)) > 20


def test_wireframe_fills_far_fewer_pixels(renderer) -> None:
    robot = load_robot("anthropomorphic")
    kin = posed(robot, robot.q_home)
    camera = go.Camera()
    camera.target = 0.75 * kin.frames[1, :3, 3] + 0.25 * kin.frames[2, :3, 3]  # close on link 2
    camera.distance = 0.35
    options = go.GraphicsOptions(robot.n_dofs + 1)
    options.show_frames[0] = False
    reference = render(renderer, camera, options, kinematics=posed(robot, robot.q_home, FAR_AWAY))
    filled = robot_mask(render(renderer, camera, options, kinematics=kin), reference).sum()
    options.toggle_wireframe()
    wire = robot_mask(render(renderer, camera, options, kinematics=kin), reference).sum()
    assert filled > 2000
    assert wire < 0.7 * filled


@pytest.mark.parametrize("name, frame", [("anthropomorphic", 2), ("spherical", 2), ("planar3", 3)])
def test_frame_toggle_draws_rgb_axes_along_its_projected_axes(renderer, name, frame) -> None:
    robot = load_robot(name)
    kin = posed(robot, robot.q_home)
    camera = framing_camera(kin)
    options = go.GraphicsOptions(robot.n_dofs + 1)
    before = render(renderer, camera, options, kinematics=kin)
    assert options.toggle_frame(frame)
    after = render(renderer, camera, options, kinematics=kin)
    length = go.RobotSizes(go.robot_reach(robot)).frame_length
    tf = kin.h_tf[frame]
    for channel in range(3):  # x red, y green, z blue
        found_after = found_before = False
        for frac in (0.45, 0.6, 0.75):
            at = camera.project((tf.t() + frac * length * tf.R()[:, channel])[None], W, H)[0]
            found_after |= bool(dominated_by(window(after, at, 1), channel, 50).any())
            found_before |= bool(dominated_by(window(before, at, 1), channel, 50).all())
        assert found_after, f"axis {channel} of frame {frame} not drawn"
        assert not found_before


def test_transparency_blends_the_robot_with_what_is_behind(renderer) -> None:
    robot = load_robot("anthropomorphic")
    kin = posed(robot, robot.q_home)
    camera = framing_camera(kin)
    options = go.GraphicsOptions(robot.n_dofs + 1)
    reference = render(renderer, camera, options, kinematics=posed(robot, robot.q_home, FAR_AWAY))
    opaque = render(renderer, camera, options, kinematics=kin)
    assert options.toggle_alpha() == gd.TRANSLUCENT_ALPHA
    translucent = render(renderer, camera, options, kinematics=kin)
    at = camera.project((0.7 * kin.frames[1, :3, 3] + 0.3 * kin.frames[2, :3, 3])[None], W, H)[0]  # on link 2
    o_px, t_px, behind_px = window(opaque, at, 2), window(translucent, at, 2), window(reference, at, 2)
    best = np.argmax(np.abs(o_px - behind_px).max(axis=1))  # the pixel most inside the thin link
    o, t, behind = o_px[best], t_px[best], behind_px[best]
    assert np.abs(o - behind).max() > 60  # the opaque link hides what is behind
    # translucent: between the opaque link and the background, channel by channel
    assert np.all((t - behind) * (o - behind) >= 0) and np.all(np.abs(t - behind) < np.abs(o - behind) + 2)
    assert np.abs(t - o).max() > 30 and np.abs(t - behind).max() > 15
    changed = robot_mask(translucent, opaque).sum()
    assert changed > 0.5 * robot_mask(opaque, reference).sum()


def test_spherical_arm_link_pointing_down_draws_below_the_joint(renderer) -> None:
    robot = load_robot("spherical")
    q = np.array([0.0, np.radians(170.0), 0.8])
    kin = posed(robot, q)
    joint, tip = kin.frames[2, :3, 3], kin.endeff_tf.t()
    assert tip[2] < joint[2] - 0.7 and np.linalg.norm(tip[:2] - joint[:2]) < 0.2  # the link points down
    camera = framing_camera(kin)
    options = go.GraphicsOptions(robot.n_dofs + 1)
    image = render(renderer, camera, options, kinematics=kin)
    reference = render(renderer, camera, options, kinematics=posed(robot, q, FAR_AWAY))
    mask = robot_mask(image, reference)
    joint_px = camera.project(joint[None], W, H)[0]
    for frac in (0.3, 0.5, 0.7):
        at = camera.project((joint + frac * (tip - joint))[None], W, H)[0]
        assert at[1] > joint_px[1] + 5  # below the joint on screen
        x, y = np.round(at).astype(int)
        assert mask[y - 1 : y + 2, x - 1 : x + 2].any(), f"nothing drawn at {frac} of the downward link"
    assert np.all(np.isfinite(kin.frames))


def test_ghost_is_drawn_in_its_colour_and_can_be_hidden(renderer) -> None:
    robot = load_robot("anthropomorphic")
    kin = posed(robot, robot.q_home)
    ghost = posed(robot, robot.q_home + np.radians([60.0, 20.0, 30.0]))
    camera = framing_camera(kin, ghost)
    options = go.GraphicsOptions(robot.n_dofs + 1)
    with_ghost = render(renderer, camera, options, kinematics=kin, ghost=ghost)
    at = camera.project(ghost.endeff_tf.t()[None], W, H)[0]
    behind = render(renderer, camera, options, kinematics=kin)
    g, b = pixel(with_ghost, at), pixel(behind, at)
    tint = np.array(gd.GHOST_COLOR[:3]) * 255
    # blended toward the ghost colour: closer to it than the picture without the ghost
    assert np.linalg.norm(g - tint) < np.linalg.norm(b - tint) - 20
    assert g[2] > g[0] + 30  # cyan-ish, not the red of a real endeffector
    options.show_ghost = False
    assert np.array_equal(render(renderer, camera, options, kinematics=kin, ghost=ghost), behind)


@pytest.mark.parametrize("reachable, color", [(True, gd.TARGET_COLOR), (False, gd.TARGET_UNREACHABLE_COLOR)])
def test_target_marker_in_its_colour_at_its_projection(renderer, reachable, color) -> None:
    robot = load_robot("anthropomorphic")
    kin = posed(robot, robot.q_home)
    camera = framing_camera(kin)
    target = HomogeneousTransform.from_rt(rot_x(0.3), kin.endeff_tf.t() + [0.0, 0.25, 0.1])
    options = go.GraphicsOptions(robot.n_dofs + 1)
    image = render(renderer, camera, options, kinematics=kin, target_tf=target, target_reachable=reachable)
    other = gd.TARGET_UNREACHABLE_COLOR if reachable else gd.TARGET_COLOR
    got = pixel(image, camera.project(target.t()[None], W, H)[0])
    assert np.linalg.norm(got - np.array(color[:3]) * 255) < np.linalg.norm(got - np.array(other[:3]) * 255)
    assert np.linalg.norm(got - np.array(color[:3]) * 255) < 110
    options.show_target = False
    assert np.array_equal(
        render(renderer, camera, options, kinematics=kin, target_tf=target, target_reachable=reachable),
        render(renderer, camera, options, kinematics=kin),
    )


def test_vector_arrow_along_its_projection(renderer) -> None:
    robot = load_robot("anthropomorphic")
    kin = posed(robot, robot.q_home)
    camera = framing_camera(kin)
    magenta = (1.0, 0.0, 1.0, 1.0)
    origin, vec = kin.endeff_tf.t(), np.array([0.0, 0.3, 0.0])
    options = go.GraphicsOptions(robot.n_dofs + 1)
    image = render(renderer, camera, options, kinematics=kin, vectors=[(origin, vec, magenta)])

    def is_magenta(rgb: np.ndarray) -> np.ndarray:
        return (rgb[..., 0] > 100) & (rgb[..., 2] > 100) & (rgb[..., 1] < 0.5 * np.minimum(rgb[..., 0], rgb[..., 2]))

    for frac in (0.3, 0.6, 0.9):
        at = camera.project((origin + frac * vec)[None], W, H)[0]
        assert is_magenta(window(image, at, 1)).any(), f"arrow missing at {frac}"
    options.show_vectors = False
    hidden = render(renderer, camera, options, kinematics=kin, vectors=[(origin, vec, magenta)])
    assert not is_magenta(hidden[..., :3].astype(int)).any()


def test_workspace_cloud_points_where_they_project_and_its_cached_picture_is_identical(renderer) -> None:
    robot = load_robot("anthropomorphic")
    kin = posed(robot, robot.q_home)
    camera = framing_camera(kin)
    rng = np.random.default_rng(5)
    centres = np.array([kin.frames[1, :3, 3] + [0, 0.3, 0], kin.endeff_tf.t() + [0, -0.25, 0], kin.frames[2, :3, 3] + [0, 0.25, 0.05]])
    points = np.repeat(centres, 40, axis=0) + rng.normal(scale=0.004, size=(120, 3))
    values = np.repeat([0.0, 0.5, 1.0], 40)
    cloud = go.WorkspaceCloud(points, values)
    options = go.GraphicsOptions(robot.n_dofs + 1)
    without = render(renderer, camera, options, kinematics=kin, workspace=cloud)
    options.show_workspace = True
    frames = [render(renderer, camera, options, kinematics=kin, workspace=cloud) for _ in range(4)]
    # drawn, drawn and captured, then re-blitted twice: all the same picture
    for later in frames[1:]:
        assert np.array_equal(later, frames[0])
    expected = go.colormap(np.array([0.0, 0.5, 1.0]))[:, :3].astype(int)
    for centre, rgb in zip(centres, expected):
        at = camera.project(centre[None], W, H)[0]
        near = window(frames[0], at, 2)
        assert np.min(np.abs(near - rgb).max(axis=1)) <= 3, f"no cloud colour {rgb} near {at}"
        assert np.min(np.abs(window(without, at, 2) - rgb).max(axis=1)) > 10
    # the robot still hides the cloud and the cloud hides the ground when re-blitted
    assert robot_mask(frames[-1], without).sum() < 2000


def test_large_cloud_renders_without_gl_error(renderer) -> None:
    robot = load_robot("humanoid7")
    kin = posed(robot, robot.q_home)
    rng = np.random.default_rng(9)
    cloud = go.WorkspaceCloud(rng.normal(scale=0.5, size=(200_000, 3)) + [0, 0, 0.8], rng.random(200_000))
    options = go.GraphicsOptions(robot.n_dofs + 1)
    options.show_workspace = True
    camera = framing_camera(kin)
    for _ in range(3):
        image = render(renderer, camera, options, kinematics=kin, workspace=cloud)
    assert len(np.unique(image.reshape(-1, 4), axis=0)) > 100


def degenerate_robot() -> RobotParams:
    """12 joints: co-located frames (zero-length links), a link straight down (−z),
    prismatic joints, a 180° twist."""
    n = 12
    a = np.zeros(n)
    a[[2, 6]] = 0.3
    d = np.zeros(n)
    d[[4, 9]] = 0.25
    alpha = np.radians([0, 90, -90, 180, 0, 90, 0, -90, 0, 90, 0, 0])
    jtype = np.zeros(n, dtype=int)
    jtype[[4, 9]] = JTYPE_PRISMATIC
    return RobotParams.from_arrays("degenerate12", a, alpha, d, np.zeros(n), jtype)


def test_degenerate_geometry_and_twelve_frames_render_cleanly(renderer) -> None:
    robot = degenerate_robot()
    q = np.zeros(12)
    q[1] = np.pi  # turn so that the next link points down
    kin = posed(robot, q)
    assert np.all(np.isfinite(kin.frames))
    options = go.GraphicsOptions(13)
    options.toggle_all_frames()
    camera = framing_camera(kin)
    image = render(renderer, camera, options, kinematics=kin)
    assert image.shape == (H, W, 4)
    options = go.GraphicsOptions(13)
    assert options.toggle_frame(12) and options.show_frames[12]
    assert not options.toggle_frame(13) and not options.toggle_frame(-1)
    with_12 = render(renderer, camera, options, kinematics=kin)
    assert not np.array_equal(with_12, render(renderer, camera, go.GraphicsOptions(13), kinematics=kin))


def test_a_link_straight_down_is_drawn_downward(renderer) -> None:
    robot = RobotParams.from_arrays("down", [0.0], [0.0], [-0.6], [0.0], [0], base_tf=HomogeneousTransform.from_rt(None, [0, 0, 1.0]))
    kin = posed(robot, np.zeros(1))
    top, bottom = kin.frames[0, :3, 3], kin.frames[1, :3, 3]
    assert bottom[2] == pytest.approx(0.4)
    camera = framing_camera(kin)
    options = go.GraphicsOptions(2)
    options.show_frames[0] = False
    image = render(renderer, camera, options, kinematics=kin)
    reference = render(renderer, camera, options, kinematics=posed(robot, np.zeros(1), FAR_AWAY))
    mask = robot_mask(image, reference)
    at = camera.project((0.5 * (top + bottom))[None], W, H)[0]
    x, y = np.round(at).astype(int)
    assert mask[y - 1 : y + 2, x - 1 : x + 2].all()


def test_save_png_round_trips(tmp_path: Path, renderer) -> None:
    robot = load_robot("planar3")
    kin = posed(robot, robot.q_home)
    image = render(renderer, framing_camera(kin), go.GraphicsOptions(4), kinematics=kin)
    path = tmp_path / "x.png"
    go.save_png(path, image)
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width, height, depth, color_type = struct.unpack(">IIBB", data[16:26])
    assert (width, height, depth, color_type) == (W, H, 8, 6)
    idat, pos = b"", 8
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        if kind == b"IDAT":
            idat += data[pos + 8 : pos + 8 + length]
        pos += 12 + length
    rows = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(H, 1 + 4 * W)
    assert np.all(rows[:, 0] == 0)
    assert np.array_equal(rows[:, 1:].reshape(H, W, 4), image)
    with pytest.raises(OSError, match="cannot write PNG to /nonexistent-dir/x.png"):
        go.save_png("/nonexistent-dir/x.png", image)


def test_projection_agrees_with_the_picture_and_rejects_points_behind_the_eye(renderer) -> None:
    robot = load_robot("planar3")
    kin = posed(robot, robot.q_home)
    camera = framing_camera(kin)
    options = go.GraphicsOptions(4)
    options.show_frames[0] = False
    image = render(renderer, camera, options, kinematics=posed(robot, robot.q_home, FAR_AWAY))
    ground = np.array(gd.GROUND_COLOR[:3]) * 255
    grid = np.array(gd.GRID_COLOR[:3]) * 255
    at = camera.project(np.array([[0.3, -0.2, 0.0]]), W, H)[0]  # a point on the ground
    got = pixel(image, at)
    assert min(np.abs(got - ground).max(), np.abs(got - grid).max()) < 60
    sky = camera.project((camera.eye() + 10.0 * (camera.eye() - camera.target))[None], W, H)
    assert np.all(np.isnan(sky))
