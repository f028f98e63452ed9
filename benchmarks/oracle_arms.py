"""The arms the optional oracle scripts (compare_mujoco.py, compare_pinocchio.py) share
with MuJoCo and Pinocchio: their URDF importers keep no drive terms (reflected motor
inertia, friction), and MuJoCo's joint ranges are soft constraints, so both sides are
compared on the rigid bodies alone (and, for MuJoCo, without joint limits)."""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from robot_sim.model.params import RobotParams


def without_drives(robot: RobotParams, limits: bool = True) -> RobotParams:
    """``robot`` without drives (same DH table and inertials), and without joint limits
    unless ``limits`` (Pinocchio reads an unlimited joint as continuous, nq = 2 per joint)."""
    if limits:
        return replace(robot, drives=None)
    n = robot.n_dofs
    return replace(robot, drives=None, q_min=np.full(n, -np.inf), q_max=np.full(n, np.inf))
