"""The viewer's drawables: ground, coordinate axes, arrows, the IK target and the robot.

Each is a :class:`robot_sim.graphics.resources.Drawable`: it holds what it shows, owns its GL objects
and paints itself inside a named GL state preset.  Poses and points are in the world
frame (z up, metres).  Part sizes follow the robot (``robot_sim.graphics.robot_parts.robot_look``).
"""
from __future__ import annotations

import functools
import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.gl import GL, along, call_list_at, compile_list, draw_arrays, set_color, spheres
from robot_sim.graphics.resources import Drawable, resources
from robot_sim.graphics.robot_parts import Part, differing, robot_look, robot_parts
from robot_sim.graphics.scene import Vector
from robot_sim.kinematics import Kinematics
from robot_sim.transforms import HomogeneousTransform


def draw_arrows(origins: ArrayLike, vecs: ArrayLike, shaft_radius: ArrayLike, head_radius: ArrayLike,
                head_length: ArrayLike) -> None:
    """Arrows (cylinder shaft + cone tip) from world ``origins`` (N, 3) to ``origins + vecs``
    in the current colour, sizes scalars or (N,); a head is at most half its arrow.
    Zero-length vectors draw nothing."""
    origins = np.asarray(origins, dtype=float).reshape(-1, 3)
    vecs = np.asarray(vecs, dtype=float).reshape(-1, 3)
    n = len(origins)
    shaft, head_r, head_l = (np.broadcast_to(np.asarray(v, dtype=float), (n,)) for v in (shaft_radius, head_radius, head_length))
    lengths = np.linalg.norm(vecs, axis=1)
    keep = lengths >= gd.MIN_LINK_LENGTH
    origins, vecs, lengths, shaft, head_r, head_l = (v[keep] for v in (origins, vecs, lengths, shaft, head_r, head_l))
    heads = np.minimum(head_l, 0.5 * lengths)
    shaft_ends = origins + vecs * ((lengths - heads) / np.where(lengths > 0.0, lengths, 1.0))[:, None]
    lists = resources().lists
    call_list_at(lists["cylinder"], along(origins, vecs, shaft, lengths - heads))
    call_list_at(lists["cone"], along(shaft_ends, vecs, head_r, heads))


def stack_ranks(origins: NDArray[np.float64], tol: float) -> NDArray[np.int64]:
    """For each of ``origins`` (N, 3), how many earlier ones lie within ``tol`` of it."""
    gaps = np.linalg.norm(origins[:, None] - origins[None], axis=-1) <= tol
    return np.tril(gaps, k=-1).sum(axis=1)


class AxesGraphics(Drawable):
    """RGB axes (x red, y green, z blue) with cone tips, ``length`` metres long, of the
    world poses ``frames`` (N, 4, 4).

    Where axes coincide nothing z-fights: a frame sharing its origin with k earlier
    ones is drawn ``1 + k * FRAME_STACK_LENGTH_STEP`` times longer and thinner (its tips
    show beyond the others), and shaft radii differ slightly from frame to frame
    (``FRAME_STACK_RADIUS_STEPS``) so axes lying along one line never share a surface.
    """

    def __init__(self, length: float, frames: ArrayLike = np.zeros((0, 4, 4))) -> None:
        super().__init__()
        self.length = float(length)
        self.frames = np.asarray(frames, dtype=float).reshape(-1, 4, 4)

    def lengths(self) -> NDArray[np.float64]:
        """Axis length (N,) of each frame, metres."""
        ranks = stack_ranks(self.frames[:, :3, 3], gd.MIN_LINK_LENGTH)
        return self.length * (1.0 + gd.FRAME_STACK_LENGTH_STEP * ranks)

    def paint(self) -> None:
        lengths = self.lengths()
        steps = np.asarray(gd.FRAME_STACK_RADIUS_STEPS)
        ranks = np.rint((lengths / self.length - 1.0) / gd.FRAME_STACK_LENGTH_STEP).astype(int)
        thin = steps[np.arange(len(lengths)) % len(steps)] * np.maximum(1.0 - gd.FRAME_STACK_THINNING * ranks, 0.4)
        for column, color in enumerate((gd.AXIS_X_COLOR, gd.AXIS_Y_COLOR, gd.AXIS_Z_COLOR)):
            set_color(color)
            draw_arrows(
                self.frames[:, :3, 3], self.frames[:, :3, column] * lengths[:, None],
                self.length * gd.FRAME_SHAFT_RADIUS_FRAC * thin, self.length * gd.FRAME_HEAD_RADIUS_FRAC * thin,
                lengths * gd.FRAME_HEAD_LENGTH_FRAC,
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
    """The floor z = 0 that the arm can pass through: a translucent square of
    ``half_extent`` metres around ``centre_xy`` with grid lines every ``step`` metres on
    world-aligned lines, blended without depth writes (draw it after the opaque parts:
    parts below the floor show through it), compiled into a display list once per GL
    context."""

    gl_preset = "translucent"

    def __init__(self, half_extent: float, step: float, centre_xy: ArrayLike = (0.0, 0.0)) -> None:
        super().__init__()
        self.step = float(step)
        self.half_extent = math.ceil(half_extent / self.step) * self.step
        self.centre_xy = np.round(np.asarray(centre_xy, dtype=float).reshape(2) / self.step) * self.step

    @classmethod
    def for_reach(cls, reach: float, centre_xy: ArrayLike = (0.0, 0.0)) -> GroundGraphics:
        """Floor sized for a robot of ``reach`` metres standing at world ``centre_xy``."""
        half = reach * gd.GROUND_EXTENT_FRAC
        wanted = half / gd.GRID_LINES_PER_HALF
        step = next((s for s in gd.GRID_STEPS if s >= wanted), gd.GRID_STEPS[-1])
        return cls(half, step, centre_xy)

    def _build(self) -> None:
        (x0, y0), h = self.centre_xy, self.half_extent
        corners = np.array([[x0 - h, y0 - h, 0], [x0 + h, y0 - h, 0], [x0 + h, y0 + h, 0], [x0 - h, y0 + h, 0]])
        set_color(gd.GROUND_COLOR)
        GL.glNormal3d(0.0, 0.0, 1.0)
        GL.glBegin(GL.GL_QUADS)
        for corner in corners:
            GL.glVertex3d(*corner)
        GL.glEnd()
        ticks = np.arange(-h, h + 0.5 * self.step, self.step)
        lines = np.zeros((len(ticks), 4, 3))
        lines[:, 0, :2] = np.c_[x0 + ticks, np.full_like(ticks, y0 - h)]
        lines[:, 1, :2] = np.c_[x0 + ticks, np.full_like(ticks, y0 + h)]
        lines[:, 2, :2] = np.c_[np.full_like(ticks, x0 - h), y0 + ticks]
        lines[:, 3, :2] = np.c_[np.full_like(ticks, x0 + h), y0 + ticks]
        GL.glDisable(GL.GL_LIGHTING)
        set_color(gd.GRID_COLOR)
        draw_arrays(GL.GL_LINES, lines.reshape(-1, 3))

    def paint(self) -> None:
        GL.glCallList(self.gl.get(lambda: compile_list(self._build)))


@functools.lru_cache(maxsize=16)
def ground_for(reach: float, centre_x: float, centre_y: float) -> GroundGraphics:
    """The floor drawable for a robot of ``reach`` metres standing at world (x, y), kept
    (with its display lists) while robots at that place are shown."""
    return GroundGraphics.for_reach(reach, (centre_x, centre_y))


class RobotGraphics(Drawable):
    """The robot posed by ``kinematics`` (kept updated by its owner: world ``frames``,
    ``endeff_tf``, ``link_com``), drawn as it is built from its DH table
    (``robot_sim.graphics.robot_parts.robot_parts``): links as their DH segments in light grey, revolute
    joints as dark-grey cylinders on their axes, prismatic joints as a sleeve and a
    sliding rod, the endeffector a red sphere, with ``show_com`` each link's centre of
    mass a small blue sphere, a base plate under frame 0 and, for a raised base, a dashed line down to the
    floor.

    ``alpha`` < 1 draws translucent (blended without depth writes: draw it after the
    opaque parts).  A ``ghost`` (the desired state) is drawn in ``GHOST_COLOR`` and only
    where it differs from ``reference`` (the arm's RobotGraphics), behind any arm surface
    it touches, so it never recolours the arm.
    """

    def __init__(self, kinematics: Kinematics, *, ghost: bool = False) -> None:
        super().__init__()
        self.kinematics = kinematics
        self.ghost = ghost
        self.alpha = 1.0
        self.reference: RobotGraphics | None = None
        self.show_com = False
        self.endeff_marker = True  # False while the pick task draws a gripper at the tool
        self.look = robot_look(kinematics.robot)
        # (frames, show_com, parts): Kinematics.update assigns a new frames array, so the
        # parts are computed once per pose however often they are asked for
        self._posed: tuple[NDArray[np.float64], bool, list[Part]] | None = None

    @property
    def gl_preset(self) -> str:  # type: ignore[override]
        return "translucent" if self.ghost or self.alpha < 1.0 else "opaque"

    def posed_parts(self) -> list[Part]:
        """All parts of the current pose (``robot_parts``), computed once per pose."""
        kin = self.kinematics
        if self._posed is None or self._posed[0] is not kin.frames or self._posed[1] != self.show_com:
            parts = robot_parts(kin.robot, kin.frames, kin.endeff_tf.mat, kin.link_com if self.show_com else None)
            self._posed = (kin.frames, self.show_com, parts)
        return self._posed[2]

    def parts(self) -> list[Part]:
        """The parts drawn for the current pose (a ghost: those that differ from the
        reference's; without ``endeff_marker``: no endeffector sphere)."""
        parts = self.posed_parts()
        if self.ghost and self.reference is not None:
            parts = differing(parts, self.reference.posed_parts())
        if not self.endeff_marker:
            parts = [part for part in parts if part.color != gd.ENDEFF_COLOR]
        return parts

    def paint(self) -> None:
        lists = resources().lists
        if self.ghost:
            GL.glDepthFunc(GL.GL_LESS)
            GL.glEnable(GL.GL_POLYGON_OFFSET_FILL)
            GL.glPolygonOffset(*gd.GHOST_POLYGON_OFFSET)
        for part in self.parts():
            set_color(gd.GHOST_COLOR if self.ghost else part.color, 1.0 if self.ghost else self.alpha)
            call_list_at(lists[part.mesh], part.placements)
        base = self.kinematics.frames[0, :3, 3]
        if base[2] > 0.0 and not self.ghost:  # a raised base: a dashed line down to the floor
            GL.glDisable(GL.GL_LIGHTING)
            GL.glEnable(GL.GL_LINE_STIPPLE)
            GL.glLineStipple(*gd.BASE_LINE_STIPPLE)
            set_color(gd.BASE_COLOR, self.alpha)
            draw_arrays(GL.GL_LINES, np.array([base, base * (1.0, 1.0, 0.0)]))


def frame_poses(kinematics: Kinematics, show_frames: list[bool], show_endeff: bool) -> NDArray[np.float64]:
    """World poses (N, 4, 4) of the frames to draw: ``h_tf[i]`` for each ``show_frames[i]``
    (indices past the robot's frames ignored), then ``endeff_tf`` when ``show_endeff``."""
    return frames_and_names(kinematics, show_frames, show_endeff)[0]


def frames_and_names(kinematics: Kinematics, show_frames: list[bool],
                     show_endeff: bool) -> tuple[NDArray[np.float64], list[str]]:
    """The frames to draw (see :func:`frame_poses`) and their names: the DH frame number,
    "E" for the endeffector."""
    index = np.flatnonzero(show_frames[: len(kinematics.frames)])
    shown, names = kinematics.frames[index], [str(i) for i in index]
    if show_endeff:
        shown, names = np.concatenate([shown, kinematics.endeff_tf.mat[None]]), names + ["E"]
    return shown, names


def frame_labels(frames: NDArray[np.float64], names: list[str], lengths: NDArray[np.float64]) -> list[tuple[NDArray, str]]:
    """One label per distinct origin among ``frames`` (N, 4, 4): the names of the frames
    there joined by commas ("4,5"), anchored a little along the bisector of the x and y
    axes of the first one, at ``FRAME_LABEL_FRAC`` of its axis ``lengths`` (N,)."""
    labels: list[tuple[NDArray, str]] = []
    origins = frames[:, :3, 3]
    taken = np.zeros(len(frames), dtype=bool)
    for i in range(len(frames)):
        if taken[i]:
            continue
        here = np.linalg.norm(origins - origins[i], axis=1) <= gd.MIN_LINK_LENGTH
        taken |= here
        anchor = origins[i] + gd.FRAME_LABEL_FRAC * lengths[i] * (frames[i, :3, 0] + frames[i, :3, 1]) / np.sqrt(2.0)
        labels.append((anchor, ",".join(n for n, h in zip(names, here) if h)))
    return labels
