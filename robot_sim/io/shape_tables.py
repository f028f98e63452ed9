"""Link geometry in robot files: ``[[joints.visual]]``, ``[[joints.collision]]`` (and the
same under ``[base]``) read with validation and written back.

One table is one shape, posed in the link's frame (frame i of the file's convention;
frame 0 under ``[base]``) by ``xyz`` [m] and ``rpy`` (the file's angle units) and given
by exactly one of:

* ``mesh = "meshes/link1.stl"``: a mesh file (STL, OBJ, PLY, DAE), relative to the robot
  file's folder, with an optional ``scale`` (one factor or three, > 0);
* ``box = [x, y, z]``: full edge lengths [m];
* ``sphere = r``: radius [m];
* ``cylinder = [radius, length]`` and ``capsule = [radius, length]`` [m], along z
  (a capsule's length is between its cap centres and may be 0).

A visual may carry ``color = [r, g, b]`` or ``[r, g, b, a]`` in 0..1.  A bad table is
one error naming the file, the joint and the field (``joints[1].visual[0].scale``).
"""
from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from robot_sim.io.checker import LENGTH_BOUND, Bound, FieldChecker
from robot_sim.io.meshes import MeshReader
from robot_sim.io.urdf_shapes import Shape, mesh_filename
from robot_sim.model.messages import clip_repr
from robot_sim.model.shapes import Box, Capsule, Cylinder, Mesh, Sphere
from robot_sim.transforms import HomogeneousTransform, rpy_from_rot

#: The keys that say what a shape is (exactly one per table).
SHAPE_KINDS = ("mesh", "box", "sphere", "cylinder", "capsule")
#: Keys of a ``[[joints.visual]]`` table; a collision table has no colour.
VISUAL_KEYS = {*SHAPE_KINDS, "xyz", "rpy", "scale", "color"}
COLLISION_KEYS = VISUAL_KEYS - {"color"}
#: The array-of-tables keys holding geometry in a joint table and in ``[base]``.
GEOMETRY_KEYS = ("visual", "collision")
#: Largest mesh scale factor accepted (a mesh in kilometres would be absurd for an arm).
MAX_SCALE = 1000.0


class ShapeTables:
    """Reads the shape tables of one robot file: ``check`` names the file in errors,
    ``directory`` is where its mesh paths start, ``to_rad`` converts its angles and
    ``length``/``angle`` bound its values.  ``meshes`` reads mesh files; None builds mesh
    shapes without reading them (to compare a file's tables with a robot's shapes)."""

    def __init__(self, check: FieldChecker, directory: Path, to_rad: float, length: Bound, angle: Bound,
                 meshes: MeshReader | None) -> None:
        self.check, self.directory, self.to_rad = check, directory, to_rad
        self.length, self.angle, self.meshes = length, angle, meshes

    def shapes(self, value: Any, where: str, kind: str) -> tuple[Shape, ...]:
        """The shapes of the array of tables ``value`` at ``where`` (e.g.
        ``joints[2].visual``); ``kind`` is "visual" or "collision"."""
        if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
            raise self.check.fail(where, f"expected an array of tables ([[...{kind}]]), got {clip_repr(value)}")
        out = [self.shape(table, f"{where}[{k}]", kind) for k, table in enumerate(value)]
        return tuple(shape for shape in out if shape is not None)

    def shape(self, table: dict[str, Any], where: str, kind: str) -> Shape | None:
        check = self.check
        check.keys(table, VISUAL_KEYS if kind == "visual" else COLLISION_KEYS, where)
        given = [key for key in SHAPE_KINDS if key in table]
        if len(given) != 1:
            raise check.fail(where, f"expected exactly one of {', '.join(SHAPE_KINDS)}, got {len(given)}")
        shape = given[0]
        xyz = check.vector(table.get("xyz", [0.0, 0.0, 0.0]), 3, f"{where}.xyz", self.length)
        rpy = check.vector(table.get("rpy", [0.0, 0.0, 0.0]), 3, f"{where}.rpy", self.angle)
        pose = HomogeneousTransform.from_xyz_rpy(xyz, np.array(rpy) * self.to_rad).mat
        color = self._color(table["color"], f"{where}.color") if "color" in table else None
        if "scale" in table and shape != "mesh":
            raise check.fail(f"{where}.scale", f"scale applies to meshes only, not to a {shape}")
        value, at = table[shape], f"{where}.{shape}"
        if shape == "mesh":
            return self._mesh(value, at, pose, self._scale(table.get("scale", 1.0), f"{where}.scale"), color)
        if shape == "box":
            return Box(self._lengths(value, 3, at, "[x, y, z] edge lengths"), pose=pose, color=color)
        if shape == "sphere":
            radius = self.check.number(value, at, self.length)
            if not radius > 0.0:
                raise check.fail(at, f"expected a radius > 0 m, got {clip_repr(value)}")
            return Sphere(radius, center=pose[:3, 3], color=color)
        radius, length = self._lengths(value, 2, at, "[radius, length]", zero_last=shape == "capsule")
        return (Cylinder if shape == "cylinder" else Capsule)(radius, length, pose=pose, color=color)

    def _lengths(self, value: Any, count: int, where: str, what: str, zero_last: bool = False) -> list[float]:
        if not isinstance(value, list) or len(value) != count:
            raise self.check.fail(where, f"expected {what} in metres, got {clip_repr(value)}")
        numbers = self.check.vector(value, count, where, self.length)
        if not all(v > 0.0 or (zero_last and k == count - 1 and v == 0.0) for k, v in enumerate(numbers)):
            rule = "> 0 (the length may be 0)" if zero_last else "> 0"
            raise self.check.fail(where, f"expected {what} {rule} m, got {clip_repr(value)}")
        return numbers

    def _scale(self, value: Any, where: str) -> np.ndarray:
        factors = [self.check.number(value, where)] if not isinstance(value, list) else self.check.vector(value, 3, where)
        if not all(0.0 < f <= MAX_SCALE for f in factors):
            raise self.check.fail(where, f"expected a scale factor or three, each > 0 and <= {MAX_SCALE:g}, got {clip_repr(value)}")
        return np.broadcast_to(np.array(factors, dtype=float), 3).copy()

    def _color(self, value: Any, where: str) -> tuple[float, ...]:
        if not isinstance(value, list) or len(value) not in (3, 4):
            raise self.check.fail(where, f"expected [r, g, b] or [r, g, b, a] in 0..1, got {clip_repr(value)}")
        rgba = [self.check.number(v, f"{where}[{k}]") for k, v in enumerate(value)]
        if not all(0.0 <= v <= 1.0 for v in rgba):
            raise self.check.fail(where, f"expected [r, g, b] or [r, g, b, a] in 0..1, got {clip_repr(value)}")
        return tuple(rgba + [1.0] * (4 - len(rgba)))

    def _mesh(self, value: Any, where: str, pose: np.ndarray, scale: np.ndarray, color: Any) -> Mesh | None:
        if not isinstance(value, str) or not value.strip():
            raise self.check.fail(where, f"expected the path of a mesh file (relative to the robot file), got {clip_repr(value)}")
        path = Path(os.path.abspath(self.directory / Path(value).expanduser()))
        if self.meshes is None:
            return Mesh(str(path), pose=pose, scale=scale, color=color)
        return self.meshes.mesh(path, where, pose, scale, color)


def shape_tables(shapes: tuple[Shape, ...], directory: Path | None, to_rad: float,
                 number: Callable[[float, float], float]) -> list[dict[str, Any]]:
    """The robot-file tables of ``shapes``: angles written as ``number(value, to_rad)``
    (the writer's shortest exact form in the file's unit), mesh paths relative to
    ``directory`` (absolute when None).  ValueError for a mesh without a file."""
    tables = []
    for shape in shapes:
        table: dict[str, Any] = {}
        if isinstance(shape, Mesh):
            if shape.path is None:
                raise ValueError("a mesh given as arrays has no file to name in a robot file")
            table["mesh"] = mesh_filename(shape.path, directory)
            if not np.array_equal(shape.scale, np.ones(3)):
                table["scale"] = [float(v) for v in shape.scale]
        elif isinstance(shape, Box):
            table["box"] = [float(v) for v in shape.size]
        elif isinstance(shape, Sphere):
            table["sphere"] = float(shape.radius)
        else:
            table["cylinder" if isinstance(shape, Cylinder) else "capsule"] = [float(shape.radius), float(shape.length)]
        pose = shape.pose
        if pose[:3, 3].any():
            table["xyz"] = [float(v) + 0.0 for v in pose[:3, 3]]
        rpy = rpy_from_rot(pose[:3, :3])
        if any(rpy) and not isinstance(shape, Sphere):
            table["rpy"] = [number(v, to_rad) for v in rpy]
        if shape.color is not None:
            table["color"] = list(shape.color)
        tables.append(table)
    return tables


def sync_shape_tables(table: Any, shapes: dict[str, tuple[Shape, ...]], directory: Path | None,
                      template_dir: Path, to_rad: float, angle: Bound, number: Callable[[float, float], float]) -> None:
    """Bring the ``[[...visual]]`` and ``[[...collision]]`` arrays of the tomlkit ``table``
    (a joint's or ``[base]``) up to date with ``shapes`` (key → shapes): an array whose
    tables load to the same shapes (mesh paths read from ``template_dir``) is kept with
    its comments, another is rewritten (mesh paths relative to ``directory``, absolute
    when None; angles by ``number``, see :func:`shape_tables`) and an empty one removed."""
    import tomlkit  # the writer's library, needed only when writing

    for key in GEOMETRY_KEYS:
        wanted = shapes[key]
        if not wanted:
            if key in table:
                del table[key]
            continue
        if key in table and _loads_to(table[key], key, wanted, template_dir, to_rad, angle):
            continue
        array = tomlkit.aot()
        for entry in shape_tables(wanted, directory, to_rad, number):
            item = tomlkit.table()
            item.update(entry)
            item.trivia.indent = "\n"  # a blank line before each [[...]] header
            array.append(item)
        table[key] = array


def _loads_to(value: Any, key: str, shapes: tuple[Shape, ...], directory: Path, to_rad: float, angle: Bound) -> bool:
    """True if the file's array ``value`` loads to exactly ``shapes`` (no mesh is read)."""
    reader = ShapeTables(FieldChecker(directory / "template"), directory, to_rad, LENGTH_BOUND, angle, None)
    try:
        unwrapped = value.unwrap() if hasattr(value, "unwrap") else value
        return reader.shapes(unwrapped, key, key) == shapes
    except ValueError:  # RobotDefinitionError: a table that does not load is rewritten
        return False
