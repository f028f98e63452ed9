"""The circle demo's path: the endeffector runs a horizontal circle, by differential IK
or as a task-space controller's reference.  Units: m, s, rad."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from robot_sim.kinematics import diff_ik_velocity
from robot_sim.model.params import RobotParams
from robot_sim.viewer import settings as vs


@dataclass
class DemoCircle:
    """Endeffector circle in the horizontal world plane through its start position (m, s)."""

    center: np.ndarray
    radius: float = vs.DEMO_CIRCLE_RADIUS_M
    period: float = vs.DEMO_CIRCLE_PERIOD_S
    time: float = 0.0

    def point_and_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Desired world position (3,) in m and linear velocity (3,) in m/s at ``time``."""
        return self._motion_at(self.time)[:2]

    def _motion_at(self, time: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position [m], velocity [m/s] and acceleration [m/s²] (3,) each at ``time`` [s]."""
        omega = 2.0 * math.pi / self.period
        c, s = math.cos(omega * time), math.sin(omega * time)
        point = self.center + self.radius * np.array([c, s, 0.0])
        velocity = self.radius * omega * np.array([-s, c, 0.0])
        return point, velocity, -self.radius * omega**2 * np.array([c, s, 0.0])

    def joint_step(self, robot: RobotParams, q: np.ndarray, tool: np.ndarray, dt: float
                   ) -> tuple[np.ndarray, np.ndarray]:
        """Joints (n,) ``dt`` s on along the circle from ``q``, whose endeffector is at
        ``tool`` (3,) [m, world], by differential IK with position feedback
        (DEMO_FEEDBACK_GAIN), clipped to the joint limits; and the joint velocity (n,)
        that took them there."""
        point, velocity = self.point_and_velocity()
        command = velocity + vs.DEMO_FEEDBACK_GAIN * (point - tool)
        q_new = np.clip(q + diff_ik_velocity(robot, q, command) * dt, robot.q_min, robot.q_max)
        return q_new, (q_new - q) / dt

    def task_reference(self, rotation: np.ndarray, start: float) -> Callable[[float], tuple]:
        """The circle as a task reference of simulated time [s] (at its start at ``start``),
        the tool held at the world orientation ``rotation`` (3, 3)."""
        zero, begun = np.zeros(3), self.time

        def at(time: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            point, velocity, accel = self._motion_at(begun + time - start)
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = rotation, point
            return pose, np.concatenate([velocity, zero]), np.concatenate([accel, zero])

        return at
