"""Checks of analytic IK solutions against forward kinematics (robot_sim.kinematics, an
implementation independent of robot_sim.ik's product of exponentials)."""
from __future__ import annotations

import numpy as np

from robot_sim.ik.family import ik_family
from robot_sim.ik.solutions import ik_solutions
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.params import RobotParams

#: Every solution reaches the pose to this [m, rad] (the issue's figure).
REACH_TOL = 1e-10


def pose_errors(robot: RobotParams, Q: np.ndarray, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position [m] and rotation [rad] errors of the tool at each row of Q against T."""
    F = forward_kinematics(robot, Q)
    pos = np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=1)
    rot = np.linalg.norm(F[:, :3, :3] - T[:3, :3], axis=(1, 2)) / np.sqrt(2.0)  # 2 sin(angle/2) ≥ angle·(1 − angle²/24)
    return pos, rot


def check_complete(robot: RobotParams, Q: np.ndarray, within_limits: bool = True) -> int:
    """For each configuration q of Q: the analytic solutions of its pose are exact, reach
    it to REACH_TOL (position only for position arms), are distinct, and include q
    (exactly within the limits, where every turn is listed; modulo 2π without).
    A 7-joint arm solves with q's free joint value.  Returns the solutions counted."""
    family = ik_family(robot)
    T = forward_kinematics(robot, Q)
    free = family.free_joint
    if free is None:
        sols = ik_solutions(robot, T, within_limits=within_limits)
        per_pose = [(sols.q[i, :sols.count[i]], sols.exact[i, :sols.count[i]]) for i in range(len(Q))]
    else:
        per_pose = []
        for q, t in zip(Q, T):
            s = ik_solutions(robot, t, q, within_limits=within_limits)
            per_pose.append((s.q, s.exact))
    total = 0
    for q, t, (S, exact) in zip(Q, T, per_pose):
        assert S.shape[0] >= 1 and exact.all(), (robot.name, q)
        pos, rot = pose_errors(robot, S, t)
        assert pos.max() <= REACH_TOL, (robot.name, q, pos.max())
        if family.task != "position":
            assert rot.max() <= REACH_TOL, (robot.name, q, rot.max())
        diff = S - q
        if not within_limits:
            rev = robot.is_revolute
            diff[:, rev] = (diff[:, rev] + np.pi) % (2 * np.pi) - np.pi
        assert np.abs(diff).max(axis=1).min() < 1e-7, (robot.name, q, S)
        gaps = np.abs(S[:, None] - S[None]).max(axis=2) + np.eye(len(S))
        assert gaps.min() > 1e-9, (robot.name, q)
        total += len(S)
    return total
