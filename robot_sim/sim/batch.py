"""Many independent arms of one robot stepped at once: :class:`BatchSimulation`.

Each step does for every running environment what ``Simulation.step`` does for one arm,
in the same order and with the same floating-point operations on arrays of shape
(n_envs, n): the controller's effort (batched: PD, PD + gravity and computed torque take
(N, n) arrays), saturation at the drives' effort limits, one integration step of all arms
by a ``Stepper`` (one compiled call), velocity limits, joint limits as hard
stops, divergence.  So environment i of a batch ends bit for bit where a ``Simulation``
with the same robot, gains, reference and initial state ends after the same steps.

Task-space controllers (``osc``, ``impedance``, ``resolved_rate``: robot_sim/control/
task_space.py, batched over (N, n) states) follow the tool: a task reference gives one or
``n_envs`` desired poses, twists and accelerations, and without one they follow the tool
motion of the desired joints, as in ``Simulation``.  Operational space and impedance are
continuous-time laws evaluated at every integration stage of the arms off their stops
(NumPy, batched), so an environment equals a ``Simulation`` to round-off (about 1e-12)
rather than bit for bit; on a stop their start effort is held over the step, as there.

Per environment: the reference (shared (n,) or per environment (n_envs, n)), the gains
(one ``Gains`` for all or a sequence of one per environment), and what happened: an
environment whose state or effort stops being finite stops alone and
:attr:`BatchSimulation.stopped` says why for that one; the others go on.

Units: q in rad (revolute) and m (prismatic), rates per second, efforts in N·m and N,
time in s.  This module imports neither OpenGL nor Qt.
"""
from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim import dynamics
from robot_sim.control.controllers import ComputedTorque, Controller, Gains
from robot_sim.control.factory import make_controller
from robot_sim.control.reference import is_task, task_from_joints
from robot_sim.control.task_space import TASK_MODES
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotParams
from robot_sim.sim import stepper as stepping
from robot_sim.sim.simulation import DEFAULT_DT, drive_limits, stop_message
from robot_sim.sim.stepper import INTEGRATORS, StepDiverged, StepResult, Stepper, runge_kutta, step_one_arm
from robot_sim.sim.stops import LimitEvent, StepPhysics, StopResolver

FloatArray = NDArray[np.float64]
#: Most environments of one BatchSimulation (its state, scratch and records grow with it;
#: sweeps run larger grids in chunks).
MAX_ENVS = 100_000
#: ``reference(t)`` → (q_des, qd_des, qdd_des), each (n,) or (n_envs, n), at time t [s];
#: for a task-space controller also (pose_d, twist_d, accel_d): (4, 4) or (n_envs, 4, 4)
#: [m], (6,) or (n_envs, 6) [m/s; rad/s] and [m/s²; rad/s²], world frame.
BatchReference = Callable[[float], tuple[ArrayLike, ArrayLike, ArrayLike]]


def _row_finite(X: FloatArray) -> NDArray[np.bool_]:
    """Per row: every entry finite, by the sum of squares as ``Simulation`` tests a vector
    (a row whose squares overflow counts as diverged there too)."""
    return np.isfinite(np.einsum("ij,ij->i", X, X))


def batched_controller(robot: RobotParams, controller: str | Controller, gains: Gains | Sequence[Gains] | None,
                       n_envs: int) -> Controller:
    """The controller of mode ``controller`` (or the given one) with its gains stacked per
    environment when ``gains`` is a sequence of ``n_envs`` Gains; the control law is the
    single-arm one evaluated on (n_envs, n) arrays."""
    if isinstance(controller, Controller):
        if gains is not None:
            raise ValueError("gains go with a motion mode name, not with a Controller instance")
        return controller
    if gains is None or isinstance(gains, Gains):
        return make_controller(controller, robot, gains)
    if controller in TASK_MODES:
        raise ValueError(f"the {controller} controller takes one Gains for all environments, not one per environment")
    gains = list(gains)
    if len(gains) != n_envs or not all(isinstance(g, Gains) for g in gains):
        raise ValueError(f"gains must be one Gains or a sequence of {n_envs} (one per environment), got {len(gains)} items")
    stacked = Gains(
        kp=np.stack([g.kp for g in gains]), kd=np.stack([g.kd for g in gains]),
        omega=gains[0].omega, zeta=gains[0].zeta,
    )
    ctrl = make_controller(controller, robot, stacked)
    if isinstance(ctrl, ComputedTorque):  # Kp = ω², Kd = 2ζω per environment, as ComputedTorque forms them
        ctrl.kp = np.array([[g.omega**2] for g in gains])
        ctrl.kd = np.array([[2.0 * g.zeta * g.omega] for g in gains])
    return ctrl


class BatchSimulation:
    """``n_envs`` arms of ``robot`` (which needs inertial data) stepped together.

    ``controller``: a motion mode (``"passive"``, ``"pd"``, ``"pdg"``, ``"ct"``, or in task
    space ``"osc"``, ``"impedance"``, ``"resolved_rate"``) built with ``gains`` (default:
    ``control.control_gains(robot)``; a sequence gives one per environment, joint modes
    only), or a ``Controller`` whose ``torque`` takes (n_envs, n) arrays.
    ``integrator`` ``"rk4"`` or ``"euler"``; ``dt`` the fixed step [s].  The arms start at
    the robot's home at rest (see :meth:`set_state`) with the home as the desired pose
    (see :meth:`set_reference`).
    """

    def __init__(
        self,
        robot: RobotParams,
        n_envs: int,
        controller: str | Controller = "passive",
        *,
        integrator: str = "rk4",
        dt: float = DEFAULT_DT,
        gains: Gains | Sequence[Gains] | None = None,
        reference: BatchReference | None = None,
    ) -> None:
        if isinstance(n_envs, bool) or not isinstance(n_envs, (int, np.integer)) or not 1 <= n_envs <= MAX_ENVS:
            raise ValueError(f"n_envs must be an integer 1..{MAX_ENVS}, got {clip_repr(n_envs)}")
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be a positive finite number of seconds, got {dt!r}")
        if integrator not in INTEGRATORS:
            raise ValueError(f"integrator must be one of {', '.join(INTEGRATORS)}, got {integrator!r}")
        dynamics.mass_matrix(robot, robot.q_home)  # fails now, naming the link, without inertials
        self.robot = robot
        self.n_envs = int(n_envs)
        self.controller = batched_controller(robot, controller, gains, self.n_envs)
        self.integrator = integrator
        self.dt = float(dt)
        self.reference = reference
        n = robot.n_dofs
        shape = (self.n_envs, n)
        self.effort_limit, self.velocity_limit = drive_limits(robot)
        self._limit_effort = bool(np.isfinite(self.effort_limit).any())
        self._limit_velocity = bool(np.isfinite(self.velocity_limit).any())
        self._limit_position = bool(np.isfinite(robot.q_min).any() or np.isfinite(robot.q_max).any())
        self._model_known = getattr(self.controller, "robot", None) is robot
        self._stepper = Stepper(robot, self.n_envs, self.dt, integrator)
        #: Simulated time [s] and steps taken, per environment (a stopped one stays put).
        self.time = np.zeros(self.n_envs)
        self.steps = np.zeros(self.n_envs, dtype=np.int64)
        #: Why each environment stopped, or None while it runs.
        self.stopped: list[str | None] = [None] * self.n_envs
        #: Limit arrivals not yet taken by :meth:`take_events`: (environment, event).
        self.events: list[tuple[int, LimitEvent]] = []
        #: Per environment and joint, in the last step: effort saturated, braked at the
        #: velocity limit, resting on a limit; applied and commanded effort [N·m or N].
        self.saturated = np.zeros(shape, dtype=bool)
        self.velocity_limited = np.zeros(shape, dtype=bool)
        self.at_limit = np.zeros(shape, dtype=bool)
        #: Reaction torque of the stops holding joints at the start of the last step.
        self.limit_torque = np.zeros(shape)
        self._on_stop = np.zeros(self.n_envs, dtype=bool)
        self._stops = StopResolver(robot)  # resolves the steps that touch a stop, as Simulation's does
        self._one_arm: Stepper | None = None  # the stop resolver's steps of one arm
        self.effort = np.zeros(shape)
        self.effort_command = np.zeros(shape)
        self.qdd = np.zeros(shape)
        self.q_des, self.qd_des, self.qdd_des = (np.zeros(shape) for _ in range(3))
        self.set_reference(q=robot.q_home)
        self.set_state(robot.q_home)

    # ------------------------------------------------------------------ inputs
    def _rows(self, value: ArrayLike, name: str) -> FloatArray:
        """``value`` (n,) for all environments or (n_envs, n) each, as (n_envs, n)."""
        n = self.robot.n_dofs
        arr = np.asarray(value, dtype=float)
        if arr.shape not in ((n,), (self.n_envs, n)):
            raise ValueError(f"{name} must have shape ({n},) or ({self.n_envs}, {n}), got shape {arr.shape}")
        if not np.isfinite(arr).all():
            raise ValueError(f"{name} must be finite, got NaN or inf in {name}")
        return np.array(np.broadcast_to(arr, (self.n_envs, n)))

    def set_state(self, q: ArrayLike, qd: ArrayLike | None = None) -> None:
        """Current joint values (clipped into the limits, as ``Simulation.load_state``) and
        rates (zero by default), shared (n,) or per environment (n_envs, n); resumes
        stopped environments."""
        q_arr = self._rows(q, "q")
        qd_arr = np.zeros_like(q_arr) if qd is None else self._rows(qd, "qd")
        self.q = np.clip(q_arr, self.robot.q_min, self.robot.q_max)
        self.qd = qd_arr
        self.qdd = np.zeros_like(self.q)
        self.at_limit = (self.q <= self.robot.q_min) | (self.q >= self.robot.q_max)
        self._on_stop = self.at_limit.any(axis=1)
        self.limit_torque = np.zeros_like(self.q)
        self.stopped = [None] * self.n_envs
        self.controller.reset(self.q.copy(), self.dt)

    def set_reference(self, q: ArrayLike | None = None, qd: ArrayLike | None = None, qdd: ArrayLike | None = None) -> None:
        """Constant desired values (those given), shared (n,) or per environment
        (n_envs, n); ignored while a ``reference`` function is set."""
        for name, value in (("q", q), ("qd", qd), ("qdd", qdd)):
            if value is not None:
                setattr(self, f"{name}_des", self._rows(value, f"{name} reference"))

    @property
    def running(self) -> NDArray[np.bool_]:
        """(n_envs,) True where the environment has not stopped."""
        return np.array([s is None for s in self.stopped])

    def take_events(self) -> list[tuple[int, LimitEvent]]:
        """The (environment, limit event) pairs since the previous call, removing them."""
        events, self.events = self.events, []
        return events

    # ------------------------------------------------------------------ running
    def step(self, n_steps: int = 1) -> int:
        """Run ``n_steps`` fixed steps of every running environment; return how many
        steps were taken (by the environments still running at the end: n_steps, or 0
        when none runs)."""
        if n_steps < 0:
            raise ValueError(f"n_steps must be >= 0, got {n_steps!r}")
        taken = 0
        with np.errstate(all="ignore"):
            for _ in range(n_steps):
                active = self.running
                if not active.any():
                    break
                t = float(self.time[int(np.argmax(active))])
                self._step(active, self._desired_at(t), t)
                taken += 1
        return taken

    def _take_reference(self, t: float) -> tuple:
        """The reference at time t [s]: task values as given, joint values as (n_envs, n)
        rows, which become the desired joint values."""
        values = tuple(self.reference(t))
        if self.controller.space == "task" and is_task(values, self.robot.n_dofs):
            return values
        q, qd, qdd = values
        self.q_des, self.qd_des, self.qdd_des = (self._rows(x, name) for x, name in zip((q, qd, qdd), ("q_des", "qd_des", "qdd_des")))
        return self.q_des, self.qd_des, self.qdd_des

    def _desired_at(self, t: float) -> Callable[[float], tuple]:
        """The controller's desired values as a function of time (the step's start t [s]
        and its stages): the reference's, or the desired joints' held over the step; for a
        task-space controller their tool motion when they are joints."""
        task = self.controller.space == "task"
        joints = self._take_reference(t) if self.reference is not None else (self.q_des, self.qd_des, self.qdd_des)
        if task and not is_task(joints, self.robot.n_dofs):
            joints = task_from_joints(self.robot, *joints)
        if self.reference is None or not (task and self.controller.continuous):
            return lambda _time: joints
        start = joints

        def at(time: float) -> tuple:
            if time == t:
                return start
            values = tuple(self.reference(time))
            return values if is_task(values, self.robot.n_dofs) else task_from_joints(self.robot, *(self._rows(x, "reference") for x in values))

        return at

    def _stop(self, envs: NDArray[np.int64], reason: Callable[[int], str]) -> None:
        for i in envs:
            self.stopped[i] = stop_message(self.time[i], reason(int(i)))

    def _step(self, active: NDArray[np.bool_], desired_at: Callable[[float], tuple], t: float) -> None:
        q, qd = self.q, self.qd
        command = np.array(np.broadcast_to(self.controller.torque(q, qd, *desired_at(t)), q.shape))
        bad = active & ~_row_finite(command)
        mode = self.controller.mode
        self._stop(np.flatnonzero(bad), lambda i: f"the {mode} controller returned a non-finite effort {command[i]}")
        active = active & ~bad
        saturated = np.abs(command) > self.effort_limit if self._limit_effort else np.zeros(q.shape, dtype=bool)
        tau = np.clip(command, -self.effort_limit, self.effort_limit) if self._limit_effort else command
        qdd_start, known = None, None
        if self._model_known:
            qdd_start = self.controller.commanded_acceleration()
            if qdd_start is not None:
                qdd_start = np.array(np.broadcast_to(qdd_start, q.shape), dtype=float)
                known = ~saturated.any(axis=1)
        continuous = self.controller.continuous
        stepped = active & self._on_stop if continuous else active  # the others: the law at every stage
        result = self._stepper.step(q, qd, tau, qdd_start, known, stepped, stops=self._limit_position)
        if continuous and (active & ~self._on_stop).any():
            self._continuous_step(active & ~self._on_stop, q, qd, tau, qdd_start, known, desired_at, t, result)
        for status, why in ((stepping.STEP_BAD_STATE, "the joint state became non-finite"),
                            (stepping.STEP_BAD_ACCEL, "the joint acceleration became non-finite")):
            failed = active & (result.status == status)
            self._stop(np.flatnonzero(failed), lambda i, why=why: why)
            active &= ~failed
        q1, qd1, qdd1 = result.q, result.qd, result.qdd
        if self._limit_position:  # as in Simulation: through the stops, then velocity limits
            active = self._through_stops(active, q, qd, tau, result)
        velocity_limited = self.velocity_limited
        if self._limit_velocity:
            velocity_limited = np.abs(qd1) > self.velocity_limit
            qd1 = np.clip(qd1, -self.velocity_limit, self.velocity_limit)
        diverged = active & ~(_row_finite(q1) & _row_finite(qd1))
        self._stop(np.flatnonzero(diverged), lambda i: "the joint state became non-finite")
        ok = active & ~diverged
        rows = ok[:, None]
        self.q = np.where(rows, q1, q)
        self.qd = np.where(rows, qd1, qd)
        self.qdd = np.where(rows, qdd1, self.qdd)
        self.effort_command = np.where(rows, command, self.effort_command)
        self.effort = np.where(rows, tau, self.effort)
        self.saturated = np.where(rows, saturated, self.saturated)
        self.velocity_limited = np.where(rows, velocity_limited, self.velocity_limited)
        self.time[ok] += self.dt
        self.steps[ok] += 1

    def _continuous_step(
        self, free: NDArray[np.bool_], q: FloatArray, qd: FloatArray, tau: FloatArray, qdd_start: FloatArray | None,
        known: NDArray[np.bool_] | None, desired_at: Callable[[float], tuple], t: float, result: StepResult,
    ) -> None:
        """The step of the ``free`` environments under a continuous-time controller, as
        ``Simulation`` takes it stage by stage: the law at every stage on the desired
        values at the stage's time, its own closed-loop acceleration on an exact model
        without effort limits, else forward dynamics of its (saturated) effort.  Written
        into ``result`` with the status the stepper would give (crossed a limit, a
        non-finite state or acceleration)."""
        controller, robot = self.controller, self.robot
        rows = free[:, None]
        bad = np.zeros(self.n_envs, dtype=np.int8)

        def accel(offset: float, Qs: FloatArray, QDs: FloatArray) -> FloatArray:
            ok = _row_finite(Qs) & _row_finite(QDs)
            bad[free & ~ok & (bad == 0)] = stepping.STEP_BAD_STATE
            use = rows & ok[:, None]
            Qs, QDs = np.where(use, Qs, q), np.where(use, QDs, qd)  # rows not stepped: finite stand-ins
            desired = desired_at(t + offset)
            if self._model_known and not self._limit_effort:
                a = controller.acceleration(Qs, QDs, *desired)
            else:
                effort = controller.torque(Qs, QDs, *desired)
                clipped = free & (np.abs(effort) > self.effort_limit).any(axis=1)
                effort = np.clip(effort, -self.effort_limit, self.effort_limit)
                own = controller.commanded_acceleration() if self._model_known else None
                if own is None:
                    a = dynamics.forward_dynamics(robot, Qs, QDs, effort)
                else:  # forward dynamics only where the effort was clipped
                    a = np.array(own, dtype=float)
                    if clipped.any():
                        a[clipped] = dynamics.forward_dynamics(robot, Qs[clipped], QDs[clipped], effort[clipped])
            bad[free & ~_row_finite(a) & (bad == 0)] = stepping.STEP_BAD_ACCEL
            return a

        a1 = qdd_start
        if a1 is None or known is None or not known[free].all():
            start = dynamics.forward_dynamics(robot, q, qd, tau)
            a1 = start if a1 is None or known is None else np.where(known[:, None], a1, start)
        q1, qd1, qdd1 = runge_kutta(self.integrator, q, qd, self.dt, a1, accel)
        result.q[free], result.qd[free], result.qdd[free] = q1[free], qd1[free], qdd1[free]
        lo, hi = robot.q_min, robot.q_max
        crossed = ((q1 < lo) | (q1 > hi)).any(axis=1) if self._limit_position else np.zeros(self.n_envs, bool)
        result.status[free] = np.where(bad[free] != 0, bad[free], np.where(crossed[free], stepping.STEP_CROSSED,
                                                                             stepping.STEP_OK))
        if self._limit_position:
            result.at_limit[free] = (q1[free] == lo) | (q1[free] == hi)

    def _stop_physics(self) -> StepPhysics:
        """The physics of one arm's step for the stop resolver: the one-arm compiled step
        (as ``Simulation`` takes it without contact or a tool wrench) and M q̈'s right-hand
        side τ − C q̇ − g."""
        if self._one_arm is None:
            self._one_arm = Stepper(self.robot, 1, self.dt, self.integrator)
        one = self._one_arm

        def stepped(q, qd, tau, a1, h, locked):
            return step_one_arm(one, q, qd, tau, a1, h, locked)

        return StepPhysics(stepped, lambda q, qd, tau: tau - dynamics.bias_torque(self.robot, q, qd))

    def _through_stops(
        self, active: NDArray[np.bool_], q: FloatArray, qd: FloatArray, tau: FloatArray, result: StepResult
    ) -> NDArray[np.bool_]:
        """The stops' part of the step, as in ``Simulation``: the stepper held the joints
        resting on their stops; the environments it left to the caller (a start on a stop
        it does not resolve, or a step that crossed a limit) are redone, in place in
        ``result``, by the stop resolver Simulation uses (the same code and one-arm steps,
        so bit for bit a Simulation); arrivals, reactions and at-limit flags recorded; the environments
        still running returned (one the stops cannot resolve stops alone)."""
        status = result.status
        on_limit = status == stepping.STEP_ON_LIMIT
        stepped = active & ((status == stepping.STEP_OK) | on_limit)
        touched = stepped & (self._on_stop | on_limit)
        self.limit_torque[touched] = np.where(self._on_stop[touched, None], result.reaction[touched], 0.0)
        self.at_limit[touched] = result.at_limit[touched]
        redo = active & ((status == stepping.STEP_AT_STOP) | (status == stepping.STEP_CROSSED))
        if redo.any():
            physics = self._stop_physics()
            active = active.copy()
            lo, hi = self.robot.q_min, self.robot.q_max
            q1, qd1, qdd1 = result.q, result.qd, result.qdd
            for i in np.flatnonzero(redo):
                trial = (q1[i].copy(), qd1[i].copy(), qdd1[i].copy()) if status[i] == stepping.STEP_CROSSED else None
                try:
                    resolved = self._stops.resolve(float(self.time[i]), self.dt, q[i], qd[i], tau[i], physics, trial)
                except (StepDiverged, np.linalg.LinAlgError) as exc:
                    self._stop([i], lambda _, why=str(exc): why)
                    active[i] = False
                    continue
                q1[i], qd1[i] = resolved.q, resolved.qd
                if trial is None:
                    qdd1[i] = resolved.qdd
                self.limit_torque[i] = resolved.outcome.reaction
                self.events.extend((int(i), event) for event in resolved.outcome.events)
                self.at_limit[i] = (q1[i] == lo) | (q1[i] == hi)
        self._on_stop = self.at_limit.any(axis=1)
        return active
