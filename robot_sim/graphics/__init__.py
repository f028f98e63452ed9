"""Drawing the robot with legacy (fixed-function) OpenGL: the public face of the viewer's
graphics, one render path for all hosts.

Everything is in the world frame (z up, metres) unless a docstring says otherwise.
:func:`render_scene` is the only render path: the Qt GL widget calls it in ``paintGL``
and :class:`OffscreenRenderer` calls it in an OSMesa context for screenshots and tests.

The work is done by private modules, one job each:

* ``robot_sim.graphics.camera``: the orbit :class:`Camera` (view, projection, framing, projection of
  points to pixels);
* ``robot_sim.graphics.scene``: :class:`Scene` (what a frame shows) and :class:`GraphicsOptions` (how);
* ``robot_sim.graphics.gl``: lazily imported PyOpenGL, matrices, client arrays, display lists and GL
  state scoped by named presets (``gl_state("opaque" | "translucent" | "overlay" |
  "unlit")``, pushed and popped around each drawable);
* ``robot_sim.graphics.meshes``: unit meshes tessellated once;
* ``robot_sim.graphics.resources``: per-context GL objects and :class:`Drawable`, the base of every
  drawable, which owns its GL objects and paints itself (pyqtgraph's item model);
* ``robot_sim.graphics.robot_parts``: the robot as its DH segments and joints, part sizes (no GL);
* ``robot_sim.graphics.items.drawables``: floor, axes, arrows, IK target, robot;
* ``robot_sim.graphics.items.text``: labels as bitmap text (no GUI toolkit);
* ``robot_sim.graphics.items.annotation``: one joint's DH parameters as dimensions and arcs;
* ``robot_sim.graphics.items.cloud``: the workspace cloud with its vertex buffer and picture cache;
* ``robot_sim.graphics.render``: :func:`render_scene`;
* ``robot_sim.graphics.offscreen``: :class:`OffscreenRenderer` (OSMesa) and :func:`save_png`.

None of them imports Qt, and ``OpenGL.GL`` is imported only when something is drawn,
so :func:`require_osmesa_platform` can still choose PyOpenGL's platform after import.
"""
from __future__ import annotations

from robot_sim.graphics.items.annotation import Annotation, AnnotationGraphics, dh_annotation
from robot_sim.graphics.camera import Camera
from robot_sim.graphics.items.cloud import WorkspaceCloud, colormap
from robot_sim.graphics.items.drawables import (
    AxesGraphics,
    GroundGraphics,
    RobotGraphics,
    TargetGraphics,
    VectorGraphics,
    frame_labels,
    frames_and_names,
)
from robot_sim.graphics.gl import GL_PRESETS, gl_state, require_osmesa_platform
from robot_sim.graphics.offscreen import OffscreenRenderer, save_png
from robot_sim.graphics.render import annotation_points, render_scene, visible_points
from robot_sim.graphics.robot_parts import (
    DHSegments,
    Part,
    RobotLook,
    dh_segments,
    differing,
    part_corners,
    robot_look,
    robot_parts,
    robot_reach,
)
from robot_sim.graphics.resources import Drawable
from robot_sim.graphics.scene import RGBA, GraphicsOptions, Scene, Vector
from robot_sim.graphics.items.text import TextGraphics, text_size

__all__ = [
    "Annotation",
    "AnnotationGraphics",
    "TextGraphics",
    "dh_annotation",
    "frame_labels",
    "frames_and_names",
    "text_size",
    "RGBA",
    "AxesGraphics",
    "Camera",
    "Drawable",
    "GL_PRESETS",
    "GraphicsOptions",
    "GroundGraphics",
    "OffscreenRenderer",
    "RobotGraphics",
    "RobotLook",
    "DHSegments",
    "Part",
    "dh_segments",
    "differing",
    "robot_look",
    "robot_parts",
    "part_corners",
    "Scene",
    "TargetGraphics",
    "Vector",
    "VectorGraphics",
    "WorkspaceCloud",
    "colormap",
    "gl_state",
    "render_scene",
    "require_osmesa_platform",
    "robot_reach",
    "save_png",
    "visible_points",
    "annotation_points",
]
