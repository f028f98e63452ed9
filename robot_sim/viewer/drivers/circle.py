"""The circle demo as a session's driver: the endeffector runs a horizontal circle
(circle_path.DemoCircle), over the still or simulated driver it interrupts.  Units: m, s."""
from __future__ import annotations

import numpy as np

from robot_sim.viewer import settings as vs
from robot_sim.viewer.drivers.base import Driven, Driver, OverDriver
from robot_sim.viewer.drivers.circle_path import DemoCircle


class CircleDriver(OverDriver):
    """Runs ``circle`` over ``inner`` (the still or a simulation driver), which says how
    (Driver.run_circle): kinematically it moves the arm; under a joint-space controller it
    moves the desired state, which the controller tracks; under a task-space controller
    the simulation follows the circle as its reference and nothing is solved here."""

    name = "circle"

    def __init__(self, circle: DemoCircle, inner: Driver) -> None:
        super().__init__(inner)
        self.circle = circle

    @classmethod
    def start(cls, session: Driven) -> CircleDriver:
        """A circle through the endeffector (the desired one under a joint-space
        controller), over the session's motion driver; in task space the simulation
        follows it at once."""
        base = session.driver.base
        driver = cls(DemoCircle(center=base.circle_start(session) - np.array([vs.DEMO_CIRCLE_RADIUS_M, 0.0, 0.0])),
                     base)
        base.follow_circle(session, driver.circle)
        return driver

    def advance(self, session: Driven, dt: float) -> None:
        """Advance the circle by ``dt`` s, run by the motion driver underneath."""
        self.circle.time += dt
        self.inner.run_circle(session, self.circle, dt)

    def moving(self, session: Driven) -> bool:
        return True

    def set_q(self, session: Driven, q: np.ndarray) -> None:
        """Setting the joints by hand ends the demo."""
        session.driver = self.inner
        self.inner.set_q(session, q)

    def target_moved(self, session: Driven) -> None:
        """Moving the IK target ends the demo."""
        session.driver = self.inner

    def engage(self, session: Driven) -> None:
        """A new motion mode underneath follows the circle if it can."""
        self.inner.follow_circle(session, self.circle)
