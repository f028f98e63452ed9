"""Playback of a planned pick task as a session's driver: the arm (current and desired
state) is put where the plan has it, in every motion mode.  Imports the planner."""
from __future__ import annotations

import numpy as np

from robot_sim.graphics.camera import Camera
from robot_sim.graphics.task_scene import TaskScene
from robot_sim.planning.pick_task import TaskPlan
from robot_sim.viewer.drivers.base import Driven, Driver, FloatArray, OverDriver
from robot_sim.viewer.pick_demo import PickDemo
from robot_sim.viewer.pick_view import clear_view_azimuth


class PickDriver(OverDriver):
    """Plays ``pick`` (time, speed, play/pause) over ``inner``, the motion driver that
    comes back when the joints are set by hand."""

    name = "pick"

    def __init__(self, pick: PickDemo, inner: Driver) -> None:
        super().__init__(inner)
        self.pick = pick

    @classmethod
    def start(cls, session: Driven, plan: TaskPlan, time: float = 0.0, effort: np.ndarray | None = None,
              mode: str = "kinematic") -> PickDriver:
        """``plan`` shown at ``time`` s over the session's motion driver, playing unless at
        the end; ``effort`` and ``mode`` as in PickDemo."""
        driver = cls(PickDemo(plan, effort, mode=mode), session.driver.base)
        driver.show_at(session, time)
        driver.pick.playing = driver.pick.time < driver.pick.duration
        return driver

    def advance(self, session: Driven, dt: float) -> None:
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

    def task_scene(self) -> TaskScene:
        """The table, the object, the gripper and the path at the playback's time."""
        return self.pick.task_scene()

    def aim(self, camera: Camera, points: FloatArray, aspect: float) -> None:
        """Turn the camera about the vertical, if it must, until the table hides none of
        the arm (pick_view.clear_view_azimuth)."""
        camera.set_view(clear_view_azimuth(camera, self.pick.plan, points, aspect), camera.elevation_deg)

    @property
    def replayed_mode(self) -> str | None:
        """The mode of the simulated run replayed kinematically (its efforts plotted)."""
        return self.pick.mode if not self.inner.physical and self.pick.effort is not None else None
