"""Playback of a planned pick task as a session's driver: the arm (current and desired
state) is put where the plan has it, in every motion mode.  Imports the planner."""
from __future__ import annotations


import numpy as np

from robot_sim.viewer.drivers.base import Driven, Driver, OverDriver
from robot_sim.viewer.pick_demo import PickDemo


class PickDriver(OverDriver):
    """Plays ``pick`` (time, speed, play/pause) over ``inner``, the motion driver that
    comes back when the joints are set by hand."""

    def __init__(self, pick: PickDemo, inner: Driver) -> None:
        super().__init__(inner)
        self.pick = pick

    def step(self, session: Driven, dt: float) -> None:
        """Advance the playback by ``dt`` s of wall time times its speed."""
        self.pick.step(dt)
        self.show_at(session, self.pick.time)

    def moving(self, session: Driven) -> bool:
        return self.pick.playing

    def set_q(self, session: Driven, q: np.ndarray) -> None:
        """Pause the playback and set the joints as the motion driver does."""
        self.pick.playing = False
        self.inner.set_q(session, q)

    def show_at(self, session: Driven, t: float) -> None:
        """Put the arm where the plan has it at ``t`` s (clamped to the task)."""
        self.pick.seek(t)
        trajectory = self.pick.plan.trajectory
        q, qd, _ = trajectory.evaluate(trajectory.t[0] + self.pick.time)
        session.state.set_q(q)
        session.state.set_q_des(q)
        session.state.set_qd(qd)
        session.update_kinematics()
