"""What the pick task shows (pure NumPy, no GL): :class:`TaskScene`, the plain data a
host fills (world frame, metres), and the placements of the unit meshes that draw its
table, obstacles, object and two-finger gripper (``items.task`` paints them)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.model.shapes import Box, Capsule, Cylinder, Shape, Sphere

FloatArray = NDArray[np.float64]


@dataclass
class TaskScene:
    """What the task shows at one instant; poses (4, 4) in the world, lengths in metres.

    ``table_top`` (3,) is the centre of the table's top face, ``table_size`` (3,) its
    extent (the box hangs below the top).  ``object_shape`` "box" or "cylinder" (axis
    along its z) of extent ``object_size`` (3,) centred at ``object_pose``.  The gripper
    hangs at ``tool_pose``: its palm at the tool frame, fingers ``gripper_opening`` apart
    along the tool's y axis reaching ``finger_length`` ahead of it (along the tool's z).
    ``path`` (N, 3) is the endeffector path drawn as a line.  ``obstacles`` are the task's
    named shapes besides the table (boxes, cylinders, spheres and capsules are drawn).
    """

    table_top: FloatArray
    table_size: FloatArray
    object_shape: str
    object_size: FloatArray
    object_pose: FloatArray
    tool_pose: FloatArray
    gripper_opening: float
    finger_length: float
    path: FloatArray = field(default_factory=lambda: np.zeros((0, 3)))
    obstacles: tuple[tuple[str, Shape], ...] = ()


def _scaled(pose: FloatArray, centre: tuple[float, float, float], size: FloatArray) -> FloatArray:
    """Placement of a unit mesh: ``pose`` · translate(centre) · scale(size)."""
    local = np.diag([*np.asarray(size, dtype=float), 1.0])
    local[:3, 3] = centre
    return pose @ local


def table_placement(task: TaskScene) -> FloatArray:
    """World placement (4, 4) of the unit box (centred, sides ±0.5) for the table."""
    pose = np.eye(4)
    pose[:3, 3] = task.table_top - [0.0, 0.0, task.table_size[2] / 2]
    return _scaled(pose, (0.0, 0.0, 0.0), task.table_size)


def gripper_placements(task: TaskScene) -> FloatArray:
    """World placements (3, 4, 4) of the unit box for the palm and the two fingers."""
    length, thick = task.finger_length, gd.GRIPPER_FINGER_THICKNESS_M
    tip = gd.GRIPPER_FINGER_TIP_PAST_M
    finger_size = np.array([gd.GRIPPER_FINGER_WIDTH_M, thick, length + tip])
    z_mid = (tip + length) / 2
    y_off = task.gripper_opening / 2 + thick / 2
    palm_size = np.array([gd.GRIPPER_FINGER_WIDTH_M, task.gripper_opening + 2 * thick, gd.GRIPPER_PALM_THICKNESS_M])
    return np.stack([
        _scaled(task.tool_pose, (0.0, 0.0, -gd.GRIPPER_PALM_THICKNESS_M / 2), palm_size),
        _scaled(task.tool_pose, (0.0, y_off, z_mid), finger_size),
        _scaled(task.tool_pose, (0.0, -y_off, z_mid), finger_size),
    ])


def obstacle_placements(obstacles: tuple[tuple[str, Shape], ...]) -> list[tuple[str, tuple, FloatArray]]:
    """(unit mesh, colour, world placements (k, 4, 4)) drawing each obstacle; a capsule is a
    cylinder and two spheres; meshes and half-spaces are not drawn here."""
    out = []
    for _, shape in obstacles:
        color = shape.color or gd.TASK_OBSTACLE_COLOR
        if isinstance(shape, Box):
            out.append(("box", color, _scaled(shape.pose, (0.0, 0.0, 0.0), shape.size)[None]))
        elif isinstance(shape, Sphere):
            out.append(("sphere", color, _scaled(shape.pose, (0.0, 0.0, 0.0), np.full(3, shape.radius))[None]))
        elif isinstance(shape, (Cylinder, Capsule)):
            size = np.array([shape.radius, shape.radius, shape.length])
            out.append(("joint", color, _scaled(shape.pose, (0.0, 0.0, -shape.length / 2), size)[None]))
            if isinstance(shape, Capsule):
                caps = [_scaled(shape.pose, (0.0, 0.0, z), np.full(3, shape.radius))
                        for z in (-shape.length / 2, shape.length / 2)]
                out.append(("sphere", color, np.stack(caps)))
    return out


def task_points(task: TaskScene) -> FloatArray:
    """World points (M, 3) enclosing the task's drawing: table corners, obstacles, object
    and path."""
    half = np.asarray(task.table_size) / 2
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (0, -2)])
    table = task.table_top + signs * half
    unit = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)  # holds every unit mesh
    obstacles = [(np.einsum("kij,mj->kmi", P[:, :3, :3], unit) + P[:, None, :3, 3]).reshape(-1, 3)
                 for _, _, P in obstacle_placements(task.obstacles)]
    return np.vstack([table, task.object_pose[None, :3, 3], task.tool_pose[None, :3, 3], task.path.reshape(-1, 3),
                      *obstacles])


def task_parts(task: TaskScene) -> list[tuple[str, tuple[float, float, float, float], FloatArray]]:
    """(unit mesh, colour, world placements (k, 4, 4)) of the table, the obstacles, the
    object (a box or a closed cylinder) and the gripper's palm and fingers."""
    if task.object_shape == "cylinder":
        size = task.object_size * [0.5, 0.5, 1.0]  # unit cylinder: radius 1, z from 0 to 1
        item = ("joint", gd.OBJECT_COLOR, _scaled(task.object_pose, (0.0, 0.0, -task.object_size[2] / 2), size)[None])
    else:
        item = ("box", gd.OBJECT_COLOR, _scaled(task.object_pose, (0.0, 0.0, 0.0), task.object_size)[None])
    return [("box", gd.TABLE_COLOR, table_placement(task)[None]), *obstacle_placements(task.obstacles), item,
            ("box", gd.GRIPPER_COLOR, gripper_placements(task))]
