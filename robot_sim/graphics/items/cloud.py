"""The workspace point cloud: a drawable owning one vertex buffer per GL context, its
colour map, and the cache of its picture for a view that stays put."""
from __future__ import annotations

import ctypes
import weakref
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.gl import GL, client_arrays, disable_client_arrays
from robot_sim.graphics.resources import ContextResources, Drawable, resources

if TYPE_CHECKING:
    from robot_sim.graphics.camera import Camera


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


class _CloudPicture:
    """The cloud's colour and depth images for one view in one context, and the view of
    the last frame that drew the cloud there."""

    def __init__(self) -> None:
        self.layer: tuple[tuple[Any, ...], NDArray, NDArray] | None = None
        self.last_view: tuple[Any, ...] | None = None


class WorkspaceCloud(Drawable):
    """Points (N, 3) of a workspace (world, metres) coloured by ``values`` (N,)
    (e.g. height or manipulability) through ``WORKSPACE_COLORMAP``, min to max.

    Drawn unlit with glDrawArrays from a vertex buffer it uploads once per GL context."""

    gl_preset = "unlit"

    def __init__(self, points: ArrayLike, values: ArrayLike) -> None:
        super().__init__()
        pts = np.asarray(points, dtype=float)
        vals = np.asarray(values, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise ValueError(f"WorkspaceCloud: points must have shape (N, 3), got {pts.shape}")
        if vals.shape != (len(pts),):
            raise ValueError(f"WorkspaceCloud: values must have shape ({len(pts)},), got {vals.shape}")
        self.points: NDArray[np.float32] = np.ascontiguousarray(pts, dtype=np.float32)
        self.values: NDArray[np.float64] = vals
        self.colors: NDArray[np.uint8] = colormap(vals)
        self._pictures: weakref.WeakKeyDictionary[ContextResources, _CloudPicture] = weakref.WeakKeyDictionary()

    def __len__(self) -> int:
        return len(self.points)

    def _upload(self) -> int:
        buffer = int(GL.glGenBuffers(1))
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, buffer)
        data = np.concatenate([self.points.view(np.uint8).ravel(), self.colors.ravel()])
        GL.glBufferData(GL.GL_ARRAY_BUFFER, data.nbytes, data, GL.GL_STATIC_DRAW)
        return buffer

    def paint(self) -> None:
        """Draw the points (``WORKSPACE_POINT_SIZE`` pixels) from this context's buffer."""
        if len(self.points) == 0:
            return
        buffer = self.gl.get(self._upload, "buffer")
        GL.glPointSize(gd.WORKSPACE_POINT_SIZE)
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, buffer)
        client_arrays(ctypes.c_void_p(0), colors=ctypes.c_void_p(self.points.nbytes))
        GL.glDrawArrays(GL.GL_POINTS, 0, len(self.points))
        disable_client_arrays()
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, 0)

    def draw_from_picture(self, camera: Camera, width: int, height: int) -> bool:
        """Put the cloud into the just-cleared colour and depth buffers from its picture
        for this view, if the view has stayed put; returns whether it did.

        llvmpipe rasterises points at about 8 million per second, so 200 000 points cost
        some 25 ms; but the cloud is fixed in the world, so its picture only changes with
        the camera or the viewport.  The second consecutive frame for the same view draws
        the points alone and reads back the colour and depth images; later frames for that
        view write them back with two glDrawPixels (about 2 ms) before anything else is
        drawn, so the depth test still hides and is hidden by the robot and the ground as
        if the points were drawn again (the one difference: a point lying exactly on the
        ground plane ties with a grid line there, and the grid, drawn later, wins the tie).
        While the view keeps changing (an orbiting camera) this returns False and the
        caller draws the points after the ground as usual, with no read-back stalling the
        pipeline.
        """
        key = (width, height, camera.view_matrix().tobytes(), camera.projection_matrix(width / height).tobytes())
        picture = self._pictures.setdefault(resources(), _CloudPicture())
        if picture.layer is not None and picture.layer[0] == key:
            _, color, depth = picture.layer
            GL.glPushAttrib(GL.GL_ENABLE_BIT | GL.GL_DEPTH_BUFFER_BIT | GL.GL_COLOR_BUFFER_BIT)
            GL.glWindowPos2i(0, 0)
            GL.glEnable(GL.GL_DEPTH_TEST)
            GL.glDepthFunc(GL.GL_ALWAYS)
            GL.glColorMask(GL.GL_FALSE, GL.GL_FALSE, GL.GL_FALSE, GL.GL_FALSE)
            GL.glDrawPixels(width, height, GL.GL_DEPTH_COMPONENT, GL.GL_FLOAT, depth)
            GL.glColorMask(GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE, GL.GL_TRUE)
            GL.glDisable(GL.GL_DEPTH_TEST)
            GL.glDrawPixels(width, height, GL.GL_RGBA, GL.GL_UNSIGNED_BYTE, color)
            GL.glPopAttrib()
            return True
        if picture.last_view != key:
            picture.last_view = key
            return False
        self.draw()
        color = GL.glReadPixels(0, 0, width, height, GL.GL_RGBA, GL.GL_UNSIGNED_BYTE)
        depth = GL.glReadPixels(0, 0, width, height, GL.GL_DEPTH_COMPONENT, GL.GL_FLOAT)
        color = np.frombuffer(color, dtype=np.uint8) if isinstance(color, bytes) else np.asarray(color, dtype=np.uint8)
        picture.layer = (key, np.ascontiguousarray(color), np.ascontiguousarray(depth, dtype=np.float32))
        return True
