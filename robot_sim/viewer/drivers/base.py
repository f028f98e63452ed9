"""The interface every driver of a viewer session implements (no Qt, no GL).

A session asks its one driver whatever depends on what moves the arm: how a wall-clock
step advances it, which joints the sliders set, what the ghost and the IK target show,
how far the tool is from its desired pose, whether the mouse can pull the arm, how the
camera frames a task.  Switching the motion mode or starting a demo replaces the driver;
the session's options, camera, trail and target stay.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Protocol

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics.camera import Camera
from robot_sim.graphics.task_scene import TaskScene
from robot_sim.kinematics import IKResult, Kinematics
from robot_sim.model.params import RobotParams
from robot_sim.model.state import RobotState
from robot_sim.transforms import HomogeneousTransform
from robot_sim.viewer.trail import Trail

if TYPE_CHECKING:
    from robot_sim.sim.stops import LimitEvent
    from robot_sim.viewer.drivers.circle_path import DemoCircle
    from robot_sim.viewer.motion import Motion
    from robot_sim.viewer.pick_demo import PickDemo

FloatArray = NDArray[np.float64]


class Driven(Protocol):
    """What a driver moves: the part of robot_sim.viewer.session.ViewerSession it reads
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

    def update_kinematics(self) -> None: ...

    def solve_target(self) -> bool: ...


class Driver:
    """Moves the session's arm.  Every driver answers :meth:`advance`, :meth:`moving`,
    :meth:`set_q` and :meth:`rest`; the other methods hold the still arm's answer (no
    simulation, no demo), which the simulated drivers and the demos override.

    ``name`` says which driver it is; ``physical`` is True while the arm is simulated,
    ``task_space`` while a task-space controller (operational space, impedance) moves it;
    ``motion`` is the simulation's :class:`~robot_sim.viewer.motion.Motion` (None when
    nothing is simulated); ``circle`` and ``pick`` are the demo shown (None: none).
    """

    name = "driver"
    physical = False
    task_space = False
    motion: Motion | None = None
    circle: DemoCircle | None = None
    pick: PickDemo | None = None

    # ---- time ----
    def advance(self, session: Driven, dt: float) -> None:
        """Advance by ``dt`` seconds of wall-clock time."""
        raise NotImplementedError

    def moving(self, session: Driven) -> bool:
        """True while a view must keep calling :meth:`advance`."""
        raise NotImplementedError

    def wall_step(self, elapsed: float, longest: float) -> float:
        """The step (s) a view's timer advances by after ``elapsed`` s of wall time:
        clamped to [1 ms, ``longest``] so a stalled timer makes no jump."""
        return min(max(elapsed, 1e-3), longest)

    def simulate(self, session: Driven, duration: float) -> None:
        """Simulate ``duration`` s at once (``--duration``); only a simulated arm can."""
        raise ValueError("simulating needs a physical motion mode")

    # ---- joints set by hand ----
    def set_q(self, session: Driven, q: np.ndarray) -> None:
        """Joints set by hand (sliders, Home, ``display(q)``), SI units (rad, m)."""
        raise NotImplementedError

    def set_point(self, session: Driven) -> FloatArray:
        """The joint values (n,) the sliders show and set: the arm's own."""
        return session.state.q()

    def rest(self, session: Driven) -> None:
        """Bring the arm to rest where it is (a demo that moved it ended)."""
        raise NotImplementedError

    # ---- IK target and ghost ----
    def reach_target(self, session: Driven) -> bool:
        """The IK target moved: solve IK for it (the ghost goes there when reachable)."""
        return session.solve_target()

    def target_toggled(self, session: Driven) -> None:
        """The IK target was shown or hidden (nothing to do unless a controller follows it)."""

    def target_moved(self, session: Driven) -> None:
        """The user moved the IK target (the circle demo ends then)."""

    def engage(self, session: Driven) -> None:
        """The motion mode underneath changed to this driver's: take over what it follows."""

    def shown_ghost(self, session: Driven) -> Kinematics | None:
        """The ghost drawn (the desired state): shown with the IK target."""
        return session.ghost if session.target_tf is not None else None

    def shown_target(self, session: Driven) -> HomogeneousTransform | None:
        """The target pose drawn: the IK target."""
        return session.target_tf

    def desired_tool_pose(self, session: Driven) -> FloatArray | None:
        """The tool's desired world pose (4, 4) the readout measures the tracking error
        from; None when nothing tracks one."""
        return None

    # ---- the panels ----
    @property
    def mode(self) -> str:
        """The motion mode (control.MOTION_MODES) the chooser shows."""
        return "kinematic"

    @property
    def replayed_mode(self) -> str | None:
        """The motion mode of a simulated run being replayed (its efforts plotted), or None."""
        return None

    # ---- the mouse pull ----
    @property
    def pull_point(self) -> FloatArray | None:
        """The pull spring's anchor (3,) in the world [m], None while nothing pulls."""
        return None

    def start_pull(self, session: Driven) -> None:
        """Begin pulling the endeffector: only a simulated arm can be pulled."""
        raise ValueError("pulling needs a physical motion mode: press Shift+M")

    def move_pull(self, point: FloatArray) -> None:
        """Move the pull's anchor to ``point`` (3,) [m, world]."""

    def end_pull(self) -> None:
        """Let go of the endeffector."""

    # ---- demos ----
    def show_at(self, session: Driven, t: float) -> None:
        """Show a pick task at ``t`` s; only the pick playback has one."""
        raise ValueError("no pick task is shown")

    def task_scene(self) -> TaskScene | None:
        """The pick task's drawing data, None without one."""
        return None

    def aim(self, camera: Camera, points: FloatArray, aspect: float) -> None:
        """Turn ``camera`` before it frames ``points`` (N, 3) at ``aspect`` (nothing to do
        without a task)."""

    def run_circle(self, session: Driven, circle: DemoCircle, dt: float) -> None:
        """One step of ``dt`` s of the circle demo over this motion driver."""
        raise NotImplementedError

    def circle_start(self, session: Driven) -> FloatArray:
        """Where the circle demo starts (3,) [m, world]: the endeffector."""
        return session.kin.endeff_tf.t()

    def follow_circle(self, session: Driven, circle: DemoCircle) -> None:
        """The circle demo starts or the mode changed under it (nothing to do unless a
        controller follows it as a reference)."""

    @property
    def base(self) -> Driver:
        """The motion driver underneath (itself unless it wraps one: the demos)."""
        return self

    def over(self, base: Driver) -> Driver:
        """This driver with ``base`` as the motion driver underneath: a motion driver is
        replaced by it, a demo keeps running over it."""
        return base


class OverDriver(Driver):
    """A demo run over the motion driver it interrupts (``inner``: still or simulated),
    which comes back when the demo ends.  What depends on the motion mode (the simulation,
    the pull, the ghost, the tracking error, the panels) is the inner driver's."""

    def __init__(self, inner: Driver) -> None:
        self.inner = inner

    @property
    def physical(self) -> bool:  # type: ignore[override]
        return self.inner.physical

    @property
    def task_space(self) -> bool:  # type: ignore[override]
        return self.inner.task_space

    @property
    def motion(self) -> Motion | None:  # type: ignore[override]
        return self.inner.motion

    @property
    def base(self) -> Driver:
        return self.inner

    def over(self, base: Driver) -> Driver:
        self.inner = base
        return self

    def stop(self, session: Driven) -> Driver:
        """End the demo: the motion driver underneath, the arm at rest where it is."""
        self.inner.rest(session)
        session.update_kinematics()
        return self.inner

    def wall_step(self, elapsed: float, longest: float) -> float:
        return self.inner.wall_step(elapsed, longest)

    def set_point(self, session: Driven) -> FloatArray:
        return self.inner.set_point(session)

    def rest(self, session: Driven) -> None:
        self.inner.rest(session)

    def reach_target(self, session: Driven) -> bool:
        return self.inner.reach_target(session)

    def target_toggled(self, session: Driven) -> None:
        self.inner.target_toggled(session)

    def engage(self, session: Driven) -> None:
        self.inner.engage(session)

    def shown_ghost(self, session: Driven) -> Kinematics | None:
        return self.inner.shown_ghost(session)

    def shown_target(self, session: Driven) -> HomogeneousTransform | None:
        return self.inner.shown_target(session)

    def desired_tool_pose(self, session: Driven) -> FloatArray | None:
        return self.inner.desired_tool_pose(session)

    @property
    def mode(self) -> str:
        return self.inner.mode

    @property
    def pull_point(self) -> FloatArray | None:
        return self.inner.pull_point

    def start_pull(self, session: Driven) -> None:
        self.inner.start_pull(session)

    def move_pull(self, point: FloatArray) -> None:
        self.inner.move_pull(point)

    def end_pull(self) -> None:
        self.inner.end_pull()
