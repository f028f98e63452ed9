"""Joint values in display units, shared by the command line's ``--q`` and the sliders
(no Qt): degrees for revolute joints and metres for prismatic ones.  Inside, joint values
are radians (revolute) and metres (prismatic)."""
from __future__ import annotations

import math

import numpy as np

from robot_sim.model.params import JTYPE_PRISMATIC, RobotParams
from robot_sim.viewer import settings as vs


def display_scale(robot: RobotParams) -> np.ndarray:
    """Per-joint factor (n,) from SI joint values (rad, m) to display units (deg, m)."""
    return np.where(robot.jtype == JTYPE_PRISMATIC, 1.0, 180.0 / math.pi)


def display_range(robot: RobotParams) -> tuple[np.ndarray, np.ndarray]:
    """Slider range (lo, hi), each (n,), in display units (deg, m).

    Joint limits where finite; otherwise ±UNLIMITED_REVOLUTE_RANGE_DEG for revolute and
    ±UNLIMITED_PRISMATIC_RANGE_M for prismatic joints.
    """
    prismatic = robot.jtype == JTYPE_PRISMATIC
    default = np.where(prismatic, vs.UNLIMITED_PRISMATIC_RANGE_M, vs.UNLIMITED_REVOLUTE_RANGE_DEG)
    scale = display_scale(robot)
    lo = np.where(np.isfinite(robot.q_min), robot.q_min * scale, -default)
    hi = np.where(np.isfinite(robot.q_max), robot.q_max * scale, default)
    return lo, hi


def wrap_display(robot: RobotParams, q: np.ndarray) -> np.ndarray:
    """Joint values (n,) in display units; unlimited revolute joints wrapped to [-180, 180)."""
    values = np.asarray(q, dtype=float) * display_scale(robot)
    wrap = (robot.jtype != JTYPE_PRISMATIC) & ~np.isfinite(robot.q_min) & ~np.isfinite(robot.q_max)
    return np.where(wrap, (values + 180.0) % 360.0 - 180.0, values)
