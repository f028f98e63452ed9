"""The task-space driver: the arm is simulated under a task-space controller (operational
space, impedance), which follows a desired tool pose: the IK target itself (no IK is
solved), the circle demo's moving pose, or else the tool pose of the desired joints.
Units: SI; poses in the world frame."""
from __future__ import annotations

from typing import TYPE_CHECKING

from robot_sim.control.reference import fixed_pose
from robot_sim.kinematics import Kinematics
from robot_sim.transforms import HomogeneousTransform
from robot_sim.viewer.drivers.base import Driven, FloatArray
from robot_sim.viewer.drivers.simulated import SimulationDriver

if TYPE_CHECKING:
    from robot_sim.viewer.drivers.circle_path import DemoCircle


class TaskSpaceDriver(SimulationDriver):
    """A :class:`SimulationDriver` whose controller takes poses: the IK target dragged is
    its desired pose, and the circle demo its Cartesian reference."""

    name = "task space"
    task_space = True

    def _following(self) -> bool:
        """True while the controller follows a pose of its own (the target, the circle)."""
        return self.motion.sim.reference is not None

    def rest(self, session: Driven) -> None:
        """Hold the tool where it is: back to the desired joints, set to the current ones,
        at rest."""
        self.motion.follow(None)
        session.state.set_q_des(session.state.q())
        super().rest(session)

    # ---- the IK target is the desired pose ----
    def reach_target(self, session: Driven) -> bool:
        """Follow the target's pose (no IK: the controller takes the pose itself)."""
        session.ik_result = None
        self.motion.follow(fixed_pose(session.target_tf.mat.copy()))
        return True

    def target_toggled(self, session: Driven) -> None:
        """A shown target is followed; hidden, the arm holds where it is."""
        if session.target_tf is not None:
            self.motion.follow(fixed_pose(session.target_tf))
        else:
            self.rest(session)

    def engage(self, session: Driven) -> None:
        """A target shown when the mode starts is followed at once."""
        if session.target_tf is not None:
            self.motion.follow(fixed_pose(session.target_tf))

    def shown_ghost(self, session: Driven) -> Kinematics | None:
        """No ghost while a pose is followed (there are no desired joints then)."""
        return None if self._following() else super().shown_ghost(session)

    def shown_target(self, session: Driven) -> HomogeneousTransform | None:
        """The IK target, or the circle's moving desired pose when no target is shown."""
        desired = self.motion.sim.desired_pose
        if session.target_tf is None and self._following() and desired is not None:
            return HomogeneousTransform(desired.copy())
        return session.target_tf

    def desired_tool_pose(self, session: Driven) -> FloatArray | None:
        """The controller's desired pose (4, 4), else the tool pose of the desired joints."""
        desired = self.motion.sim.desired_pose
        return super().desired_tool_pose(session) if desired is None else desired

    # ---- the circle is the controller's reference ----
    def run_circle(self, session: Driven, circle: DemoCircle, dt: float) -> None:
        """Simulate ``dt`` s: the controller follows the circle itself (nothing is solved)."""
        self.advance(session, dt)

    def circle_start(self, session: Driven) -> FloatArray:
        """The endeffector itself."""
        return session.kin.endeff_tf.t()

    def follow_circle(self, session: Driven, circle: DemoCircle) -> None:
        """Make the circle the controller's reference, the tool held at its current
        orientation."""
        self.motion.follow(circle.task_reference(session.kin.endeff_tf.R().copy(), self.motion.sim.time))

