"""Drawing the robot with legacy (fixed-function) OpenGL: one render path for all hosts.

Everything here is in the world frame (z up, metres) unless a docstring says otherwise.
:func:`render_scene` is the only render path: the Qt GL widget calls it in ``paintGL``
and :class:`OffscreenRenderer` calls it in an OSMesa context for screenshots and tests.

Geometry is tessellated once per GL context into display lists of unit meshes
(cylinder, disk, sphere, cone, box) that each part scales and places with the
modelview matrix, so a frame issues a few calls per part and allocates no GL objects.
The workspace point cloud lives in a vertex buffer object uploaded once per context.

This module never imports Qt, and imports ``OpenGL.GL`` only when something is drawn,
so :func:`require_osmesa_platform` can still choose PyOpenGL's platform after import.
"""
from __future__ import annotations

import ctypes
import functools
import importlib
import math
import os
import struct
import sys
import weakref
import zlib
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

import graphics_defs as gd
from kinematics import Kinematics
from robot_defs import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotParams
from transforms import HomogeneousTransform, rotations_z_onto

RGBA = tuple[float, float, float, float]
Vector = tuple[ArrayLike, ArrayLike, RGBA]  # (origin (3,), vector (3,), rgba) in the world

_Z_AXIS = np.array([0.0, 0.0, 1.0])


class _LazyModule:
    """Stands for a module that is imported on first attribute access.

    PyOpenGL fixes its platform (GLX, EGL, OSMesa) when ``OpenGL.GL`` is first imported;
    deferring that import lets a host pick the platform after importing this module.
    Looked-up attributes are cached on the instance, so later lookups cost a dict access.
    """

    def __init__(self, name: str) -> None:
        self._name = name

    def __getattr__(self, attr: str) -> Any:
        module: ModuleType = importlib.import_module(self._name)
        value = getattr(module, attr)
        setattr(self, attr, value)
        return value


GL: Any = _LazyModule("OpenGL.GL")
# Unwrapped entry points.  PyOpenGL's gl*Pointer wrappers keep every array passed to
# them alive in per-context storage, which raises "no valid context" inside Qt's
# contexts once windows have been closed and reopened; the arrays here are consumed at
# once (display lists) or are VBO offsets, so nothing needs keeping.  The per-part
# matrix loads and list calls of a frame also skip the wrappers' argument conversion.
GL_RAW: Any = _LazyModule("OpenGL.raw.GL.VERSION.GL_1_1")
_DOUBLE_P = ctypes.POINTER(ctypes.c_double)


def require_osmesa_platform() -> None:
    """Make PyOpenGL use OSMesa (offscreen, no display) in this process.

    Sets ``PYOPENGL_PLATFORM=osmesa`` when PyOpenGL has not chosen a platform yet.
    Raises RuntimeError when it already has and the choice is not OSMesa: PyOpenGL
    cannot switch platforms, so offscreen rendering must run in its own process.
    """
    platform_module = sys.modules.get("OpenGL.platform")
    if platform_module is None:
        os.environ["PYOPENGL_PLATFORM"] = "osmesa"
        return
    chosen = type(platform_module.PLATFORM).__name__
    if chosen != "OSMesaPlatform":
        raise RuntimeError(
            f"PyOpenGL was already imported with the {chosen} platform; offscreen rendering "
            "needs OSMesa. Set PYOPENGL_PLATFORM=osmesa before anything imports OpenGL, "
            "or render offscreen in a separate process."
        )


# --------------------------------------------------------------------------- camera


@dataclass
class Camera:
    """Orbit camera looking at ``target`` from ``distance`` metres, world z up.

    The eye sits at ``target + distance * (cos(el) cos(az), cos(el) sin(az), sin(el))``
    with azimuth ``az`` measured about world z from +x and elevation ``el`` above the
    xy plane.  ``fov_deg`` is the vertical field of view.  :meth:`reset` returns to the
    values the camera was constructed with.
    """

    distance: float = gd.CAMERA_DISTANCE
    azimuth_deg: float = gd.CAMERA_AZIMUTH_DEG
    elevation_deg: float = gd.CAMERA_ELEVATION_DEG
    target: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3))
    fov_deg: float = gd.CAMERA_FOV_DEG
    _home: tuple[float, float, float, NDArray[np.float64], float] = field(
        init=False, repr=False, compare=False
    )

    def __post_init__(self) -> None:
        self.target = np.array(self.target, dtype=float).reshape(3)
        self.distance = float(np.clip(self.distance, gd.CAMERA_MIN_DISTANCE, gd.CAMERA_MAX_DISTANCE))
        self.elevation_deg = self._clamp_elevation(self.elevation_deg)
        self._home = (self.distance, self.azimuth_deg, self.elevation_deg, self.target.copy(), self.fov_deg)

    @staticmethod
    def _clamp_elevation(elevation_deg: float) -> float:
        limit = gd.CAMERA_MAX_ELEVATION_DEG
        return float(np.clip(elevation_deg, -limit, limit))

    def reset(self) -> None:
        """Return to the distance, angles, target and field of view given at construction."""
        distance, azimuth, elevation, target, fov = self._home
        self.distance, self.azimuth_deg, self.elevation_deg, self.fov_deg = distance, azimuth, elevation, fov
        self.target = target.copy()

    def orbit(self, d_az_deg: float, d_el_deg: float) -> None:
        """Turn the eye about the target: azimuth wraps to [-180, 180), elevation is
        clamped to ±``CAMERA_MAX_ELEVATION_DEG`` (short of the poles)."""
        self.azimuth_deg = (self.azimuth_deg + d_az_deg + 180.0) % 360.0 - 180.0
        self.elevation_deg = self._clamp_elevation(self.elevation_deg + d_el_deg)

    def zoom(self, factor: float) -> None:
        """Multiply the distance by ``factor`` (< 1 moves closer, > 1 farther), clamped to
        [``CAMERA_MIN_DISTANCE``, ``CAMERA_MAX_DISTANCE``] metres.  Non-positive or
        non-finite factors are ignored."""
        if factor > 0.0 and math.isfinite(factor):
            self.distance = float(
                np.clip(self.distance * factor, gd.CAMERA_MIN_DISTANCE, gd.CAMERA_MAX_DISTANCE)
            )

    def eye(self) -> NDArray[np.float64]:
        """Eye position (3,) in the world, metres."""
        az, el = np.radians(self.azimuth_deg), np.radians(self.elevation_deg)
        direction = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
        return self.target + self.distance * direction

    def view_plane_axes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """World unit vectors (3,) pointing right and up on the screen."""
        forward = self.target - self.eye()
        forward /= np.linalg.norm(forward)
        right = np.cross(forward, _Z_AXIS)
        right /= np.linalg.norm(right)
        return right, np.cross(right, forward)

    def world_per_pixel(self, height: int) -> float:
        """Metres per pixel in the plane through the target facing the camera, for a
        viewport ``height`` pixels tall."""
        return 2.0 * self.distance * math.tan(math.radians(self.fov_deg) / 2.0) / max(int(height), 1)

    def pan(self, dx_px: float, dy_px: float, viewport_height: int) -> None:
        """Move the target in the view plane so the scene follows a mouse drag of
        (``dx_px`` right, ``dy_px`` down) pixels in a viewport ``viewport_height`` tall."""
        right, up = self.view_plane_axes()
        scale = self.world_per_pixel(viewport_height)
        self.target = self.target + scale * (-dx_px * right + dy_px * up)

    def fit(self, points: ArrayLike, aspect: float = 1.0) -> None:
        """Aim at the centre of the bounding box of ``points`` (N, 3) (world, metres) and
        set the distance so the sphere around them fits the field of view of a viewport
        ``aspect`` = width / height: the vertical one, or the horizontal one when the
        viewport is taller than wide.  Non-finite rows are ignored; with no finite point
        nothing changes."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        if len(pts) == 0:
            return
        centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
        radius = max(float(np.max(np.linalg.norm(pts - centre, axis=1))), gd.CAMERA_FIT_MIN_RADIUS)
        half_fov = math.radians(self.fov_deg) / 2.0
        half_fov = min(half_fov, math.atan(math.tan(half_fov) * max(aspect, 1e-3)))
        self.target = centre
        self.distance = float(
            np.clip(gd.CAMERA_FIT_MARGIN * radius / math.sin(half_fov), gd.CAMERA_MIN_DISTANCE, gd.CAMERA_MAX_DISTANCE)
        )

    def view_matrix(self) -> NDArray[np.float64]:
        """World -> eye transform (4, 4) (OpenGL eye space: x right, y up, looking down -z)."""
        eye = self.eye()
        right, up = self.view_plane_axes()
        back = np.cross(right, up)
        view = np.eye(4)
        view[0, :3], view[1, :3], view[2, :3] = right, up, back
        view[:3, 3] = -view[:3, :3] @ eye
        return view

    def projection_matrix(self, aspect: float) -> NDArray[np.float64]:
        """Perspective projection (4, 4) eye -> clip for ``aspect`` = width / height.

        Near and far planes follow the distance (``CAMERA_NEAR_FRAC``, ``CAMERA_FAR_FRAC``,
        ``CAMERA_FAR_MARGIN``) so depth precision stays good at any zoom."""
        near = self.distance * gd.CAMERA_NEAR_FRAC
        far = self.distance * gd.CAMERA_FAR_FRAC + gd.CAMERA_FAR_MARGIN
        f = 1.0 / math.tan(math.radians(self.fov_deg) / 2.0)
        proj = np.zeros((4, 4))
        proj[0, 0] = f / max(aspect, 1e-9)
        proj[1, 1] = f
        proj[2, 2] = (far + near) / (near - far)
        proj[2, 3] = 2.0 * far * near / (near - far)
        proj[3, 2] = -1.0
        return proj

    def project(self, points: ArrayLike, width: int, height: int) -> NDArray[np.float64]:
        """Pixel coordinates (N, 2) of world ``points`` (N, 3) in a ``width`` x ``height`` image.

        x grows to the right, y downwards from the top row; integer values are pixel
        centres, so ``image[round(y), round(x)]`` is the pixel a point lands on.  Uses the
        same matrices as :func:`render_scene`.  Points behind the eye give NaN.
        """
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        clip = np.c_[pts, np.ones(len(pts))] @ (self.projection_matrix(width / height) @ self.view_matrix()).T
        w = clip[:, 3]
        with np.errstate(divide="ignore", invalid="ignore"):
            ndc = clip[:, :2] / w[:, None]
        pixels = np.empty((len(pts), 2))
        pixels[:, 0] = (ndc[:, 0] + 1.0) * 0.5 * width - 0.5
        pixels[:, 1] = (1.0 - ndc[:, 1]) * 0.5 * height - 0.5
        pixels[w <= 0.0] = np.nan
        return pixels


# -------------------------------------------------------------------------- options


class GraphicsOptions:
    """What the viewer shows; hosts flip these from keys, the renderer only reads them.

    ``show_frames[i]`` shows frame i (``h_tf[i]``) for i in 0..n_frames-1, with
    ``n_frames = n_dofs + 1``; the base frame (index 0) starts shown, the others hidden.
    The endeffector (tool) frame ``endeff_tf`` has its own flag ``show_endeff_frame``
    so frame indices stay equal to DH frame numbers.
    """

    def __init__(self, n_frames: int) -> None:
        if int(n_frames) < 1:
            raise ValueError(f"GraphicsOptions: n_frames must be >= 1 (frames 0..n_dofs), got {n_frames}")
        self.wireframe: bool = False
        self.alpha: float = 1.0
        self.show_frames: list[bool] = [True] + [False] * (int(n_frames) - 1)
        self.show_endeff_frame: bool = False
        self.show_vectors: bool = True
        self.show_workspace: bool = False
        self.show_ghost: bool = True
        self.show_target: bool = True

    @property
    def n_frames(self) -> int:
        """Number of DH frames that can be toggled (frames 0..n_frames-1)."""
        return len(self.show_frames)

    def toggle_frame(self, i: int) -> bool:
        """Flip frame ``i``'s visibility.  Returns True when ``i`` is a frame index
        (0..n_frames-1) and was flipped; False, changing nothing, otherwise."""
        if not isinstance(i, (int, np.integer)) or not 0 <= i < len(self.show_frames):
            return False
        self.show_frames[i] = not self.show_frames[i]
        return True

    def toggle_endeff_frame(self) -> bool:
        """Flip the endeffector frame's visibility; returns the new state."""
        self.show_endeff_frame = not self.show_endeff_frame
        return self.show_endeff_frame

    def toggle_all_frames(self) -> None:
        """Show every frame (DH frames and endeffector) unless all are shown already,
        in which case hide all but the base frame."""
        show = not (all(self.show_frames) and self.show_endeff_frame)
        self.show_frames = [True] + [show] * (len(self.show_frames) - 1)
        self.show_endeff_frame = show

    def toggle_wireframe(self) -> bool:
        """Flip wireframe drawing of the robot; returns the new state."""
        self.wireframe = not self.wireframe
        return self.wireframe

    def toggle_alpha(self) -> float:
        """Switch the robot between opaque (1.0) and ``TRANSLUCENT_ALPHA``; returns the alpha."""
        self.alpha = gd.TRANSLUCENT_ALPHA if self.alpha >= 1.0 else 1.0
        return self.alpha


# ----------------------------------------------------------------- unit meshes


def _ring(slices: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Cosines and sines (slices + 1,) of angles 0..2π, first and last equal."""
    angles = np.linspace(0.0, 2.0 * np.pi, slices + 1)
    return np.cos(angles), np.sin(angles)


def _quads_to_triangles(a: NDArray, b: NDArray, c: NDArray, d: NDArray) -> NDArray:
    """Triangles (2M, 3, k) of quads with corners a, b, c, d (each (M, k)) in order."""
    return np.concatenate([np.stack([a, b, c], axis=1), np.stack([a, c, d], axis=1)])


def _cylinder_mesh(slices: int) -> tuple[NDArray, NDArray]:
    """Side of the unit cylinder: radius 1, z from 0 to 1, smooth radial normals."""
    c, s = _ring(slices)
    rim = np.c_[c, s, np.zeros_like(c)]
    bottom, top = rim, rim + _Z_AXIS
    verts = _quads_to_triangles(bottom[:-1], bottom[1:], top[1:], top[:-1])
    normals = _quads_to_triangles(rim[:-1], rim[1:], rim[1:], rim[:-1])
    return verts, normals


def _disk_mesh(slices: int, z: float, facing: float) -> tuple[NDArray, NDArray]:
    """Unit disk at height ``z`` with its normal along ``facing`` * z (``facing`` = ±1)."""
    c, s = _ring(slices)
    rim = np.c_[c, s, np.full_like(c, z)]
    centre = np.tile([0.0, 0.0, z], (slices, 1))
    verts = np.stack([centre, rim[:-1], rim[1:]], axis=1)
    normals = np.broadcast_to([0.0, 0.0, facing], verts.shape)
    return verts, normals


def _cone_mesh(slices: int) -> tuple[NDArray, NDArray]:
    """Unit cone: base disk of radius 1 at z = 0 (facing -z), apex at z = 1."""
    c, s = _ring(slices)
    rim = np.c_[c, s, np.zeros_like(c)]
    slant = np.c_[c, s, np.ones_like(c)] / math.sqrt(2.0)
    mid = 0.5 * (slant[:-1] + slant[1:])
    apex = np.tile(_Z_AXIS, (slices, 1))
    side_v = np.stack([rim[:-1], rim[1:], apex], axis=1)
    side_n = np.stack([slant[:-1], slant[1:], mid], axis=1)
    base_v, base_n = _disk_mesh(slices, 0.0, -1.0)
    return np.concatenate([side_v, base_v]), np.concatenate([side_n, base_n])


def _sphere_mesh(slices: int, stacks: int) -> tuple[NDArray, NDArray]:
    """Unit sphere centred at the origin; normals equal positions."""
    c, s = _ring(slices)
    polar = np.linspace(0.0, np.pi, stacks + 1)
    ring_z, ring_r = np.cos(polar), np.sin(polar)
    grid = np.stack(
        [ring_r[:, None] * c[None, :], ring_r[:, None] * s[None, :], np.repeat(ring_z[:, None], slices + 1, 1)],
        axis=-1,
    )  # (stacks + 1, slices + 1, 3)
    a, b = grid[:-1, :-1].reshape(-1, 3), grid[1:, :-1].reshape(-1, 3)
    cc, d = grid[1:, 1:].reshape(-1, 3), grid[:-1, 1:].reshape(-1, 3)
    verts = _quads_to_triangles(a, b, cc, d)
    return verts, verts


def _box_mesh() -> tuple[NDArray, NDArray]:
    """Unit cube centred at the origin (sides from -0.5 to 0.5), flat face normals."""
    verts, normals = [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, v = np.eye(3)[(axis + 1) % 3], np.eye(3)[(axis + 2) % 3]
            n = sign * np.eye(3)[axis]
            corners = 0.5 * np.array([n - u - v, n + u - v, n + u + v, n - u + v])
            verts.append(corners[[0, 1, 2, 0, 2, 3]].reshape(2, 3, 3))
            normals.append(np.broadcast_to(n, (2, 3, 3)))
    return np.concatenate(verts), np.concatenate(normals)


def _unit_meshes() -> dict[str, tuple[NDArray, NDArray]]:
    """All unit meshes as triangle vertex and normal arrays (M, 3, 3)."""
    n = gd.CYLINDER_SLICES
    side = _cylinder_mesh(n)
    top, bottom = _disk_mesh(n, 1.0, 1.0), _disk_mesh(n, 0.0, -1.0)
    return {
        "cylinder": side,
        # A revolute joint: the cylinder closed by disks at both ends.
        "joint": tuple(np.concatenate(parts) for parts in zip(side, top, bottom)),  # type: ignore[dict-item]
        "cone": _cone_mesh(n),
        "sphere": _sphere_mesh(gd.SPHERE_SLICES, gd.SPHERE_STACKS),
        "box": _box_mesh(),
    }


def _pointer(data: NDArray | ctypes.c_void_p) -> ctypes.c_void_p:
    """Address of a contiguous array, or a VBO byte offset passed through."""
    return data if isinstance(data, ctypes.c_void_p) else ctypes.c_void_p(data.ctypes.data)


def _client_arrays(
    vertices: NDArray | ctypes.c_void_p,
    colors: NDArray | ctypes.c_void_p | None = None,
    normals: NDArray | None = None,
) -> None:
    """Point the fixed-function client arrays at contiguous float32 ``vertices`` (and
    optional float32 normals, uint8 RGBA colours) and enable them; when a VBO is bound
    the arguments are byte offsets.  The arrays must outlive the draw call."""
    GL.glEnableClientState(GL.GL_VERTEX_ARRAY)
    GL_RAW.glVertexPointer(3, GL.GL_FLOAT, 0, _pointer(vertices))
    if normals is not None:
        GL.glEnableClientState(GL.GL_NORMAL_ARRAY)
        GL_RAW.glNormalPointer(GL.GL_FLOAT, 0, _pointer(normals))
    if colors is not None:
        GL.glEnableClientState(GL.GL_COLOR_ARRAY)
        GL_RAW.glColorPointer(4, GL.GL_UNSIGNED_BYTE, 0, _pointer(colors))


def _disable_client_arrays() -> None:
    for state in (GL.GL_VERTEX_ARRAY, GL.GL_NORMAL_ARRAY, GL.GL_COLOR_ARRAY):
        GL.glDisableClientState(state)


def _compile_list(mode: int, vertices: NDArray, normals: NDArray | None = None) -> int:
    """A display list drawing ``vertices`` (and normals) as primitives of ``mode``."""
    verts = np.ascontiguousarray(vertices, dtype=np.float32).reshape(-1, 3)
    norms = None if normals is None else np.ascontiguousarray(normals, dtype=np.float32).reshape(-1, 3)
    GL.glBindBuffer(GL.GL_ARRAY_BUFFER, 0)
    _client_arrays(verts, normals=norms)
    list_id = GL.glGenLists(1)
    GL.glNewList(list_id, GL.GL_COMPILE)
    GL.glDrawArrays(mode, 0, len(verts))
    GL.glEndList()
    _disable_client_arrays()
    return int(list_id)


class _ContextResources:
    """GL objects of one context: unit-mesh display lists, ground lists, cloud VBOs."""

    def __init__(self) -> None:
        self.lists = {name: _compile_list(GL.GL_TRIANGLES, v, n) for name, (v, n) in _unit_meshes().items()}
        self._ground_lists: dict[tuple[float, ...], int] = {}
        self._cloud_buffers: dict[int, int] = {}
        self._dead_buffers: list[int] = []
        # the cloud's picture for one view: (view key, RGBA bytes, depth floats), and the
        # view of the last frame that drew the cloud; see _draw_cloud_layer
        self.cloud_layer: tuple[tuple[Any, ...], NDArray, NDArray] | None = None
        self.cloud_view: tuple[Any, ...] | None = None

    def valid(self) -> bool:
        """True while the current context still holds these objects (a context created
        at a reused address has none of them)."""
        return bool(GL.glIsList(self.lists["sphere"]))

    def ground_list(self, key: tuple[float, ...], build: Any) -> int:
        """Display list for ground parameters ``key``, compiled by ``build()`` once."""
        if key not in self._ground_lists:
            list_id = GL.glGenLists(1)
            GL.glNewList(list_id, GL.GL_COMPILE)
            build()
            GL.glEndList()
            self._ground_lists[key] = int(list_id)
        return self._ground_lists[key]

    def cloud_buffer(self, cloud: WorkspaceCloud) -> int:
        """VBO holding ``cloud``'s positions then colours, uploaded on first use; freed
        (at the next frame in this context) once the cloud is garbage-collected."""
        key = id(cloud)
        buffer = self._cloud_buffers.get(key)
        if buffer is None:
            buffer = int(GL.glGenBuffers(1))
            GL.glBindBuffer(GL.GL_ARRAY_BUFFER, buffer)
            data = np.concatenate([cloud.points.view(np.uint8).ravel(), cloud.colors.ravel()])
            GL.glBufferData(GL.GL_ARRAY_BUFFER, data.nbytes, data, GL.GL_STATIC_DRAW)
            self._cloud_buffers[key] = buffer
            weakref.finalize(cloud, self._forget_cloud, key)
        return buffer

    def _forget_cloud(self, key: int) -> None:
        buffer = self._cloud_buffers.pop(key, None)
        if buffer is not None:
            self._dead_buffers.append(buffer)
        if self.cloud_layer is not None and self.cloud_layer[0][0] == key:
            self.cloud_layer = None

    def free_dead(self) -> None:
        """Delete buffers of collected clouds (the context must be current)."""
        if self._dead_buffers:
            GL.glDeleteBuffers(len(self._dead_buffers), np.array(self._dead_buffers, dtype=np.uint32))
            self._dead_buffers.clear()


_RESOURCES: dict[int, _ContextResources] = {}


def _context_key() -> int:
    """Address of the current GL context (0 when the platform cannot tell)."""
    from OpenGL import contextdata, error

    try:
        context = contextdata.getContext()
    except error.Error:
        return 0
    if isinstance(context, int):
        return context
    return int(ctypes.cast(context, ctypes.c_void_p).value or 0)


def _resources() -> _ContextResources:
    """The current context's resources, built on first use or after the context changed."""
    key = _context_key()
    resources = _RESOURCES.get(key)
    if resources is None or not resources.valid():
        resources = _RESOURCES[key] = _ContextResources()
    return resources


# --------------------------------------------------------------------- drawables


@functools.lru_cache(maxsize=64)
def robot_reach(robot: RobotParams) -> float:
    """Characteristic size of ``robot`` in metres: the sum of |a| and |d| over its joints
    (a prismatic joint's d counted at its largest finite limit) plus the tool offset,
    clamped to [``REACH_MIN``, ``REACH_MAX``].  Part sizes are fractions of it.  Computed
    once per robot (parameters are immutable), not on each of a frame's three uses."""
    stroke = np.where(np.isfinite(robot.q_max), np.abs(robot.q_max), np.abs(robot.q_home))
    d = np.abs(robot.dh_d) + np.where(robot.jtype == JTYPE_PRISMATIC, stroke, 0.0)
    total = float(np.sum(np.abs(robot.dh_a)) + np.sum(d) + np.linalg.norm(robot.endeff_tf.t()))
    return float(np.clip(total, gd.REACH_MIN, gd.REACH_MAX))


def _set_color(rgba: Sequence[float], alpha: float = 1.0) -> None:
    GL.glColor4f(rgba[0], rgba[1], rgba[2], rgba[3] * alpha)


def _gl_matrix(mat: NDArray[np.float64]) -> NDArray[np.float64]:
    """A row-major (4, 4) matrix laid out column-major as glLoadMatrix/glMultMatrix want."""
    return np.ascontiguousarray(np.asarray(mat, dtype=np.float64).T)


def _along(origins: ArrayLike, vecs: ArrayLike, radii: ArrayLike, lengths: ArrayLike) -> NDArray[np.float64]:
    """World placements (N, 4, 4) of unit meshes modelled along +z from 0 to 1 with radius
    1: scaled to ``radii`` across and ``lengths`` along, starting at ``origins`` (N, 3)
    and pointing along ``vecs`` (N, 3)."""
    rot = rotations_z_onto(vecs)
    n = len(rot)
    mats = np.zeros((n, 4, 4))
    mats[:, :3, :3] = rot * np.stack(np.broadcast_arrays(radii, radii, lengths), axis=-1).reshape(n, 1, 3)
    mats[:, :3, 3] = origins
    mats[:, 3, 3] = 1.0
    return mats


def _spheres(centres: ArrayLike, radius: float) -> NDArray[np.float64]:
    """World placements (N, 4, 4) of the unit sphere scaled to ``radius`` at ``centres``."""
    centres = np.asarray(centres, dtype=float).reshape(-1, 3)
    mats = np.zeros((len(centres), 4, 4))
    mats[:, [0, 1, 2], [0, 1, 2]] = radius
    mats[:, :3, 3] = centres
    mats[:, 3, 3] = 1.0
    return mats


def _call_list_at(list_id: int, placements: NDArray[np.float64]) -> None:
    """Draw display list ``list_id`` once per world placement (N, 4, 4): one matrix load
    and one call each (PyOpenGL's per-call cost dominates these frames), composed with
    the current modelview (the camera's view)."""
    if len(placements) == 0:
        return
    view = np.asarray(GL.glGetDoublev(GL.GL_MODELVIEW_MATRIX), dtype=np.float64).reshape(4, 4)
    for mat in np.ascontiguousarray(np.swapaxes(view.T @ placements, 1, 2)):
        GL_RAW.glLoadMatrixd(mat.ctypes.data_as(_DOUBLE_P))
        GL_RAW.glCallList(list_id)
    GL.glLoadMatrixd(view)


def _draw_arrows(
    resources: _ContextResources, origins: ArrayLike, vecs: ArrayLike, shaft_radius: float, head_radius: float,
    head_length: float,
) -> None:
    """Arrows (cylinder shaft + cone tip) from world ``origins`` (N, 3) to ``origins + vecs``;
    a head is at most half its arrow.  Zero-length vectors draw nothing."""
    origins = np.asarray(origins, dtype=float).reshape(-1, 3)
    vecs = np.asarray(vecs, dtype=float).reshape(-1, 3)
    lengths = np.linalg.norm(vecs, axis=1)
    keep = lengths >= gd.MIN_LINK_LENGTH
    origins, vecs, lengths = origins[keep], vecs[keep], lengths[keep]
    heads = np.minimum(head_length, 0.5 * lengths)
    shaft_ends = origins + vecs * ((lengths - heads) / np.where(lengths > 0.0, lengths, 1.0))[:, None]
    _call_list_at(resources.lists["cylinder"], _along(origins, vecs, shaft_radius, lengths - heads))
    _call_list_at(resources.lists["cone"], _along(shaft_ends, vecs, head_radius, heads))


class AxesGraphics:
    """RGB axes of a frame (x red, y green, z blue) with cone tips, ``length`` metres long."""

    def __init__(self, length: float) -> None:
        self.length = float(length)

    def render(self, tf: HomogeneousTransform) -> None:
        """Draw the axes of frame ``tf`` (pose in the world)."""
        self.render_many(tf.mat[None])

    def render_many(self, frames: NDArray[np.float64]) -> None:
        """Draw the axes of every frame in ``frames`` (N, 4, 4) (poses in the world)."""
        resources = _resources()
        for column, color in enumerate((gd.AXIS_X_COLOR, gd.AXIS_Y_COLOR, gd.AXIS_Z_COLOR)):
            _set_color(color)
            _draw_arrows(
                resources, frames[:, :3, 3], frames[:, :3, column] * self.length,
                self.length * gd.FRAME_SHAFT_RADIUS_FRAC, self.length * gd.FRAME_HEAD_RADIUS_FRAC,
                self.length * gd.FRAME_HEAD_LENGTH_FRAC,
            )


class VectorGraphics:
    """Arrows from a point along a world vector, sized for a robot of ``reach`` metres."""

    def __init__(self, reach: float) -> None:
        self.reach = float(reach)

    def render(self, origin: ArrayLike, vec: ArrayLike, rgba: RGBA) -> None:
        """Draw ``vec`` (world, drawn at 1 m per unit) starting at world point ``origin``."""
        _set_color(rgba)
        _draw_arrows(
            _resources(), origin, vec, self.reach * gd.VECTOR_SHAFT_RADIUS_FRAC,
            self.reach * gd.VECTOR_HEAD_RADIUS_FRAC, self.reach * gd.VECTOR_HEAD_LENGTH_FRAC,
        )


class GroundGraphics:
    """The ground plane z = 0: a square of ``half_extent`` metres around ``centre_xy``
    with grid lines every ``step`` metres on world-aligned lines."""

    def __init__(self, half_extent: float, step: float, centre_xy: ArrayLike = (0.0, 0.0)) -> None:
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
        _set_color(gd.GROUND_COLOR)
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
        _set_color(gd.GRID_COLOR)
        verts = np.ascontiguousarray(lines.reshape(-1, 3), dtype=np.float32)
        _client_arrays(verts)
        GL.glDrawArrays(GL.GL_LINES, 0, len(verts))
        _disable_client_arrays()
        GL.glEnable(GL.GL_LIGHTING)

    def render(self) -> None:
        """Draw the plane and its grid (compiled into a display list once per context)."""
        key = (self.half_extent, self.step, *self.centre_xy)
        GL.glCallList(_resources().ground_list(key, self._build))


class WorkspaceCloud:
    """Points (N, 3) of a workspace (world, metres) coloured by ``values`` (N,)
    (e.g. height or manipulability) through ``WORKSPACE_COLORMAP``, min to max.

    Drawn with glDrawArrays from a VBO uploaded once per GL context."""

    def __init__(self, points: ArrayLike, values: ArrayLike) -> None:
        pts = np.asarray(points, dtype=float)
        vals = np.asarray(values, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise ValueError(f"WorkspaceCloud: points must have shape (N, 3), got {pts.shape}")
        if vals.shape != (len(pts),):
            raise ValueError(f"WorkspaceCloud: values must have shape ({len(pts)},), got {vals.shape}")
        self.points: NDArray[np.float32] = np.ascontiguousarray(pts, dtype=np.float32)
        self.values: NDArray[np.float64] = vals
        self.colors: NDArray[np.uint8] = colormap(vals)

    def __len__(self) -> int:
        return len(self.points)

    def render(self) -> None:
        """Draw the points (unlit, ``WORKSPACE_POINT_SIZE`` pixels)."""
        if len(self.points) == 0:
            return
        buffer = _resources().cloud_buffer(self)
        GL.glDisable(GL.GL_LIGHTING)
        GL.glPointSize(gd.WORKSPACE_POINT_SIZE)
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, buffer)
        _client_arrays(ctypes.c_void_p(0), colors=ctypes.c_void_p(self.points.nbytes))
        GL.glDrawArrays(GL.GL_POINTS, 0, len(self.points))
        _disable_client_arrays()
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, 0)
        GL.glEnable(GL.GL_LIGHTING)


def colormap(values: ArrayLike) -> NDArray[np.uint8]:
    """RGBA colours (N, 4) uint8 of ``values`` (N,) through ``WORKSPACE_COLORMAP``, scaled
    from the finite minimum (first stop) to the maximum (last stop); constant values take
    the middle colour, non-finite ones the first."""
    vals = np.asarray(values, dtype=float).ravel()
    finite = np.isfinite(vals)
    unit = np.zeros_like(vals)
    if finite.any():
        lo, hi = vals[finite].min(), vals[finite].max()
        unit[finite] = (vals[finite] - lo) / (hi - lo) if hi > lo else 0.5
    stops = np.asarray(gd.WORKSPACE_COLORMAP)
    rgba = np.full((len(vals), 4), 255, dtype=np.uint8)
    for channel in range(3):
        rgba[:, channel] = np.round(255.0 * np.interp(unit, stops[:, 0], stops[:, channel + 1]))
    return rgba


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


class RobotGraphics:
    """The robot as in the DH tutorial: links are light-grey cylinders between successive
    frame origins, revolute joints dark-grey closed cylinders along their axes, prismatic
    joints dark-grey boxes along theirs, the endeffector a red sphere and each link's
    centre of mass a small blue sphere.  A base above the ground (frame 0 at z > 0)
    stands on a grey pedestal."""

    def render(self, kinematics: Kinematics, options: GraphicsOptions, *, ghost: bool = False) -> None:
        """Draw the robot posed by ``kinematics`` (updated: world ``h_tf``, ``endeff_tf``,
        ``link_com``).  Translucent (``options.alpha`` < 1, or ``ghost``) drawing blends
        without writing depth, so call it after the opaque parts of the scene.  A ghost is
        drawn entirely in ``GHOST_COLOR``.  Wireframe follows ``options.wireframe``."""
        robot = kinematics.robot
        sizes = RobotSizes(robot_reach(robot))
        resources = _resources()
        alpha = 1.0 if ghost else float(options.alpha)
        translucent = ghost or alpha < 1.0

        def color(rgba: RGBA) -> None:
            _set_color(gd.GHOST_COLOR if ghost else rgba, alpha)

        if translucent:
            GL.glEnable(GL.GL_BLEND)
            GL.glDepthMask(GL.GL_FALSE)
        if options.wireframe:
            GL.glPolygonMode(GL.GL_FRONT_AND_BACK, GL.GL_LINE)

        frames = kinematics.frames
        origins = frames[:, :3, 3]
        endeff = kinematics.endeff_tf.t()
        if origins[0, 2] > 0.0:  # a raised base stands on a pedestal from the ground
            color(gd.PEDESTAL_COLOR)
            foot = origins[0] * (1.0, 1.0, 0.0)
            pedestal = _along(foot[None], (origins[0] - foot)[None], sizes.reach * gd.PEDESTAL_RADIUS_FRAC, origins[0, 2])
            _call_list_at(resources.lists["joint"], pedestal)

        # links between successive frame origins, then the tool segment
        chain = np.vstack([origins, endeff])
        vecs = np.diff(chain, axis=0)
        lengths = np.linalg.norm(vecs, axis=1)
        keep = lengths >= gd.MIN_LINK_LENGTH
        color(gd.LINK_COLOR)
        _call_list_at(resources.lists["cylinder"], _along(chain[:-1][keep], vecs[keep], sizes.link_radius, lengths[keep]))

        # joint i+1 sits at frame i along its z axis: revolute a closed cylinder centred
        # there, prismatic a box
        revolute = robot.jtype == JTYPE_REVOLUTE
        cylinder = np.diag([sizes.joint_radius, sizes.joint_radius, sizes.joint_length, 1.0])
        cylinder[2, 3] = -0.5 * sizes.joint_length
        width, length = sizes.reach * gd.PRISMATIC_WIDTH_FRAC, sizes.reach * gd.PRISMATIC_LENGTH_FRAC
        color(gd.JOINT_COLOR)
        _call_list_at(resources.lists["joint"], frames[:-1][revolute] @ cylinder)
        _call_list_at(resources.lists["box"], frames[:-1][~revolute] @ np.diag([width, width, length, 1.0]))

        color(gd.ENDEFF_COLOR)
        _call_list_at(resources.lists["sphere"], _spheres(endeff, sizes.reach * gd.ENDEFF_RADIUS_FRAC))
        color(gd.COM_COLOR)
        _call_list_at(resources.lists["sphere"], _spheres(kinematics.link_com[1:], sizes.reach * gd.COM_RADIUS_FRAC))

        GL.glPolygonMode(GL.GL_FRONT_AND_BACK, GL.GL_FILL)
        if translucent:
            GL.glDepthMask(GL.GL_TRUE)
            GL.glDisable(GL.GL_BLEND)

    def render_frames(self, kinematics: Kinematics, options: GraphicsOptions) -> None:
        """Draw the frames selected in ``options`` as RGB axes: ``h_tf[i]`` for each
        ``show_frames[i]`` (indices past the robot's frames are ignored) and
        ``endeff_tf`` when ``show_endeff_frame``."""
        axes = AxesGraphics(RobotSizes(robot_reach(kinematics.robot)).frame_length)
        shown = kinematics.frames[np.flatnonzero(options.show_frames[: len(kinematics.frames)])]
        if options.show_endeff_frame:
            shown = np.concatenate([shown, kinematics.endeff_tf.mat[None]])
        axes.render_many(shown)


# ------------------------------------------------------------------------- scene


@dataclass
class Scene:
    """What one frame shows; all poses in the world frame.

    ``kinematics``: the robot's current state (updated).  ``ghost``: the desired state,
    drawn translucent in ``GHOST_COLOR``, or None.  ``target_tf``: the IK target, drawn as
    a small frame and marker sphere, yellow, or magenta when ``target_reachable`` is
    False.  ``vectors``: arrows (origin (3,), vector (3,), rgba), 1 m per unit.
    ``workspace``: a point cloud or None.
    """

    kinematics: Kinematics
    ghost: Kinematics | None = None
    target_tf: HomogeneousTransform | None = None
    target_reachable: bool = True
    vectors: list[Vector] = field(default_factory=list)
    workspace: WorkspaceCloud | None = None


_ROBOT_GRAPHICS = RobotGraphics()


def _setup_lights(view: NDArray[np.float64]) -> None:
    """Headlight fixed in eye space, sky light fixed in the world, colour material."""
    GL.glMatrixMode(GL.GL_MODELVIEW)
    GL.glLoadIdentity()
    GL.glLightfv(GL.GL_LIGHT0, GL.GL_POSITION, gd.HEADLIGHT_DIRECTION)
    GL.glLightfv(GL.GL_LIGHT0, GL.GL_DIFFUSE, gd.HEADLIGHT_DIFFUSE)
    GL.glLightfv(GL.GL_LIGHT0, GL.GL_SPECULAR, gd.SPECULAR_COLOR)
    GL.glLoadMatrixd(_gl_matrix(view))
    GL.glLightfv(GL.GL_LIGHT1, GL.GL_POSITION, gd.SKYLIGHT_DIRECTION)
    GL.glLightfv(GL.GL_LIGHT1, GL.GL_DIFFUSE, gd.SKYLIGHT_DIFFUSE)
    GL.glLightfv(GL.GL_LIGHT1, GL.GL_SPECULAR, (0.0, 0.0, 0.0, 1.0))
    GL.glLightModelfv(GL.GL_LIGHT_MODEL_AMBIENT, gd.AMBIENT_LIGHT)
    GL.glLightModeli(GL.GL_LIGHT_MODEL_TWO_SIDE, GL.GL_TRUE)
    for cap in (GL.GL_LIGHTING, GL.GL_LIGHT0, GL.GL_LIGHT1, GL.GL_COLOR_MATERIAL, GL.GL_NORMALIZE):
        GL.glEnable(cap)
    GL.glColorMaterial(GL.GL_FRONT_AND_BACK, GL.GL_AMBIENT_AND_DIFFUSE)
    GL.glMaterialfv(GL.GL_FRONT_AND_BACK, GL.GL_SPECULAR, gd.SPECULAR_COLOR)
    GL.glMaterialf(GL.GL_FRONT_AND_BACK, GL.GL_SHININESS, gd.SHININESS)


def _cloud_from_layer(resources: _ContextResources, cloud: WorkspaceCloud, camera: Camera, width: int, height: int) -> bool:
    """Put the workspace cloud into the just-cleared colour and depth buffers from its
    picture for this view, if the view has stayed put; returns whether it did.

    llvmpipe rasterises points at about 8 million per second, so 200 000 points cost
    some 25 ms; but the cloud is fixed in the world, so its picture only changes with the
    camera or the viewport.  The second consecutive frame for the same view draws the
    points alone and reads back the colour and depth images; later frames for that view
    write them back with two glDrawPixels (about 2 ms) before anything else is drawn, so
    the depth test still hides and is hidden by the robot and the ground as if the points
    were drawn again (the one difference: a point lying exactly on the ground plane ties
    with a grid line there, and the grid, drawn later, wins the tie).  While the view keeps changing (an orbiting camera) this
    returns False and the caller draws the points after the ground as usual, with no
    read-back stalling the pipeline.
    """
    key = (id(cloud), width, height, camera.view_matrix().tobytes(), camera.projection_matrix(width / height).tobytes())
    layer = resources.cloud_layer
    if layer is not None and layer[0] == key:
        _, color, depth = layer
        GL.glWindowPos2i(0, 0)
        GL.glDepthFunc(GL.GL_ALWAYS)
        GL.glColorMask(GL.GL_FALSE, GL.GL_FALSE, GL.GL_FALSE, GL.GL_FALSE)
        GL.glDrawPixels(width, height, GL.GL_DEPTH_COMPONENT, GL.GL_FLOAT, depth)
        GL.glColorMask(GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE)
        GL.glDisable(GL.GL_DEPTH_TEST)
        GL.glDrawPixels(width, height, GL.GL_RGBA, GL.GL_UNSIGNED_BYTE, color)
        GL.glEnable(GL.GL_DEPTH_TEST)
        GL.glDepthFunc(GL.GL_LEQUAL)
        return True
    if resources.cloud_view != key:
        resources.cloud_view = key
        return False
    cloud.render()
    color = GL.glReadPixels(0, 0, width, height, GL.GL_RGBA, GL.GL_UNSIGNED_BYTE)
    depth = GL.glReadPixels(0, 0, width, height, GL.GL_DEPTH_COMPONENT, GL.GL_FLOAT)
    color = np.frombuffer(color, dtype=np.uint8) if isinstance(color, bytes) else np.asarray(color, dtype=np.uint8)
    resources.cloud_layer = (key, np.ascontiguousarray(color), np.ascontiguousarray(depth, dtype=np.float32))
    return True


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
    if _context_key() == 0:
        raise RuntimeError("render_scene: no current OpenGL context (the host failed to create or bind one)")
    resources = _resources()
    resources.free_dead()
    kin = scene.kinematics
    reach = robot_reach(kin.robot)

    GL.glViewport(0, 0, width, height)
    GL.glClearColor(*gd.BACKGROUND_COLOR)
    GL.glClear(GL.GL_COLOR_BUFFER_BIT | GL.GL_DEPTH_BUFFER_BIT)
    GL.glMatrixMode(GL.GL_PROJECTION)
    GL.glLoadMatrixd(_gl_matrix(camera.projection_matrix(width / height)))
    view = camera.view_matrix()
    _setup_lights(view)
    GL.glEnable(GL.GL_DEPTH_TEST)
    GL.glDepthFunc(GL.GL_LEQUAL)
    GL.glDisable(GL.GL_CULL_FACE)
    GL.glBlendFunc(GL.GL_SRC_ALPHA, GL.GL_ONE_MINUS_SRC_ALPHA)

    cloud = scene.workspace if options.show_workspace else None
    cloud_drawn = cloud is not None and _cloud_from_layer(resources, cloud, camera, width, height)
    GroundGraphics.for_reach(reach, kin.h_tf[0].t()[:2]).render()
    if cloud is not None and not cloud_drawn:
        cloud.render()
    opaque = options.alpha >= 1.0
    if opaque:
        _ROBOT_GRAPHICS.render(kin, options)
    if options.show_ghost and scene.ghost is not None:
        _ROBOT_GRAPHICS.render(scene.ghost, options, ghost=True)
    if not opaque:
        _ROBOT_GRAPHICS.render(kin, options)

    GL.glClear(GL.GL_DEPTH_BUFFER_BIT)
    _ROBOT_GRAPHICS.render_frames(kin, options)
    if options.show_target and scene.target_tf is not None:
        AxesGraphics(reach * gd.TARGET_FRAME_LENGTH_FRAC).render(scene.target_tf)
        _set_color(gd.TARGET_COLOR if scene.target_reachable else gd.TARGET_UNREACHABLE_COLOR)
        _call_list_at(resources.lists["sphere"], _spheres(scene.target_tf.t(), reach * gd.TARGET_MARKER_RADIUS_FRAC))
    if options.show_vectors:
        arrows = VectorGraphics(reach)
        for origin, vec, rgba in scene.vectors:
            arrows.render(origin, vec, rgba)


# ----------------------------------------------------------------------- offscreen


class OffscreenRenderer:
    """An OSMesa context rendering ``width`` x ``height`` RGBA images without a display.

    Use as a context manager or call :meth:`close`.  Needs PyOpenGL on its OSMesa
    platform (see :func:`require_osmesa_platform`, called here) and libOSMesa.
    """

    def __init__(self, width: int, height: int) -> None:
        if int(width) < 1 or int(height) < 1:
            raise ValueError(f"OffscreenRenderer: size must be positive, got {width}x{height}")
        require_osmesa_platform()
        self.width, self.height = int(width), int(height)
        missing = (
            f"OSMesa is not available; install the Debian package {gd.OSMESA_PACKAGE} "
            f"(apt-get install {gd.OSMESA_PACKAGE})"
        )
        try:
            from OpenGL import osmesa

            self._osmesa = osmesa
            self._context = osmesa.OSMesaCreateContextExt(
                osmesa.OSMESA_RGBA, gd.DEPTH_BUFFER_BITS, gd.OSMESA_STENCIL_BITS, 0, None
            )
        except Exception as exc:  # ImportError, NullFunctionError, ctypes errors
            raise RuntimeError(f"{missing}: {exc}") from exc
        if not self._context:
            raise RuntimeError(f"{missing}: OSMesaCreateContextExt failed")
        self._buffer = np.zeros((self.height, self.width, 4), dtype=np.uint8)
        self._make_current()
        self._key = _context_key()

    def _make_current(self) -> None:
        if self._context is None:
            raise RuntimeError("OffscreenRenderer: render() after close()")
        ok = self._osmesa.OSMesaMakeCurrent(self._context, self._buffer, GL.GL_UNSIGNED_BYTE, self.width, self.height)
        if not ok:
            raise RuntimeError(f"OSMesaMakeCurrent failed for a {self.width}x{self.height} buffer")
        self._osmesa.OSMesaPixelStore(self._osmesa.OSMESA_Y_UP, 0)  # row 0 = top of the image

    def render(self, camera: Camera, scene: Scene, options: GraphicsOptions) -> NDArray[np.uint8]:
        """Render ``scene`` and return a copy of the image (H, W, 4) uint8 RGBA, row 0 at the top."""
        self._make_current()
        render_scene(camera, scene, options, self.width, self.height)
        GL.glFinish()
        return self._buffer.copy()

    def close(self) -> None:
        """Free the context and its GL objects; further render() calls raise."""
        if self._context is not None:
            _RESOURCES.pop(self._key, None)
            self._osmesa.OSMesaDestroyContext(self._context)
            self._context = None

    def __enter__(self) -> OffscreenRenderer:
        return self

    def __exit__(self, *exc_info: object) -> None:
        self.close()


# ------------------------------------------------------------------------------- PNG


def save_png(path: str | os.PathLike[str], image: ArrayLike) -> None:
    """Write ``image`` (H, W, 3) RGB or (H, W, 4) RGBA uint8, row 0 at the top, as a PNG.

    Raises ValueError for another shape or dtype and OSError naming the path when it
    cannot be written."""
    img = np.asarray(image)
    if img.dtype != np.uint8 or img.ndim != 3 or img.shape[2] not in (3, 4) or 0 in img.shape:
        raise ValueError(f"save_png: need an (H, W, 3|4) uint8 image, got {img.shape} {img.dtype}")
    height, width, channels = img.shape
    rows = np.zeros((height, 1 + width * channels), dtype=np.uint8)  # filter byte 0 per row
    rows[:, 1:] = img.reshape(height, -1)

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    color_type = 6 if channels == 4 else 2
    header = struct.pack(">IIBBBBB", width, height, 8, color_type, 0, 0, 0)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows.tobytes(), 6))
    png += chunk(b"IEND", b"")
    try:
        Path(path).write_bytes(png)
    except OSError as exc:
        raise OSError(exc.errno, f"cannot write PNG to {os.fspath(path)}: {exc.strerror}", os.fspath(path)) from exc
