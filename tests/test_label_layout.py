"""Labels never overlap each other or an arrow: the placement pass (label_layout) against
brute-force oracles, and the DH annotation of every joint of four robots rendered
offscreen, each label's text found inside its own box."""
from __future__ import annotations

import numpy as np
import pytest

from robot_sim import graphics as go

go.require_osmesa_platform()

from robot_sim.app import prepare  # noqa: E402
from robot_sim.graphics import defs as gd  # noqa: E402
from robot_sim.graphics.label_layout import (  # noqa: E402
    boxes_overlap,
    candidate_boxes,
    place_labels,
    polyline_segments,
    segments_hit_box,
)
from robot_sim.graphics.items.text import LabelsItem  # noqa: E402

W, H = 800, 600


def sampled_hit(box: np.ndarray, segment: np.ndarray) -> bool:
    """Oracle: does any of 2001 points along ``segment`` fall inside ``box``?"""
    t = np.linspace(0.0, 1.0, 2001)[:, None]
    points = segment[0] + t * (segment[1] - segment[0])
    return bool(np.any((points[:, 0] >= box[0]) & (points[:, 0] <= box[2]) & (points[:, 1] >= box[1]) & (points[:, 1] <= box[3])))


def test_segment_box_test_agrees_with_sampling() -> None:
    rng = np.random.default_rng(1)
    box = np.array([40.0, 30.0, 70.0, 45.0])
    segments = rng.uniform(0.0, 100.0, size=(400, 2, 2))
    segments[:50, :, 1] = 37.0  # horizontal ones through the box's rows
    segments[50:100, :, 0] = 55.0  # vertical ones through its columns
    got = segments_hit_box(box, segments)
    want = np.array([sampled_hit(box, s) for s in segments])
    assert np.count_nonzero(want) > 40 and np.count_nonzero(~want) > 40
    # sampling can miss a corner graze of under 1/2000 of a segment: compare where it is clear
    np.testing.assert_array_equal(got, want)


def test_a_free_label_stays_at_its_usual_place() -> None:
    placement = place_labels([[100.0, 100.0]], [(60, 14)], (W, H))
    dx, dy = gd.LABEL_OFFSET_PX
    np.testing.assert_array_equal(placement.boxes[0], [100 + dx, 100 - dy - 14, 160 + dx, 100 - dy])
    assert not placement.moved[0] and np.all(np.isnan(placement.leaders[0]))


def test_crowded_labels_spread_apart_inside_the_picture() -> None:
    anchors = np.array([[5.0, 8.0]] * 6 + [[400.0, 300.0]] * 6)  # six at a corner, six in the middle
    sizes = [(90, 14)] * 12
    placement = place_labels(anchors, sizes, (W, H))
    boxes = placement.boxes
    for i in range(len(boxes)):
        assert not np.any(boxes_overlap(boxes[i], boxes[i + 1:])), i
    assert np.all(boxes[:, :2] >= 0) and np.all(boxes[:, 2] <= W) and np.all(boxes[:, 3] <= H)
    assert placement.moved.sum() >= 10


def test_a_label_moves_off_an_arrow_and_gets_a_leader() -> None:
    anchor = np.array([200.0, 200.0])
    usual = candidate_boxes(anchor, (80, 14))[0]
    arrow = np.array([[[usual[0] - 10, 0.5 * (usual[1] + usual[3])], [usual[2] + 10, 0.5 * (usual[1] + usual[3])]]])
    placement = place_labels([anchor], [(80, 14)], (W, H), arrow)
    box = placement.boxes[0]
    assert placement.moved[0] and not segments_hit_box(box, arrow)[0]
    start, end = placement.leaders[0]
    np.testing.assert_array_equal(start, anchor)
    on_edge = np.isclose(end[0], box[[0, 2]]).any() or np.isclose(end[1], box[[1, 3]]).any()
    assert on_edge and box[0] <= end[0] <= box[2] and box[1] <= end[1] <= box[3]


def test_labels_nowhere_are_left_out() -> None:
    placement = place_labels([[np.nan, np.nan], [50.0, 50.0]], [(30, 14), (30, 14)], (W, H))
    assert np.all(np.isnan(placement.boxes[0])) and np.all(np.isfinite(placement.boxes[1]))


@pytest.fixture(scope="module")
def renderer() -> go.OffscreenRenderer:
    with go.OffscreenRenderer(W, H) as r:
        yield r


ROBOTS = {"puma560": 6, "panda": 7, "stanford": 6, "scara": 4}  # standard, modified, prismatic, SCARA


def arrows_of(session: object) -> np.ndarray:
    """Pixel segments (K, 2, 2) of what the labels must keep off, computed here from the
    kinematics: the two drawn frames' axes and the annotation's dimensions and arcs."""
    kin, options, camera = session.kin, session.options, session.camera
    frames, _ = go.frames_and_names(kin, options.show_frames, options.show_endeff_frame)
    lengths = go.axis_lengths(frames, go.robot_look(session.robot).frame_length)
    axes = [np.stack([f[:3, 3], f[:3, 3] + length * f[:3, k]]) for f, length in zip(frames, lengths) for k in range(3)]
    annotation = go.dh_annotation(kin.frames, options.annotate_joint, session.robot.is_modified,
                                  go.robot_look(session.robot).frame_length)
    return polyline_segments([camera.project(points, W, H) for points in [p for p, _, _ in annotation.lines] + axes])


@pytest.mark.parametrize("robot", list(ROBOTS))
def test_every_joints_annotation_has_its_labels_apart_and_off_the_arrows(renderer: go.OffscreenRenderer,
                                                                        robot: str) -> None:
    for joint in range(1, ROBOTS[robot] + 1):
        args = ["--robot", robot, "--annotate", str(joint), "--frames", f"{joint - 1},{joint}", "--size", f"{W}x{H}"]
        session = prepare.session_from_config(prepare.prepare(args))
        image = renderer.render(session.camera, session.scene(), session.options)
        item = renderer.view.item(LabelsItem)
        labels, boxes = item.labels, item.placement.boxes
        assert len(labels) == 6 or (len(labels) == 5 and joint > 1), (robot, joint, [t for _, t, _ in labels])
        assert np.all(np.isfinite(boxes)), (robot, joint)
        for i in range(len(boxes)):
            assert not np.any(boxes_overlap(boxes[i], boxes[i + 1:])), (robot, joint, labels[i][1])
        assert np.all(boxes[:, :2] >= 0) and np.all(boxes[:, 2] <= W) and np.all(boxes[:, 3] <= H)
        arrows = arrows_of(session)
        for box, (_, text, _) in zip(boxes, labels):
            assert not np.any(segments_hit_box(box, arrows)), (robot, joint, text)
        for box, (_, text, rgba) in zip(boxes, labels):  # the text is drawn in its box, in its colour
            left, top, right, bottom = np.round(box).astype(int)
            patch = image[max(top, 0):bottom + 1, max(left, 0):right + 1, :3].astype(int)
            ink = np.all(np.abs(patch - np.round(255 * np.asarray(rgba[:3]))) <= 40, axis=-1)
            assert np.count_nonzero(ink) >= 4 * len(text.replace(" ", "")), (robot, joint, text)
