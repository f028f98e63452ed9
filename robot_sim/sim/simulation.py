"""Fixed-step physics simulation of a manipulator: controller → drive limits → dynamics → state.

:class:`Simulation` integrates the joint state of a robot with inertial data at a fixed
step (1 kHz by default), decoupled from rendering: :meth:`Simulation.advance` takes the
wall-clock time since the previous call and runs as many whole steps as fit (carrying the
remainder), so the picture shows the state at the last whole step and the simulated time
keeps pace with the wall clock while the computation keeps up.

One step of length h, in this order:

1. The desired state: from the ``reference`` when given (a joint reference, or a task
   reference of tool poses for a task-space controller: robot_sim/control/reference.py),
   else the desired state of the :class:`~robot_state.RobotState` (what the sliders, the
   IK ghost or the demo set; a task-space controller follows the tool motion of those
   joints).
2. The controller's effort, held constant over the step (a digital controller at the step
   rate), saturated at the drive's effort limit; joints that saturate are reported in
   :attr:`Simulation.saturated`.  ``JointState.u`` holds the applied effort.  A
   continuous-time controller (``controller.continuous``: operational space, impedance)
   is evaluated again at every integration stage, on the reference at the stage's time,
   so its closed loop is integrated to the integrator's order; the effort reported is the
   step's first.  A step that touches a joint stop holds the first stage's effort.
3. Forward dynamics (``dynamics.forward_dynamics``) with the optional pull force at the tool (a spring toward a point,
   see :meth:`Simulation.set_pull`), integrated by semi-implicit (symplectic) Euler —
   ``qd += h·qdd(q, qd); q += h·qd`` — or classical RK4.
   Joint limits are stops consistent with the mass matrix (the one stop resolver of
   robot_sim/sim/stops.py over ``joint_stops``, shared with ``BatchSimulation``): a step that
   would carry a joint past its limit is cut at the instant it arrives (the step length
   found by Newton's method on the integrator's own step, to 1e-12 rad or m), the stops
   apply the impact impulse over the joints they touch (inelastic unless ``restitution``
   is set; kinetic energy never increases), a :class:`LimitEvent` records the arrival
   and the impulse, and the rest of the step is integrated from there.  A joint resting
   on its stop at zero velocity whose acceleration pushes into it is held: the step
   integrates the dynamics with that joint's row and column removed, and
   :attr:`Simulation.limit_torque` is the stop's reaction torque.  It is released when
   the reaction would pull (checked at the start of every step).  A step resting on
   stops is one call of the compiled step like a free one (``Stepper`` with
   ``stops``: the held rows solved inside it); arrivals, impacts and releases go through
   the stop resolver, whose outcome is a ``StopOutcome``.  Steps that touch no stop are
   computed exactly as without stops.
4. Velocity limits: the drive brakes a joint at its velocity limit (``qd`` clipped).

Contact (``checker=``, a :class:`~robot_sim.collision.CollisionChecker` of the robot):
links that meet an obstacle, the floor or each other get penalty contact forces
(:mod:`robot_sim.sim.contact`, Coulomb friction ``friction``).  At the start of a
step the pairs near contact are chosen and their gains, friction anchors and contact
frames (normal, and witness points held in their bodies) fixed; the contact torque then
enters the dynamics at every stage of the integrator, from that stage's (q, qd) in the
held frames (docs/contact.md): one compiled call (``ContactModel.step``) unless a
pull, a tool wrench or a continuous-time controller acts too.  Steps with no pair near
contact are computed exactly as without contact.

A step whose state or effort is not finite (or whose mass matrix cannot be solved)
does not happen: the simulation keeps the last finite state, stops, and
:attr:`Simulation.stopped` says why.

Units: q in rad (revolute) and m (prismatic), qd and qdd their rates, efforts in N·m and
N, time in s, forces in N in the world frame.  This module imports neither OpenGL nor Qt.
"""
from __future__ import annotations

import math
import time as _time
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim import dynamics
from robot_sim.collision.checker import CollisionChecker
from robot_sim.control.controllers import Controller, Integrated, Passive, StepContext
from robot_sim.control.factory import make_controller
from robot_sim.control.reference import Desired, Reference, task_from_joints
from robot_sim.kinematics import Kinematics
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotParams
from robot_sim.model.state import RobotState
from robot_sim.sim import stepper as stepping
from robot_sim.sim.contact import DEFAULT_FRICTION, ContactForce, ContactModel
from robot_sim.sim.stepper import INTEGRATORS, StageAccel, StepDiverged, Stepper, raise_for, runge_kutta, step_one_arm
from robot_sim.sim.stops import LimitEvent, Resolved, StepPhysics, StopOutcome, StopResolver

FloatArray = NDArray[np.float64]

DEFAULT_DT = 1e-3
#: At most this much simulated time per :meth:`Simulation.advance` call [s]: when the
#: computation falls behind the wall clock, the simulation slows down (real-time factor
#: below 1) instead of trying to catch up with ever longer bursts.
DEFAULT_MAX_LAG = 0.1
#: Wall-clock span over which the real-time factor is averaged [s].
RTF_WINDOW = 0.5


def drive_limits(robot: RobotParams) -> tuple[FloatArray, FloatArray]:
    """Effort [N·m or N] and velocity [rad/s or m/s] limits per joint (inf without drives)."""
    n = robot.n_dofs
    drives = robot.drives
    if drives is None:
        return np.full(n, np.inf), np.full(n, np.inf)
    return np.asarray(drives.effort_limit, dtype=float), np.asarray(drives.velocity_limit, dtype=float)


def stop_message(time: float, reason: str) -> str:
    """What :attr:`Simulation.stopped` says when a step at ``time`` [s] failed for ``reason``."""
    return f"simulation stopped at t = {time:.3f} s: {reason}; kept the last finite state"


def _finite(a: FloatArray) -> bool:
    """True if every entry of the vector is finite (one dot product: a state whose squares
    overflow is as diverged as one holding inf)."""
    return math.isfinite(a @ a)


class Simulation:
    """Physics loop for one robot (which needs inertial data, see ``dynamics``).

    ``state`` (a new one at the robot's home if omitted) supplies the initial current
    state and the desired state, and receives the simulated state after every call of
    :meth:`step` or :meth:`advance`.  ``controller`` defaults to :class:`control.Passive`.
    ``dt`` is the fixed step [s]; ``integrator`` ``"rk4"`` or ``"euler"`` (semi-implicit).
    ``restitution`` in [0, 1] is the joint stops' coefficient of restitution (0: inelastic).
    ``checker`` (a CollisionChecker of ``robot``) turns on contact with its world and
    between its checked links, with Coulomb ``friction`` μ >= 0 (0.5 unless given; module
    docstring).
    ``reference``: None (follow the state's desired values), a callable of time [s]
    returning (q_des, qd_des, qdd_des) or (pose_d, twist_d, accel_d), or a ``Trajectory``
    (its ``poses``, when it has them, are the task reference); see
    robot_sim/control/reference.py.
    """

    def __init__(
        self,
        robot: RobotParams,
        state: RobotState | None = None,
        controller: Controller | None = None,
        *,
        dt: float = DEFAULT_DT,
        integrator: str = "rk4",
        reference: Any = None,
        max_lag: float = DEFAULT_MAX_LAG,
        restitution: float = 0.0,
        checker: CollisionChecker | None = None,
        friction: float = DEFAULT_FRICTION,
    ) -> None:
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be a positive finite number of seconds, got {dt!r}")
        if isinstance(controller, str):  # a mode name, as BatchSimulation takes
            controller = make_controller(controller, robot)
        elif controller is not None and not isinstance(controller, Controller):
            raise TypeError(f"controller must be a Controller or a mode name, got {type(controller).__name__}")
        if not (isinstance(max_lag, (int, float)) and math.isfinite(max_lag) and max_lag >= dt):
            raise ValueError(f"max_lag must be a finite number of seconds >= dt ({dt}), got {max_lag!r}")
        if state is not None and state.robot.n_dofs != robot.n_dofs:
            raise ValueError(f"state must be a RobotState of a robot with {robot.n_dofs} joints, got {state.robot.n_dofs}")
        dynamics.mass_matrix(robot, robot.q_home)  # fails now, naming the link, without inertials
        if checker is not None and (not isinstance(checker, CollisionChecker) or checker.robot is not robot):
            raise ValueError("checker must be a CollisionChecker built for this simulation's robot, got "
                             f"{checker!r}")
        #: Penalty contact (None without a checker); ``contact.forces`` are the touching pairs.
        self.contact = ContactModel(checker, friction=friction) if checker is not None else None
        self._touching = False  # some pair is active in the current step
        self.robot = robot
        self.state = state if state is not None else RobotState(robot)
        self.controller: Controller = controller if controller is not None else Passive(robot)
        self.dt = float(dt)
        self.max_lag = float(max_lag)
        self.integrator = integrator
        self._stops = StopResolver(robot)  # the one stop resolver (shared with BatchSimulation's code)
        self.restitution = restitution
        self.reference = reference
        n = robot.n_dofs
        self.effort_limit, self.velocity_limit = drive_limits(robot)
        self._limit_effort = bool(np.isfinite(self.effort_limit).any())
        self._limit_velocity = bool(np.isfinite(self.velocity_limit).any())
        self._limit_position = bool(np.isfinite(robot.q_min).any() or np.isfinite(robot.q_max).any())
        #: Simulated time [s] and number of steps taken.
        self.time = 0.0
        self.steps = 0
        #: Why the simulation stopped (divergence), or None while it runs.
        self.stopped: str | None = None
        #: Limit arrivals not yet taken by :meth:`take_events`.
        self.events: list[LimitEvent] = []
        #: Per joint: effort saturated / braked at the velocity limit / resting on a limit,
        #: in the last step.
        self.saturated = np.zeros(n, dtype=bool)
        self.velocity_limited = np.zeros(n, dtype=bool)
        self.at_limit = np.zeros(n, dtype=bool)
        #: Reaction torque [N·m or N] of the stops holding joints at the start of the last
        #: step (zero for free joints): M q̈ = τ − C q̇ − g (…) + limit_torque.
        self.limit_torque = self._no_reaction = self._stops.no_reaction
        #: Applied (saturated) and commanded effort of the last step [N·m or N].
        self.effort = np.zeros(n)
        self.effort_command = np.zeros(n)
        #: Simulated seconds per wall-clock second over the last :data:`RTF_WINDOW` of
        #: :meth:`advance` calls (NaN until measured).
        self.real_time_factor = math.nan
        #: Wall-clock seconds of computation per simulated second over the same window.
        self.compute_load = math.nan
        self._pending = 0.0
        self._rtf_wall = self._rtf_sim = self._rtf_cpu = 0.0
        self._pull: tuple[FloatArray, float, float] | None = None
        self._pull_kin: tuple[Kinematics, RobotState] | None = None
        self.pull_force = np.zeros(3)
        self._stepper: Stepper | None = None
        self._wrench: FloatArray | None = None
        #: The bytes of the state's desired joint values, rates and accelerations, and those
        #: (q, q̇, q̈) as read then.
        self._desired_joints: tuple[bytes, tuple] | None = None
        #: The desired joints (q, q̇, q̈) last followed in task space and their tool motion.
        self._task_of_joints: tuple | None = None
        #: The desired tool pose (4, 4) of the last step under a task-space controller.
        self.desired_pose: FloatArray | None = None
        self.load_state()

    # ------------------------------------------------------------------ configuration
    @property
    def integrator(self) -> str:
        """``"rk4"`` (classical Runge–Kutta) or ``"euler"`` (semi-implicit Euler)."""
        return self._integrator

    @integrator.setter
    def integrator(self, name: str) -> None:
        if name not in INTEGRATORS:
            raise ValueError(f"integrator must be one of {', '.join(INTEGRATORS)}, got {name!r}")
        self._integrator = name

    @property
    def reference(self) -> Any:
        """What the controller follows (None: the state's desired values); see the class."""
        return self._reference_source

    @reference.setter
    def reference(self, source: Any) -> None:
        self._reference = None if source is None else Reference(self.robot, source)
        self._reference_source = source

    @property
    def restitution(self) -> float:
        """Coefficient of restitution of the joint stops, in [0, 1]: an arriving joint
        leaves at this fraction of its approach speed (0: it stops on the limit)."""
        return self._restitution

    @restitution.setter
    def restitution(self, value: float) -> None:
        if not (isinstance(value, (int, float)) and 0.0 <= value <= 1.0):
            raise ValueError(f"restitution must be a number in [0, 1], got {value!r}")
        self._restitution = self._stops.restitution = float(value)

    def load_state(self) -> None:
        """Take the current q and qd from the RobotState (after it was set from outside,
        e.g. in kinematic mode), clipped into the joint limits, and resume a stopped run."""
        self.q = np.clip(self.state.q(), self.robot.q_min, self.robot.q_max)
        self.qd = self.state.qd().copy()
        self.qdd = np.zeros(self.robot.n_dofs)
        self.at_limit = (self.q <= self.robot.q_min) | (self.q >= self.robot.q_max)
        self._any_at_limit = bool(self.at_limit.any())
        self.stopped = None
        self._pending = 0.0
        if self.contact is not None:
            self.contact.reset()
        self._published = self.state.joint_state.motion_snapshot()
        self.controller.reset(self.q.copy(), self.dt)

    def _follow_state(self) -> None:
        """The RobotState is the one source of truth: when its q or qd were set from outside
        since this loop last wrote them (``sim.state.set_q(q)``), the next step starts there."""
        if self.state.joint_state.motion_snapshot() != self._published:
            self.load_state()

    def set_pull(self, point: ArrayLike, stiffness: float, damping: float = 0.0) -> None:
        """Pull the endeffector toward ``point`` (3,) [m, world] with a spring of
        ``stiffness`` [N/m] and a damper of ``damping`` [N·s/m] on the tool point's velocity;
        the force acts at the tool frame origin (a pure force, no moment)."""
        p = np.asarray(point, dtype=float)
        if p.shape != (3,) or not np.isfinite(p).all():
            raise ValueError(f"point must be a finite (3,) position in metres, got {point!r}")
        for name, value in (("stiffness", stiffness), ("damping", damping)):
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
        self._pull = (p, float(stiffness), float(damping))

    def clear_pull(self) -> None:
        """Release the endeffector (no pull force from the next step on)."""
        self._pull = None
        self.pull_force = np.zeros(3)

    def set_tool_wrench(self, wrench: ArrayLike | None) -> None:
        """Apply the constant wrench (6,) [force (N); moment (N·m)], world frame, to the
        tool frame's origin from the next step on (on top of any pull); None removes it."""
        if wrench is None:
            self._wrench = None
            return
        w = np.asarray(wrench, dtype=float)
        if w.shape != (6,) or not np.isfinite(w).all():
            raise ValueError(f"wrench must be a finite (6,) [force; moment] in N and N·m, got {wrench!r}")
        self._wrench = w.copy()

    def take_events(self) -> list[LimitEvent]:
        """The limit events since the previous call (oldest first), removing them."""
        events, self.events = self.events, []
        return events

    # ------------------------------------------------------------------ running
    def advance(self, dt_wall: float) -> int:
        """Run the whole steps that fit in ``dt_wall`` [s] of wall-clock time plus the
        remainder carried from earlier calls (at most ``max_lag`` of simulated time per
        call); return the number of steps taken."""
        if not (math.isfinite(dt_wall) and dt_wall >= 0):
            raise ValueError(f"dt_wall must be a finite number of seconds >= 0, got {dt_wall!r}")
        self._pending += dt_wall
        n_steps = int(self._pending / self.dt + 1e-9)
        max_steps = int(self.max_lag / self.dt + 1e-9)
        if n_steps > max_steps:
            n_steps, self._pending = max_steps, 0.0
        else:
            self._pending -= n_steps * self.dt
        start = _time.perf_counter()
        taken = self.step(n_steps)
        self._rtf_cpu += _time.perf_counter() - start
        self._rtf_wall += dt_wall
        self._rtf_sim += taken * self.dt
        if self._rtf_wall >= RTF_WINDOW:
            self.real_time_factor = self._rtf_sim / self._rtf_wall
            self.compute_load = self._rtf_cpu / self._rtf_sim if self._rtf_sim > 0 else math.nan
            self._rtf_wall = self._rtf_sim = self._rtf_cpu = 0.0
        return taken

    def step(self, n_steps: int = 1) -> int:
        """Run ``n_steps`` fixed steps (fewer if the simulation stops), write the result to
        the RobotState and return the number of steps taken."""
        if isinstance(n_steps, bool) or not isinstance(n_steps, (int, np.integer)) or n_steps < 0:
            raise ValueError(f"n_steps must be a whole number >= 0, got {clip_repr(n_steps)}")
        self._follow_state()
        if self.stopped is not None or n_steps == 0:
            return 0
        desired_at = self._desired_source()
        desired = None
        taken = 0
        law = self._sampled_law()
        if law is not None:  # whole steps in one compiled call (no NumPy warnings to mute)
            desired = desired_at(self.time)
            taken = self._run_law(law, desired, n_steps)
            if taken == 0:
                desired = None
        if taken < n_steps:
            with np.errstate(all="ignore"):
                while taken < n_steps:
                    try:  # a step the compiled loop does not take (a stop, a failure) or the loop's own
                        desired = self._step(desired_at)
                    except (StepDiverged, np.linalg.LinAlgError) as exc:
                        self.stopped = stop_message(self.time, str(exc))
                        break
                    taken += 1
                    if law is not None and taken < n_steps:
                        fixed = desired_at(self.time)
                        run = self._run_law(law, fixed, n_steps - taken)
                        if run:
                            taken, desired = taken + run, fixed
        self._publish(desired)
        return taken

    def _sampled_law(self) -> tuple[str, FloatArray, FloatArray] | None:
        """The controller's sampled law and gains (``Controller.sampled_law``) when whole
        steps of it may run in one compiled call: the compiled backend, the controller's
        model is the simulated robot, the desired values are fixed over the call (no
        reference), and nothing but the effort and the contact acts (no pull or tool
        wrench; contact whose lever arms do not vary with q)."""
        controller = self.controller
        if (self._reference is not None or self._pull is not None or self._wrench is not None
                or controller.space != "joint" or controller.continuous or dynamics.backend() != "compiled"
                or getattr(controller, "robot", self.robot) is not self.robot
                or (self.contact is not None and self.contact.compiled() is None)):
            return None
        return controller.sampled_law()

    def _run_law(self, law: tuple[str, FloatArray, FloatArray], desired: Desired, n_steps: int) -> int:
        """Up to ``n_steps`` steps of the sampled ``law`` toward ``desired`` in one compiled
        call (``Stepper.run_law``: the same bits as :meth:`_step` one step at a time, with
        joints resting on their stops and the contact of unchanged pairs inside); the
        number taken, whose record it writes as :meth:`_finish` does."""
        contact = None if self.contact is None else self.contact.compiled()
        taken, (q, qd, qdd, command, effort, saturated, braked), stops = self._stepper_of().run_law(
            *law, desired, self.effort_limit, self.velocity_limit, self.q, self.qd, n_steps, stops=self._limit_position,
            on_limit=self._any_at_limit, contact=contact,
        )
        if taken:
            self.q, self.qd, self.qdd = q, qd, qdd
            self.effort_command, self.effort = command, effort
            self.saturated, self.velocity_limited = saturated, braked
            if stops is not None:
                self.at_limit, self.limit_torque = stops
                self._any_at_limit = bool(self.at_limit.any())
            if contact is not None:
                self._touching = self.contact.active
            for _ in range(taken):  # the clock as the step-by-step loop advances it
                self.time += self.dt
            self.steps += taken
        return taken

    def _desired_source(self) -> Callable[[float], Desired]:
        """The desired values as a function of time, in the controller's space: the
        reference, or the state's desired joints (their tool motion for a task-space
        controller), fixed over the call.  ValueError if a joint controller is given a
        task-only reference."""
        space = self.controller.space
        if self._reference is not None:
            return self._reference.for_space(space)
        snapshot = self.state.joint_state_des.motion_snapshot(accelerations=True)
        if self._desired_joints is None or self._desired_joints[0] != snapshot:  # read once per change
            self._desired_joints = (snapshot, (self.state.q_des(), self.state.qd_des(), self.state.qdd_des()))
        fixed = self._desired_joints[1]
        if space == "task":  # the tool motion of the same joints as last call is not recomputed
            cached = self._task_of_joints
            if cached is None or not all(np.array_equal(a, b) for a, b in zip(cached[0], fixed)):
                cached = self._task_of_joints = (fixed, task_from_joints(self.robot, *fixed))
            fixed = cached[1]
        return lambda _time: fixed

    # ------------------------------------------------------------------ one step
    def _step(self, desired_at: Callable[[float], Desired]) -> Desired:
        """One step; returns the desired values at its start."""
        q, qd, t = self.q, self.qd, self.time
        desired = desired_at(t)
        controller = self.controller
        self._touching = self.contact is not None and self.contact.begin_step(q, qd, self.dt)
        alone = self._pull is None and self._wrench is None and not self._touching  # nothing but the effort acts
        taken = None
        if alone and controller.integrates:  # the controller may take the whole step, its law inside the compiled step
            taken = controller.integrate(q, qd, StepContext(
                t, self.dt, self._integrator, desired_at, desired, self.effort_limit, self._stepper_of(),
                self._limit_position, self._any_at_limit,
            ))
        if taken is not None:
            command = taken.command
        else:
            command = controller.torque(q, qd, *desired)
            if not _finite(command):
                raise StepDiverged(f"the {controller.mode} controller returned a non-finite effort {command}")
        saturated = np.abs(command) > self.effort_limit if self._limit_effort else self.saturated
        tau = np.clip(command, -self.effort_limit, self.effort_limit) if saturated.any() else command
        if taken is not None:
            q1, qd1, qdd, stops = self._resolve(q, qd, tau, taken)
            self._finish(q1, qd1, qdd, command, tau, saturated, stops)
            return desired
        f_tool = self._tool_wrench(q, qd)
        # The first stage's acceleration is known when the controller's model is the
        # simulated robot and nothing else acts (computed torque: its reference
        # acceleration, to round-off), which saves one forward dynamics per step.
        known = None
        plain = f_tool is None and not self._touching  # nothing but the effort acts
        if tau is command and plain and getattr(controller, "robot", None) is self.robot:
            known = controller.commanded_acceleration()
        stops = None
        if controller.continuous and not self._any_at_limit:  # the law at every stage
            if known is None or not _finite(known):
                known = self._accel(q, qd, tau, f_tool)
            q1, qd1, qdd = runge_kutta(self._integrator, q, qd, self.dt, known, self._continuous_accel(desired_at, t, f_tool))
            if self._limit_position and self._stops.crosses(q1):
                q1, qd1, _, stops = self._through_stops(q, qd, tau, f_tool, (q1, qd1, qdd))
        elif plain:  # one stepper call; it holds joints resting on their stops itself
            step = self._stepper_of().step(
                q[None], qd[None], tau[None], None if known is None else known[None], stepping.ONE_KNOWN,
                stops=self._limit_position,
            )
            status = int(step.status[0])
            held = self._any_at_limit or status == stepping.STEP_ON_LIMIT
            if status == stepping.STEP_OK and not held:  # the common step: no stop touched
                q1, qd1, qdd = step.q[0].copy(), step.qd[0].copy(), step.qdd[0].copy()
            else:
                q1, qd1, qdd, stops = self._resolve(q, qd, tau, Integrated(
                    step.q[0].copy(), step.qd[0].copy(), step.qdd[0].copy(), command, status,
                    step.reaction[0].copy() if held else None, step.at_limit[0].copy() if held else None,
                ))
        elif self._any_at_limit:
            q1, qd1, qdd, stops = self._through_stops(q, qd, tau, f_tool)
        else:
            q1, qd1, qdd = self._stepped(q, qd, tau, f_tool)[0]
            if self._limit_position and self._stops.crosses(q1):
                q1, qd1, _, stops = self._through_stops(q, qd, tau, f_tool, (q1, qd1, qdd))
        self._finish(q1, qd1, qdd, command, tau, saturated, stops)
        return desired

    def _resolve(
        self, q: FloatArray, qd: FloatArray, tau: FloatArray, taken: Integrated
    ) -> tuple[FloatArray, FloatArray, FloatArray, StopOutcome | None]:
        """(q, q̇) at the end of a step taken in one call (the stepper's, or a controller's
        with its law inside) from (q, q̇) with effort tau, its start's q̈, and the stops'
        outcome (None: no stop touched): by the stop resolver where the step was not
        taken from a start on a stop (AT_STOP) or crossed a limit (CROSSED); from the
        stops held inside the step where joints rest on them."""
        status = taken.status
        if status == stepping.STEP_AT_STOP:
            return self._through_stops(q, qd, tau, None)
        raise_for(status)
        if status == stepping.STEP_CROSSED:
            resolved = self._through_stops(q, qd, tau, None, (taken.q, taken.qd, taken.qdd))
            return resolved.q, resolved.qd, taken.qdd, resolved.outcome
        if taken.at_limit is not None and (self._any_at_limit or status == stepping.STEP_ON_LIMIT):
            reaction = taken.reaction if self._any_at_limit else self._no_reaction
            return taken.q, taken.qd, taken.qdd, StopOutcome(reaction, (), taken.at_limit)
        return taken.q, taken.qd, taken.qdd, None

    def _finish(
        self, q1: FloatArray, qd1: FloatArray, qdd: FloatArray, command: FloatArray, tau: FloatArray,
        saturated: NDArray[np.bool_], stops: StopOutcome | None,
    ) -> None:
        """End a step at (q1, qd1): velocity limits, finiteness, the stops' outcome, the
        step's record."""
        velocity_limited = self.velocity_limited
        if self._limit_velocity:
            velocity_limited = np.abs(qd1) > self.velocity_limit
            qd1 = np.clip(qd1, -self.velocity_limit, self.velocity_limit)
        if not (_finite(q1) and _finite(qd1)):
            raise StepDiverged("the joint state became non-finite")
        if stops is not None:
            self.limit_torque = stops.reaction
            if stops.events:
                self.events.extend(stops.events)
            at_limit = stops.at_limit
            if at_limit is None:
                at_limit = (q1 == self.robot.q_min) | (q1 == self.robot.q_max)
            self.at_limit, self._any_at_limit = at_limit, bool(at_limit.any())
        self.q, self.qd, self.qdd = q1, qd1, qdd
        self.effort_command, self.effort = command, tau
        self.saturated = saturated
        self.velocity_limited = velocity_limited
        self.time += self.dt
        self.steps += 1

    def _continuous_accel(self, desired_at: Callable[[float], Desired], t: float, f_tool: FloatArray | None) -> StageAccel:
        """Stage accelerations of a continuous controller, evaluated at each stage's state
        and time: its own closed-loop acceleration when its model is the robot and nothing
        else acts (no pull, no effort limit to check), else forward dynamics of its
        (saturated) effort."""
        controller = self.controller
        exact = f_tool is None and not self._touching and getattr(controller, "robot", None) is self.robot

        def accel(offset: float, q: FloatArray, qd: FloatArray) -> FloatArray:
            desired = desired_at(t + offset)
            if exact and not self._limit_effort:
                qdd = controller.acceleration(q, qd, *desired)
                if qdd is not None:
                    if not _finite(qdd):
                        raise StepDiverged("the joint acceleration became non-finite")
                    return qdd
            tau = controller.torque(q, qd, *desired)
            if not _finite(tau):
                raise StepDiverged(f"the {controller.mode} controller returned a non-finite effort {tau}")
            clipped = self._limit_effort and bool((np.abs(tau) > self.effort_limit).any())
            if clipped:
                tau = np.clip(tau, -self.effort_limit, self.effort_limit)
            elif exact and (known := controller.commanded_acceleration()) is not None and _finite(known):
                return known
            return self._accel(q, qd, tau, f_tool)

        return accel

    def _dynamics(
        self,
        q: FloatArray,
        qd: FloatArray,
        tau: FloatArray,
        f_tool: FloatArray | None,
        held: NDArray[np.bool_] | None,
    ) -> tuple[FloatArray, FloatArray | None]:
        """q̈ at (q, qd) with the ``held`` joints locked on their stops (None: none) and
        the stops' reaction (None without held joints)."""
        tau = self._with_contact(q, qd, tau)
        try:
            if held is None:
                qdd, torque = dynamics.forward_dynamics(self.robot, q, qd, tau, f_tool=f_tool), None
            else:
                qdd, torque = dynamics.constrained_forward_dynamics(self.robot, q, qd, tau, held, f_tool=f_tool)
        except ValueError:  # refused a stage state that overflowed (finite rates, huge values)
            if _finite(q) and _finite(qd):
                raise
            raise StepDiverged("the joint state became non-finite") from None
        if not _finite(qdd):
            raise StepDiverged("the joint acceleration became non-finite")
        return qdd, torque

    def _accel(
        self, q: FloatArray, qd: FloatArray, tau: FloatArray, f_tool: FloatArray | None, held: NDArray[np.bool_] | None = None
    ) -> FloatArray:
        return self._dynamics(q, qd, tau, f_tool, held)[0]

    def _stepper_of(self) -> Stepper:
        """The one-arm stepper of this simulation's robot and integrator (made on first use)."""
        stepper = self._stepper
        if stepper is None or stepper.dt != self.dt or stepper.method != self._integrator:
            stepper = self._stepper = Stepper(self.robot, 1, self.dt, self._integrator)
        return stepper

    def _stepped(
        self,
        q: FloatArray,
        qd: FloatArray,
        tau: FloatArray,
        f_tool: FloatArray | None,
        a1: FloatArray | None = None,
        h: float | None = None,
        locked: NDArray[np.bool_] | None = None,
    ) -> tuple[tuple[FloatArray, FloatArray, FloatArray], FloatArray | None]:
        """((q, qd) after a step of ``h`` (default ``dt``) with the ``locked`` joints held,
        the acceleration at its start (``a1`` when known and nothing is locked)), and the
        stops' reaction at the start (None without locked joints)."""
        if h is None:
            h = self.dt
        if f_tool is None and not self._touching:  # one call of the Stepper
            return step_one_arm(self._stepper_of(), q, qd, tau, a1, h, locked)
        if f_tool is None and locked is None:  # in contact: one compiled call, the contact torque at every stage
            return self.contact.step(q, qd, tau, a1, h, self._integrator == "rk4", self._stepper_of().gravity), None
        reaction = None
        if a1 is None or locked is not None or not _finite(a1):
            a1, reaction = self._dynamics(q, qd, tau, f_tool, locked)
        return runge_kutta(self._integrator, q, qd, h, a1, lambda _offset, qs, qds: self._accel(qs, qds, tau, f_tool, locked)), reaction


    # ------------------------------------------------------------------ joint stops
    def _through_stops(
        self,
        q: FloatArray,
        qd: FloatArray,
        tau: FloatArray,
        f_tool: FloatArray | None,
        trial: tuple[FloatArray, FloatArray, FloatArray] | None = None,
    ) -> Resolved:
        """One step that touches stops, by the one stop resolver (robot_sim/sim/stops.py)
        with this step's physics (contact and tool wrench included).  ``trial`` is the free
        step from (q, qd) when it was already taken (and crossed a limit); without it the
        step starts on a stop."""
        physics = StepPhysics(
            stepped=lambda qs, qds, effort, a1, h, locked: self._stepped(qs, qds, effort, f_tool, a1, h, locked),
            rhs=lambda qs, qds, effort: self._with_contact(qs, qds, effort)
            - dynamics.bias_torque(self.robot, qs, qds, f_tool=f_tool),
        )
        return self._stops.resolve(self.time, self.dt, q, qd, tau, physics, trial)

    @property
    def contact_forces(self) -> list[ContactForce]:
        """The touching pairs of the last step (empty without contact)."""
        return self.contact.forces if self._touching else []

    def _with_contact(self, q: FloatArray, qd: FloatArray, tau: FloatArray) -> FloatArray:
        """The effort plus the contact torque at the stage state (q, qd) of this step."""
        return tau + self.contact.torque(q, qd) if self._touching else tau

    def _tool_wrench(self, q: FloatArray, qd: FloatArray) -> FloatArray | None:
        """The wrench on the tool over this step: the pull spring's force and the constant
        wrench, or None when neither acts."""
        if self._pull is None:
            return self._wrench
        point, stiffness, damping = self._pull
        if self._pull_kin is None:
            self._pull_kin = (Kinematics(self.robot), RobotState(self.robot))
        kin, at_q = self._pull_kin
        at_q.set_q(q)
        kin.update(at_q.joint_state)
        force = stiffness * (point - kin.endeff_tf.t()) - damping * (kin.jacobian[:3] @ qd)
        self.pull_force = force
        wrench = np.concatenate([force, np.zeros(3)])
        return wrench if self._wrench is None else wrench + self._wrench

    def _publish(self, desired: Desired | None) -> None:
        """Write the simulated state to the RobotState and the desired values of the last
        step: with a joint reference into the state, a task controller's pose into
        :attr:`desired_pose`."""
        state = self.state
        state.write_motion(self.q, self.qd, self.qdd, self.effort)
        self._published = state.joint_state.motion_snapshot()
        if desired is None:
            return
        self.desired_pose = desired[0] if self.controller.space == "task" else None
        ref = self._reference
        if ref is not None and ref.joint is not None:
            joint = desired if self.controller.space == "joint" else ref.joint(self.time - self.dt)
            state.set_q_des(joint[0])
            state.set_qd_des(joint[1])
            state.set_qdd_des(joint[2])
