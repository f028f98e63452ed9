"""The viewer's drawables: ground, coordinate axes, arrows, the IK target and the robot.

Each is a :class:`_gfx_resources.Drawable`: it holds what it shows, owns its GL objects
and paints itself inside a named GL state preset.  Poses and points are in the world
frame (z up, metres).  Part sizes follow the robot's reach (:func:`robot_reach`).
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

import graphics_defs as gd
from _gfx_gl import GL, along, call_list_at, client_arrays, compile_list, disable_client_arrays, set_color, spheres
from _gfx_resources import Drawable, resources
from _gfx_scene import RGBA, Vector
from kinematics import Kinematics
from robot_defs import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotParams
from transforms import HomogeneousTransform


@functools.lru_cache(maxsize=64)
def robot_reach(robot: RobotParams) -> float:
    """Characteristic size of ``robot`` in metres: the sum of |a| and |d| over its joints
    (a prismatic joint's d counted at its largest finite limit) plus the tool offset,
    clamped to [``REACH_MIN``, ``REACH_MAX``].  Part sizes are fractions of it.  Computed
    once per robot (parameters are immutable)."""
    stroke = np.where(np.isfinite(robot.q_max), np.abs(robot.q_max), np.abs(robot.q_home))
    d = np.abs(robot.dh_d) + np.where(robot.jtype == JTYPE_PRISMATIC, stroke, 0.0)
    total = float(np.sum(np.abs(robot.dh_a)) + np.sum(d) + np.linalg.norm(robot.endeff_tf.t()))
    return float(np.clip(total, gd.REACH_MIN, gd.REACH_MAX))


@dataclass
class RobotSizes:
    """Part sizes (metres) for a robot of ``reach`` metres, from the ``*_FRAC`` constants."""

    reach: float

    @property
    def link_radius(self) -> float:
        return self.reach * gd.LINK_RADIUS_FRAC

    @property
    def joint_radius(self) -> float:
        return self.reach * gd.JOINT_RADIUS_FRAC

    @property
    def joint_length(self) -> float:
        return self.reach * gd.JOINT_LENGTH_FRAC

    @property
    def frame_length(self) -> float:
        return self.reach * gd.FRAME_LENGTH_FRAC


def draw_arrows(origins: ArrayLike, vecs: ArrayLike, shaft_radius: float, head_radius: float, head_length: float) -> None:
    """Arrows (cylinder shaft + cone tip) from world ``origins`` (N, 3) to ``origins + vecs``
    in the current colour; a head is at most half its arrow.  Zero-length vectors draw
    nothing."""
    origins = np.asarray(origins, dtype=float).reshape(-1, 3)
    vecs = np.asarray(vecs, dtype=float).reshape(-1, 3)
    lengths = np.linalg.norm(vecs, axis=1)
    keep = lengths >= gd.MIN_LINK_LENGTH
    origins, vecs, lengths = origins[keep], vecs[keep], lengths[keep]
    heads = np.minimum(head_length, 0.5 * lengths)
    shaft_ends = origins + vecs * ((lengths - heads) / np.where(lengths > 0.0, lengths, 1.0))[:, None]
    lists = resources().lists
    call_list_at(lists["cylinder"], along(origins, vecs, shaft_radius, lengths - heads))
    call_list_at(lists["cone"], along(shaft_ends, vecs, head_radius, heads))


class AxesGraphics(Drawable):
    """RGB axes (x red, y green, z blue) with cone tips, ``length`` metres long, of the
    world poses ``frames`` (N, 4, 4)."""

    def __init__(self, length: float, frames: ArrayLike = np.zeros((0, 4, 4))) -> None:
        super().__init__()
        self.length = float(length)
        self.frames = np.asarray(frames, dtype=float).reshape(-1, 4, 4)

    def paint(self) -> None:
        for column, color in enumerate((gd.AXIS_X_COLOR, gd.AXIS_Y_COLOR, gd.AXIS_Z_COLOR)):
            set_color(color)
            draw_arrows(
                self.frames[:, :3, 3], self.frames[:, :3, column] * self.length,
                self.length * gd.FRAME_SHAFT_RADIUS_FRAC, self.length * gd.FRAME_HEAD_RADIUS_FRAC,
                self.length * gd.FRAME_HEAD_LENGTH_FRAC,
            )


class VectorGraphics(Drawable):
    """Arrows from a point along a world vector (1 m per unit), sized for a robot of
    ``reach`` metres: ``vectors`` holds (origin (3,), vector (3,), rgba) triples."""

    def __init__(self, reach: float, vectors: list[Vector] | None = None) -> None:
        super().__init__()
        self.reach = float(reach)
        self.vectors = list(vectors or [])

    def paint(self) -> None:
        for origin, vec, rgba in self.vectors:
            set_color(rgba)
            draw_arrows(
                origin, vec, self.reach * gd.VECTOR_SHAFT_RADIUS_FRAC,
                self.reach * gd.VECTOR_HEAD_RADIUS_FRAC, self.reach * gd.VECTOR_HEAD_LENGTH_FRAC,
            )


class TargetGraphics(Drawable):
    """The IK target: a small frame and a marker sphere at world pose ``tf``, yellow, or
    magenta when not ``reachable``; sized for a robot of ``reach`` metres."""

    def __init__(self, reach: float, tf: HomogeneousTransform, reachable: bool = True) -> None:
        super().__init__()
        self.reach, self.tf, self.reachable = float(reach), tf, reachable

    def paint(self) -> None:
        AxesGraphics(self.reach * gd.TARGET_FRAME_LENGTH_FRAC, self.tf.mat[None]).paint()
        set_color(gd.TARGET_COLOR if self.reachable else gd.TARGET_UNREACHABLE_COLOR)
        call_list_at(resources().lists["sphere"], spheres(self.tf.t(), self.reach * gd.TARGET_MARKER_RADIUS_FRAC))


class GroundGraphics(Drawable):
    """The ground plane z = 0: a square of ``half_extent`` metres around ``centre_xy``
    with grid lines every ``step`` metres on world-aligned lines, compiled into a display
    list once per GL context."""

    def __init__(self, half_extent: float, step: float, centre_xy: ArrayLike = (0.0, 0.0)) -> None:
        super().__init__()
        self.step = float(step)
        self.half_extent = math.ceil(half_extent / self.step) * self.step
        self.centre_xy = np.round(np.asarray(centre_xy, dtype=float).reshape(2) / self.step) * self.step

    @classmethod
    def for_reach(cls, reach: float, centre_xy: ArrayLike = (0.0, 0.0)) -> GroundGraphics:
        """Ground sized for a robot of ``reach`` metres standing at world ``centre_xy``."""
        half = reach * gd.GROUND_EXTENT_FRAC
        wanted = half / gd.GRID_LINES_PER_HALF
        step = next((s for s in gd.GRID_STEPS if s >= wanted), gd.GRID_STEPS[-1])
        return cls(half, step, centre_xy)

    def _build(self) -> None:
        (x0, y0), h = self.centre_xy, self.half_extent
        corners = np.array([[x0 - h, y0 - h, 0], [x0 + h, y0 - h, 0], [x0 + h, y0 + h, 0], [x0 - h, y0 + h, 0]])
        GL.glEnable(GL.GL_POLYGON_OFFSET_FILL)
        GL.glPolygonOffset(*gd.GROUND_POLYGON_OFFSET)
        set_color(gd.GROUND_COLOR)
        GL.glNormal3d(0.0, 0.0, 1.0)
        GL.glBegin(GL.GL_QUADS)
        for corner in corners:
            GL.glVertex3d(*corner)
        GL.glEnd()
        GL.glDisable(GL.GL_POLYGON_OFFSET_FILL)
        ticks = np.arange(-h, h + 0.5 * self.step, self.step)
        lines = np.zeros((len(ticks), 4, 3))
        lines[:, 0, :2] = np.c_[x0 + ticks, np.full_like(ticks, y0 - h)]
        lines[:, 1, :2] = np.c_[x0 + ticks, np.full_like(ticks, y0 + h)]
        lines[:, 2, :2] = np.c_[np.full_like(ticks, x0 - h), y0 + ticks]
        lines[:, 3, :2] = np.c_[np.full_like(ticks, x0 + h), y0 + ticks]
        GL.glDisable(GL.GL_LIGHTING)
        set_color(gd.GRID_COLOR)
        verts = np.ascontiguousarray(lines.reshape(-1, 3), dtype=np.float32)
        client_arrays(verts)
        GL.glDrawArrays(GL.GL_LINES, 0, len(verts))
        disable_client_arrays()

    def paint(self) -> None:
        GL.glCallList(self.gl.get(lambda: compile_list(self._build)))


@functools.lru_cache(maxsize=16)
def ground_for(reach: float, centre_x: float, centre_y: float) -> GroundGraphics:
    """The ground drawable for a robot of ``reach`` metres standing at world (x, y), kept
    (with its display lists) while robots at that place are shown."""
    return GroundGraphics.for_reach(reach, (centre_x, centre_y))


class RobotGraphics(Drawable):
    """The robot posed by ``kinematics`` (kept updated by its owner: world ``h_tf``,
    ``endeff_tf``, ``link_com``), as in the DH tutorial: links are light-grey cylinders
    between successive frame origins, revolute joints dark-grey closed cylinders along
    their axes, prismatic joints dark-grey boxes along theirs, the endeffector a red
    sphere and each link's centre of mass a small blue sphere.  A base above the ground
    (frame 0 at z > 0) stands on a grey pedestal.

    ``alpha`` < 1 or ``ghost`` draws translucent (blended without depth writes: draw it
    after the opaque parts); a ghost is drawn entirely in ``GHOST_COLOR``.
    """

    def __init__(self, kinematics: Kinematics, *, ghost: bool = False) -> None:
        super().__init__()
        self.kinematics = kinematics
        self.ghost = ghost
        self.alpha = 1.0
        robot = kinematics.robot
        self.sizes = RobotSizes(robot_reach(robot))
        self.revolute = robot.jtype == JTYPE_REVOLUTE
        self.joint_cylinder = np.diag([self.sizes.joint_radius, self.sizes.joint_radius, self.sizes.joint_length, 1.0])
        self.joint_cylinder[2, 3] = -0.5 * self.sizes.joint_length
        side, length = self.sizes.reach * gd.PRISMATIC_WIDTH_FRAC, self.sizes.reach * gd.PRISMATIC_LENGTH_FRAC
        self.prismatic_box = np.diag([side, side, length, 1.0])

    @property
    def gl_preset(self) -> str:  # type: ignore[override]
        return "translucent" if self.ghost or self.alpha < 1.0 else "opaque"

    def _color(self, rgba: RGBA) -> None:
        set_color(gd.GHOST_COLOR if self.ghost else rgba, 1.0 if self.ghost else self.alpha)

    def paint(self) -> None:
        kin, sizes, lists = self.kinematics, self.sizes, resources().lists
        frames = kin.frames
        origins = frames[:, :3, 3]
        endeff = kin.endeff_tf.t()
        if origins[0, 2] > 0.0:  # a raised base stands on a pedestal from the ground
            self._color(gd.PEDESTAL_COLOR)
            foot = origins[0] * (1.0, 1.0, 0.0)
            pedestal = along(foot[None], (origins[0] - foot)[None], sizes.reach * gd.PEDESTAL_RADIUS_FRAC, origins[0, 2])
            call_list_at(lists["joint"], pedestal)

        # links between successive frame origins, then the tool segment
        chain = np.vstack([origins, endeff])
        vecs = np.diff(chain, axis=0)
        lengths = np.linalg.norm(vecs, axis=1)
        keep = lengths >= gd.MIN_LINK_LENGTH
        self._color(gd.LINK_COLOR)
        call_list_at(lists["cylinder"], along(chain[:-1][keep], vecs[keep], sizes.link_radius, lengths[keep]))

        # joint i+1 sits at frame i along its z axis: revolute a closed cylinder centred
        # there, prismatic a box
        self._color(gd.JOINT_COLOR)
        call_list_at(lists["joint"], frames[:-1][self.revolute] @ self.joint_cylinder)
        call_list_at(lists["box"], frames[:-1][~self.revolute] @ self.prismatic_box)

        self._color(gd.ENDEFF_COLOR)
        call_list_at(lists["sphere"], spheres(endeff, sizes.reach * gd.ENDEFF_RADIUS_FRAC))
        self._color(gd.COM_COLOR)
        call_list_at(lists["sphere"], spheres(kin.link_com[1:], sizes.reach * gd.COM_RADIUS_FRAC))


def frame_poses(kinematics: Kinematics, show_frames: list[bool], show_endeff: bool) -> NDArray[np.float64]:
    """World poses (N, 4, 4) of the frames to draw: ``h_tf[i]`` for each ``show_frames[i]``
    (indices past the robot's frames ignored), then ``endeff_tf`` when ``show_endeff``."""
    shown = kinematics.frames[np.flatnonzero(show_frames[: len(kinematics.frames)])]
    if show_endeff:
        shown = np.concatenate([shown, kinematics.endeff_tf.mat[None]])
    return shown
