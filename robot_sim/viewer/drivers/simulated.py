"""The simulation driver: the arm is simulated (a joint-space motion mode of
:class:`robot_sim.viewer.motion.Motion`) and its controller tracks the desired joints,
which the sliders, the IK target and the circle demo set.  Units: SI; points in the world."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from robot_sim.graphics import defs as gd
from robot_sim.kinematics import Kinematics
from robot_sim.transforms import HomogeneousTransform
from robot_sim.viewer import settings as vs
from robot_sim.viewer.drivers.base import Driven, Driver, FloatArray

if TYPE_CHECKING:
    from robot_sim.viewer.drivers.circle_path import DemoCircle
    from robot_sim.viewer.motion import Motion


class SimulationDriver(Driver):
    """Steps ``motion``'s simulation in wall-clock time; sliders set the controller's set point."""

    name = "simulated"
    physical = True

    def __init__(self, motion: Motion) -> None:
        self.motion = motion

    # ---- time ----
    def advance(self, session: Driven, dt: float) -> None:
        """Simulate ``dt`` s of wall-clock time (Simulation.advance caps a lag)."""
        session.limit_events.extend(self.motion.advance(dt))
        session.update_kinematics()

    def moving(self, session: Driven) -> bool:
        """True until the simulation stops (a stop it cannot go past)."""
        return self.motion.sim.stopped is None

    def wall_step(self, elapsed: float, longest: float) -> float:
        """The wall time itself: the simulation keeps wall-clock time (it caps a lag)."""
        return elapsed

    def simulate(self, session: Driven, duration: float) -> None:
        """Simulate ``duration`` seconds at once (the command line's ``--duration``); with
        the session's trail on, in pieces of TRAIL_SAMPLE_S so the trail holds the path."""
        if session.trail is None:
            self.motion.simulate(duration)
        else:
            if not (math.isfinite(duration) and duration >= 0):
                raise ValueError(f"duration must be a finite number of seconds >= 0, got {duration!r}")
            steps = round(duration / self.motion.sim.dt)
            chunk = max(1, round(vs.TRAIL_SAMPLE_S / self.motion.sim.dt))
            for done in range(0, steps, chunk):
                self.motion.sim.step(min(chunk, steps - done))
                session.update_kinematics()
                if self.motion.sim.stopped:
                    break
            self.motion.sim.take_events()
        session.update_kinematics()

    # ---- joints set by hand ----
    def set_q(self, session: Driven, q: np.ndarray) -> None:
        """Only the desired q is set (at rest): the controller moves the arm there; a shown
        IK target snaps to the desired endeffector pose."""
        self.motion.follow(None)  # the sliders' joints are the set point again
        session.state.set_q_des(q)
        session.state.set_qd_des(np.zeros(session.robot.n_dofs))
        session.update_kinematics()
        if session.target_tf is not None:
            session.target_tf = HomogeneousTransform(session.ghost.endeff_tf.mat.copy())
            session.ik_result = None

    def set_point(self, session: Driven) -> FloatArray:
        """The controller's desired joints (n,)."""
        return session.state.q_des()

    def rest(self, session: Driven) -> None:
        """The set point at rest: the desired velocities are zeroed."""
        session.state.set_qd_des(np.zeros(session.robot.n_dofs))

    # ---- ghost and tracking ----
    def shown_ghost(self, session: Driven) -> Kinematics | None:
        """The ghost (the set point) with the IK target, and while the arm is visibly away
        from it (more than GHOST_APART_TOL in a joint)."""
        state = session.state
        apart = bool(np.any(np.abs(state.q_des() - state.q()) > gd.GHOST_APART_TOL))
        return session.ghost if session.target_tf is not None or apart else None

    def desired_tool_pose(self, session: Driven) -> FloatArray | None:
        """The tool pose (4, 4) of the desired joints."""
        return session.ghost.endeff_tf.mat

    @property
    def mode(self) -> str:
        return self.motion.mode

    # ---- the mouse pull (a spring on the endeffector) ----
    @property
    def pull_point(self) -> FloatArray | None:
        return self.motion.pull_point

    def start_pull(self, session: Driven) -> None:
        """Begin the pull at the endeffector."""
        self.motion.start_pull()

    def move_pull(self, point: FloatArray) -> None:
        self.motion.move_pull(point)

    def end_pull(self) -> None:
        self.motion.end_pull()

    # ---- the circle demo over the simulation ----
    def run_circle(self, session: Driven, circle: DemoCircle, dt: float) -> None:
        """The circle moves the desired joints (and their velocity), which the controller
        tracks; then ``dt`` s are simulated."""
        state = session.state
        q_new, qd = circle.joint_step(session.robot, state.q_des(), session.ghost.endeff_tf.t(), dt)
        state.set_q_des(q_new)
        state.set_qd_des(qd)
        session.update_kinematics()
        self.advance(session, dt)

    def circle_start(self, session: Driven) -> FloatArray:
        """The desired endeffector position: the circle moves the set point."""
        return session.ghost.endeff_tf.t()
