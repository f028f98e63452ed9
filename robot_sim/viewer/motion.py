"""How a viewer's arm moves, without Qt: kinematically (joints follow the desired values)
or physically (the physics loop's ``Simulation`` driven by one of the controllers of
``robot_sim.control.controllers``).

:class:`Motion` owns the mode (:data:`control.MOTION_MODES`), the gains and the
simulation of one robot and its :class:`~robot_sim.model.state.RobotState`.  In a physical mode the
state's desired values (sliders, IK ghost, demo) are the controller's set point and the
current values are simulated; the mouse can pull the endeffector with a spring
(:meth:`Motion.start_pull`).  Simulated links rest on the world's obstacles and the
floor (penalty contact with friction, ``sim.contact``).  A robot file without inertial data is simulated with
``robot_sim.model.estimate.estimate_inertials`` and :attr:`Motion.estimated` says so.

Units: SI (rad, m, s, N, N·m); points in the world frame.
"""
from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim import dynamics
from robot_sim.collision.checker import CollisionChecker
from robot_sim.dynamics import GRAVITY
from robot_sim.control.controllers import MOTION_LABELS, MOTION_MODES, Gains, control_gains
from robot_sim.control.factory import make_controller
from robot_sim.control.reference import Desired
from robot_sim.model.estimate import estimate_inertials
from robot_sim.kinematics import forward_kinematics, random_configurations
from robot_sim.model.params import RobotParams
from robot_sim.model.state import RobotState
from robot_sim.model.world import World
from robot_sim.sim.simulation import LimitEvent, Simulation

FloatArray = NDArray[np.float64]

#: Pull spring: stiffness such that pulling the endeffector PULL_STRETCH_M away takes the
#: arm's whole weight, and a damping ratio of PULL_DAMPING_RATIO for the arm's total mass
#: hanging on the spring.
PULL_STRETCH_M = 0.2
PULL_DAMPING_RATIO = 0.5
#: Configurations sampled for the effort bars' scale of joints without an effort limit.
EFFORT_SCALE_SAMPLES = 256
EFFORT_SCALE_SEED = 8


class Motion:
    """Motion mode, controller gains and simulation of one robot shown by a viewer.

    ``gain_overrides`` (keys ``bandwidth``, ``damping``, ``kp``, ``kd``) go to
    :func:`control.control_gains` over the file's ``[control]`` table.  ``world`` holds
    what the links touch (the floor when None).
    """

    def __init__(self, robot: RobotParams, state: RobotState, gain_overrides: dict[str, Any] | None = None,
                 world: World | None = None) -> None:
        self.estimated = robot.inertials is None
        self.robot = estimate_inertials(robot) if self.estimated else robot
        self.state = state
        self.gains: Gains = control_gains(self.robot, **(gain_overrides or {}))
        self.sim = Simulation(self.robot, state, checker=CollisionChecker(self.robot, world))
        self.mode = "kinematic"
        self.pull_point: FloatArray | None = None
        mass = float(np.sum(self.robot.inertials.mass))
        self.pull_stiffness = mass * float(np.linalg.norm(GRAVITY)) / PULL_STRETCH_M
        self.pull_damping = 2.0 * PULL_DAMPING_RATIO * math.sqrt(self.pull_stiffness * mass)
        self.effort_scale = self._effort_scale()

    @property
    def physical(self) -> bool:
        """True in every mode but ``kinematic``."""
        return self.mode != "kinematic"

    @property
    def task_space(self) -> bool:
        """True in a task-space mode (operational space, impedance): the controller follows
        a desired tool pose, the state's desired joints' or :meth:`follow`'s."""
        return self.physical and self.sim.controller.space == "task"

    def follow(self, reference: Callable[[float], Desired] | None) -> None:
        """Under a task-space mode: follow ``reference`` (a task reference of the
        simulation's time, see robot_sim/control/reference.py) instead of the state's
        desired joints; None goes back to them."""
        self.sim.reference = reference

    @property
    def label(self) -> str:
        """Human-readable name of the mode (``"PD + gravity"``)."""
        return MOTION_LABELS[self.mode]

    def set_mode(self, mode: str) -> None:
        """Switch to ``mode`` (one of MOTION_MODES); a physical mode starts from the state's
        current q and qd.  ValueError for an unknown mode (nothing changes)."""
        if mode not in MOTION_MODES:
            raise ValueError(f"mode must be one of {', '.join(MOTION_MODES)}, got {mode!r}")
        if mode != "kinematic":
            self.sim.controller = make_controller(mode, self.robot, self.gains)
            self.sim.reference = None
            self.sim.load_state()
        else:
            self.end_pull()
            self.state.set_qd(np.zeros(self.robot.n_dofs))
        self.mode = mode

    def cycle(self) -> str:
        """Switch to the next mode of MOTION_MODES (wrapping) and return it."""
        self.set_mode(MOTION_MODES[(MOTION_MODES.index(self.mode) + 1) % len(MOTION_MODES)])
        return self.mode

    def advance(self, dt_wall: float) -> list[LimitEvent]:
        """Simulate ``dt_wall`` seconds of wall-clock time (physical modes; see
        Simulation.advance) and return the joint-limit arrivals meanwhile."""
        if not self.physical:
            return []
        self.sim.advance(dt_wall)
        return self.sim.take_events()

    def simulate(self, duration: float) -> None:
        """Simulate ``duration`` seconds at once (the command line's ``--duration``)."""
        if not (math.isfinite(duration) and duration >= 0):
            raise ValueError(f"duration must be a finite number of seconds >= 0, got {duration!r}")
        self.sim.step(round(duration / self.sim.dt))
        self.sim.take_events()

    # ---- pulling the endeffector with the mouse ----
    def start_pull(self) -> FloatArray:
        """Begin a pull at the endeffector's current position (returned, world m)."""
        self.pull_point = forward_kinematics(self.robot, self.state.q())[:3, 3].copy()
        self.sim.set_pull(self.pull_point, self.pull_stiffness, self.pull_damping)
        return self.pull_point

    def move_pull(self, point: ArrayLike) -> None:
        """Move the spring's anchor to ``point`` (3,) [m, world]."""
        self.sim.set_pull(point, self.pull_stiffness, self.pull_damping)
        self.pull_point = np.asarray(point, dtype=float).copy()

    def end_pull(self) -> None:
        """Release the endeffector."""
        self.pull_point = None
        self.sim.clear_pull()

    # ---- what the window shows ----
    def effort_fraction(self) -> FloatArray:
        """Applied effort of each joint as a signed fraction of :attr:`effort_scale` (n,)."""
        return self.sim.effort / self.effort_scale

    def _effort_scale(self) -> FloatArray:
        """Per joint: the effort limit where the drive gives one; otherwise twice the
        largest gravity torque over random configurations, or, for a joint gravity never
        loads, its PD gain times 0.5 rad [N·m or N]."""
        limit = self.sim.effort_limit
        samples = random_configurations(self.robot, EFFORT_SCALE_SAMPLES, np.random.default_rng(EFFORT_SCALE_SEED))
        gravity = 2.0 * np.abs(dynamics.gravity_torque(self.robot, samples)).max(axis=0)
        nominal = np.where(gravity > 1e-9, gravity, 0.5 * self.gains.kp)
        return np.where(np.isfinite(limit), limit, np.maximum(nominal, 1e-9))

    def status_text(self) -> str:
        """Status bar part: mode, simulated time, real-time factor, why it stopped."""
        if not self.physical:
            return "kinematic"
        rtf = self.sim.real_time_factor
        text = f"{self.label} · t = {self.sim.time:.2f} s · RTF " + ("—" if math.isnan(rtf) else f"{rtf:.2f}")
        if self.estimated:
            text += " · estimated inertials"
        if self.sim.stopped:
            text += f" · {self.sim.stopped}"
        return text
