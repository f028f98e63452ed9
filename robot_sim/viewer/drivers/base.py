"""The interface every driver of a viewer session implements (no Qt, no GL)."""
from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

import numpy as np

from robot_sim.kinematics import IKResult, Kinematics
from robot_sim.model.params import RobotParams
from robot_sim.model.state import RobotState
from robot_sim.transforms import HomogeneousTransform
from robot_sim.viewer.trail import Trail

if TYPE_CHECKING:
    from robot_sim.control.simulation import LimitEvent
    from robot_sim.viewer.motion import Motion


class Driven(Protocol):
    """What a driver moves: the part of robot_sim.viewer.session.Driven it reads
    and writes (the session imports the drivers, so they name this instead)."""

    robot: RobotParams
    state: RobotState
    kin: Kinematics
    ghost: Kinematics
    target_tf: HomogeneousTransform | None
    ik_result: IKResult | None
    trail: Trail | None
    limit_events: list[LimitEvent]
    driver: Driver

    @property
    def motion(self) -> Motion: ...

    @property
    def physical(self) -> bool: ...

    @property
    def task_space(self) -> bool: ...

    def update_kinematics(self) -> None: ...


class Driver:
    """Moves the session's arm: :meth:`step` advances it by wall time, :meth:`moving` says
    whether a view should keep stepping, :meth:`set_q` puts joints where the user asked.
    ``physical`` is True while the arm is simulated."""

    physical = False

    def step(self, session: Driven, dt: float) -> None:
        """Advance by ``dt`` seconds of wall-clock time."""
        raise NotImplementedError

    def moving(self, session: Driven) -> bool:
        """True while a view must keep calling :meth:`step`."""
        raise NotImplementedError

    def set_q(self, session: Driven, q: np.ndarray) -> None:
        """Joints set by hand (sliders, Home, ``display(q)``), SI units (rad, m)."""
        raise NotImplementedError

    def rest(self, session: Driven) -> None:
        """Bring the arm to rest where it is (a demo that moved it ended)."""
        raise NotImplementedError

    @property
    def base(self) -> Driver:
        """The motion driver underneath (itself unless it wraps one: the demos)."""
        return self


class OverDriver(Driver):
    """A demo run over the motion driver it interrupts (``inner``: still or simulated),
    which comes back when the demo ends; physical while that one is."""

    def __init__(self, inner: Driver) -> None:
        self.inner = inner

    @property
    def physical(self) -> bool:  # type: ignore[override]
        return self.inner.physical

    @property
    def base(self) -> Driver:
        return self.inner
