"""The robot drawn truthfully (offscreen, OSMesa): links as their DH segments, prismatic
sleeve and rod, part sizes from each link, a floor the arm passes through, a ghost only
where it differs, velocity arrows outside the endeffector.

Expected positions come from forward kinematics and ``Camera.project``; "robot pixels"
differ from a render of the same scene with the robot a kilometre below the floor (see
test_render.py, whose helpers and renderer fixture this module shares).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from robot_sim import graphics as go

go.require_osmesa_platform()

from robot_sim.graphics import defs as gd  # noqa: E402
from robot_sim.graphics.items.text import LabelsItem  # noqa: E402
from robot_sim.kinematics import forward_kinematics  # noqa: E402
from robot_sim.model.params import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotParams
from robot_sim.io.robot_file import available_robots, load_robot  # noqa: E402
from render_helpers import (  # noqa: E402
    DEG,
    Frames,
    along,
    color_mask,
    framed,
    key_points,
    options_for,
    posed,
    project,
    render,  # noqa: F401 - the module's renderer fixture
    robot_mask,
    window,
)
from robot_sim.transforms import HomogeneousTransform  # noqa: E402
from robot_sim.viewer.session import ViewerSession  # noqa: E402

R_, P_ = JTYPE_REVOLUTE, JTYPE_PRISMATIC


def grey_mask(image: np.ndarray, empty: np.ndarray, lo: int = 110) -> np.ndarray:
    """Robot pixels of the light-grey link colour: bright and without a hue."""
    px = image[..., :3].astype(int)
    return robot_mask(image, empty) & (px.min(axis=-1) >= lo) & (px.max(axis=-1) - px.min(axis=-1) <= 25)


def red_at(image: np.ndarray, camera: go.Camera, point: np.ndarray, radius: int = 2) -> bool:
    return bool(window(color_mask(image, gd.ENDEFF_COLOR), project(camera, point)[0], radius).any())


# ------------------------------------------------------------- DH segments


def test_scara_column_is_drawn_vertical_not_as_a_diagonal_strut(render: Frames) -> None:
    """SCARA link 1 is d1 = 0.387 m up z0, then a1 = 0.325 m along x1: the column's
    midpoint is link grey, the midpoint of the straight line from frame 0 to frame 1
    (the old strut) is empty."""
    kin = posed("scara", [0.0, 60 * DEG, 0.1, 0.0])
    o0, o1 = kin.h_tf[0].t(), kin.h_tf[1].t()
    column_top = o0 + 0.387 * kin.h_tf[0].R()[:, 2]
    np.testing.assert_allclose(o1 - column_top, 0.325 * kin.h_tf[1].R()[:, 0], atol=1e-12)
    camera = framed(key_points(kin), azimuth_deg=-90.0, elevation_deg=5.0)  # x1 (world x) across the screen
    image, empty = render.pair(camera, kin, options_for(kin))
    grey = grey_mask(image, empty)
    for f in (0.45, 0.6, 0.75):
        xy = project(camera, along(o0, column_top, (f,)))[0]
        assert window(grey, xy, 1).any(), f"no link grey {f:.0%} up the column at {xy.round(1)}"
    arm_xy = project(camera, along(column_top, o1, (0.5,)))[0]
    assert window(grey, arm_xy, 1).any(), "no link grey along x1 at the top of the column"
    strut = project(camera, 0.5 * (o0 + o1))[0]
    assert not window(robot_mask(image, empty), strut, 2).any(), f"something drawn on the old strut at {strut.round(1)}"


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_dh_segments_are_the_d_and_a_of_the_table(convention: str) -> None:
    """Read off the frames, the segments' signed lengths are the table's d and a, and
    they chain frame i−1's origin to frame i's origin (both conventions)."""
    rng = np.random.default_rng(5)
    n = 5
    robot = RobotParams.from_arrays(
        "r", rng.uniform(-0.5, 0.5, n), rng.uniform(-np.pi, np.pi, n), rng.uniform(-0.5, 0.5, n),
        rng.uniform(-np.pi, np.pi, n), [R_, P_, R_, R_, P_], convention=convention,
    )
    q = rng.uniform(-1.0, 1.0, n) * np.where(robot.jtype == P_, 0.2, 1.0)
    frames = forward_kinematics(robot, q, all_frames=True)[:-1]
    seg = go.dh_segments(frames, convention == "modified")
    d = robot.dh_d + np.where(robot.jtype == P_, q, 0.0)
    np.testing.assert_allclose(seg.d, d, atol=1e-12)
    np.testing.assert_allclose(np.abs(seg.a), np.abs(robot.dh_a), atol=1e-12)
    first, second = (seg.offset_start, seg.offset_end), (seg.axis_start, seg.axis_end)
    if convention == "standard":
        first, second = second, first
    np.testing.assert_allclose(first[0], frames[:-1, :3, 3], atol=1e-12)
    np.testing.assert_allclose(first[1], second[0], atol=1e-12)
    np.testing.assert_allclose(second[1], frames[1:, :3, 3], atol=1e-12)
    axis_frame = frames[:-1] if convention == "standard" else frames[1:]
    np.testing.assert_allclose(seg.axis, axis_frame[:, :3, 2], atol=1e-12)


# ------------------------------------------------------------ part sizes


@pytest.mark.parametrize("name", available_robots())
def test_no_joint_reaches_into_another_or_the_endeffector_at_home(name: str) -> None:
    """At home two joints' radii together stay within their distance (cylinders may
    cross, none swallows another; joints closer than JOINT_CROSSING_FRAC of the reach
    share a housing and cross, like a wrist's) and no joint reaches into the endeffector sphere."""
    robot = load_robot(name)
    look = go.robot_look(robot)
    home = forward_kinematics(robot, robot.q_home, all_frames=True)
    seg = go.dh_segments(home[:-1], robot.is_modified)
    bound = np.hypot(look.joint_radius, look.joint_half_length)
    endeff = home[-1, :3, 3]
    gaps = np.linalg.norm(seg.joint - endeff, axis=1)
    holds_endeff = gaps < 1e-6  # lengthened to show through the sphere
    cylinder = (robot.jtype == R_) & ~holds_endeff
    for i in range(robot.n_dofs):
        for j in range(robot.n_dofs):
            gap = np.linalg.norm(seg.joint[i] - seg.joint[j])
            if i != j and gap > gd.JOINT_CROSSING_FRAC * look.reach and cylinder[i] and cylinder[j]:
                radii = look.joint_radius[i] + look.joint_radius[j]
                assert radii <= 2 * gd.JOINT_CLEARANCE * gap + 1e-9, f"{name}: joints {i + 1}, {j + 1} overlap"
        if holds_endeff[i]:  # the sphere is wider than the joint, the joint pokes out of it
            assert look.joint_radius[i] < look.endeff_radius < look.joint_half_length[i], name
        else:
            assert bound[i] + look.endeff_radius <= gaps[i] + 1e-9, f"{name}: joint {i + 1} reaches into the endeffector"
    assert np.all(look.link_radius[:-1] < look.joint_radius), f"{name}: a link as thick as its joint"
    assert look.endeff_radius <= gd.JOINT_RADIUS_MAX_FRAC * look.reach * gd.ENDEFF_NEAR_RATIO ** 2, name


@pytest.mark.parametrize("name", available_robots())
def test_endeffector_shows_at_home_for_every_shipped_robot(render: Frames, name: str) -> None:
    """Red within the endeffector sphere's picture from four sides (PUMA's sits in its
    wrist centre: the sphere is wider than the wrist joints, which pierce it)."""
    kin = posed(name)
    radius = go.robot_look(kin.robot).endeff_radius
    for azimuth in (45.0, 135.0, -45.0, -135.0):
        camera = framed(key_points(kin), azimuth_deg=azimuth)
        image = render(camera, go.Scene(kin), options_for(kin))
        radius_px = radius / camera.world_per_pixel(240) * camera.distance / np.linalg.norm(camera.eye() - kin.endeff_tf.t())
        assert red_at(image, camera, kin.endeff_tf.t(), max(2, int(0.9 * radius_px))), (
            f"{name}: endeffector hidden from azimuth {azimuth}")


def test_stanford_endeffector_ball_does_not_dominate() -> None:
    robot = load_robot("stanford")
    look = go.robot_look(robot)
    assert look.endeff_radius <= 1.25 * look.joint_radius.max()
    assert look.endeff_radius <= 0.025 * look.reach


def scaled(robot: RobotParams, factor: float) -> RobotParams:
    return RobotParams.from_arrays(f"{robot.name} x{factor}", robot.dh_a * factor, robot.dh_alpha, robot.dh_d * factor,
                                   robot.dh_th, robot.jtype)


def test_a_3_cm_arm_looks_like_a_3_m_arm(render: Frames) -> None:
    """Part sizes follow the arm: scaled by 1/100, every part size scales by 1/100, and
    framed alike the two pictures are the same shape (not a blob)."""
    big = scaled(load_robot("planar3"), 3.0 / go.robot_reach(load_robot("planar3")))
    small = scaled(big, 0.01)
    assert go.robot_reach(small) == pytest.approx(0.03)
    a, b = go.robot_look(big), go.robot_look(small)
    np.testing.assert_allclose(b.joint_radius, 0.01 * a.joint_radius, rtol=1e-9)
    np.testing.assert_allclose(b.link_radius, 0.01 * a.link_radius, rtol=1e-9)
    assert b.endeff_radius == pytest.approx(0.01 * a.endeff_radius)
    counts = []
    for robot in (big, small):
        kin = posed(robot, [30 * DEG, -60 * DEG, 45 * DEG])
        camera = framed(key_points(kin))
        image, empty = render.pair(camera, kin, options_for(kin))
        counts.append(int(robot_mask(image, empty).sum()))
        assert red_at(image, camera, kin.endeff_tf.t())
    assert 0.8 < counts[1] / counts[0] < 1.25, f"robot pixels: 3 m arm {counts[0]}, 3 cm arm {counts[1]}"


# ------------------------------------------------------------------ floor


def test_straight_down_link_on_a_raised_base_shows_its_endeffector(render: Frames) -> None:
    robot = RobotParams.from_arrays("down from the base", [0.0, 0.3], [0.0, 0.0], [-0.6, 0.0], [0.0, 0.0], [R_, R_],
                                    base_tf=HomogeneousTransform.from_rt(t=[0.0, 0.0, 1.0]))
    kin = posed(robot, [0.0, 90 * DEG])
    below_base = kin.h_tf[0].t() - [0.0, 0.0, 0.6]
    np.testing.assert_allclose(kin.h_tf[1].t(), below_base, atol=1e-12)
    np.testing.assert_allclose(kin.endeff_tf.t(), below_base + [0.0, 0.3, 0.0], atol=1e-12)
    for azimuth in (0.0, 90.0, 200.0):
        camera = framed(key_points(kin), azimuth_deg=azimuth)
        image, empty = render.pair(camera, kin, options_for(kin))
        assert red_at(image, camera, kin.endeff_tf.t()), f"endeffector hidden from azimuth {azimuth}"
        down = project(camera, along(kin.h_tf[0].t(), below_base, (0.5, 0.8)))
        for xy in down:
            assert window(grey_mask(image, empty), xy, 1).any(), f"the link down from the base is hidden at {xy.round(1)}"


FLAT = RobotParams.from_arrays("flat", [0.3, 0.25, 0.15], [0.0] * 3, [0.0] * 3, [0.0] * 3, [R_] * 3)  # in z = 0


@pytest.mark.parametrize("elevation", [25.0, 60.0, -20.0])
def test_an_arm_lying_at_floor_height_shows_its_endeffector(render: Frames, elevation: float) -> None:
    kin = posed(FLAT, [20 * DEG, 40 * DEG, -30 * DEG])
    assert abs(kin.endeff_tf.t()[2]) < 1e-12
    camera = framed(key_points(kin), elevation_deg=elevation)
    image, empty = render.pair(camera, kin, options_for(kin))
    assert red_at(image, camera, kin.endeff_tf.t()), f"endeffector on the floor hidden at elevation {elevation}"
    mid = project(camera, along(kin.h_tf[1].t(), kin.h_tf[2].t(), (0.5,)))[0]
    assert window(robot_mask(image, empty), mid, 1).any()


def test_parts_below_the_floor_show_through_it(render: Frames) -> None:
    """A base 0.2 m below the floor: its links show (tinted) from above."""
    kin = posed(FLAT, [20 * DEG, 40 * DEG, -30 * DEG], HomogeneousTransform.from_rt(t=[0.0, 0.0, -0.2]))
    camera = framed(np.vstack([key_points(kin), [[0.0, 0.0, 0.0]]]), elevation_deg=40.0)
    image, empty = render.pair(camera, kin, options_for(kin))
    for f in (0.3, 0.6):
        xy = project(camera, along(kin.h_tf[1].t(), kin.h_tf[2].t(), (f,)))[0]
        assert window(robot_mask(image, empty), xy, 1).any(), f"link below the floor hidden at {xy.round(1)}"
    red = color_mask(image, gd.ENDEFF_COLOR, margin=10, ratio=1.3, min_high=40)
    assert window(red, project(camera, kin.endeff_tf.t())[0]).any(), "endeffector below the floor hidden"


# ------------------------------------------------------------------ ghost


def test_a_ghost_on_the_arm_changes_no_pixel(render: Frames) -> None:
    kin = posed("puma560", [10 * DEG, 30 * DEG, -60 * DEG, 20 * DEG, 40 * DEG, 0.0])
    ghost = posed("puma560", [10 * DEG, 30 * DEG, -60 * DEG, 20 * DEG, 40 * DEG, 0.0])
    camera = framed(key_points(kin))
    options = options_for(kin)
    plain = render(camera, go.Scene(kin), options)
    assert np.array_equal(render(camera, go.Scene(kin, ghost=ghost), options), plain)


def test_a_ghost_differing_in_the_last_joints_leaves_the_upper_arm_alone(render: Frames) -> None:
    q = [10 * DEG, 30 * DEG, -60 * DEG, 20 * DEG, 40 * DEG, 0.0]
    kin = posed("puma560", q)
    ghost = posed("puma560", q[:3] + [-50 * DEG, 80 * DEG, 0.0])
    camera = framed(np.vstack([key_points(kin), key_points(ghost)]))
    options = options_for(kin)
    plain, empty = render.pair(camera, kin, options)
    with_ghost = render(camera, go.Scene(kin, ghost=ghost), options)
    changed = robot_mask(with_ghost, plain, tol=3)
    for f in (0.3, 0.5, 0.7):  # the upper arm (link 2, a2 = 0.43 m) is where it was
        xy = project(camera, along(kin.h_tf[1].t(), kin.h_tf[2].t(), (f,)))[0]
        assert not window(changed, xy, 2).any(), f"the ghost recoloured the upper arm at {xy.round(1)}"
    assert changed.sum() > 20, "the ghost's wrist is not drawn"
    ghost_parts = go.robot_parts(ghost.robot, ghost.frames, ghost.endeff_tf.mat)
    shown = go.differing(ghost_parts, go.robot_parts(kin.robot, kin.frames, kin.endeff_tf.mat))
    # the base, links 1..3 and joints 1..4 coincide; link 4's offset is zero-length
    assert sum(len(p.placements) for p in shown) < sum(len(p.placements) for p in ghost_parts)


# ------------------------------------------------------------- velocity arrows


def test_demo_velocity_arrows_start_outside_the_endeffector_and_show(render: Frames) -> None:
    session = ViewerSession(load_robot("anthropomorphic"), aspect=320 / 240)
    session.toggle_demo()
    for _ in range(20):
        session.step(0.02)
    scene = session.scene()
    centre = session.kin.endeff_tf.t()
    radius = go.robot_look(session.robot).endeff_radius
    session.fit_camera()
    camera = session.camera
    image = render(camera, scene, session.options)
    radius_px = radius / camera.world_per_pixel(240)
    centre_px = project(camera, centre)[0]
    origin, vec, rgba = scene.vectors[0]  # linear velocity, the demo's 0.16 m/s
    assert np.linalg.norm(vec) > 4 * radius
    assert np.linalg.norm(np.asarray(origin) - centre) == pytest.approx(radius)
    tip = project(camera, np.asarray(origin) + vec)[0]
    assert np.linalg.norm(tip - centre_px) > 2 * radius_px + 5, "arrow tip inside the endeffector's picture"
    orange = color_mask(image, rgba, margin=20, ratio=1.3)
    assert window(orange, project(camera, np.asarray(origin) + 0.5 * vec)[0], 2).any(), "no arrow halfway"
    assert math.isfinite(radius_px)


# ------------------------------------------------------------ frame labels


def white_mask(image: np.ndarray) -> np.ndarray:
    return np.all(image[..., :3] >= 235, axis=-1)


def label_slices(box: np.ndarray) -> tuple[slice, slice]:
    """Image rows and columns of a label's box (left, top, right, bottom), a pixel around."""
    left, top, right, bottom = np.round(box).astype(int)
    return slice(max(top - 1, 0), bottom + 3), slice(max(left - 1, 0), right + 2)


def test_frame_labels_are_written_next_to_each_drawn_frame(render: Frames) -> None:
    """Frames 0..3 and E of the anthropomorphic arm: each label's box (where the label
    placement put it, clear of the axes) holds white text pixels that are not there with
    labels off; frames 0 and 1 share their origin and one label "0,1"."""
    kin = posed("anthropomorphic", [30 * DEG, 60 * DEG, -45 * DEG])
    options = options_for(kin, base_frame=True)
    options.toggle_all_frames()
    frames, names = go.frames_and_names(kin, options.show_frames, options.show_endeff_frame)
    assert names == ["0", "1", "2", "3", "E"]
    camera = framed(go.visible_points(go.Scene(kin), options))
    labelled = render(camera, go.Scene(kin), options)
    placed = render.renderer.view.item(LabelsItem)
    boxes, leaders = placed.placement.boxes.copy(), placed.placement.leaders.copy()
    placed_texts = [text for _, text, _ in placed.labels]
    options.show_labels = False
    plain = render(camera, go.Scene(kin), options)
    labels = go.frame_labels(frames, names, go.axis_lengths(frames, go.robot_look(kin.robot).frame_length))
    texts = [text for _, text in labels]
    assert texts == ["0,1", "2", "3,E"]  # frame 1 sits on frame 0 (d1 = 0), no tool offset
    new = white_mask(labelled) & ~white_mask(plain)
    assert placed_texts == texts
    for (anchor, text), box in zip(labels, boxes):
        rows, cols = label_slices(box)
        assert new[rows, cols].sum() >= 8 * len(text), f"label {text!r} not written at {box.round(1)}"
    leader_px = np.nansum(np.linalg.norm(leaders[:, 1] - leaders[:, 0], axis=-1))
    budget = sum(go.text_size(t)[0] * go.text_size(t)[1] for t in texts) + 2 * (leader_px + len(texts))
    assert new.sum() <= budget, "white pixels beyond the label boxes and their leaders"


def test_coinciding_frames_do_not_share_surfaces() -> None:
    """PUMA's frames 4, 5 and 6 share the wrist centre: each later one is longer (its
    tips show beyond the others) and thinner, so no two axes z-fight."""
    kin = posed("puma560", [0.0, 45 * DEG, -135 * DEG, 0.0, 45 * DEG, 0.0])
    frames = kin.frames[[3, 4, 5, 6]]
    np.testing.assert_allclose(frames[1:, :3, 3], frames[1:2, :3, 3].repeat(3, 0), atol=1e-12)
    lengths = go.axis_lengths(frames, 1.0)
    assert lengths[0] == lengths[1] == 1.0 and lengths[1] < lengths[2] < lengths[3]


def test_a_later_frame_on_the_same_origin_shows_its_tip(render: Frames) -> None:
    """Two frames at one origin, the second's x along the first's x: the second's x tip
    (longer) is red beyond the first's."""
    robot = RobotParams.from_arrays("twins", [0.0, 0.3], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [R_, R_])
    kin = posed(robot, [0.0, 0.0])
    options = options_for(kin, base_frame=True)
    options.toggle_frame(1)
    length = go.robot_look(robot).frame_length
    camera = framed(np.vstack([key_points(kin), [[0.0, 0.0, length]]]), azimuth_deg=-80.0, elevation_deg=30.0)
    image = render(camera, go.Scene(kin), options)
    tip = (1.0 + 0.5 * gd.FRAME_STACK_LENGTH_STEP) * length
    assert window(color_mask(image, gd.AXIS_X_COLOR), project(camera, [tip, 0.0, 0.0])[0], 1).any()


# ------------------------------------------------------- DH annotation


def label_values(annotation: object) -> dict[str, float]:
    out = {}
    for _, text, _ in annotation.labels:  # type: ignore[attr-defined]
        name, value = text.split(" = ")
        out[name] = float(value.split()[0].rstrip("°"))
    return out


def test_standard_annotation_states_the_table_values() -> None:
    robot = load_robot("puma560")
    q = np.array([10, 45, -135, 20, 45, 0]) * DEG
    frames = forward_kinematics(robot, q, all_frames=True)[:-1]
    for j in range(1, 7):
        values = label_values(go.dh_annotation(frames, j, False, 0.1))
        theta = math.degrees(robot.dh_th[j - 1] + q[j - 1])
        assert values[f"d{j}"] == pytest.approx(robot.dh_d[j - 1], abs=5e-4)
        assert values[f"a{j}"] == pytest.approx(robot.dh_a[j - 1], abs=5e-4)
        assert values[f"θ{j}"] == pytest.approx((theta + 180) % 360 - 180, abs=0.05)
        assert values[f"α{j}"] == pytest.approx(math.degrees(robot.dh_alpha[j - 1]), abs=0.05)


def test_modified_annotation_states_craigs_values() -> None:
    """Row i of a Craig table holds a_{i-1}, α_{i-1}, θ_i, d_i: the labels say so."""
    rng = np.random.default_rng(11)
    a, alpha, d = rng.uniform(-0.4, 0.4, 4), rng.uniform(-2.5, 2.5, 4), rng.uniform(-0.4, 0.4, 4)
    robot = RobotParams.from_arrays("craig", a, alpha, d, [0.0] * 4, [R_, R_, P_, R_], convention="modified")
    q = np.array([0.3, -0.7, 0.1, 1.2])
    frames = forward_kinematics(robot, q, all_frames=True)[:-1]
    for j in range(1, 5):
        values = label_values(go.dh_annotation(frames, j, True, 0.1))
        assert values[f"a{j - 1}"] == pytest.approx(a[j - 1], abs=5e-4)
        assert values[f"α{j - 1}"] == pytest.approx(math.degrees(alpha[j - 1]), abs=0.05)
        assert values[f"d{j}"] == pytest.approx(d[j - 1] + (q[j - 1] if j == 3 else 0.0), abs=5e-4)
        theta = math.degrees(q[j - 1] if j != 3 else 0.0)
        assert values[f"θ{j}"] == pytest.approx(theta, abs=0.05)


@pytest.mark.parametrize("name,q,joint", [
    ("puma560", [0.0, 45.0, -135.0, 0.0, 45.0, 0.0], 2),
    ("scara", [-30.0, 60.0, 0.1, 0.0], 2),
    ("stanford", [0.0, 60.0, 0.5, 0.0, 30.0, 0.0], 3),
])
def test_annotation_is_drawn_where_the_joints_frames_project(render: Frames, name: str, q: list[float], joint: int) -> None:
    robot = load_robot(name)
    q_si = np.where(robot.jtype == P_, q, np.radians(q))
    kin = posed(robot, q_si)
    options = options_for(kin, base_frame=True)
    options.show_only_frames([joint - 1, joint])
    options.annotate_joint = joint
    camera = framed(go.visible_points(go.Scene(kin), options))
    annotated = render(camera, go.Scene(kin), options)
    options.annotate_joint = None
    plain = render(camera, go.Scene(kin), options)
    annotation = go.dh_annotation(kin.frames, joint, robot.is_modified, go.robot_look(robot).frame_length)
    found: dict[tuple[float, ...], bool] = {}
    for points, rgba, dashed in annotation.lines:
        if dashed or np.linalg.norm(points[-1] - points[0]) < 1e-6:
            continue  # extension lines and spokes; a zero d or a makes no line
        hue = color_mask(annotated, rgba, margin=15, ratio=1.2) & ~color_mask(plain, rgba, margin=15, ratio=1.2)
        middle = points[len(points) // 2] if len(points) > 2 else 0.5 * (points[0] + points[1])
        found[rgba] = found.get(rgba, False) or bool(window(hue, project(camera, middle)[0], 2).any())
    assert len(found) >= 2 and all(found.values()), f"{name}: annotation lines missing: {found}"
    o_prev, o_joint = (project(camera, kin.frames[k, :3, 3])[0] for k in (joint - 1, joint))
    changed = robot_mask(annotated, plain)
    assert window(changed, o_joint, 12).any() and window(changed, o_prev, 12).any()


def test_an_annotated_joint_number_out_of_range_draws_nothing(render: Frames) -> None:
    kin = posed("planar3")
    options = options_for(kin)
    camera = framed(key_points(kin))
    plain = render(camera, go.Scene(kin), options)
    for joint in (0, 4, 17):
        options.annotate_joint = joint
        assert np.array_equal(render(camera, go.Scene(kin), options), plain)
    with pytest.raises(ValueError, match="annotate_joint: expected a joint number 1..3, got 4"):
        go.dh_annotation(kin.frames, 4, False, 0.1)


def test_pictures_are_opaque_where_translucent_parts_blend(render: Frames) -> None:
    """The floor, the ghost and a translucent arm blend their colours only: every pixel
    keeps alpha 255, so PNGs and the window's grab() show what the view shows."""
    kin = posed("puma560", [10 * DEG, 30 * DEG, -60 * DEG, 20 * DEG, 40 * DEG, 0.0])
    ghost = posed("puma560", [40 * DEG, 10 * DEG, -30 * DEG, 0.0, 0.0, 0.0])
    options = options_for(kin)
    options.toggle_alpha()
    camera = framed(np.vstack([key_points(kin), key_points(ghost)]))
    image = render(camera, go.Scene(kin, ghost=ghost), options)
    assert image[..., 3].min() == 255


@pytest.mark.parametrize("name", ["puma560", "panda", "stanford", "ur5"])
def test_annotation_labels_never_show_a_negative_zero(name: str) -> None:
    """A length or angle read off the frames as −1e−17 is labelled 0, not "-0.000"
    (PUMA 560's d2 showed "d2 = -0.000 m" in the window)."""
    robot = load_robot(name)
    rng = np.random.default_rng(5)
    lo, hi = np.maximum(robot.q_min, -np.pi), np.minimum(robot.q_max, np.pi)
    for q in [robot.q_home, *(lo + (hi - lo) * rng.random((20, robot.n_dofs)))]:
        frames = forward_kinematics(robot, q, all_frames=True)[:-1]
        for j in range(1, robot.n_dofs + 1):
            for _, text, _ in go.dh_annotation(frames, j, robot.is_modified, 0.1).labels:
                value = text.split(" = ")[1]
                assert not (value.startswith("-") and float(value.split()[0].rstrip("°")) == 0.0), text
