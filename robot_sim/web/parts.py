"""Drawn parts in the browser: the project's unit meshes (robot_sim.graphics.meshes) sent
once as indexed triangle meshes, and copies of them placed by 4x4 world matrices sent as
instance poses (orientation, position, per-axis scale) of viser's batched meshes.

A :class:`PartsLayer` keeps one batched mesh per slot; while a slot keeps its unit mesh
and its number of copies, an update sends only the copies' poses (and colours when they
change), never the mesh again.  World frame, metres.
"""
from __future__ import annotations

import functools
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics.meshes import unit_meshes

#: Vertices closer than this (m, of a unit mesh) are merged, so curved surfaces get
#: smooth normals in the browser.
MERGE_TOL = 1e-6


@functools.lru_cache(maxsize=None)
def unit_mesh(name: str) -> tuple[NDArray[np.float32], NDArray[np.uint32]]:
    """Vertices (V, 3) and triangles (F, 3) of the unit mesh ``name`` (a key of
    ``robot_sim.graphics.meshes.unit_meshes``), equal corners merged."""
    triangles = unit_meshes()[name][0].reshape(-1, 3)
    keys = np.round(triangles / MERGE_TOL).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    faces = inverse.reshape(-1, 3)
    faces = faces[(faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])]
    return triangles[first].astype(np.float32), faces.astype(np.uint32)


def instance_poses(placements: ArrayLike) -> tuple[NDArray[np.float32], NDArray[np.float32], NDArray[np.float32]]:
    """Orientations (N, 4) as w, x, y, z, positions (N, 3) and per-axis scales (N, 3) of
    ``placements`` (N, 4, 4): each a rotation times a diagonal scale, then a translation
    (the form of every placement in robot_sim.graphics).  A zero scale gives the identity
    orientation for that axis."""
    mats = np.asarray(placements, dtype=float).reshape(-1, 4, 4)
    linear = mats[:, :3, :3]
    scales = np.linalg.norm(linear, axis=1)
    rotation = linear / np.where(scales > 0.0, scales, 1.0)[:, None, :]
    degenerate = scales <= 0.0
    if degenerate.any():  # a flattened copy: any rotation shows it the same
        rotation = np.where(degenerate[:, None, :], np.eye(3)[None], rotation)
    return _quaternions(rotation).astype(np.float32), mats[:, :3, 3].astype(np.float32), scales.astype(np.float32)


def _quaternions(rotation: NDArray[np.float64]) -> NDArray[np.float64]:
    """Unit quaternions (N, 4), w first, of rotation matrices (N, 3, 3)."""
    import viser.transforms as vtf

    return np.asarray(vtf.SO3.from_matrix(rotation).wxyz, dtype=float).reshape(-1, 4)


def rgb255(rgba: ArrayLike) -> NDArray[np.uint8]:
    """RGB bytes (..., 3) of colours given as floats in 0..1 (..., 3 or 4)."""
    values = np.asarray(rgba, dtype=float)[..., :3]
    return np.clip(np.rint(values * 255.0), 0, 255).astype(np.uint8)


class PartsLayer:
    """Slots of batched unit meshes under the scene node ``prefix`` (e.g. "/robot")."""

    def __init__(self, scene: Any, prefix: str) -> None:
        self.scene = scene
        self.prefix = prefix
        self._slots: list[tuple[Any, str, int, bytes, bytes, bool]] = []  # handle, mesh, count, colours, opacities, wire
        self._poses: list[bytes] = []  # per slot: the poses last sent

    def update(self, parts: Sequence[tuple[str, ArrayLike, ArrayLike]], *, opacity: float = 1.0,
               wireframe: bool = False, visible: bool = True,
               opacities: Sequence[ArrayLike | None] | None = None) -> None:
        """Show ``parts``: (unit mesh name, colour rgba (4,) or per copy (N, 4), placements
        (N, 4, 4)) per slot; ``opacity`` for all, or ``opacities`` per slot and copy
        (N,) (0 hides a copy without changing the count)."""
        for index, (mesh, colors, placements) in enumerate(parts):
            mats = np.asarray(placements, dtype=float).reshape(-1, 4, 4)
            count = len(mats)
            rgb = np.broadcast_to(rgb255(colors), (count, 3)) if count else np.zeros((0, 3), np.uint8)
            alpha = None if opacities is None or opacities[index] is None else \
                np.asarray(opacities[index], dtype=np.float32).reshape(count)
            wxyz, pos, scale = instance_poses(mats)
            node_opacity = None if opacity >= 1.0 else float(opacity)
            if index < len(self._slots):
                handle, old_mesh, old_count, old_rgb, old_alpha, old_wire = self._slots[index]
                if old_mesh == mesh and old_count == count == 0:
                    continue
                if old_mesh == mesh and old_count == count:
                    poses = wxyz.tobytes() + pos.tobytes() + scale.tobytes()
                    if self._poses[index] != poses:  # nothing is sent for copies that did not move
                        handle.batched_wxyzs, handle.batched_positions, handle.batched_scales = wxyz, pos, scale
                        self._poses[index] = poses
                    if rgb.tobytes() != old_rgb:
                        handle.batched_colors = np.ascontiguousarray(rgb)
                    alpha_key = b"" if alpha is None else alpha.tobytes()
                    if alpha_key != old_alpha:
                        handle.batched_opacities = alpha
                    if handle.opacity != node_opacity:
                        handle.opacity = node_opacity
                    if old_wire != wireframe:
                        handle.wireframe = wireframe
                    handle.visible = visible
                    self._slots[index] = (handle, mesh, count, rgb.tobytes(), alpha_key, wireframe)
                    continue
                handle.remove()
            self._slots[index:index + 1] = [self._add(index, mesh, count, wxyz, pos, scale, rgb, alpha,
                                                      node_opacity, wireframe, visible)]
            self._poses[index:index + 1] = [wxyz.tobytes() + pos.tobytes() + scale.tobytes()]
        for handle, *_ in self._slots[len(parts):]:
            handle.remove()
        del self._slots[len(parts):]
        del self._poses[len(parts):]

    def _add(self, index: int, mesh: str, count: int, wxyz: NDArray, pos: NDArray, scale: NDArray, rgb: NDArray,
             alpha: NDArray | None, opacity: float | None, wireframe: bool,
             visible: bool) -> tuple[Any, str, int, bytes, bytes, bool]:
        vertices, faces = unit_mesh(mesh)
        if len(pos) == 0:  # viser needs a copy: an empty slot is one copy shrunk to nothing
            wxyz, pos, scale = np.array([[1, 0, 0, 0]], np.float32), np.zeros((1, 3), np.float32), np.zeros((1, 3), np.float32)
            rgb = np.zeros((1, 3), np.uint8)
            alpha = None if alpha is None else np.zeros(1, np.float32)
        handle = self.scene.add_batched_meshes_simple(
            f"{self.prefix}/{index}", vertices, faces, batched_wxyzs=wxyz, batched_positions=pos,
            batched_scales=scale, batched_colors=np.ascontiguousarray(rgb), batched_opacities=alpha,
            opacity=opacity, wireframe=wireframe, lod="off", visible=visible)
        return handle, mesh, count, rgb.tobytes(), b"" if alpha is None else alpha.tobytes(), wireframe

    def clear(self) -> None:
        """Remove every slot's node."""
        for handle, *_ in self._slots:
            handle.remove()
        self._slots.clear()
        self._poses.clear()
