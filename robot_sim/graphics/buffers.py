"""Vertex buffers of the render path: static meshes uploaded once (positions, normals,
triangle indices), and stream buffers refilled each frame with per-instance placements
and colours or with line vertices.

Attributes follow :mod:`robot_sim.graphics.shaders`' fixed locations.  A placement
(4, 4) is given row-major, as everywhere in the project; the ``a_model`` attribute
takes its columns.  All arrays live in buffer objects, so the raw entry points are
called with byte offsets (PyOpenGL's wrappers would keep the arrays alive per context).
"""
from __future__ import annotations

import ctypes
import functools
import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics.gl import GL, _LazyModule
from robot_sim.graphics.shaders import COLOR, MODEL, NORMAL, POSITION

_GL2: Any = _LazyModule("OpenGL.raw.GL.VERSION.GL_2_0")
_GL3: Any = _LazyModule("OpenGL.raw.GL.VERSION.GL_3_3")
_GL31: Any = _LazyModule("OpenGL.raw.GL.VERSION.GL_3_1")
_FLOAT = 4


def _offset(nbytes: int) -> ctypes.c_void_p:
    return ctypes.c_void_p(nbytes)


def set_constant_color(rgba: ArrayLike) -> None:
    """Colour of every vertex drawn while the colour array is disabled."""
    GL.glDisableVertexAttribArray(COLOR)
    r, g, b, a = (float(c) for c in rgba)
    GL.glVertexAttrib4f(COLOR, r, g, b, a)


def set_constant_model(placement: ArrayLike) -> None:
    """Model matrix (4, 4) row-major of everything drawn while the model array is disabled."""
    mat = np.asarray(placement, dtype=np.float64)
    for column in range(4):
        GL.glDisableVertexAttribArray(MODEL + column)
        GL.glVertexAttrib4f(MODEL + column, *map(float, mat[:, column]))


def closed_winding(vertices: ArrayLike, indices: ArrayLike) -> int:
    """How triangles ``indices`` (F, 3) into ``vertices`` (V, 3) enclose a volume: +1 when
    they close it with every face counter-clockwise seen from outside, -1 when every face
    is clockwise, 0 when they do not close it (an open or inconsistently wound mesh).

    Corners at the same position (to 1e-6) are one vertex, so seams and poles close;
    triangles with two corners there are dropped.  Closed means every directed edge occurs
    once and its reverse once; the sign is that of the enclosed (signed) volume."""
    positions = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    _, merged = np.unique(np.round(positions, 6), axis=0, return_inverse=True)
    tri = merged.reshape(-1)[np.asarray(indices, dtype=np.int64).reshape(-1, 3)]
    tri = tri[(tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 2] != tri[:, 0])]
    if len(tri) == 0:
        return 0
    heads, tails = tri.reshape(-1), tri[:, [1, 2, 0]].reshape(-1)
    n = int(merged.max()) + 1
    forward, backward = np.sort(heads * n + tails), np.sort(tails * n + heads)
    if np.any(forward[1:] == forward[:-1]) or not np.array_equal(forward, backward):
        return 0
    corners = positions[np.asarray(indices, dtype=np.int64).reshape(-1, 3)]
    volume = float(np.einsum("ij,ij->", corners[:, 0], np.cross(corners[:, 1], corners[:, 2])))
    return int(np.sign(volume))


#: A coarse mesh (:meth:`StaticMesh.coarse`) is used only when it keeps at most this
#: fraction of the triangles; else the mesh itself is drawn.
COARSE_MAX_KEPT = 0.5


#: Normals are told apart by rounding them to multiples of 1 / this (about 7 degrees):
#: vertices of one cell whose normals differ more keep normals of their own.
CLUSTER_NORMAL_STEPS = 8


def clustered(vertices: NDArray[np.float32], normals: NDArray[np.float32], indices: NDArray[np.uint32],
              cell: float) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """The mesh ``vertices``/``normals`` (V, 3), triangles ``indices`` (3F,) with its
    vertices clustered on a grid of ``cell`` (the vertices' units, metres).

    Every vertex moves to the mean of the distinct positions in its grid cell (vertices
    at one position, to 1e-6, always share a cell, so seams of repeated vertices do not
    open); it keeps its own normal direction class (``CLUSTER_NORMAL_STEPS``), averaged
    over the cell, so sharp edges stay sharp.  Triangles with two corners in one cell
    are dropped.  Every vertex moves by less than a cell's diagonal, so silhouettes and
    shadows move by at most that.  Returns positions (K, 3), unit normals (K, 3) and
    triangles (M, 3) into them."""
    rounded = np.round(vertices.astype(np.float64), 6)
    distinct, inverse = np.unique(rounded, axis=0, return_inverse=True)
    _, cell_of_distinct, counts = np.unique(np.floor(distinct / cell).astype(np.int64), axis=0,
                                            return_inverse=True, return_counts=True)
    cell_of_distinct = cell_of_distinct.reshape(-1)
    centres = np.stack([np.bincount(cell_of_distinct, weights=distinct[:, axis]) / counts for axis in range(3)], axis=1)
    cells = cell_of_distinct[inverse.reshape(-1)]  # (V,) grid cell of every vertex
    classes = np.rint(normals * CLUSTER_NORMAL_STEPS).astype(np.int64)
    _, out, members = np.unique(np.c_[cells, classes], axis=0, return_inverse=True, return_counts=True)
    out = out.reshape(-1)
    summed = np.stack([np.bincount(out, weights=normals[:, axis]) for axis in range(3)], axis=1)
    length = np.linalg.norm(summed, axis=1, keepdims=True)
    mean_normals = np.where(length > 1e-12, summed / np.maximum(length, 1e-12), [0.0, 0.0, 1.0])
    cell_of_out = np.zeros(len(members), dtype=np.int64)
    cell_of_out[out] = cells
    tri, tri_cells = out[indices.reshape(-1, 3)], cells[indices.reshape(-1, 3)]
    keep = (tri_cells[:, 0] != tri_cells[:, 1]) & (tri_cells[:, 1] != tri_cells[:, 2]) & (tri_cells[:, 2] != tri_cells[:, 0])
    return centres[cell_of_out], mean_normals, tri[keep]


class StaticMesh:
    """Triangles uploaded once per context: ``vertices`` and ``normals`` (V, 3) float32,
    ``indices`` (F, 3) into them.  ``draw(n)`` draws n instances (0: once) with whatever
    colour and model attributes are set.

    A closed mesh (:func:`closed_winding`) can be drawn with its back faces culled: they
    lie behind its front faces, so an opaque picture or a depth map (seen from outside)
    is the same without them, and llvmpipe, which pays for every triangle it rasterizes
    at every multisample, draws about half the triangles."""

    def __init__(self, vertices: ArrayLike, normals: ArrayLike, indices: ArrayLike) -> None:
        self.vertices = np.ascontiguousarray(vertices, dtype=np.float32).reshape(-1, 3)
        self.normals = np.ascontiguousarray(normals, dtype=np.float32).reshape(-1, 3)
        self.indices = np.ascontiguousarray(indices, dtype=np.uint32).reshape(-1)
        if self.normals.shape != self.vertices.shape:
            raise ValueError(f"StaticMesh: normals {self.normals.shape} differ from vertices {self.vertices.shape}")
        if len(self.indices) and int(self.indices.max()) >= len(self.vertices):
            raise ValueError(f"StaticMesh: index {int(self.indices.max())} past {len(self.vertices)} vertices")
        self._handles: tuple[int, int] | None = None
        self._coarse: dict[int, StaticMesh] = {}

    @functools.cached_property
    def radius(self) -> float:
        """Distance (metres, mesh units) of the farthest vertex from the mesh's origin."""
        return float(np.sqrt((self.vertices.astype(np.float64) ** 2).sum(axis=1).max(initial=0.0)))

    @functools.cached_property
    def winding(self) -> int:
        """:func:`closed_winding` of the mesh (computed on first use)."""
        return closed_winding(self.vertices, self.indices)

    def coarse(self, cell: float) -> StaticMesh:
        """A cheaper stand-in for a picture in which ``cell`` metres (mesh units) are too
        small to see: the mesh :func:`clustered` on the power-of-two grid at most ``cell``
        wide, built once per grid; the mesh itself when that keeps more than
        ``COARSE_MAX_KEPT`` of its triangles or ``cell`` is not positive."""
        if not cell > 0.0:
            return self
        level = math.floor(math.log2(cell))
        if level not in self._coarse:
            vertices, normals, tri = clustered(self.vertices, self.normals, self.indices, 2.0 ** level)
            fewer = len(tri) <= COARSE_MAX_KEPT * self.n_triangles
            self._coarse[level] = StaticMesh(vertices, normals, tri) if fewer else self
        return self._coarse[level]

    @classmethod
    def from_triangles(cls, vertices: ArrayLike, normals: ArrayLike) -> StaticMesh:
        """A mesh from triangle corner arrays (M, 3, 3) of positions and normals, corners
        with equal position and normal merged (fewer vertices to shade)."""
        corners = np.hstack([np.asarray(vertices, dtype=np.float32).reshape(-1, 3),
                             np.asarray(normals, dtype=np.float32).reshape(-1, 3)])
        unique, index = np.unique(np.round(corners, 6), axis=0, return_inverse=True)
        return cls(unique[:, :3], unique[:, 3:], index.reshape(-1))

    @property
    def n_triangles(self) -> int:
        """Number of triangles."""
        return len(self.indices) // 3

    def upload(self) -> None:
        """Create the vertex and index buffers in the current context (once)."""
        if self._handles is not None:
            return
        vbo, ebo = (int(b) for b in GL.glGenBuffers(2))
        data = np.ascontiguousarray(np.hstack([self.vertices, self.normals]))
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, vbo)
        GL.glBufferData(GL.GL_ARRAY_BUFFER, data.nbytes, data, GL.GL_STATIC_DRAW)
        GL.glBindBuffer(GL.GL_ELEMENT_ARRAY_BUFFER, ebo)
        GL.glBufferData(GL.GL_ELEMENT_ARRAY_BUFFER, self.indices.nbytes, self.indices, GL.GL_STATIC_DRAW)
        GL.glBindBuffer(GL.GL_ELEMENT_ARRAY_BUFFER, 0)
        self._handles = (vbo, ebo)

    def draw(self, instances: int = 0, mode: int | None = None, cull: bool = False) -> None:
        """Draw the triangles (or ``mode`` primitives over the same indices), ``instances``
        times instanced when > 0; with back faces culled when ``cull`` and the mesh is
        closed (its placements must keep the winding: positive determinants)."""
        self.upload()
        facing = self.winding if cull else 0
        if facing:
            GL.glEnable(GL.GL_CULL_FACE)
            GL.glCullFace(GL.GL_BACK if facing > 0 else GL.GL_FRONT)
        assert self._handles is not None
        vbo, ebo = self._handles
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, vbo)
        GL.glEnableVertexAttribArray(POSITION)
        _GL2.glVertexAttribPointer(POSITION, 3, GL.GL_FLOAT, GL.GL_FALSE, 6 * _FLOAT, _offset(0))
        GL.glEnableVertexAttribArray(NORMAL)
        _GL2.glVertexAttribPointer(NORMAL, 3, GL.GL_FLOAT, GL.GL_FALSE, 6 * _FLOAT, _offset(3 * _FLOAT))
        GL.glBindBuffer(GL.GL_ELEMENT_ARRAY_BUFFER, ebo)
        mode = GL.GL_TRIANGLES if mode is None else mode
        if instances > 0:
            _GL31.glDrawElementsInstanced(mode, len(self.indices), GL.GL_UNSIGNED_INT, _offset(0), instances)
        else:
            GL.glDrawElements(mode, len(self.indices), GL.GL_UNSIGNED_INT, _offset(0))
        if facing:
            GL.glDisable(GL.GL_CULL_FACE)
        GL.glBindBuffer(GL.GL_ELEMENT_ARRAY_BUFFER, 0)
        GL.glDisableVertexAttribArray(NORMAL)

    def delete(self) -> None:
        """Delete the buffers, the coarse meshes' too (their context must be current); a
        later draw uploads again."""
        if self._handles is not None:
            GL.glDeleteBuffers(2, list(self._handles))
            self._handles = None
        for mesh in self._coarse.values():
            if mesh is not self:
                mesh.delete()

    def forget(self) -> None:
        """Drop the buffers' handles without deleting them (their context is gone)."""
        self._handles = None
        for mesh in self._coarse.values():
            if mesh is not self:
                mesh.forget()


class StaticPoints:
    """Points uploaded once per context: positions (N, 3) float32 and colours (N, 4)
    uint8 (normalised to 0..1 on the way in)."""

    def __init__(self, points: ArrayLike, colors: ArrayLike) -> None:
        self.points = np.ascontiguousarray(points, dtype=np.float32).reshape(-1, 3)
        self.colors = np.ascontiguousarray(colors, dtype=np.uint8).reshape(-1, 4)
        if len(self.colors) != len(self.points):
            raise ValueError(f"StaticPoints: {len(self.colors)} colours for {len(self.points)} points")
        self._handle = 0

    def draw(self, mode: int) -> None:
        """Draw the points as ``mode`` primitives (GL_POINTS, GL_LINES, ...)."""
        if not self._handle:
            self._handle = int(GL.glGenBuffers(1))
            GL.glBindBuffer(GL.GL_ARRAY_BUFFER, self._handle)
            data = np.concatenate([self.points.view(np.uint8).ravel(), self.colors.ravel()])
            GL.glBufferData(GL.GL_ARRAY_BUFFER, data.nbytes, data, GL.GL_STATIC_DRAW)
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, self._handle)
        GL.glEnableVertexAttribArray(POSITION)
        _GL2.glVertexAttribPointer(POSITION, 3, GL.GL_FLOAT, GL.GL_FALSE, 0, _offset(0))
        GL.glEnableVertexAttribArray(COLOR)
        _GL2.glVertexAttribPointer(COLOR, 4, GL.GL_UNSIGNED_BYTE, GL.GL_TRUE, 0, _offset(self.points.nbytes))
        GL.glDrawArrays(mode, 0, len(self.points))
        GL.glDisableVertexAttribArray(COLOR)

    def delete(self) -> None:
        """Delete the buffer (its context must be current)."""
        if self._handle:
            GL.glDeleteBuffers(1, [self._handle])
            self._handle = 0

    def forget(self) -> None:
        """Drop the handle without deleting it (its context is gone)."""
        self._handle = 0


class StreamBuffer:
    """One buffer object refilled with fresh data each time it is used."""

    def __init__(self) -> None:
        self.handle = 0

    def fill(self, data: NDArray) -> None:
        """Bind the buffer as the array buffer and replace its contents with ``data``."""
        if not self.handle:
            self.handle = int(GL.glGenBuffers(1))
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, self.handle)
        GL.glBufferData(GL.GL_ARRAY_BUFFER, data.nbytes, data, GL.GL_STREAM_DRAW)

    def instances(self, placements: ArrayLike, colors: ArrayLike) -> int:
        """Bind placements (N, 4, 4) row-major and colours (N, 4) (or one (4,)) as the
        per-instance model and colour attributes; returns N."""
        mats = np.asarray(placements, dtype=np.float32).reshape(-1, 4, 4)
        n = len(mats)
        cols = np.broadcast_to(np.asarray(colors, dtype=np.float32).reshape(-1, 4), (n, 4))
        data = np.ascontiguousarray(np.concatenate([mats.transpose(0, 2, 1).reshape(n, 16), cols], axis=1))
        self.fill(data)
        stride = 20 * _FLOAT
        for column in range(4):
            GL.glEnableVertexAttribArray(MODEL + column)
            _GL2.glVertexAttribPointer(MODEL + column, 4, GL.GL_FLOAT, GL.GL_FALSE, stride, _offset(4 * column * _FLOAT))
            _GL3.glVertexAttribDivisor(MODEL + column, 1)
        GL.glEnableVertexAttribArray(COLOR)
        _GL2.glVertexAttribPointer(COLOR, 4, GL.GL_FLOAT, GL.GL_FALSE, stride, _offset(16 * _FLOAT))
        _GL3.glVertexAttribDivisor(COLOR, 1)
        return n

    @staticmethod
    def end_instances() -> None:
        """Back to constant model and colour attributes (no divisors)."""
        for location in (*range(MODEL, MODEL + 4), COLOR):
            _GL3.glVertexAttribDivisor(location, 0)
            GL.glDisableVertexAttribArray(location)

    def attributes(self, data: ArrayLike, layout: tuple[tuple[int, int], ...]) -> int:
        """Bind rows of ``data`` (N, k) float32 as vertex attributes: ``layout`` lists
        (location, size) in the order of the row's columns; returns N."""
        rows = np.ascontiguousarray(data, dtype=np.float32)
        rows = rows.reshape(len(rows), -1)
        self.fill(rows)
        stride, offset = rows.shape[1] * _FLOAT, 0
        for location, size in layout:
            GL.glEnableVertexAttribArray(location)
            _GL2.glVertexAttribPointer(location, size, GL.GL_FLOAT, GL.GL_FALSE, stride, _offset(offset * _FLOAT))
            offset += size
        return len(rows)

    def vertices(self, points: ArrayLike, colors: ArrayLike | None = None) -> int:
        """Bind points (N, 3) (and per-vertex colours (N, 4) floats or uint8) as the
        position (and colour) arrays; returns N."""
        pts = np.asarray(points, dtype=np.float32).reshape(-1, 3)
        if colors is None:
            return self.attributes(pts, ((POSITION, 3),))
        cols = np.asarray(colors)
        cols = cols.astype(np.float32) / 255.0 if cols.dtype == np.uint8 else cols.astype(np.float32)
        return self.attributes(np.hstack([pts, cols.reshape(-1, 4)]), ((POSITION, 3), (COLOR, 4)))

    def delete(self) -> None:
        """Delete the buffer (its context must be current)."""
        if self.handle:
            GL.glDeleteBuffers(1, [self.handle])
            self.handle = 0

    def forget(self) -> None:
        """Drop the handle without deleting it (its context is gone)."""
        self.handle = 0
