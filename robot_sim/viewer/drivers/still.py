"""The still driver: joints set by hand; the shown arm moves toward its desired values at
bounded joint speed (ANIM_SPEED_*) and then rests.  Units: rad, m, s."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from robot_sim.model.params import JTYPE_PRISMATIC
from robot_sim.transforms import HomogeneousTransform
from robot_sim.viewer import settings as vs
from robot_sim.viewer.drivers.base import Driven, Driver

if TYPE_CHECKING:
    from robot_sim.viewer.drivers.circle_path import DemoCircle


class StillDriver(Driver):
    """Kinematic motion: current q follows the desired q (the ghost) at bounded speed."""

    name = "still"

    def advance(self, session: Driven, dt: float) -> None:
        """Move the current q toward the desired q at bounded joint speed for ``dt`` s."""
        state, robot = session.state, session.robot
        q, q_des = state.q(), state.q_des()
        speed = np.where(robot.jtype == JTYPE_PRISMATIC, vs.ANIM_SPEED_PRISMATIC, vs.ANIM_SPEED_REVOLUTE)
        step = np.clip(q_des - q, -speed * dt, speed * dt)
        arrived = np.all(np.abs(q_des - q) <= np.maximum(speed * dt, vs.ANIM_ARRIVED_TOL))
        state.set_q(q_des if arrived else q + step)
        state.set_qd(np.zeros_like(q) if arrived else step / dt)
        session.update_kinematics()

    def moving(self, session: Driven) -> bool:
        """True until the current q has reached the desired q."""
        state = session.state
        return bool(np.any(np.abs(state.q_des() - state.q()) > vs.ANIM_ARRIVED_TOL))

    def set_q(self, session: Driven, q: np.ndarray) -> None:
        """Current and desired q at rest; a shown IK target snaps to the endeffector."""
        state = session.state
        state.set_q(q)
        state.set_q_des(q)
        state.set_qd(np.zeros(session.robot.n_dofs))
        session.update_kinematics()
        if session.target_tf is not None:
            session.target_tf = HomogeneousTransform(session.kin.endeff_tf.mat.copy())
            session.ik_result = None

    def rest(self, session: Driven) -> None:
        """Zero joint velocities."""
        session.state.set_qd(np.zeros(session.robot.n_dofs))

    def run_circle(self, session: Driven, circle: DemoCircle, dt: float) -> None:
        """The circle moves the arm itself (current and desired q, and q̇)."""
        state = session.state
        q_new, qd = circle.joint_step(session.robot, state.q(), session.kin.endeff_tf.t(), dt)
        state.set_q_des(q_new)
        state.set_q(q_new)
        state.set_qd(qd)
        session.update_kinematics()
