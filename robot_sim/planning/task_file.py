"""Pick-and-place task descriptions: :class:`TaskSpec` and the loader for task TOML files.

A task file is data (``tomllib``), validated like a robot file: a bad file raises
:class:`TaskDefinitionError` naming the file, the field, the value and what is accepted.

```toml
name = "pick the block"          # optional
units = "deg"                    # "deg" or "rad": every rpy below
[table]                          # a box; xyz is the centre of its top face (world, m)
xyz = [0.5, 0.0, 0.3]
size = [0.5, 0.7, 0.3]           # x, y, z extent (m); the box hangs below xyz
[object]
shape = "box"                    # "box" (size = [x, y, z]) or "cylinder" (size = [diameter, height])
size = [0.04, 0.04, 0.08]
xyz = [0.45, -0.2, 0.34]         # object frame = its centre, world (m)
rpy = [0.0, 0.0, 0.0]
[grasp]                          # tool frame in the object frame (default: a finger length above
xyz = [0.0, 0.0, 0.06]           # the centre, z down: the fingers reach from the tool to the centre)
rpy = [180.0, 0.0, 0.0]
[place]                          # object frame in the world when placed
xyz = [0.45, 0.2, 0.34]
rpy = [0.0, 0.0, 0.0]
[motion]                         # optional
approach = 0.10                  # m: pre-grasp and retreat height above grasp / place
lift = 0.15                      # m: lift height
speed = 0.15                     # m/s: mean tool speed of the straight-line moves
dwell = 0.5                      # s: closing / opening the gripper
[[obstacles]]                    # optional, any number: the world file's format
name = "post"                    # (robot_sim.io.world_file; "table" is the table's name)
shape = "cylinder"
radius = 0.02
length = 0.3
xyz = [0.5, 0.0, 0.45]
```

SI units inside; no Qt, no OpenGL.
"""
from __future__ import annotations

import dataclasses
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robot_sim.model.arrays import frozen
from robot_sim.io import robot_file
from robot_sim.io.checker import LENGTH_BOUND, Bound, FieldChecker
from robot_sim.model.messages import clip_repr
from robot_sim.io.robot_file import UNITS
from robot_sim.io.world_file import WorldDefinitionError, parse_world
from robot_sim.model.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Shape, Sphere
from robot_sim.model.world import FLOOR_NAME, World
from robot_sim.transforms import HomogeneousTransform, rot_x

FloatArray = NDArray[np.float64]

SHAPES = ("box", "cylinder")
TOP_KEYS = {"name", "units", "table", "object", "grasp", "place", "motion", "obstacles"}
#: The table's obstacle name in the task's world (an obstacle may not take it).
TABLE_NAME = "table"
TABLE_KEYS = {"xyz", "size"}
OBJECT_KEYS = {"shape", "size", "xyz", "rpy"}
POSE_KEYS = {"xyz", "rpy"}
MOTION_DEFAULTS = {"approach": 0.10, "lift": 0.15, "speed": 0.15, "dwell": 0.5}
#: Accepted range of each [motion] value (smallest, largest, unit): the motion is sampled
#: at 1 kHz, so these bound its length before anything is planned.
MOTION_BOUNDS = {"approach": (0.0, 10.0, "m"), "lift": (0.0, 10.0, "m"), "speed": (0.001, 10.0, "m/s"),
                 "dwell": (0.0, 60.0, "s")}
#: Length of the simulated two-finger gripper's fingers with the default grasp [m]: its
#: palm is at the tool frame and the fingertips this far ahead along the tool's z axis,
#: at the object's centre (:meth:`TaskSpec.finger_length`; the arm's own links end at the
#: tool frame, the fingers are not collision shapes).
GRIPPER_FINGER_LENGTH = 0.06
#: Default grasp: the fingertips at the object's centre, the tool a finger length above
#: it with its z axis pointing down (object −z).
DEFAULT_GRASP = np.block([[rot_x(math.pi), np.array([[0.0], [0.0], [GRIPPER_FINGER_LENGTH]])],
                          [np.zeros((1, 3)), np.ones((1, 1))]])


class TaskDefinitionError(ValueError):
    """A task description could not be loaded; the message names file, field and value."""


@dataclass(frozen=True, eq=False)
class TaskSpec:
    """One pick-and-place task, SI units, world frame unless said otherwise.

    ``table_top`` (3,) is the centre of the table's top face and ``table_size`` (3,) its
    extent (the box hangs below the top); ``object_shape`` is "box" or "cylinder" with
    ``object_size`` (3,) its x, y, z extent in its own frame (a cylinder's axis is its z);
    ``object_pose`` (4, 4) the object's centre frame before the task, ``grasp`` (4, 4) the
    tool frame in the object frame, ``place`` (4, 4) the object's frame when placed.
    ``approach``, ``lift`` [m], ``speed`` [m/s] and ``dwell`` [s] shape the motion.
    ``obstacles`` are named shapes in the world besides the table and the floor.
    """

    name: str
    table_top: FloatArray
    table_size: FloatArray
    object_shape: str
    object_size: FloatArray
    object_pose: FloatArray
    grasp: FloatArray
    place: FloatArray
    approach: float = MOTION_DEFAULTS["approach"]
    lift: float = MOTION_DEFAULTS["lift"]
    speed: float = MOTION_DEFAULTS["speed"]
    dwell: float = MOTION_DEFAULTS["dwell"]
    source: str = field(default="<generated>")
    obstacles: tuple[tuple[str, Shape], ...] = ()

    def __post_init__(self) -> None:
        for key in ("table_top", "table_size", "object_size", "object_pose", "grasp", "place"):
            object.__setattr__(self, key, frozen(getattr(self, key)))

    def table_box(self) -> Box:
        """The table as a box obstacle (world frame): its top face centred at ``table_top``."""
        pose = np.eye(4)
        pose[:3, 3] = np.asarray(self.table_top) - [0.0, 0.0, self.table_size[2] / 2]
        return Box(self.table_size, pose)

    def object_shape_at(self, pose: FloatArray) -> Box | Cylinder:
        """The object as a shape posed at ``pose`` (4×4, its centre frame)."""
        if self.object_shape == "cylinder":
            return Cylinder(self.object_size[0] / 2, self.object_size[2], pose)
        return Box(self.object_size, pose)

    def world(self, *, table: bool = True) -> World:
        """The task's world: the floor, the table (unless ``table`` is False) and the
        obstacles; the object is not in it (the arm reaches into it to grasp it)."""
        items = ([(TABLE_NAME, self.table_box())] if table else []) + list(self.obstacles)
        return World(items)

    def finger_length(self) -> float:
        """How far the gripper's fingers reach ahead of the tool frame [m]: to the object's
        centre along the tool's z axis (GRIPPER_FINGER_LENGTH with the default grasp)."""
        return float(max(0.0, np.linalg.inv(self.grasp)[2, 3]))

    def grip_width(self) -> float:
        """Width of the object between the fingers [m]: its extent along the tool's y axis."""
        y = self.grasp[:3, 1]
        if self.object_shape == "cylinder":
            radial = math.hypot(y[0], y[1]) * self.object_size[0]
            return float(max(radial, abs(y[2]) * self.object_size[2]))
        return float(np.abs(y) @ self.object_size)


class _Checker(FieldChecker):
    """The robot file's field checker (same messages, numbers clipped and overflow-safe),
    raising :class:`TaskDefinitionError`, with the task file's tables, positive sizes and
    poses."""

    def fail(self, where: str, message: str) -> TaskDefinitionError:  # type: ignore[override]
        return TaskDefinitionError(f"{self.path}: {where}: {message}")

    def table(self, data: dict[str, Any], key: str, allowed: set[str]) -> dict[str, Any]:
        if key not in data:
            raise self.fail(key, f"missing required table [{key}]")
        table = data[key]
        if not isinstance(table, dict):
            raise self.fail(key, f"expected a table, got {clip_repr(table)}")
        self.keys(table, allowed, key)
        return table

    def positive(self, value: Any, where: str) -> float:
        number = self.number(value, where, LENGTH_BOUND)
        if number <= 0.0:
            raise self.fail(where, f"expected a positive number, got {clip_repr(value)}")
        return number

    def vector(self, value: Any, length: int, where: str, positive: bool = False,  # type: ignore[override]
               bound: Bound = LENGTH_BOUND) -> list[float]:
        if not isinstance(value, list) or len(value) != length:
            kind = "positive numbers" if positive else "numbers"
            raise self.fail(where, f"expected a list of {length} {kind}, got {clip_repr(value)}")
        if positive:
            return [self.positive(v, f"{where}[{i}]") for i, v in enumerate(value)]
        return [self.number(v, f"{where}[{i}]", bound) for i, v in enumerate(value)]

    def pose(self, table: dict[str, Any], where: str, to_rad: float) -> FloatArray:
        xyz = self.vector(table.get("xyz", [0.0, 0.0, 0.0]), 3, f"{where}.xyz")
        angle = robot_file.ANGLE_BOUNDS["rad" if to_rad == 1.0 else "deg"]
        rpy = self.vector(table.get("rpy", [0.0, 0.0, 0.0]), 3, f"{where}.rpy", bound=angle)
        return HomogeneousTransform.from_xyz_rpy(xyz, np.array(rpy) * to_rad).mat


def load_task(path: str | Path) -> TaskSpec:
    """Read and validate a task file (see the module docstring for the format); read like a
    robot file (a regular UTF-8 file of at most 1 MiB, TOML nested sanely)."""
    path = Path(path)
    return parse_task(robot_file.read_toml(path, "task file", TaskDefinitionError), path)


def parse_task(data: dict[str, Any], path: str | Path) -> TaskSpec:
    """Validate parsed TOML ``data`` from ``path`` (named in errors) into a :class:`TaskSpec`."""
    check = _Checker(Path(path))
    check.keys(data, TOP_KEYS, "")
    name = data.get("name", Path(path).stem)
    if not isinstance(name, str) or not name.strip():
        raise check.fail("name", f"expected a non-empty string, got {clip_repr(name)}")
    units = data.get("units", "deg")
    if not isinstance(units, str) or units not in UNITS:
        raise check.fail("units", f"unknown units {clip_repr(units)}; accepted: 'deg' or 'rad'")
    to_rad = UNITS[units]

    table = check.table(data, "table", TABLE_KEYS)
    for key in ("xyz", "size"):
        if key not in table:
            raise check.fail(f"table.{key}", "missing required field")
    top = check.vector(table["xyz"], 3, "table.xyz")
    table_size = check.vector(table["size"], 3, "table.size", positive=True)

    obj = check.table(data, "object", OBJECT_KEYS)
    shape = obj.get("shape")
    if not isinstance(shape, str) or shape not in SHAPES:
        raise check.fail("object.shape", f"unknown shape {clip_repr(shape)}; accepted: 'box' or 'cylinder'")
    for key in ("size", "xyz"):
        if key not in obj:
            raise check.fail(f"object.{key}", "missing required field")
    if shape == "box":
        size = check.vector(obj["size"], 3, "object.size", positive=True)
    else:
        diameter, height = check.vector(obj["size"], 2, "object.size", positive=True)
        size = [diameter, diameter, height]
    object_pose = check.pose(obj, "object", to_rad)

    grasp = DEFAULT_GRASP
    if "grasp" in data:
        grasp = check.pose(check.table(data, "grasp", POSE_KEYS), "grasp", to_rad)
    place_table = check.table(data, "place", POSE_KEYS)
    if "xyz" not in place_table:
        raise check.fail("place.xyz", "missing required field")
    place = check.pose(place_table, "place", to_rad)

    motion = dict(MOTION_DEFAULTS)
    if "motion" in data:
        table_m = data["motion"]
        if not isinstance(table_m, dict):
            raise check.fail("motion", f"expected a table, got {clip_repr(table_m)}")
        check.keys(table_m, set(MOTION_DEFAULTS), "motion")
        for key, value in table_m.items():
            low, high, unit = MOTION_BOUNDS[key]
            motion[key] = check.number(value, f"motion.{key}")
            if not low < motion[key] <= high:
                raise check.fail(f"motion.{key}", f"expected more than {low:g} and at most {high:g} {unit}, "
                                                  f"got {clip_repr(value)}")
    obstacles = ()
    if "obstacles" in data:
        try:
            world = parse_world({"units": units, "floor": False, "obstacles": data["obstacles"]}, path)
        except WorldDefinitionError as exc:
            raise TaskDefinitionError(str(exc)) from None
        obstacles = world.obstacles
        for k, (name_k, _) in enumerate(obstacles):
            if name_k == TABLE_NAME:
                raise check.fail(f"obstacles[{k}].name", f"{TABLE_NAME!r} is the table's name; name the obstacle otherwise")
    return TaskSpec(
        name=name, table_top=top, table_size=table_size, object_shape=shape, object_size=size,
        object_pose=object_pose, grasp=grasp, place=place, source=str(path), obstacles=obstacles, **motion,
    )


def with_world_obstacles(spec: TaskSpec, world: World) -> TaskSpec:
    """``spec`` with the obstacles of ``world`` (besides its floor, which every task has)
    added after its own; TaskDefinitionError for a name the task already uses."""
    taken = {TABLE_NAME, *(name for name, _ in spec.obstacles)}
    added = tuple((name, shape) for name, shape in world.obstacles if not isinstance(shape, HalfSpace)
                  or name != FLOOR_NAME)
    for name, _ in added:
        if name in taken:
            raise TaskDefinitionError(f"{spec.source}: the world's obstacle {clip_repr(name)} has the name of "
                                      "the task's table or one of its obstacles; name it otherwise")
    return dataclasses.replace(spec, obstacles=spec.obstacles + added) if added else spec


def task_toml(spec: TaskSpec) -> str:
    """The task as a task file (degrees), e.g. to save a generated default for editing."""
    def pose(mat: FloatArray) -> str:
        tf = HomogeneousTransform(mat)
        xyz = ", ".join(f"{v:.6g}" for v in tf.t())
        rpy = ", ".join(f"{math.degrees(v):.6g}" for v in tf.rpy())
        return f"xyz = [{xyz}]\nrpy = [{rpy}]\n"

    def vec(values: FloatArray) -> str:
        return "[" + ", ".join(f"{v:.6g}" for v in values) + "]"

    def obstacle(name: str, shape: Shape) -> str:
        head = f"\n[[obstacles]]\nname = {json.dumps(name)}\n"
        if isinstance(shape, Sphere):
            return head + f'shape = "sphere"\nradius = {shape.radius:.6g}\nxyz = {vec(shape.center)}\n'
        if isinstance(shape, Box):
            return head + f'shape = "box"\nsize = {vec(shape.size)}\n{pose(shape.pose)}'
        if isinstance(shape, (Cylinder, Capsule)):
            kind = "cylinder" if isinstance(shape, Cylinder) else "capsule"
            return head + (f'shape = "{kind}"\nradius = {shape.radius:.6g}\nlength = {shape.length:.6g}\n'
                           f"{pose(shape.pose)}")
        if isinstance(shape, Mesh) and shape.path is not None:
            return head + (f'shape = "mesh"\nmesh = {json.dumps(str(shape.path))}\nscale = {vec(shape.scale)}\n'
                           f"{pose(shape.pose)}")
        raise ValueError(f"task_toml: obstacle {name!r} ({type(shape).__name__}) has no task-file form")

    size = spec.object_size if spec.object_shape == "box" else spec.object_size[[0, 2]]
    motion = "".join(f"{key} = {getattr(spec, key):.6g}\n" for key in MOTION_DEFAULTS)
    return (
        f'name = {json.dumps(spec.name)}\nunits = "deg"\n\n[table]\nxyz = {vec(spec.table_top)}\n'
        f"size = {vec(spec.table_size)}\n\n[object]\nshape = \"{spec.object_shape}\"\n"
        f"size = {vec(size)}\n{pose(spec.object_pose)}\n[grasp]\n{pose(spec.grasp)}\n"
        f"[place]\n{pose(spec.place)}\n[motion]\n{motion}"
        + "".join(obstacle(n, sh) for n, sh in spec.obstacles)
    )
