"""The simulation driver: the arm is simulated (a physical motion mode of
:class:`robot_sim.viewer.motion.Motion`) and its controller tracks the desired values.
Units: SI."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from robot_sim.transforms import HomogeneousTransform
from robot_sim.viewer import settings as vs
from robot_sim.viewer.drivers.base import Driven, Driver

if TYPE_CHECKING:
    from robot_sim.viewer.motion import Motion


class SimulationDriver(Driver):
    """Steps ``motion``'s simulation in wall-clock time; sliders set the controller's set point."""

    physical = True

    def __init__(self, motion: Motion) -> None:
        self.motion = motion

    def step(self, session: Driven, dt: float) -> None:
        """Simulate ``dt`` s of wall-clock time (Simulation.advance caps a lag)."""
        session.limit_events.extend(self.motion.advance(dt))
        session.update_kinematics()

    def moving(self, session: Driven) -> bool:
        """True until the simulation stops (a stop it cannot go past)."""
        return self.motion.sim.stopped is None

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

    def rest(self, session: Driven) -> None:
        """The set point at rest: in task space the controller holds the tool where it is
        (back to the desired joints, set to the current ones), in joint space the desired
        velocities are zeroed."""
        if session.task_space:
            self.motion.follow(None)
            session.state.set_q_des(session.state.q())
        session.state.set_qd_des(np.zeros(session.robot.n_dofs))

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
