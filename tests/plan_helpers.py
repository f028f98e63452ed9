"""Checks of planned paths written independently of robot_sim.planning: a joint path is
sampled so finely that no point of any collision shape moves more than ``step`` metres
between samples, measured from the link frames' actual motion (forward kinematics:
origin displacement plus rotation angle times the shape's farthest point from the
frame), not from the planner's bound; every sample must be free for the checker."""
from __future__ import annotations

import numpy as np

from robot_sim.collision import CollisionChecker
from robot_sim.collision.distance import shape_distance
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.shapes import Box, Sphere

STEP = 5e-4  # m


def _extent(shape) -> float:
    if isinstance(shape, Box):
        return float(np.linalg.norm(shape.size) / 2)
    if isinstance(shape, Sphere):
        return float(shape.radius)
    return float(np.hypot(shape.radius, shape.length / 2) + shape.radius)


def measured_samples(checker: CollisionChecker, path: np.ndarray, step: float = STEP) -> np.ndarray:
    """The polyline through ``path`` (K, n) sampled at most ``step`` of measured motion apart."""
    robot = checker.robot
    index = {name: k for k, name in enumerate(robot.link_names)}
    q0 = np.asarray(path[0], dtype=float)
    shapes = checker.shapes(q0)
    link = np.array([index[name] for name, _ in shapes])
    F0 = forward_kinematics(robot, q0, all_frames=True)
    reach = np.array([np.linalg.norm(np.asarray(s.pose)[:3, 3] - F0[k][:3, 3]) + _extent(s)
                      for k, (_, s) in zip(link, shapes)])
    out = [np.asarray(path[:1], dtype=float)]
    for a, b in zip(path[:-1], path[1:]):
        m = 8
        while True:
            Q = a + (np.arange(m + 1) / m)[:, None] * (b - a)
            F = forward_kinematics(robot, Q, all_frames=True)[:, link]
            move = np.linalg.norm(np.diff(F[:, :, :3, 3], axis=0), axis=2)
            cos = (np.einsum("mkij,mkij->mk", F[:-1, :, :3, :3], F[1:, :, :3, :3]) - 1.0) / 2.0
            if np.max(move + np.arccos(np.clip(cos, -1.0, 1.0)) * reach) <= step:
                break
            m *= 2
        out.append(Q[1:])
    return np.concatenate(out)


def free_at(checker: CollisionChecker, path: np.ndarray, step: float = STEP) -> bool:
    """Whether every measured sample of the polyline through ``path`` is free (for every
    member of a checker made of checkers)."""
    if hasattr(checker, "members"):
        return all(free_at(member, path, step) for member in checker.members)
    return not bool(np.any(checker.in_collision(measured_samples(checker, np.asarray(path, dtype=float), step))))


def straight_transport_clearance(plan) -> float:
    """Smallest distance [m] between the task's wall and the object carried in a straight
    line (poses interpolated element-wise, the orientation is the same at both ends) from
    where the planned transport starts to where it ends: negative when a straight
    transport would go through the wall."""
    marks = plan.phase_times()
    start, end = (plan.state_at(marks[p]).object_pose for p in ("transport", "place"))
    wall = dict(plan.spec.obstacles)["wall"]
    return min(shape_distance(plan.spec.object_shape_at(start + f * (end - start)), wall).distance
               for f in np.linspace(0.0, 1.0, 41))


# A task file with the object's x as a format field.
TASK = """\
name = "block"
units = "deg"
[table]
xyz = [0.4, 0.0, 0.2]
size = [0.4, 0.6, 0.2]
[object]
shape = "cylinder"
size = [0.05, 0.1]
xyz = [{x}, -0.2, 0.25]
[place]
xyz = [0.4, 0.2, 0.25]
rpy = [0.0, 0.0, 90.0]
[motion]
lift = 0.1
"""
