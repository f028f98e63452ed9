"""Shapes (:mod:`robot_sim.model.shapes`) packed into kind codes and float records for
the compiled kernels (:mod:`.layout`), and the bounding sphere of each.

A mesh enters as its convex hull: its support point in any direction is its farthest
vertex, so its vertices (deduplicated) are all the kernels need.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.model.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Sphere

from robot_sim.collision import layout as L

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Packed:
    """Shapes packed for the kernels: ``kinds`` (S,), ``recs`` (S, REC) with each
    shape's pose in its parent frame, ``verts`` (V, 3) the convex shapes' vertices in
    their own frames, and ``bound_center`` (S, 3) / ``bound_radius`` (S,) a sphere in
    the parent frame holding each shape (radius inf for a half-space)."""

    kinds: NDArray[np.int64]
    recs: FloatArray
    verts: FloatArray
    bound_center: FloatArray
    bound_radius: FloatArray


def _record(pose: FloatArray) -> FloatArray:
    rec = np.zeros(L.REC)
    rec[L.ROT:L.ROT + 9] = pose[:3, :3].reshape(9)
    rec[L.POS:L.POS + 3] = pose[:3, 3]
    return rec


def pack(shapes: list) -> Packed:
    """Pack ``shapes`` (any of the model's shape types), keeping their order; meshes made
    from one read of a file at one scale share one block of vertices."""
    kinds, recs, verts, centers, radii = [], [], [], [], []
    n_verts = 0
    blocks: dict[tuple[int, bytes], tuple[int, int, FloatArray, float]] = {}  # a mesh's vertices, packed once
    for shape in shapes:
        center, radius = None, 0.0
        if isinstance(shape, Sphere):
            kind, rec = L.SPHERE, _record(shape.pose)
            rec[L.RADIUS] = shape.radius
            radius = shape.radius
        elif isinstance(shape, Capsule):
            kind, rec = L.CAPSULE, _record(shape.pose)
            rec[L.RADIUS], rec[L.HALF_LENGTH] = shape.radius, 0.5 * shape.length
            radius = shape.radius + 0.5 * shape.length
        elif isinstance(shape, Box):
            kind, rec = L.BOX, _record(shape.pose)
            rec[L.HALF_X:L.HALF_Z + 1] = shape.half_extents
            radius = float(np.linalg.norm(shape.half_extents))
        elif isinstance(shape, Cylinder):
            kind, rec = L.CYLINDER, _record(shape.pose)
            rec[L.CYL_RADIUS], rec[L.HALF_LENGTH] = shape.radius, 0.5 * shape.length
            radius = math.hypot(shape.radius, 0.5 * shape.length)
        elif isinstance(shape, Mesh):
            kind, rec = L.CONVEX, _record(shape.pose)
            key = (id(shape.data[0]), shape.scale.tobytes())  # shapes of one file share one block
            if key not in blocks:
                v = np.unique(np.asarray(shape.vertices, dtype=float), axis=0)
                mid = 0.5 * (v.min(axis=0) + v.max(axis=0))
                blocks[key] = (n_verts, len(v), mid, float(np.linalg.norm(v - mid, axis=1).max()))
                verts.append(v)
                n_verts += len(v)
            start, count, mid, radius = blocks[key]
            center = shape.pose[:3, :3] @ mid + shape.pose[:3, 3]
            rec[L.VSTART], rec[L.VCOUNT] = start, count
        elif isinstance(shape, HalfSpace):
            kind, rec = L.HALFSPACE, _record(shape.pose)
            radius = math.inf
        else:
            raise TypeError(f"cannot pack {type(shape).__name__}: expected a Box, Sphere, Cylinder, "
                            "Capsule, Mesh or HalfSpace")
        kinds.append(kind)
        recs.append(rec)
        centers.append(rec[L.POS:L.POS + 3] if center is None else center)
        radii.append(radius)
    return Packed(
        kinds=np.array(kinds, dtype=np.int64),
        recs=np.array(recs, dtype=float).reshape(-1, L.REC),
        verts=np.concatenate(verts) if verts else np.zeros((0, 3)),
        bound_center=np.array(centers, dtype=float).reshape(-1, 3),
        bound_radius=np.array(radii, dtype=float),
    )
