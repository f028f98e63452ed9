"""OpenGL plumbing of the viewer: the lazily imported PyOpenGL modules, the platform
choice, matrices and client arrays, display lists, and GL state scoped by named presets.

Nothing here knows about robots.  ``OpenGL.GL`` is imported on first use only, so a host
can still choose PyOpenGL's platform (:func:`require_osmesa_platform`) after importing
the viewer's modules.
"""
from __future__ import annotations

import contextlib
import ctypes
import importlib
import os
import sys
from types import ModuleType
from typing import Any, Iterator, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.transforms import rotations_z_onto


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


def context_key() -> int:
    """Address of the current GL context (0 when none is current or the platform cannot tell)."""
    from OpenGL import contextdata, error

    try:
        context = contextdata.getContext()
    except error.Error:
        return 0
    if isinstance(context, int):
        return context
    return int(ctypes.cast(context, ctypes.c_void_p).value or 0)


# ------------------------------------------------------------------ GL state presets

# Named GL states in the manner of pyqtgraph's GLOptions: capabilities switched on or
# off, the depth mask and the blend function.  ``gl_state`` sets one around a drawing
# and restores the previous state afterwards.
GL_PRESETS: dict[str, dict[str, Any]] = {
    # lit solid parts, depth tested and written
    "opaque": {"enable": ("DEPTH_TEST", "LIGHTING"), "disable": ("BLEND",), "depth_mask": True, "blend": None},
    # lit parts seen through: blended, depth tested, not written (draw after the opaque pass)
    "translucent": {"enable": ("DEPTH_TEST", "LIGHTING", "BLEND"), "disable": (), "depth_mask": False,
                    "blend": ("SRC_ALPHA", "ONE_MINUS_SRC_ALPHA")},
    # unlit lines, points and text drawn over everything (labels, grid lines)
    "overlay": {"enable": ("BLEND",), "disable": ("DEPTH_TEST", "LIGHTING"), "depth_mask": False,
                "blend": ("SRC_ALPHA", "ONE_MINUS_SRC_ALPHA")},
    # unlit lines and points, depth tested and written (grid, point cloud)
    "unlit": {"enable": ("DEPTH_TEST",), "disable": ("LIGHTING", "BLEND"), "depth_mask": True, "blend": None},
}

_PUSHED_BITS = ("ENABLE_BIT", "COLOR_BUFFER_BIT", "DEPTH_BUFFER_BIT", "POLYGON_BIT", "CURRENT_BIT", "LINE_BIT",
                "PIXEL_MODE_BIT", "LIST_BIT")


@contextlib.contextmanager
def gl_state(preset: str, *, wireframe: bool = False) -> Iterator[None]:
    """Draw inside the GL state named ``preset`` (a key of ``GL_PRESETS``), polygons as
    lines when ``wireframe``; the previous state is pushed and restored on exit."""
    spec = GL_PRESETS[preset]
    mask = 0
    for bit in _PUSHED_BITS:
        mask |= getattr(GL, f"GL_{bit}")
    GL.glPushAttrib(mask)
    try:
        for cap in spec["enable"]:
            GL.glEnable(getattr(GL, f"GL_{cap}"))
        for cap in spec["disable"]:
            GL.glDisable(getattr(GL, f"GL_{cap}"))
        GL.glDepthMask(GL.GL_TRUE if spec["depth_mask"] else GL.GL_FALSE)
        if spec["blend"] is not None:  # colour blends; the framebuffer's alpha stays 1 (opaque pictures)
            src, dst = spec["blend"]
            GL.glBlendFuncSeparate(getattr(GL, f"GL_{src}"), getattr(GL, f"GL_{dst}"), GL.GL_ZERO, GL.GL_ONE)
        GL.glPolygonMode(GL.GL_FRONT_AND_BACK, GL.GL_LINE if wireframe else GL.GL_FILL)
        yield
    finally:
        GL.glPopAttrib()


# ------------------------------------------------------------- arrays and matrices


def set_color(rgba: Sequence[float], alpha: float = 1.0) -> None:
    """Current colour ``rgba`` with its alpha multiplied by ``alpha``."""
    GL.glColor4f(rgba[0], rgba[1], rgba[2], rgba[3] * alpha)


def gl_matrix(mat: NDArray[np.float64]) -> NDArray[np.float64]:
    """A row-major (4, 4) matrix laid out column-major as glLoadMatrix/glMultMatrix want."""
    return np.ascontiguousarray(np.asarray(mat, dtype=np.float64).T)


def _pointer(data: NDArray | ctypes.c_void_p) -> ctypes.c_void_p:
    """Address of a contiguous array, or a VBO byte offset passed through."""
    return data if isinstance(data, ctypes.c_void_p) else ctypes.c_void_p(data.ctypes.data)


def client_arrays(
    vertices: NDArray | ctypes.c_void_p,
    colors: NDArray | ctypes.c_void_p | None = None,
    normals: NDArray | None = None,
    texcoords: NDArray | None = None,
) -> None:
    """Point the fixed-function client arrays at contiguous float32 ``vertices`` (and
    optional float32 normals and 2-D texture coordinates, uint8 RGBA colours) and enable
    them; when a VBO is bound the arguments are byte offsets.  The arrays must outlive
    the draw call."""
    GL.glEnableClientState(GL.GL_VERTEX_ARRAY)
    GL_RAW.glVertexPointer(3, GL.GL_FLOAT, 0, _pointer(vertices))
    if normals is not None:
        GL.glEnableClientState(GL.GL_NORMAL_ARRAY)
        GL_RAW.glNormalPointer(GL.GL_FLOAT, 0, _pointer(normals))
    if colors is not None:
        GL.glEnableClientState(GL.GL_COLOR_ARRAY)
        GL_RAW.glColorPointer(4, GL.GL_UNSIGNED_BYTE, 0, _pointer(colors))
    if texcoords is not None:
        GL.glEnableClientState(GL.GL_TEXTURE_COORD_ARRAY)
        GL_RAW.glTexCoordPointer(2, GL.GL_FLOAT, 0, _pointer(texcoords))


def disable_client_arrays() -> None:
    """Disable every client array :func:`client_arrays` may have enabled."""
    for state in (GL.GL_VERTEX_ARRAY, GL.GL_NORMAL_ARRAY, GL.GL_COLOR_ARRAY, GL.GL_TEXTURE_COORD_ARRAY):
        GL.glDisableClientState(state)


def draw_arrays(mode: int, vertices: ArrayLike, normals: ArrayLike | None = None) -> None:
    """Draw world ``vertices`` (N, 3) (and normals) as primitives of ``mode`` at once."""
    verts = np.ascontiguousarray(vertices, dtype=np.float32).reshape(-1, 3)
    if len(verts) == 0:
        return
    norms = None if normals is None else np.ascontiguousarray(normals, dtype=np.float32).reshape(-1, 3)
    GL.glBindBuffer(GL.GL_ARRAY_BUFFER, 0)
    client_arrays(verts, normals=norms)
    GL.glDrawArrays(mode, 0, len(verts))
    disable_client_arrays()


def compile_list(draw: Any) -> int:
    """A new display list holding what ``draw()`` issues."""
    list_id = int(GL.glGenLists(1))
    GL.glNewList(list_id, GL.GL_COMPILE)
    draw()
    GL.glEndList()
    return list_id


def along(origins: ArrayLike, vecs: ArrayLike, radii: ArrayLike, lengths: ArrayLike) -> NDArray[np.float64]:
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


def spheres(centres: ArrayLike, radius: ArrayLike) -> NDArray[np.float64]:
    """World placements (N, 4, 4) of the unit sphere scaled to ``radius`` (scalar or (N,))
    at ``centres`` (N, 3)."""
    centres = np.asarray(centres, dtype=float).reshape(-1, 3)
    mats = np.zeros((len(centres), 4, 4))
    mats[:, [0, 1, 2], [0, 1, 2]] = np.broadcast_to(np.asarray(radius, dtype=float).reshape(-1, 1), (len(centres), 3))
    mats[:, :3, 3] = centres
    mats[:, 3, 3] = 1.0
    return mats


def call_list_at(list_id: int, placements: NDArray[np.float64]) -> None:
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
