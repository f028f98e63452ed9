"""The one render path of every host: :func:`render_scene` draws a Scene seen by a
Camera with GraphicsOptions into the current GL context (Qt widget or OSMesa)."""
from __future__ import annotations

import weakref

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.camera import Camera
from robot_sim.graphics.items.annotation import AnnotationGraphics, dh_annotation
from robot_sim.graphics.items.drawables import (
    AxesGraphics,
    RobotGraphics,
    TargetGraphics,
    VectorGraphics,
    frame_labels,
    frame_poses,
    frames_and_names,
    ground_for,
)
from robot_sim.graphics.robot_parts import part_corners, robot_look, robot_parts, robot_reach
from robot_sim.graphics.gl import GL, context_key, gl_matrix
from robot_sim.graphics.items.trail import TrailGraphics
from robot_sim.graphics.resources import resources
from robot_sim.graphics.scene import GraphicsOptions, Scene
from robot_sim.graphics.items.task import TaskGraphics, task_points
from robot_sim.graphics.items.text import TextGraphics
from robot_sim.kinematics import Kinematics

# The robot drawables of the Kinematics objects being shown (a viewer keeps one for the
# current and one for the desired state); they go when their Kinematics goes.
_ROBOT_ITEMS: weakref.WeakKeyDictionary[Kinematics, RobotGraphics] = weakref.WeakKeyDictionary()


_TEXT = TextGraphics()  # the labels of every frame (it keeps the font's display lists)


def robot_item(kinematics: Kinematics, ghost: bool = False) -> RobotGraphics:
    """The persistent drawable of the robot posed by ``kinematics``."""
    item = _ROBOT_ITEMS.get(kinematics)
    if item is None or item.ghost != ghost:
        item = _ROBOT_ITEMS[kinematics] = RobotGraphics(kinematics, ghost=ghost)
    return item


def _setup_lights(view: NDArray[np.float64]) -> None:
    """Headlight fixed in eye space, sky light fixed in the world, colour material."""
    GL.glMatrixMode(GL.GL_MODELVIEW)
    GL.glLoadIdentity()
    GL.glLightfv(GL.GL_LIGHT0, GL.GL_POSITION, gd.HEADLIGHT_DIRECTION)
    GL.glLightfv(GL.GL_LIGHT0, GL.GL_DIFFUSE, gd.HEADLIGHT_DIFFUSE)
    GL.glLightfv(GL.GL_LIGHT0, GL.GL_SPECULAR, gd.SPECULAR_COLOR)
    GL.glLoadMatrixd(gl_matrix(view))
    GL.glLightfv(GL.GL_LIGHT1, GL.GL_POSITION, gd.SKYLIGHT_DIRECTION)
    GL.glLightfv(GL.GL_LIGHT1, GL.GL_DIFFUSE, gd.SKYLIGHT_DIFFUSE)
    GL.glLightfv(GL.GL_LIGHT1, GL.GL_SPECULAR, (0.0, 0.0, 0.0, 1.0))
    GL.glLightModelfv(GL.GL_LIGHT_MODEL_AMBIENT, gd.AMBIENT_LIGHT)
    GL.glLightModeli(GL.GL_LIGHT_MODEL_TWO_SIDE, GL.GL_TRUE)
    for cap in (GL.GL_LIGHT0, GL.GL_LIGHT1, GL.GL_COLOR_MATERIAL, GL.GL_NORMALIZE):
        GL.glEnable(cap)
    GL.glColorMaterial(GL.GL_FRONT_AND_BACK, GL.GL_AMBIENT_AND_DIFFUSE)
    GL.glMaterialfv(GL.GL_FRONT_AND_BACK, GL.GL_SPECULAR, gd.SPECULAR_COLOR)
    GL.glMaterialf(GL.GL_FRONT_AND_BACK, GL.GL_SHININESS, gd.SHININESS)


def render_scene(camera: Camera, scene: Scene, options: GraphicsOptions, width: int, height: int) -> None:
    """Draw ``scene`` seen by ``camera`` into the current GL context's framebuffer,
    ``width`` x ``height`` pixels.  The one render path of every host.

    Order: clear; opaque pass (workspace cloud, robot when opaque); translucent pass
    (the floor, the ghost where it differs from the robot, the robot when
    ``options.alpha`` < 1), blended without depth writes; then, over a cleared depth buffer so nothing hides them, the annotations:
    selected frames, the IK target and the vectors.  Raises RuntimeError when no GL
    context is current.
    """
    width, height = max(int(width), 1), max(int(height), 1)
    if context_key() == 0:
        raise RuntimeError("render_scene: no current OpenGL context (the host failed to create or bind one)")
    resources().free_dead()
    kin = scene.kinematics
    reach = robot_reach(kin.robot)

    GL.glViewport(0, 0, width, height)
    GL.glClearColor(*gd.BACKGROUND_COLOR)
    GL.glDepthMask(GL.GL_TRUE)
    GL.glClear(GL.GL_COLOR_BUFFER_BIT | GL.GL_DEPTH_BUFFER_BIT)
    GL.glMatrixMode(GL.GL_PROJECTION)
    GL.glLoadMatrixd(gl_matrix(camera.projection_matrix(width / height)))
    _setup_lights(camera.view_matrix())
    GL.glDepthFunc(GL.GL_LEQUAL)
    GL.glDisable(GL.GL_CULL_FACE)

    cloud = scene.workspace if options.show_workspace else None
    cloud_drawn = cloud is not None and cloud.draw_from_picture(camera, width, height)
    if cloud is not None and not cloud_drawn:
        cloud.draw()
    if scene.task is not None:
        TaskGraphics(scene.task).draw()
    robot = robot_item(kin)
    robot.alpha, robot.wireframe, robot.show_com = float(options.alpha), options.wireframe, options.show_com
    robot.endeff_marker = scene.task is None  # the gripper is the endeffector
    if robot.gl_preset == "opaque":
        robot.draw()
    base_xy = kin.frames[0, :2, 3]
    ground_for(reach, float(base_xy[0]), float(base_xy[1])).draw()
    if scene.trail is not None:
        TrailGraphics(scene.trail).draw()
    if options.show_ghost and scene.ghost is not None:
        ghost = robot_item(scene.ghost, ghost=True)
        ghost.reference, ghost.wireframe, ghost.show_com = robot, options.wireframe, options.show_com
        ghost.endeff_marker = robot.endeff_marker
        ghost.draw()
    if robot.gl_preset != "opaque":
        robot.draw()

    GL.glClear(GL.GL_DEPTH_BUFFER_BIT)
    frames, names = frames_and_names(kin, options.show_frames, options.show_endeff_frame)
    axes = AxesGraphics(robot.look.frame_length, frames)
    axes.draw()
    if options.show_target and scene.target_tf is not None:
        TargetGraphics(reach, scene.target_tf, scene.target_reachable).draw()
    if options.show_vectors:
        VectorGraphics(reach, scene.vectors).draw()
    labels = [(p, text, gd.LABEL_COLOR) for p, text in frame_labels(frames, names, axes.lengths())] if options.show_labels else []
    joint = options.annotate_joint
    if joint is not None and 1 <= joint <= kin.robot.n_dofs:  # a joint number left from another robot draws nothing
        annotation = dh_annotation(kin.frames, joint, kin.robot.is_modified, robot.look.frame_length)
        AnnotationGraphics(annotation).draw()
        labels += annotation.labels
    if labels:
        _TEXT.labels = labels
        _TEXT.place(camera.project(np.array([p for p, _, _ in labels]), width, height), height)
        _TEXT.draw()


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
    """World points (N, 3) that enclose what :func:`render_scene` draws for ``scene``
    and ``options``: the corners of the robot's parts at its current pose, the point
    of the floor under its base, the tips of the drawn frames' axes, the ghost (desired
    state) when drawn, the IK target with its axes, the vectors, the workspace cloud, the
    pick task's table and path and the DH annotation when shown.  For framing (``fit``)."""
    kin = scene.kinematics
    look = robot_look(kin.robot)
    com = kin.link_com if options.show_com else None
    parts = robot_parts(kin.robot, kin.frames, kin.endeff_tf.mat, com)
    frames = frame_poses(kin, options.show_frames, options.show_endeff_frame)
    points = [part_corners(parts), kin.frames[0, :3, 3] * (1.0, 1.0, 0.0), frames[:, :3, 3]]
    if options.show_ghost and scene.ghost is not None:
        ghost = scene.ghost
        points.append(part_corners(robot_parts(ghost.robot, ghost.frames, ghost.endeff_tf.mat, None)))
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
