"""What the render path draws, as world points to frame (pure NumPy, no GL): the
camera's ``fit`` takes them so the picture shows everything drawn."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.annotation_geometry import dh_annotation
from robot_sim.graphics.frame_axes import frame_poses
from robot_sim.graphics.task_scene import task_points
from robot_sim.graphics.looks import look_for
from robot_sim.graphics.robot_parts import part_corners, robot_look
from robot_sim.graphics.scene import GraphicsOptions, Scene
from robot_sim.graphics.solid import posed_parts
from robot_sim.graphics.visuals import piece_corners, visual_pieces


def annotation_points(scene: Scene, options: GraphicsOptions) -> NDArray[np.float64] | None:
    """World points (N, 3) of the DH annotation of ``options.annotate_joint`` (its lines,
    its label anchors and the axis tips of the two frames it relates), or None when no
    annotation is drawn.  For framing one joint's parameters (``fit``)."""
    kin, joint = scene.kinematics, options.annotate_joint
    if joint is None or not 1 <= joint <= kin.robot.n_dofs:
        return None
    look = robot_look(kin.robot)
    annotation = dh_annotation(kin.frames, joint, kin.robot.is_modified, look.frame_length)
    ends = kin.frames[joint - 1:joint + 1]
    points = [line for line, _, _ in annotation.lines] + [anchor for anchor, _, _ in annotation.labels]
    points += [ends[:, :3, 3]] + [ends[:, :3, 3] + look.frame_length * ends[:, :3, k] for k in range(3)]
    return np.vstack([np.asarray(p, dtype=float).reshape(-1, 3) for p in points])


def visible_points(scene: Scene, options: GraphicsOptions) -> NDArray[np.float64]:
    """World points (N, 3) that enclose what the render path draws for ``scene`` and
    ``options``: the corners of the robot's parts (or of its visual shapes) at its
    current pose in its look, the point of the floor under its base, the tips of the
    drawn frames' axes, the ghost (desired state) when drawn, the IK target with its
    axes, the vectors, the workspace cloud, the pick task's table and path and the DH
    annotation when shown.  For framing (``fit``)."""
    kin = scene.kinematics
    look = robot_look(kin.robot)
    shown = look_for(kin.robot, options.look)
    parts_look = "solid" if shown == "solid" else "dh"
    frames = frame_poses(kin, options.show_frames, options.show_endeff_frame)
    points = [kin.frames[0, :3, 3] * (1.0, 1.0, 0.0), frames[:, :3, 3]]
    if shown != "mesh":
        points.append(part_corners(posed_parts(kin, parts_look, options.show_com)))
    if shown in ("mesh", "both"):
        points.append(piece_corners(visual_pieces(kin.robot), kin.frames))
    if options.show_ghost and scene.ghost is not None:
        points.append(part_corners(posed_parts(scene.ghost, parts_look, False)))
    points += [frames[:, :3, 3] + look.frame_length * frames[:, :3, k] for k in range(3)]
    if options.show_target and scene.target_tf is not None:
        target, length = scene.target_tf.mat, look.reach * gd.TARGET_FRAME_LENGTH_FRAC
        points += [target[:3, 3]] + [target[:3, 3] + length * target[:3, k] for k in range(3)]
    if options.show_vectors:
        points += [np.asarray(origin, dtype=float) + np.asarray(vec, dtype=float) for origin, vec, _ in scene.vectors]
    if options.show_workspace and scene.workspace is not None:
        points.append(np.asarray(scene.workspace.points, dtype=float))
    if scene.task is not None:
        points.append(task_points(scene.task))
    annotation = annotation_points(scene, options)
    if annotation is not None:
        points.append(annotation)
    return np.vstack([np.asarray(p, dtype=float).reshape(-1, 3) for p in points])
