"""Many independent arms of one robot stepped at once: :class:`BatchSimulation`.

Each step does for every running environment what ``Simulation.step`` does for one arm,
in the same order and with the same floating-point operations on arrays of shape
(n_envs, n): the controller's effort (batched: PD, PD + gravity and computed torque take
(N, n) arrays), saturation at the drives' effort limits, one integration step of all arms
by a ``dynamics.Stepper`` (one compiled call), velocity limits, joint limits as hard
stops, divergence.  So environment i of a batch ends bit for bit where a ``Simulation``
with the same robot, gains, reference and initial state ends after the same steps.

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
from robot_sim.control.simulation import DEFAULT_DT, INTEGRATORS, LimitEvent, Simulation, drive_limits, stop_message
from robot_sim.model.params import RobotParams

FloatArray = NDArray[np.float64]
#: ``reference(t)`` → (q_des, qd_des, qdd_des), each (n,) or (n_envs, n), at time t [s].
BatchReference = Callable[[float], tuple[ArrayLike, ArrayLike, ArrayLike]]


def _row_finite(X: FloatArray) -> NDArray[np.bool_]:
    """Per row: every entry finite, by the sum of squares as ``Simulation`` tests a vector
    (a row whose squares overflow counts as diverged there too)."""
    return np.isfinite(np.einsum("ij,ij->i", X, X))


def _sampled_joint_space(controller: Controller) -> Controller:
    """``controller`` if it is a sampled joint-space controller (what the batch steps);
    ValueError for a task-space one (osc, impedance, resolved rate: evaluated at every
    stage by ``Simulation``; their ``torque`` takes (N, n) states for a batched loop)."""
    if controller.space != "joint" or controller.continuous:
        raise ValueError(
            f"BatchSimulation steps the joint-space controllers (passive, pd, pdg, ct); {controller.mode} is a "
            "task-space controller: run it with Simulation (its torque() is batched over (N, n) states)"
        )
    return controller


def batched_controller(robot: RobotParams, controller: str | Controller, gains: Gains | Sequence[Gains] | None,
                       n_envs: int) -> Controller:
    """The controller of mode ``controller`` (or the given one) with its gains stacked per
    environment when ``gains`` is a sequence of ``n_envs`` Gains; the control law is the
    single-arm one evaluated on (n_envs, n) arrays."""
    if isinstance(controller, Controller):
        if gains is not None:
            raise ValueError("gains go with a motion mode name, not with a Controller instance")
        _sampled_joint_space(controller)
        return controller
    if gains is None or isinstance(gains, Gains):
        return _sampled_joint_space(make_controller(controller, robot, gains))
    gains = list(gains)
    if len(gains) != n_envs or not all(isinstance(g, Gains) for g in gains):
        raise ValueError(f"gains must be one Gains or a sequence of {n_envs} (one per environment), got {len(gains)} items")
    stacked = Gains(
        kp=np.stack([g.kp for g in gains]), kd=np.stack([g.kd for g in gains]),
        omega=gains[0].omega, zeta=gains[0].zeta,
    )
    ctrl = _sampled_joint_space(make_controller(controller, robot, stacked))
    if isinstance(ctrl, ComputedTorque):  # Kp = ω², Kd = 2ζω per environment, as ComputedTorque forms them
        ctrl.kp = np.array([[g.omega**2] for g in gains])
        ctrl.kd = np.array([[2.0 * g.zeta * g.omega] for g in gains])
    return ctrl


class BatchSimulation:
    """``n_envs`` arms of ``robot`` (which needs inertial data) stepped together.

    ``controller``: a motion mode (``"passive"``, ``"pd"``, ``"pdg"``, ``"ct"``) built with
    ``gains`` (default: ``control.control_gains(robot)``; a sequence gives one per
    environment), or a ``Controller`` whose ``torque`` takes (n_envs, n) arrays.
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
        if isinstance(n_envs, bool) or not isinstance(n_envs, (int, np.integer)) or n_envs < 1:
            raise ValueError(f"n_envs must be a positive integer, got {n_envs!r}")
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
        self._stepper = dynamics.Stepper(robot, self.n_envs, self.dt, integrator)
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
        self._scratch: Simulation | None = None  # resolves the steps that touch a stop
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
                if self.reference is not None:
                    self._take_reference(self.time[int(np.argmax(active))])
                self._step(active)
                taken += 1
        return taken

    def _take_reference(self, t: float) -> None:
        q, qd, qdd = self.reference(t)
        self.q_des, self.qd_des, self.qdd_des = (self._rows(x, name) for x, name in zip((q, qd, qdd), ("q_des", "qd_des", "qdd_des")))

    def _stop(self, envs: NDArray[np.int64], reason: Callable[[int], str]) -> None:
        for i in envs:
            self.stopped[i] = stop_message(self.time[i], reason(int(i)))

    def _step(self, active: NDArray[np.bool_]) -> None:
        q, qd = self.q, self.qd
        command = np.array(np.broadcast_to(self.controller.torque(q, qd, self.q_des, self.qd_des, self.qdd_des), q.shape))
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
        result = self._stepper.step(q, qd, tau, qdd_start, known, active, stops=self._limit_position)
        for status, why in ((dynamics.STEP_BAD_STATE, "the joint state became non-finite"),
                            (dynamics.STEP_BAD_ACCEL, "the joint acceleration became non-finite")):
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

    def _through_stops(
        self, active: NDArray[np.bool_], q: FloatArray, qd: FloatArray, tau: FloatArray, result: dynamics.StepResult
    ) -> NDArray[np.bool_]:
        """The stops' part of the step, as in ``Simulation``: the stepper held the joints
        resting on their stops; the environments it left to the caller (a start on a stop
        it does not resolve, or a step that crossed a limit) are redone, in place in
        ``result``, by ``Simulation.step_through_stops`` (the same code, so bit for bit a
        Simulation); arrivals, reactions and at-limit flags recorded; the environments
        still running returned (one the stops cannot resolve stops alone)."""
        status = result.status
        on_limit = status == dynamics.STEP_ON_LIMIT
        stepped = active & ((status == dynamics.STEP_OK) | on_limit)
        touched = stepped & (self._on_stop | on_limit)
        self.limit_torque[touched] = np.where(self._on_stop[touched, None], result.reaction[touched], 0.0)
        self.at_limit[touched] = result.at_limit[touched]
        redo = active & ((status == dynamics.STEP_AT_STOP) | (status == dynamics.STEP_CROSSED))
        if redo.any():
            if self._scratch is None:
                self._scratch = Simulation(self.robot, dt=self.dt, integrator=self.integrator)
            active = active.copy()
            lo, hi = self.robot.q_min, self.robot.q_max
            q1, qd1, qdd1 = result.q, result.qd, result.qdd
            for i in np.flatnonzero(redo):
                trial = (q1[i].copy(), qd1[i].copy(), qdd1[i].copy()) if status[i] == dynamics.STEP_CROSSED else None
                out = self._scratch.step_through_stops(float(self.time[i]), q[i], qd[i], tau[i], trial)
                if isinstance(out, str):
                    self._stop([i], lambda _, why=out: why)
                    active[i] = False
                    continue
                q1[i], qd1[i], start_qdd, self.limit_torque[i], events = out
                if start_qdd is not None:
                    qdd1[i] = start_qdd
                self.events.extend((int(i), event) for event in events)
                self.at_limit[i] = (q1[i] == lo) | (q1[i] == hi)
        self._on_stop = self.at_limit.any(axis=1)
        return active
