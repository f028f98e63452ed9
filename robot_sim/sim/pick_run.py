"""The pick task run by a simulated controller: the planned trajectory is the reference of
``simulation.Simulation`` (fixed step, inverse/forward dynamics of ``dynamics``), and the
run reports how well the arm tracked it and where the object ended up.  No Qt.

World frame, SI units (rad or m, N·m or N, s).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.control.factory import make_controller
from robot_sim.kinematics import forward_kinematics
from robot_sim.planning.pick_task import TaskPlan
from robot_sim.model.state import RobotState
from robot_sim.sim.simulation import DEFAULT_DT, Simulation
from robot_sim.planning.scaling import Trajectory

FloatArray = NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class SimulatedPick:
    """A simulated run of a :class:`TaskPlan`: ``motion`` is what the arm did (t, q, q̇,
    q̈ and tool poses, sampled every step), ``effort`` (N, n) the applied joint efforts,
    ``joint_error`` (n,) the largest |q − q_des| per joint [rad or m], ``tool_error`` the
    largest distance between the simulated and the planned tool position [m],
    ``placed_pose`` (4, 4) where the object is let go, ``stopped`` the simulation's
    reason for stopping early (None when it ran to the end)."""

    plan: TaskPlan
    mode: str
    motion: Trajectory
    effort: FloatArray
    joint_error: FloatArray
    tool_error: float
    placed_pose: FloatArray
    stopped: str | None

    def summary(self) -> str:
        """One line: controller, tracking errors and the placement error."""
        place_err = float(np.linalg.norm(self.placed_pose[:3, 3] - self.plan.spec.place[:3, 3]))
        line = (f"{self.plan.robot.name}, {self.mode}: largest joint tracking error "
                f"{np.max(self.joint_error):.3g} (joint {int(np.argmax(self.joint_error)) + 1}), "
                f"tool {1e3 * self.tool_error:.3g} mm; object placed {1e3 * place_err:.3g} mm from its place pose")
        return line if self.stopped is None else f"{line}; {self.stopped}"


def simulate_pick(plan: TaskPlan, mode: str = "ct", dt: float = DEFAULT_DT) -> SimulatedPick:
    """Run ``plan`` with the controller of motion mode ``mode`` (``"ct"`` computed torque,
    ``"pd"``, ``"pdg"``; gains from the robot file or the defaults of
    ``control.control_gains``) from the plan's start at rest, for the plan's duration.

    The object is attached to the simulated tool over the plan's grasp interval, so
    ``placed_pose`` is the simulated tool pose at the release time times the grasp's
    inverse.  Needs the robot's inertial data (ValueError from ``dynamics`` otherwise).
    """
    robot, traj = plan.robot, plan.trajectory
    state = RobotState(robot)
    state.set_q(traj.q[0])
    state.set_q_des(traj.q[0])
    t0 = float(traj.t[0])
    sim = Simulation(robot, state, make_controller(mode, robot), dt=dt,
                     reference=lambda t: traj.evaluate(t0 + t))
    n_steps = int(round(plan.duration / dt))
    n = robot.n_dofs
    q, qd, qdd, effort = (np.zeros((n_steps + 1, n)) for _ in range(4))
    q[0] = traj.q[0]
    taken = n_steps
    for k in range(1, n_steps + 1):
        if sim.step(1) == 0:
            taken = k - 1
            break
        q[k], qd[k], qdd[k], effort[k] = sim.q, sim.qd, sim.qdd, sim.effort
    t = t0 + dt * np.arange(taken + 1)
    q, qd, qdd, effort = q[: taken + 1], qd[: taken + 1], qdd[: taken + 1], effort[: taken + 1]
    poses = forward_kinematics(robot, q)
    q_des, _, _ = traj.evaluate(t)
    planned_tool = forward_kinematics(robot, q_des)[:, :3, 3]
    motion = Trajectory(t, q, qd, qdd, poses, traj.marks)
    k_release = min(int(round((plan.t_release - t0) / dt)), taken)
    placed = poses[k_release] @ np.linalg.inv(plan.spec.grasp)
    return SimulatedPick(
        plan=plan, mode=mode, motion=motion, effort=effort,
        joint_error=np.max(np.abs(q - q_des), axis=0),
        tool_error=float(np.max(np.linalg.norm(poses[:, :3, 3] - planned_tool, axis=1))),
        placed_pose=placed, stopped=sim.stopped,
    )
