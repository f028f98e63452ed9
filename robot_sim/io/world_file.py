"""World files: the obstacles around a robot, read into a :class:`~robot_sim.model.world.World`.

A world file is data (``tomllib``), validated like a robot file: a bad file raises
:class:`WorldDefinitionError` naming the file, the field, the value and what is accepted.

```toml
units = "deg"            # optional, "rad" (default) or "deg": every rpy below
floor = true             # optional: the half-space z <= 0, named "floor" (default true)

[[obstacles]]
name = "table"           # unique, not "floor" while the floor is on
shape = "box"            # box | sphere | cylinder | capsule | mesh
size = [0.8, 0.6, 0.04]  # box: full edge lengths (m)
xyz = [0.5, 0.0, 0.38]   # the shape's centre in the world (m)
rpy = [0.0, 0.0, 0.0]    # its orientation (roll, pitch, yaw about x, y, z)

[[obstacles]]
name = "post"
shape = "cylinder"       # cylinder and capsule: radius and length (m) along their z
radius = 0.03            # sphere: radius only
length = 0.5
xyz = [0.3, 0.4, 0.25]

[[obstacles]]
name = "fixture"
shape = "mesh"           # collides as the convex hull of its vertices
mesh = "meshes/fixture.stl"   # relative to this file
scale = [0.001, 0.001, 0.001]
```
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from robot_sim.io.checker import LENGTH_BOUND, FieldChecker
from robot_sim.io.meshes import MeshError, read_mesh
from robot_sim.io.robot_file import ANGLE_BOUNDS, UNITS, read_toml
from robot_sim.model.messages import clip_repr
from robot_sim.model.shapes import Box, Capsule, Cylinder, Mesh, Sphere
from robot_sim.model.world import FLOOR_NAME, World
from robot_sim.transforms import HomogeneousTransform

TOP_KEYS = {"units", "floor", "obstacles"}
POSE_KEYS = {"name", "shape", "xyz", "rpy", "color"}
#: Size keys of each shape (besides POSE_KEYS).
SHAPE_KEYS = {
    "box": {"size"},
    "sphere": {"radius"},
    "cylinder": {"radius", "length"},
    "capsule": {"radius", "length"},
    "mesh": {"mesh", "scale"},
}
MAX_OBSTACLES = 1000


class WorldDefinitionError(ValueError):
    """A world file could not be loaded; the message names file, field and value."""


class _Checker(FieldChecker):
    def fail(self, where: str, message: str) -> WorldDefinitionError:  # type: ignore[override]
        return WorldDefinitionError(f"{self.path}: {where}: {message}")

    def positive(self, value: Any, where: str) -> float:
        x = self.number(value, where, LENGTH_BOUND)
        if x <= 0.0:
            raise self.fail(where, f"expected a length > 0 m, got {clip_repr(value)}")
        return x


def load_world(path: str | Path) -> World:
    """Read and validate the world file at ``path`` (format: module docstring)."""
    path = Path(path)
    return parse_world(read_toml(path, "world file", WorldDefinitionError), path)


def parse_world(data: dict[str, Any], path: str | Path) -> World:
    """Validate the parsed TOML ``data`` of a world file (``path`` names it in errors and
    anchors relative mesh paths) and build the world."""
    path = Path(path)
    check = _Checker(path)
    check.keys(data, TOP_KEYS, "")
    units = data.get("units", "rad")
    if not isinstance(units, str) or units not in UNITS:
        raise check.fail("units", f"unknown units {clip_repr(units)}; accepted: 'deg' or 'rad'")
    floor = data.get("floor", True)
    if not isinstance(floor, bool):
        raise check.fail("floor", f"expected true or false, got {clip_repr(floor)}")
    obstacles = data.get("obstacles", [])
    if not isinstance(obstacles, list):
        raise check.fail("obstacles", "expected [[obstacles]] tables")
    if len(obstacles) > MAX_OBSTACLES:
        raise check.fail("obstacles", f"{len(obstacles)} obstacles; at most {MAX_OBSTACLES} are accepted")
    names = {FLOOR_NAME} if floor else set()
    items = []
    for k, table in enumerate(obstacles):
        where = f"obstacles[{k}]"
        name, shape = _obstacle(check, table, where, units, path)
        if name in names:
            hint = " (the floor is on: name it otherwise or set floor = false)" if name == FLOOR_NAME else ""
            raise check.fail(f"{where}.name", f"obstacle name {clip_repr(name)} is used twice{hint}")
        names.add(name)
        items.append((name, shape))
    return World(items, floor=floor)


def _obstacle(check: _Checker, table: Any, where: str, units: str, path: Path) -> tuple[str, Any]:
    if not isinstance(table, dict):
        raise check.fail(where, f"expected a table, got {clip_repr(table)}")
    kind = table.get("shape")
    if not isinstance(kind, str) or kind not in SHAPE_KEYS:
        raise check.fail(f"{where}.shape", f"unknown shape {clip_repr(kind)}; accepted: {', '.join(SHAPE_KEYS)}")
    check.keys(table, POSE_KEYS | SHAPE_KEYS[kind], where)
    name = table.get("name")
    if not isinstance(name, str) or not name.strip() or not name.isprintable():
        raise check.fail(f"{where}.name", f"expected a non-empty name on one line, got {clip_repr(name)}")
    xyz = check.vector(table.get("xyz", [0.0, 0.0, 0.0]), 3, f"{where}.xyz", LENGTH_BOUND)
    rpy = check.vector(table.get("rpy", [0.0, 0.0, 0.0]), 3, f"{where}.rpy", ANGLE_BOUNDS[units])
    pose = HomogeneousTransform.from_xyz_rpy(xyz, np.array(rpy) * UNITS[units]).mat
    color = None
    if "color" in table:
        color = check.vector(table["color"], 4, f"{where}.color")
        if not all(0.0 <= c <= 1.0 for c in color):
            raise check.fail(f"{where}.color", f"expected RGBA numbers in 0..1, got {clip_repr(table['color'])}")
        color = tuple(color)
    for key in sorted(SHAPE_KEYS[kind] - {"scale"}):
        if key not in table:
            raise check.fail(f"{where}.{key}", f"missing: a {kind} needs {' and '.join(sorted(SHAPE_KEYS[kind] - {'scale'}))}")
    if kind == "box":
        size = [check.positive(v, f"{where}.size[{i}]") for i, v in enumerate(_list3(check, table["size"], f"{where}.size"))]
        return name, Box(size, pose, color)
    if kind == "sphere":
        return name, Sphere(check.positive(table["radius"], f"{where}.radius"), xyz, color)
    if kind in ("cylinder", "capsule"):
        radius = check.positive(table["radius"], f"{where}.radius")
        length = check.positive(table["length"], f"{where}.length")
        return name, (Cylinder if kind == "cylinder" else Capsule)(radius, length, pose, color)
    return name, _mesh(check, table, where, pose, color, path)


def _list3(check: _Checker, value: Any, where: str) -> list:
    if not isinstance(value, list) or len(value) != 3:
        raise check.fail(where, f"expected a list of 3 numbers, got {clip_repr(value)}")
    return value


def _mesh(check: _Checker, table: dict, where: str, pose: np.ndarray, color: Any, path: Path) -> Mesh:
    rel = table["mesh"]
    if not isinstance(rel, str) or not rel:
        raise check.fail(f"{where}.mesh", f"expected a file path, got {clip_repr(rel)}")
    scale = [1.0, 1.0, 1.0]
    if "scale" in table:
        scale = [check.positive(v, f"{where}.scale[{i}]") for i, v in enumerate(_list3(check, table["scale"], f"{where}.scale"))]
    try:
        file = Path(os.path.abspath(path.parent / Path(rel).expanduser()))
    except (OSError, ValueError):
        raise check.fail(f"{where}.mesh", f"not a usable file path: {clip_repr(rel)}") from None
    try:
        vertices, faces = read_mesh(file)  # the one mesh reader: formats, size caps, cache
    except MeshError as exc:
        raise check.fail(f"{where}.mesh", str(exc)) from None
    return Mesh.from_file_data(file, vertices, faces, pose=pose, scale=scale, color=color)
