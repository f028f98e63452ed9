"""The circle demo: the endeffector runs a horizontal circle by differential IK, over the
still or simulated driver it interrupts.  Units: m, s, rad."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from robot_sim.kinematics import diff_ik_velocity
from robot_sim.viewer import settings as vs
from robot_sim.viewer.drivers.base import Driven, Driver, OverDriver


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


class CircleDriver(OverDriver):
    """Runs ``circle`` over ``inner`` (the still or the simulation driver).  Kinematically
    it moves the arm; under a joint-space controller it moves the desired state, which the
    controller tracks; under a task-space controller the simulation follows the circle as
    its reference and nothing is solved here."""

    def __init__(self, circle: DemoCircle, inner: Driver) -> None:
        super().__init__(inner)
        self.circle = circle

    @classmethod
    def start(cls, session: Driven) -> CircleDriver:
        """A circle through the endeffector (the desired one under a joint-space
        controller), over the session's motion driver; in task space the simulation
        follows it at once."""
        task_space = session.task_space
        start = (session.ghost if session.physical and not task_space else session.kin).endeff_tf.t()
        driver = cls(DemoCircle(center=start - np.array([vs.DEMO_CIRCLE_RADIUS_M, 0.0, 0.0])), session.driver.base)
        if task_space:
            driver.follow(session)
        return driver

    def step(self, session: Driven, dt: float) -> None:
        """Advance the circle by ``dt`` s (qd from diff_ik_velocity with position feedback),
        then the simulation underneath, if any."""
        self.circle.time += dt
        if not session.task_space:  # in task space the simulation follows the circle itself
            point, velocity = self.circle.point_and_velocity()
            physical = self.physical
            ee = (session.ghost if physical else session.kin).endeff_tf.t()
            command = velocity + vs.DEMO_FEEDBACK_GAIN * (point - ee)
            state = session.state
            q = state.q_des() if physical else state.q()
            qd = diff_ik_velocity(session.robot, q, command)
            q_new = np.clip(q + qd * dt, session.robot.q_min, session.robot.q_max)
            state.set_q_des(q_new)
            if physical:
                state.set_qd_des((q_new - q) / dt)
            else:
                state.set_q(q_new)
                state.set_qd((q_new - q) / dt)
            session.update_kinematics()
        if self.physical:
            self.inner.step(session, dt)

    def moving(self, session: Driven) -> bool:
        return True

    def set_q(self, session: Driven, q: np.ndarray) -> None:
        """Setting the joints by hand ends the demo."""
        session.driver = self.inner
        self.inner.set_q(session, q)

    def follow(self, session: Driven) -> None:
        """Make the circle the task-space controller's reference, the tool held at its
        current orientation."""
        motion = session.motion
        motion.follow(self.circle.task_reference(session.kin.endeff_tf.R().copy(), motion.sim.time))
