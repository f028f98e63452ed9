"""Drawing the robot with OpenGL 3.3 shaders: the public face of the viewer's graphics,
one render path for all hosts.

Everything is in the world frame (z up, metres) unless a docstring says otherwise.
:class:`View` is the render path: it holds the scene's persistent items and draws them;
the Qt GL widget owns one and calls it in ``paintGL``, and :class:`OffscreenRenderer`
owns one in an OSMesa context for screenshots, recordings and tests.

Modules, one job each:

* ``camera``: the orbit :class:`Camera` (view, projection, framing, projection of points
  to pixels); ``framing``: the world points of what is drawn (for ``fit``);
* ``scene``: :class:`Scene` (what a frame shows) and :class:`GraphicsOptions` (how);
  ``themes``: the dark and light colours of the world; ``looks``: DH / solid / mesh / both;
* ``render``: :class:`View`; ``item``: :class:`Item`, the base of every drawable, which
  owns its GL objects and paints itself in one layer (pyqtgraph's item model);
  ``frame``: what items paint with (matrices, lights, shared GL resources, helpers);
* ``items/``: one drawable per file (robot, meshes, ghost, floor, frames, target,
  vectors, cloud, task, trail, annotation, labels, the cloud's colour scale), found by
  :func:`item_classes`; ``label_layout``: where labels go, clear of each other and of
  arrows; ``vector_clip``: which arrows are drawn, shortened to the view;
* ``shaders``: the GLSL programs; ``buffers``: vertex buffers; ``targets``: the
  multisampled target and the shadow map; ``lighting``: lights and the shadow's view;
* ``meshes``: unit meshes tessellated once; ``placements``: where copies of them go;
  ``robot_parts``: the robot as its DH segments and joints, part sizes; ``solid``: the
  solid look; ``visuals``: the robot's own shapes as drawable pieces; ``arrows``: arrow
  placements; ``frame_axes``, ``annotation_geometry``, ``floor_grid``: frames, the DH
  annotation and the floor as geometry (these and the modules above draw nothing, so the
  browser view (robot_sim.web) uses them too);
* ``font``: the label font (FreeType glyph atlas); ``offscreen``: :class:`OffscreenRenderer`
  (OSMesa) and :func:`save_png`; ``gl``: the lazily imported PyOpenGL and platform choice.

None of them imports Qt, and ``OpenGL.GL`` is imported only when something is drawn,
so :func:`require_osmesa_platform` can still choose PyOpenGL's platform after import.
"""
from __future__ import annotations

from robot_sim.graphics.camera import Camera
from robot_sim.graphics.font import text_size
from robot_sim.graphics.framing import annotation_points, visible_points
from robot_sim.graphics.gl import require_osmesa_platform
from robot_sim.graphics.item import Item
from robot_sim.graphics.annotation_geometry import Annotation, dh_annotation
from robot_sim.graphics.items.color_scale import ColorScale, color_scale_layout
from robot_sim.graphics.label_layout import LabelPlacement, place_labels
from robot_sim.graphics.workspace import WorkspaceCloud, colormap
from robot_sim.graphics.floor_grid import FloorGrid
from robot_sim.graphics.frame_axes import axis_lengths, frame_labels, frames_and_names
from robot_sim.graphics.looks import LOOKS, look_for, looks_of
from robot_sim.graphics.offscreen import OffscreenRenderer, save_png
from robot_sim.graphics.render import View, item_classes
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
from robot_sim.graphics.scene import RGBA, GraphicsOptions, Scene, Vector
from robot_sim.graphics.solid import solid_parts
from robot_sim.graphics.themes import DEFAULT_THEME, THEMES, Theme

__all__ = [
    "Annotation", "Camera", "ColorScale", "DHSegments", "LabelPlacement", "FloorGrid", "GraphicsOptions", "Item", "LOOKS", "OffscreenRenderer",
    "DEFAULT_THEME", "Part", "RGBA", "RobotLook", "Scene", "THEMES", "Theme", "Vector", "View", "WorkspaceCloud",
    "annotation_points", "axis_lengths", "color_scale_layout", "colormap", "dh_annotation", "dh_segments", "differing", "frame_labels",
    "frames_and_names", "item_classes", "look_for", "looks_of", "part_corners", "place_labels", "require_osmesa_platform",
    "robot_look", "robot_parts", "robot_reach", "save_png", "solid_parts", "text_size", "visible_points",
]
