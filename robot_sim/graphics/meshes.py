"""Unit meshes of the viewer as triangle arrays (pure NumPy, no GL).

Every mesh is modelled once at unit size; parts scale and place it with a matrix.
Vertex and normal arrays have shape (M, 3, 3): M triangles of three corners.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd

#: Corners (8, 3) of the cube of half side 1 about the origin.
CUBE_CORNERS = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])

Z_AXIS = np.array([0.0, 0.0, 1.0])


def _ring(slices: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Cosines and sines (slices + 1,) of angles 0..2π, first and last equal."""
    angles = np.linspace(0.0, 2.0 * np.pi, slices + 1)
    return np.cos(angles), np.sin(angles)


def _quads_to_triangles(a: NDArray, b: NDArray, c: NDArray, d: NDArray) -> NDArray:
    """Triangles (2M, 3, k) of quads with corners a, b, c, d (each (M, k)) in order."""
    return np.concatenate([np.stack([a, b, c], axis=1), np.stack([a, c, d], axis=1)])


def cylinder_mesh(slices: int) -> tuple[NDArray, NDArray]:
    """Side of the unit cylinder: radius 1, z from 0 to 1, smooth radial normals."""
    c, s = _ring(slices)
    rim = np.c_[c, s, np.zeros_like(c)]
    bottom, top = rim, rim + Z_AXIS
    verts = _quads_to_triangles(bottom[:-1], bottom[1:], top[1:], top[:-1])
    normals = _quads_to_triangles(rim[:-1], rim[1:], rim[1:], rim[:-1])
    return verts, normals


def disk_mesh(slices: int, z: float, facing: float) -> tuple[NDArray, NDArray]:
    """Unit disk at height ``z`` with its normal along ``facing`` * z (``facing`` = ±1)."""
    c, s = _ring(slices)
    rim = np.c_[c, s, np.full_like(c, z)]
    centre = np.tile([0.0, 0.0, z], (slices, 1))
    ahead, behind = (rim[:-1], rim[1:]) if facing > 0 else (rim[1:], rim[:-1])  # counter-clockwise seen from outside
    verts = np.stack([centre, ahead, behind], axis=1)
    normals = np.broadcast_to([0.0, 0.0, facing], verts.shape)
    return verts, normals


def cone_mesh(slices: int) -> tuple[NDArray, NDArray]:
    """Unit cone: base disk of radius 1 at z = 0 (facing -z), apex at z = 1."""
    c, s = _ring(slices)
    rim = np.c_[c, s, np.zeros_like(c)]
    slant = np.c_[c, s, np.ones_like(c)] / math.sqrt(2.0)
    mid = 0.5 * (slant[:-1] + slant[1:])
    apex = np.tile(Z_AXIS, (slices, 1))
    side_v = np.stack([rim[:-1], rim[1:], apex], axis=1)
    side_n = np.stack([slant[:-1], slant[1:], mid], axis=1)
    base_v, base_n = disk_mesh(slices, 0.0, -1.0)
    return np.concatenate([side_v, base_v]), np.concatenate([side_n, base_n])


def sphere_mesh(slices: int, stacks: int) -> tuple[NDArray, NDArray]:
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


def box_mesh() -> tuple[NDArray, NDArray]:
    """Unit cube centred at the origin (sides from -0.5 to 0.5), flat face normals."""
    verts, normals = [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, v = np.eye(3)[(axis + 1) % 3], np.eye(3)[(axis + 2) % 3]
            n = sign * np.eye(3)[axis]
            corners = 0.5 * np.array([n - u - v, n + u - v, n + u + v, n - u + v])
            order = [0, 1, 2, 0, 2, 3] if sign > 0 else [0, 2, 1, 0, 3, 2]  # counter-clockwise seen from outside
            verts.append(corners[order].reshape(2, 3, 3))
            normals.append(np.broadcast_to(n, (2, 3, 3)))
    return np.concatenate(verts), np.concatenate(normals)


def unit_meshes() -> dict[str, tuple[NDArray, NDArray]]:
    """All unit meshes by name as triangle vertex and normal arrays (M, 3, 3)."""
    n = gd.CYLINDER_SLICES
    side = cylinder_mesh(n)
    top, bottom = disk_mesh(n, 1.0, 1.0), disk_mesh(n, 0.0, -1.0)
    return {
        "cylinder": side,
        # A revolute joint: the cylinder closed by disks at both ends.
        "joint": tuple(np.concatenate(parts) for parts in zip(side, top, bottom)),  # type: ignore[dict-item]
        "cone": cone_mesh(n),
        "sphere": sphere_mesh(gd.SPHERE_SLICES, gd.SPHERE_STACKS),
        "box": box_mesh(),
    }
