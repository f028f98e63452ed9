"""The one render path of every host: :func:`render_scene` draws a Scene seen by a
Camera with GraphicsOptions into the current GL context (Qt widget or OSMesa)."""
from __future__ import annotations

import weakref

import numpy as np
from numpy.typing import NDArray

import graphics_defs as gd
from _gfx_camera import Camera
from _gfx_drawables import AxesGraphics, RobotGraphics, TargetGraphics, VectorGraphics, frame_poses, ground_for, robot_reach
from _gfx_gl import GL, context_key, gl_matrix
from _gfx_resources import resources
from _gfx_scene import GraphicsOptions, Scene
from kinematics import Kinematics

# The robot drawables of the Kinematics objects being shown (a viewer keeps one for the
# current and one for the desired state); they go when their Kinematics goes.
_ROBOT_ITEMS: weakref.WeakKeyDictionary[Kinematics, RobotGraphics] = weakref.WeakKeyDictionary()


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

    Order: clear; opaque pass (ground, workspace cloud, robot when opaque); translucent
    pass (robot when ``options.alpha`` < 1, then the ghost), blended without depth
    writes; then, over a cleared depth buffer so nothing hides them, the annotations:
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
    base_xy = kin.h_tf[0].t()[:2]
    ground_for(reach, float(base_xy[0]), float(base_xy[1])).draw()
    if cloud is not None and not cloud_drawn:
        cloud.draw()
    robot = robot_item(kin)
    robot.alpha, robot.wireframe = float(options.alpha), options.wireframe
    if robot.gl_preset == "opaque":
        robot.draw()
    if options.show_ghost and scene.ghost is not None:
        ghost = robot_item(scene.ghost, ghost=True)
        ghost.wireframe = options.wireframe
        ghost.draw()
    if robot.gl_preset != "opaque":
        robot.draw()

    GL.glClear(GL.GL_DEPTH_BUFFER_BIT)
    AxesGraphics(robot.sizes.frame_length, frame_poses(kin, options.show_frames, options.show_endeff_frame)).draw()
    if options.show_target and scene.target_tf is not None:
        TargetGraphics(reach, scene.target_tf, scene.target_reachable).draw()
    if options.show_vectors:
        VectorGraphics(reach, scene.vectors).draw()
