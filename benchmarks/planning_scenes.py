"""Planning benchmark scenes, shared by ``bench_planning.py`` and the optional oracle
scripts: a table in front of the arm, 3 to 8 random boxes and cylinders on and above it,
and start and goal configurations that are free, with the tool above the table on either
side, and whose straight joint-space line collides (obstacles separate them).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robot_sim.collision import Box, CollisionChecker, Cylinder, World
from robot_sim.kinematics import forward_kinematics, random_configurations
from robot_sim.model.params import RobotParams

ROBOTS = ("panda", "ur5", "humanoid7")
TABLE_TOP = 0.2  # m, above the floor (z = 0, the robots' base height)
TABLE = (np.array([0.55, 0.0, TABLE_TOP - 0.025]), np.array([0.6, 1.2, 0.05]))  # centre, size
OBSTACLES = (3, 8)
CANDIDATES = 3000
#: Start and goal joint values stay within ±JOINT_SPAN: with ±2π ranges (UR5) two random
#: configurations are often on opposite sides of an elbow fold, not connected at all.
JOINT_SPAN = 2.8


@dataclass(frozen=True)
class Scene:
    """One problem: the world, the checker of the arm in it, start and goal."""

    world: World
    checker: CollisionChecker
    q_start: np.ndarray
    q_goal: np.ndarray


def _pose(xyz: np.ndarray, yaw: float = 0.0) -> np.ndarray:
    T = np.eye(4)
    c, s = np.cos(yaw), np.sin(yaw)
    T[:2, :2] = [[c, -s], [s, c]]
    T[:3, 3] = xyz
    return T


def random_world(rng: np.random.Generator) -> World:
    """Floor, table and 3–8 boxes and cylinders standing on it or floating above it."""
    centre, size = TABLE
    items = {"table": Box(size, _pose(centre))}
    for k in range(int(rng.integers(OBSTACLES[0], OBSTACLES[1] + 1))):
        xy = [rng.uniform(0.35, 0.8), rng.uniform(-0.5, 0.5)]
        if rng.random() < 0.5:
            dims = rng.uniform([0.04, 0.04, 0.05], [0.15, 0.15, 0.35])
            z = TABLE_TOP + dims[2] / 2 if rng.random() < 0.6 else rng.uniform(0.35, 0.7)
            items[f"box{k}"] = Box(dims, _pose([*xy, z], rng.uniform(0, np.pi)))
        else:
            radius, length = rng.uniform(0.02, 0.07), rng.uniform(0.1, 0.4)
            z = TABLE_TOP + length / 2 if rng.random() < 0.6 else rng.uniform(0.35, 0.7)
            items[f"cylinder{k}"] = Cylinder(radius, length, _pose([*xy, z]))
    return World(items)


def make_scene(robot: RobotParams, rng: np.random.Generator, padding: float = 0.0) -> Scene:
    """A random world with free start and goal that its obstacles separate."""
    while True:
        world = random_world(rng)
        checker = CollisionChecker(robot, world, padding=padding)
        Q = random_configurations(robot, CANDIDATES, rng)
        Q = np.clip(Q, -JOINT_SPAN, JOINT_SPAN)  # wide revolute ranges (±2π) hold several copies
        tip = forward_kinematics(robot, Q)[:, :3, 3]
        above = (tip[:, 0] > 0.3) & (tip[:, 0] < 0.85) & (tip[:, 2] > TABLE_TOP + 0.05)
        ok = above & ~checker.in_collision(Q)
        left, right = Q[ok & (tip[:, 1] < -0.15)], Q[ok & (tip[:, 1] > 0.15)]
        for qa, qb in zip(left, right):
            if not checker.path_is_free(np.stack([qa, qb])):
                return Scene(world, checker, qa, qb)
