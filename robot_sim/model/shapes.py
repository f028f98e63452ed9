"""Geometry data: the solid shapes links and obstacles are made of.

Every shape is immutable (a frozen dataclass whose arrays are read-only) and carries
its placement in its parent frame (link frame i for a robot's shapes, the world for
obstacles) as ``pose``, a (4, 4) homogeneous transform in metres.  Cylinders and
capsules have their axis along the pose's z and are centred at the pose's origin.
Units are SI (metres); colours are RGBA in 0..1.

``shape.moved(tf)`` gives the same shape with ``pose = tf @ pose``: it moves a link's
shapes into the world once the link frame ``tf`` is known.

This module holds data only (no distances; those live in ``robot_sim.collision``) and
imports nothing of the project.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from collections.abc import Callable
from typing import Any, Optional, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]
Color = tuple[float, float, float, float]

#: Tolerance of the rotation block's orthonormality when a pose is checked.
POSE_TOL = 1e-6


def _readonly(arr: np.ndarray) -> np.ndarray:
    arr.setflags(write=False)
    return arr


def _pose(value: Any, what: str) -> FloatArray:
    """A rigid (4, 4) float transform, read-only; ValueError naming ``what`` otherwise."""
    try:
        m = np.array(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{what}.pose: expected a (4, 4) rigid transform, got {value!r}") from exc
    if m.shape != (4, 4) or not np.all(np.isfinite(m)):
        raise ValueError(f"{what}.pose: expected a finite (4, 4) rigid transform, got shape {m.shape}")
    rot = m[:3, :3]
    if (not np.allclose(rot.T @ rot, np.eye(3), atol=POSE_TOL)
            or abs(np.linalg.det(rot) - 1.0) > POSE_TOL
            or not np.allclose(m[3], (0.0, 0.0, 0.0, 1.0), atol=POSE_TOL)):
        raise ValueError(f"{what}.pose: not a rigid transform (rotation block must be orthonormal "
                         f"with det +1, bottom row [0, 0, 0, 1]): {m.tolist()}")
    return _readonly(m)


def _vector(value: Any, what: str, *, positive: bool = False) -> FloatArray:
    try:
        v = np.array(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{what}: expected 3 numbers, got {value!r}") from exc
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{what}: expected 3 finite numbers, got {value!r}")
    if positive and not np.all(v > 0.0):
        raise ValueError(f"{what}: every entry must be > 0, got {v.tolist()}")
    return _readonly(v)


def _length(value: Any, what: str, *, allow_zero: bool = False) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{what}: expected a number in metres, got {value!r}") from exc
    if not math.isfinite(x) or x < 0.0 or (x == 0.0 and not allow_zero):
        accepted = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{what}: expected a finite length {accepted} m, got {value!r}")
    return x


def _color(value: Any, what: str) -> Optional[Color]:
    if value is None:
        return None
    try:
        c = tuple(float(x) for x in value)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{what}.color: expected RGBA (or RGB) numbers in 0..1, got {value!r}") from exc
    if len(c) == 3:
        c = c + (1.0,)
    if len(c) != 4 or not all(0.0 <= x <= 1.0 for x in c):
        raise ValueError(f"{what}.color: expected RGBA (or RGB) numbers in 0..1, got {value!r}")
    return c  # type: ignore[return-value]


class _ShapeBase:
    """Equality by value (arrays compared element-wise), hashing and ``moved``."""

    def _key(self) -> tuple:
        out = []
        for f in dataclasses.fields(self):  # type: ignore[arg-type]
            if not f.compare:
                continue
            v = getattr(self, f.name)
            out.append(v.tobytes() if isinstance(v, np.ndarray) else v)
        return (type(self).__name__, *out)

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and self._key() == other._key()  # type: ignore[attr-defined]

    def __hash__(self) -> int:
        return hash(self._key())

    def moved(self, tf: ArrayLike):  # noqa: ANN201 - returns the same type
        """This shape with ``pose = tf @ pose`` (``tf`` a (4, 4) rigid transform)."""
        t = _pose(tf, f"{type(self).__name__}.moved(tf)")
        return dataclasses.replace(self, pose=t @ self.pose)  # type: ignore[arg-type]


@dataclass(frozen=True, eq=False)
class Box(_ShapeBase):
    """A box of full edge lengths ``size`` (3,) in metres, centred at ``pose``'s origin
    with its edges along the pose's axes."""

    size: FloatArray
    pose: FloatArray = field(default_factory=lambda: np.eye(4))
    color: Optional[Color] = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "size", _vector(self.size, "Box.size", positive=True))
        object.__setattr__(self, "pose", _pose(self.pose, "Box"))
        object.__setattr__(self, "color", _color(self.color, "Box"))

    @property
    def half_extents(self) -> FloatArray:
        """Half edge lengths (3,) in metres."""
        return self.size / 2.0


@dataclass(frozen=True, eq=False)
class Sphere(_ShapeBase):
    """A sphere of ``radius`` metres about ``center`` (3,) in its parent frame."""

    radius: float
    center: FloatArray = field(default_factory=lambda: np.zeros(3))
    color: Optional[Color] = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _length(self.radius, "Sphere.radius"))
        object.__setattr__(self, "center", _vector(self.center, "Sphere.center"))
        object.__setattr__(self, "color", _color(self.color, "Sphere"))

    @property
    def pose(self) -> FloatArray:
        """The translation transform (4, 4) to ``center``."""
        m = np.eye(4)
        m[:3, 3] = self.center
        return _readonly(m)

    def moved(self, tf: ArrayLike) -> "Sphere":
        """This sphere with its centre moved by ``tf`` (a (4, 4) rigid transform)."""
        t = _pose(tf, "Sphere.moved(tf)")
        return dataclasses.replace(self, center=t[:3, :3] @ self.center + t[:3, 3])


@dataclass(frozen=True, eq=False)
class Cylinder(_ShapeBase):
    """A solid cylinder of ``radius`` and ``length`` (metres) along the pose's z,
    centred at the pose's origin."""

    radius: float
    length: float
    pose: FloatArray = field(default_factory=lambda: np.eye(4))
    color: Optional[Color] = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _length(self.radius, "Cylinder.radius"))
        object.__setattr__(self, "length", _length(self.length, "Cylinder.length"))
        object.__setattr__(self, "pose", _pose(self.pose, "Cylinder"))
        object.__setattr__(self, "color", _color(self.color, "Cylinder"))


@dataclass(frozen=True, eq=False)
class Capsule(_ShapeBase):
    """All points within ``radius`` of the segment of ``length`` metres along the pose's
    z, centred at the pose's origin (``length`` is between the cap centres; 0 is a
    sphere)."""

    radius: float
    length: float
    pose: FloatArray = field(default_factory=lambda: np.eye(4))
    color: Optional[Color] = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "radius", _length(self.radius, "Capsule.radius"))
        object.__setattr__(self, "length", _length(self.length, "Capsule.length", allow_zero=True))
        object.__setattr__(self, "pose", _pose(self.pose, "Capsule"))
        object.__setattr__(self, "color", _color(self.color, "Capsule"))

    @property
    def endpoints(self) -> FloatArray:
        """The segment's two cap centres (2, 3) in the parent frame (-z end first)."""
        half = 0.5 * self.length * self.pose[:3, 2]
        c = self.pose[:3, 3]
        return _readonly(np.stack([c - half, c + half]))


MeshSource = Union[str, Path, tuple]


@dataclass(frozen=True, eq=False)
class Mesh(_ShapeBase):
    """A triangle mesh: ``source`` is a file path (loaded through trimesh when the
    vertices are first needed) or a ``(vertices (V, 3), faces (F, 3))`` pair.

    ``vertices`` are scaled by ``scale`` (3,) and expressed in the shape frame (before
    ``pose``); collision treats a mesh as its convex hull.
    """

    source: MeshSource
    pose: FloatArray = field(default_factory=lambda: np.eye(4))
    scale: FloatArray = field(default_factory=lambda: np.ones(3))
    color: Optional[Color] = None
    _data: list = field(default_factory=list, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "pose", _pose(self.pose, "Mesh"))
        object.__setattr__(self, "scale", _vector(self.scale, "Mesh.scale", positive=True))
        object.__setattr__(self, "color", _color(self.color, "Mesh"))
        src = self.source
        if isinstance(src, (str, Path)):
            object.__setattr__(self, "source", str(src))
        elif isinstance(src, (tuple, list)) and len(src) == 2:
            verts, faces = _mesh_arrays(src[0], src[1], "Mesh.source")
            object.__setattr__(self, "source", (verts, faces))
        else:
            raise ValueError(f"Mesh.source: expected a file path or a (vertices (V, 3), faces (F, 3)) "
                             f"pair, got {type(src).__name__}")

    @classmethod
    def from_file_data(
        cls, path: Union[str, Path], vertices: ArrayLike, faces: ArrayLike, *,
        pose: Optional[ArrayLike] = None, scale: ArrayLike = (1.0, 1.0, 1.0), color: Optional[Color] = None,
    ) -> "Mesh":
        """The mesh of file ``path`` whose contents, unscaled vertices (V, 3) [m] and
        faces (F, 3), were already read (by ``robot_sim.io.meshes`` while a robot loads,
        which checks the file then): ``path`` is kept and never read again."""
        mesh = cls(str(path), pose=np.eye(4) if pose is None else pose, scale=scale, color=color)
        mesh._data.append(_mesh_arrays(vertices, faces, f"Mesh {str(path)!r}"))
        return mesh

    def _key(self) -> tuple:
        src = self.source if isinstance(self.source, str) else (
            self.source[0].tobytes(), self.source[1].tobytes())
        return ("Mesh", src, self.pose.tobytes(), self.scale.tobytes(), self.color)

    @property
    def path(self) -> Optional[str]:
        """The mesh file's path, or None for a mesh given as arrays."""
        return self.source if isinstance(self.source, str) else None

    @property
    def data(self) -> tuple[FloatArray, NDArray[np.int64]]:
        """The unscaled vertices (V, 3) [m] and faces (F, 3), read-only: the same arrays
        for every shape made from one read of a file (so users may share work on them)."""
        return self._arrays()

    def _arrays(self) -> tuple[FloatArray, NDArray[np.int64]]:
        if isinstance(self.source, tuple):
            return self.source
        if not self._data:
            self._data.append(_load_mesh_file(self.source))
        return self._data[0]

    @property
    def vertices(self) -> FloatArray:
        """Scaled vertices (V, 3) in metres in the shape frame (before ``pose``)."""
        out = self._arrays()[0] * self.scale
        return _readonly(out)

    @property
    def faces(self) -> NDArray[np.int64]:
        """Triangles (F, 3) as indices into ``vertices``."""
        return self._arrays()[1]

    def moved(self, tf: ArrayLike) -> "Mesh":
        """This mesh with ``pose = tf @ pose``; a file already read is not read again."""
        t = _pose(tf, "Mesh.moved(tf)")
        out = dataclasses.replace(self, pose=t @ self.pose)
        out._data.extend(self._data)
        return out


def _owned(values: Any, dtype: Any) -> np.ndarray:
    """``values`` as an array this shape may keep: a read-only array is shared (a mesh
    file read once serves every shape made of it), anything else copied."""
    arr = np.asarray(values, dtype=dtype)
    return arr if not arr.flags.writeable else np.array(arr)


def _mesh_arrays(vertices: Any, faces: Any, what: str) -> tuple[FloatArray, NDArray[np.int64]]:
    try:
        v = _owned(vertices, float)
        f = _owned(faces, None)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{what}: vertices must be (V, 3) numbers and faces (F, 3) integers") from exc
    if v.ndim != 2 or v.shape[1] != 3 or len(v) < 1 or not np.all(np.isfinite(v)):
        raise ValueError(f"{what}: vertices must be a finite (V, 3) array with V >= 1, got shape {v.shape}")
    if f.size == 0:
        f = np.zeros((0, 3), dtype=np.int64)
    if f.ndim != 2 or f.shape[1] != 3 or not np.issubdtype(f.dtype, np.integer):
        raise ValueError(f"{what}: faces must be an (F, 3) integer array, got shape {f.shape} of {f.dtype}")
    if f.size and (f.min() < 0 or f.max() >= len(v)):
        raise ValueError(f"{what}: face indices must lie in 0..{len(v) - 1}, got {f.min()}..{f.max()}")
    return _readonly(v), _readonly(f.astype(np.int64, copy=False))


#: The reader of mesh files, ``read(path) -> (vertices (V, 3), faces (F, 3))``:
#: ``robot_sim.io.meshes`` installs its one reader here when imported (this module
#: imports nothing of the project).
MESH_FILE_READER: list[Callable[[Path], tuple[FloatArray, NDArray[np.int64]]]] = []


def _load_mesh_file(path: str) -> tuple[FloatArray, NDArray[np.int64]]:
    if not MESH_FILE_READER:
        raise ValueError(f"Mesh {path[:80]!r}: mesh files are read by robot_sim.io.meshes; "
                         "use rs.Mesh or import robot_sim.io.meshes first")
    vertices, faces = MESH_FILE_READER[0](Path(path))
    return _mesh_arrays(vertices, faces, f"Mesh {path[:80]!r}")


@dataclass(frozen=True, eq=False)
class HalfSpace(_ShapeBase):
    """The solid ``{x : normal · x <= offset}`` (the floor by default: everything
    below z = 0).  ``normal`` is stored normalised; ``offset`` is in metres."""

    normal: FloatArray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    offset: float = 0.0
    color: Optional[Color] = None

    def __post_init__(self) -> None:
        raw = _vector(self.normal, "HalfSpace.normal")
        norm = float(np.linalg.norm(raw))
        if norm < 1e-12:
            raise ValueError(f"HalfSpace.normal: must be a non-zero direction, got {raw.tolist()}")
        try:
            off = float(self.offset)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"HalfSpace.offset: expected a number in metres, got {self.offset!r}") from exc
        if not math.isfinite(off):
            raise ValueError(f"HalfSpace.offset: expected a finite number, got {self.offset!r}")
        n = _readonly(raw / norm)
        object.__setattr__(self, "normal", n)
        object.__setattr__(self, "offset", off / norm)
        object.__setattr__(self, "color", _color(self.color, "HalfSpace"))

    @property
    def pose(self) -> FloatArray:
        """A frame on the boundary plane: origin ``offset * normal``, z along ``normal``."""
        z = self.normal
        helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        x = np.cross(helper, z)
        x /= np.linalg.norm(x)
        m = np.eye(4)
        m[:3, 0], m[:3, 1], m[:3, 2] = x, np.cross(z, x), z
        m[:3, 3] = self.offset * z
        return _readonly(m)

    def moved(self, tf: ArrayLike) -> "HalfSpace":
        """The half-space carried by ``tf``: ``{tf @ x : normal · x <= offset}``."""
        t = _pose(tf, "HalfSpace.moved(tf)")
        n = t[:3, :3] @ self.normal
        return dataclasses.replace(self, normal=n, offset=self.offset + float(n @ t[:3, 3]))


#: Every shape type, for isinstance checks and dispatch.
Shape = Union[Box, Sphere, Cylinder, Capsule, Mesh, HalfSpace]
SHAPE_TYPES: tuple[type, ...] = (Box, Sphere, Cylinder, Capsule, Mesh, HalfSpace)
