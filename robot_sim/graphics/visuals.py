"""A robot's visual shapes turned into drawable pieces (pure NumPy, no GL).

Each piece is drawn at ``frames[piece.frame] @ piece.local``: frame 0 for the base
link's shapes (``robot.base_visuals``), frame i + 1 for ``robot.visuals[i]`` (the link
moved by joint i + 1, in the robot's own convention).  Primitives become unit meshes
placed and scaled by ``local``; a mesh keeps its vertices and faces, and
:func:`vertex_normals` gives it smooth (area-weighted) vertex normals.
Metres.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.meshes import CUBE_CORNERS
from robot_sim.model.params import RobotParams
from robot_sim.model.shapes import Box, Capsule, Cylinder, Mesh, Sphere

RGBA = tuple[float, float, float, float]


@dataclass(frozen=True)
class VisualPiece:
    """One thing to draw: unit mesh ``unit`` (a name of ``meshes.unit_meshes``) or the
    triangle mesh ``vertices`` (V, 3) / ``faces`` (F, 3), placed at ``local`` (4, 4) in
    robot frame ``frame``, in ``color``."""

    frame: int
    local: NDArray[np.float64]
    color: RGBA
    unit: str | None = None
    vertices: NDArray[np.float64] | None = None
    faces: NDArray[np.int64] | None = None

    @functools.cached_property
    def box(self) -> NDArray[np.float64]:
        """Corners (8, 4) of the bounding box of the piece's own vertices (homogeneous,
        in its ``local`` frame): the mesh's, or the unit mesh's."""
        unit_box = np.c_[CUBE_CORNERS, np.ones(8)]
        if self.vertices is not None:
            lo, hi = self.vertices.min(axis=0), self.vertices.max(axis=0)
            return np.c_[np.where(unit_box[:, :3] < 0, lo, hi), np.ones(8)]
        if self.unit in ("joint", "cylinder"):
            return unit_box * (1.0, 1.0, 0.5, 1.0) + (0.0, 0.0, 0.5, 0.0)
        return unit_box * (0.5, 0.5, 0.5, 1.0) if self.unit == "box" else unit_box


def vertex_normals(vertices: NDArray[np.float64], faces: NDArray[np.int64]) -> NDArray[np.float64]:
    """Unit normals (V, 3) at ``vertices`` (V, 3): the sum of the cross products of the
    faces (F, 3) around each vertex (area-weighted, counter-clockwise faces outward);
    a vertex on no face gets +z."""
    tri = vertices[faces]
    face_n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    normals = np.zeros_like(vertices)
    for axis in range(3):
        normals[:, axis] = np.bincount(faces.ravel(), weights=np.repeat(face_n[:, axis], 3), minlength=len(vertices))
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.where(length > 0.0, normals / np.where(length > 0.0, length, 1.0), [0.0, 0.0, 1.0])
    return normals


def _scaled(pose: NDArray[np.float64], offset: tuple[float, float, float], scale: tuple[float, float, float]) -> NDArray:
    local = np.diag([*scale, 1.0])
    local[:3, 3] = offset
    return pose @ local


def shape_pieces(shape: object, frame: int) -> list[VisualPiece]:
    """The pieces of one visual ``shape`` (a :mod:`robot_sim.model.shapes` shape) of
    robot frame ``frame``.  Raises TypeError for anything else."""
    color = tuple(shape.color) if getattr(shape, "color", None) is not None else gd.VISUAL_COLOR  # type: ignore[attr-defined]
    if isinstance(shape, Mesh):
        vertices, faces = np.asarray(shape.vertices, dtype=float), np.asarray(shape.faces, dtype=np.int64)
        return [VisualPiece(frame, np.asarray(shape.pose, dtype=float), color, vertices=vertices, faces=faces)]
    if isinstance(shape, Box):
        return [VisualPiece(frame, _scaled(shape.pose, (0.0, 0.0, 0.0), tuple(shape.size)), color, unit="box")]
    if isinstance(shape, Sphere):
        r = shape.radius
        return [VisualPiece(frame, _scaled(shape.pose, (0.0, 0.0, 0.0), (r, r, r)), color, unit="sphere")]
    if isinstance(shape, Cylinder):
        r, length = shape.radius, shape.length
        return [VisualPiece(frame, _scaled(shape.pose, (0.0, 0.0, -length / 2), (r, r, length)), color, unit="joint")]
    if isinstance(shape, Capsule):
        r, length = shape.radius, shape.length
        return [VisualPiece(frame, _scaled(shape.pose, (0.0, 0.0, -length / 2), (r, r, length)), color, unit="cylinder")] + [
            VisualPiece(frame, _scaled(shape.pose, (0.0, 0.0, z), (r, r, r)), color, unit="sphere")
            for z in (-length / 2, length / 2)]
    raise TypeError(f"visual shape: expected a Box, Sphere, Cylinder, Capsule or Mesh, got {type(shape).__name__}")


def visual_pieces(robot: RobotParams) -> list[VisualPiece]:
    """Every piece of ``robot``'s visuals (base link first)."""
    pieces = [p for shape in robot.base_visuals for p in shape_pieces(shape, 0)]
    for i, shapes in enumerate(robot.visuals):
        pieces += [p for shape in shapes for p in shape_pieces(shape, i + 1)]
    return pieces


def piece_corners(pieces: list[VisualPiece], frames: NDArray[np.float64]) -> NDArray[np.float64]:
    """World corners (N, 3) of the bounding boxes of ``pieces`` at robot ``frames``."""
    out = [(piece.box @ (frames[piece.frame] @ piece.local).T)[:, :3] for piece in pieces]
    return np.vstack(out) if out else np.zeros((0, 3))
