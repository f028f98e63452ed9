"""Task-space controllers: the tool's desired pose, twist and acceleration in, joint effort out.

Each controller's :meth:`TaskSpaceController.torque` takes the joint state ``q``, ``qd``
(n,) or (N, n) and the desired tool pose ``pose_d`` (4, 4) [m], twist ``twist_d`` (6,)
[m/s; rad/s] and acceleration ``accel_d`` (6,) [m/s²; rad/s²] in the world frame (or one
of each per configuration: (N, 4, 4), (N, 6), (N, 6)), and returns the joint effort (n,)
or (N, n) [N·m or N].  The task error is ``e = [p_d − p; log(R_d Rᵀ)]``; arms with fewer
than six joints control the position rows only (:func:`kinematics.task_rows`).

* :class:`OperationalSpace` (``"osc"``, Khatib):
  ``τ = Jᵀ Λ (ẍ_d + K_d ė + K_p e − J̇ q̇) + b(q, q̇) + Nᵀ τ₀`` with ``Λ = (J M⁻¹ Jᵀ)⁻¹``,
  damped near singularities (:data:`SINGULAR_RATIO`), and the dynamically consistent
  projector ``N = I − J̄ J``, ``J̄ = M⁻¹ Jᵀ Λ``.  ``b = C q̇ + g + friction`` is the
  model's bias torque (Coriolis included: without it the error would not obey the linear
  law).  ``K_p = ω²``, ``K_d = 2ζω``; ``ẍ_d + K_d ė + K_p e`` is the commanded second
  derivative of e itself, turned into an angular acceleration through the log map's
  Jacobian (:func:`task_error.rotation_command`), so that on an exact model
  ``ë + K_d ė + K_p e = 0`` holds exactly, at any angle and for moving references.
* :class:`Impedance` (``"impedance"``): ``τ = Jᵀ (K e + D ė) + g + friction + Nᵀ τ₀`` with
  Cartesian stiffness K and damping D (6×6, or translational and rotational scalars) and
  ė the twist error ``ẋ_d − J q̇``.  No Coriolis compensation: with a fixed reference the
  arm is passive (kinetic plus spring energy never increases), and a constant tool force
  F settles at the displacement K⁻¹ F.
* :class:`ResolvedRate` (``"resolved_rate"``, the Robotics Toolbox's ``p_servo``, MoveIt
  Servo): ``q̇_d = J⁺ (ẋ_d + K e) + (I − J⁺J) k₀ (q₀ − q_d)`` at the desired joint values
  q_d, integrated once per control period into q_d and tracked by joint-space computed
  torque.  ``J⁺`` is the damped pseudo-inverse.

τ₀ is a posture PD toward ``null_space`` (the robot's home by default, None for none),
mass-weighted so its null-space motion has the task's bandwidth: ``τ₀ = M q̈₀`` with
``q̈₀ = ω₀² (q₀ − q) − 2ζω₀ q̇``.

Gains come from :func:`controllers.control_gains` (``bandwidth`` f [Hz], ω = 2πf, and
damping ratio ζ, over the robot file's ``[control]`` table).  OSC and impedance are
continuous-time laws (``continuous = True``): the simulation evaluates them at every
integration stage.  Resolved rate is a sampled controller with state (q_d): the
simulation calls it once per step after :meth:`ResolvedRate.reset`.

This module imports neither OpenGL nor Qt.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim import dynamics
from robot_sim.control.controllers import ComputedTorque, Controller, Gains, Integrated, StepContext, control_gains
from robot_sim.control.task_error import rotation_command, rotation_logs
from robot_sim.kernels import status
from robot_sim.kernels.model import compiled_model, kernel_array
from robot_sim.kinematics import characteristic_length, task_rows, tool_kinematics
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotParams
from robot_sim.transforms import rotation_log

FloatArray = NDArray[np.float64]

#: Λ is damped where the tool's apparent mass in some direction would exceed this many
#: times the arm's mass (rotation rows scaled by the robot's characteristic length L):
#: near a singularity, where it grows without bound; there it is capped at that mass.
#: Away from it the law is exact.
INERTIA_CAP = 100.0
#: The damped pseudo-inverse of resolved rate damps where the smallest singular value of
#: the (L-scaled) Jacobian falls below this fraction of L [m].
SINGULAR_LENGTH = 1e-2
#: Task-space modes of :func:`make_task_controller`.
TASK_MODES = ("osc", "impedance", "resolved_rate")


def _posture(robot: RobotParams, null_space: Any) -> FloatArray | None:
    """The posture target q₀ (n,) of ``null_space``: "home", a joint vector, or None."""
    if null_space is None:
        return None
    if isinstance(null_space, str):
        if null_space != "home":
            raise ValueError(f'null_space must be "home", a joint vector of {robot.n_dofs} values or None, got {null_space!r}')
        return np.asarray(robot.q_home, dtype=float).copy()
    target = np.asarray(null_space, dtype=float) if not isinstance(null_space, bool) else None
    if target is None or target.shape != (robot.n_dofs,) or not np.isfinite(target).all():
        raise ValueError(
            f'null_space must be "home", a finite joint vector of {robot.n_dofs} values or None, got {clip_repr(null_space)}'
        )
    return target


def _finite(a: FloatArray) -> bool:
    """True if every entry is finite (one dot product; a sum of squares that overflows
    is checked entry by entry)."""
    flat = a.reshape(-1)
    return math.isfinite(flat @ flat) or bool(np.isfinite(flat).all())


def _batch(robot: RobotParams, q: ArrayLike, qd: ArrayLike) -> tuple[bool, FloatArray, FloatArray]:
    """(single, Q, QD) with Q, QD of shape (N, n); ValueError naming the argument."""
    n = robot.n_dofs
    Q, QD = np.asarray(q, dtype=float), np.asarray(qd, dtype=float)
    for name, arr, value in (("q", Q, q), ("qd", QD, qd)):
        if arr.ndim not in (1, 2) or arr.shape[-1] != n or not _finite(arr):
            raise ValueError(f"{name} must be finite with shape ({n},) or (N, {n}), got {clip_repr(value)}")
    if Q.shape != QD.shape:
        raise ValueError(f"qd must have the shape of q, {Q.shape}, got {QD.shape}")
    if Q.ndim == 1:
        return True, Q[None], QD[None]
    return False, Q, QD


def _desired(pose_d: ArrayLike, twist_d: ArrayLike, accel_d: ArrayLike, N: int) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The desired pose (N, 4, 4), twist and acceleration (N, 6), from one or N of each."""
    out = []
    for name, value, shape in (("pose_d", pose_d, (4, 4)), ("twist_d", twist_d, (6,)), ("accel_d", accel_d, (6,))):
        arr = np.asarray(getattr(value, "mat", value), dtype=float)
        if arr.shape == shape:
            arr = arr[None] if N == 1 else np.broadcast_to(arr, (N, *shape))
        if arr.shape != (N, *shape) or not _finite(arr):
            raise ValueError(f"{name} must be finite with shape {shape} or {(N, *shape)}, got {clip_repr(value)}")
        out.append(arr)
    return out[0], out[1], out[2]


def _mv(A: FloatArray, x: FloatArray) -> FloatArray:
    """Batched matrix-vector product (N, a, b) @ (N, b) → (N, a)."""
    return np.matmul(A, x[..., None])[..., 0]


def damping(A: FloatArray, weights: FloatArray, eps: float) -> FloatArray:
    """λ² (N,) for the damped inverse of symmetric positive semi-definite A (N, m, m):
    ``ε − s_min`` where the smallest eigenvalue s_min of ``W A W`` (W = diag(weights)) is
    below ``eps`` = ε, else 0 (exact)."""
    s_min = np.linalg.eigvalsh(A * weights[:, None] * weights[None, :])[:, 0]
    return np.maximum(eps - s_min, 0.0)


def damped_inverse(A: FloatArray, weights: FloatArray, eps: float) -> FloatArray:
    """``W (W A W + λ² I)⁻¹ W`` (N, m, m) with λ² of :func:`damping`: the inverse of A
    away from singularity, at most 1/ε (in W's units) at it."""
    ww = weights[:, None] * weights[None, :]
    s, U = np.linalg.eigh(A * ww)
    f = 1.0 / (s + np.maximum(eps - s[:, :1], 0.0))
    return np.matmul(U * f[:, None, :], U.transpose(0, 2, 1)) * ww


class TaskSpaceController(Controller):
    """Base of the task-space controllers: the task rows, their weights and the posture.

    ``space = "task"``: the simulation hands :meth:`torque` a desired tool pose, twist and
    acceleration.  After each :meth:`torque` call ``error`` holds e (N, m) or (m,) [m; rad]
    of the rows :attr:`rows`.
    """

    space = "task"
    continuous = True

    def __init__(self, robot: RobotParams, gains: Gains, null_space: Any = "home") -> None:
        self.robot = robot
        self.omega, self.zeta = gains.omega, gains.zeta
        self.kp = gains.omega**2
        self.kd = 2.0 * gains.zeta * gains.omega
        self.rows = task_rows(robot)
        self.full = self.rows.shape[0] == 6
        #: Index of the task rows: a slice when all six (no fancy-index copies).
        self.take = slice(0, 6) if self.full else self.rows
        length = characteristic_length(robot)
        self.weights = np.where(self.rows < 3, 1.0, length)
        mass = float(np.sum(robot.inertials.mass)) if robot.inertials is not None else 1.0
        self.eps_inertia = 1.0 / (INERTIA_CAP * mass)
        self.eps_jacobian = (SINGULAR_LENGTH * length) ** 2
        self.posture = _posture(robot, null_space)
        self.error: FloatArray = np.zeros(self.rows.shape[0])
        self._qdd: FloatArray | None = None

    def torque(
        self, q: ArrayLike, qd: ArrayLike, pose_d: ArrayLike, twist_d: ArrayLike, accel_d: ArrayLike, joints: Any = None
    ) -> FloatArray:  # type: ignore[override]
        """Joint effort (n,) or (N, n) [N·m or N] toward the desired tool motion.  ``joints``:
        optionally the desired joint motion (q, q̇, q̈) the tool motion comes from, which the
        posture then tracks in the null space instead of the fixed ``null_space`` target."""
        raise NotImplementedError

    def commanded_acceleration(self) -> FloatArray | None:
        """The joint acceleration of the last :meth:`torque` on this controller's model."""
        return self._qdd

    def acceleration(
        self, q: ArrayLike, qd: ArrayLike, pose_d: ArrayLike, twist_d: ArrayLike, accel_d: ArrayLike, joints: Any = None
    ) -> FloatArray:
        """The closed-loop joint acceleration [rad/s² or m/s²] the law gives on its model,
        (n,) or (N, n): what the simulation integrates when nothing else acts."""
        self.torque(q, qd, pose_d, twist_d, accel_d, joints)
        assert self._qdd is not None
        return self._qdd

    # ---- shared pieces ----
    def _kinematics(self, Q: FloatArray, QD: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Tool poses (N, 4, 4), Jacobians (N, 6, n) and J̇q̇ (N, 6) at (Q, QD) (N, n)."""
        if Q.shape[0] == 1:
            T, J, jd = tool_kinematics(self.robot, Q[0], QD[0], check=False)
            return T[None], J[None], jd[None]
        return tool_kinematics(self.robot, Q, QD, check=False)

    def _mass(self, Q: FloatArray) -> FloatArray:
        return dynamics.mass_matrix(self.robot, Q[0])[None] if Q.shape[0] == 1 else dynamics.mass_matrix(self.robot, Q)

    def _posture_accel(self, Q: FloatArray, QD: FloatArray, joints: Any) -> FloatArray | None:
        """q̈₀ (N, n) of the posture PD toward ``null_space`` or, when given, the desired
        joint motion ``joints`` (q, q̇, q̈) (then q̈₀ = q̈_d + ω² (q_d − q) + 2ζω (q̇_d − q̇));
        None without a posture task."""
        if self.posture is None:
            return None
        if joints is None:
            return self.kp * (self.posture - Q) - self.kd * QD
        n = self.robot.n_dofs
        try:
            q_d, qd_d, qdd_d = (np.asarray(x, dtype=float) for x in joints)
        except (TypeError, ValueError):
            q_d = None
        if q_d is None or not all(x.shape in ((n,), Q.shape) and _finite(x) for x in (q_d, qd_d, qdd_d)):
            raise ValueError(f"joints must be finite (q, qd, qdd) of shape ({n},) or {Q.shape}, got {clip_repr(joints)}")
        return qdd_d + self.kp * (q_d - Q) + self.kd * (qd_d - QD)

    def _errors(self, T: FloatArray, Td: FloatArray) -> tuple[FloatArray, FloatArray | None]:
        """(e, R_e): the task error (N, m) of the rows and R_d Rᵀ (N, 3, 3) when the rotation
        rows are controlled (else None)."""
        e_p = Td[:, :3, 3] - T[:, :3, 3]
        if not self.full:
            return e_p[:, self.take], None
        R_e = np.matmul(Td[:, :3, :3], T[:, :3, :3].transpose(0, 2, 1))
        phi = rotation_log(R_e[0])[None] if R_e.shape[0] == 1 else rotation_logs(R_e)
        return np.concatenate([e_p, phi], axis=1), R_e


class OperationalSpace(TaskSpaceController):
    """Khatib's operational-space control (see the module docstring).

    The law is solved as one linear system, the KKT conditions of "the joint acceleration
    closest to the posture's q̈₀ in the M norm whose task acceleration is the commanded a":
    ``[M  −Jᵀ; J  λ²W⁻²] [q̈; F] = [M q̈₀; a − J̇q̇]``, so ``F = Λ (a − J̇q̇ − J q̈₀)`` with the
    damped ``Λ = W (W J M⁻¹ Jᵀ W + λ² I)⁻¹ W`` and ``τ = M q̈ + b``.  The damping λ² is chosen
    by :meth:`torque` from the smallest eigenvalue of ``W J M⁻¹ Jᵀ W`` (see
    :func:`damping`); :meth:`acceleration` keeps it, so over one integration step the law is
    one smooth function.
    """

    integrates = True  # its closed loop over a step in one compiled call (:meth:`integrate`)

    mode = "osc"

    def __init__(self, robot: RobotParams, gains: Gains, null_space: Any = "home") -> None:
        super().__init__(robot, gains, null_space)
        self._lam2: FloatArray | None = None
        m = self.rows.shape[0]
        self._kkt_shape = (robot.n_dofs + m, robot.n_dofs + m)
        self._inv_w2 = np.diag(1.0 / self.weights**2)
        self._kernel: tuple | None = None
        self._packed: tuple | None = None  # the last desired values packed for osc_step
        self._limit: tuple | None = None  # the last effort limits given to integrate, as osc_step takes them
        self._step_kernel: tuple | None = None

    def _step_parts(self) -> tuple:
        """(osc_step, model table, frame-0 gravity, modified, base, tool, rows, q_min,
        q_max), made on first use; the limits writeable (numba compiles a kernel again for
        read-only arrays)."""
        if self._step_kernel is None:
            from robot_sim.control import task_space_compiled as tc

            _, table, g0 = dynamics.compiled_kernels(self.robot)
            limits = (kernel_array(self.robot.q_min), kernel_array(self.robot.q_max))
            self._step_kernel = (tc.osc_step, table, g0, *self._kernel_parts()[2:], *limits)
        return self._step_kernel

    def integrate(self, q: FloatArray, qd: FloatArray, step: StepContext) -> Integrated | None:
        """One step of length ``step.h`` [s] of the closed loop on this controller's model
        from (q, q̇) (n,) at time ``step.t``, by ``step.integrator`` with the law evaluated
        at every stage on the desired values at the stage's time: one compiled call
        (task_space_compiled.osc_step), its status OK, or CROSSED when the step ended
        beyond the robot's joint limits.  None where it does not apply (a joint starting
        on a stop, the NumPy backend, non-finite values, an effort beyond ``step.limit``
        at some stage): then the loop steps the law stage by stage."""
        n = self.robot.n_dofs
        if step.on_stop or dynamics.backend() != "compiled" or q.shape != (n,) or qd.shape != (n,):
            return None
        kernel, table, g0, modified, base, tool, rows, q_min, q_max = self._step_parts()
        t, h, desired_at, limit = step.t, step.h, step.desired_at, step.limit
        desired = (desired_at(t), desired_at(t + 0.5 * h), desired_at(t + h))
        fixed = desired[1] is desired[0] and desired[2] is desired[0]
        if fixed and self._packed is not None and self._packed[0] is desired[0]:
            packed = self._packed[1]
        else:
            try:
                packed = self._pack(desired)
            except (TypeError, ValueError):  # the stage-by-stage law says what is wrong
                return None
            self._packed = (desired[0], packed) if fixed else None
        q1, qd1, a1, tau, e = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(rows.shape[0])
        if self._limit is None or self._limit[0] is not limit:
            self._limit = (limit, kernel_array(limit), bool(np.isfinite(limit).any()))
        result = kernel(table, g0, self._limit[1], self._limit[2], modified, base, tool, rows, self.weights,
                        step.integrator == "rk4", h, q, qd, *packed, self.posture is not None, self.kp, self.kd,
                        self.eps_inertia, q_min, q_max, q1, qd1, a1, tau, e)
        if result not in (0, 3):
            return None
        self.error, self._qdd = e, a1
        return Integrated(q1, qd1, a1, tau, status.CROSSED if result == 3 else status.OK)

    def _pack(self, desired: tuple) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """TD (3, 4, 4), VD, AD (3, 6) and the posture's POST (3, 3, n) of three desired values."""
        n = self.robot.n_dofs
        TD = np.empty((3, 4, 4))
        VD, AD = np.empty((3, 6)), np.empty((3, 6))
        POST = np.zeros((3, 3, n))
        for i, d in enumerate(desired):
            TD[i], VD[i], AD[i] = getattr(d[0], "mat", d[0]), d[1], d[2]
            if len(d) > 3:
                POST[i] = np.asarray(d[3], dtype=float)
            elif self.posture is not None:
                POST[i, 0] = self.posture
        return TD, VD, AD, POST

    def _kernel_parts(self) -> tuple:
        """(osc_one, model table, modified, base, tool, rows) of the compiled law, made
        on first use (numba is imported then)."""
        if self._kernel is None:
            from robot_sim.control import task_space_compiled as tc

            model = compiled_model(self.robot)
            self._kernel = (tc.osc_one, model.table, model.modified, model.base, model.tool,
                            np.ascontiguousarray(self.rows, dtype=np.int64))
        return self._kernel

    def _compiled(self, q: Any, qd: Any, pose_d: Any, twist_d: Any, accel_d: Any, joints: Any, lam2: float):
        """(q̈, τ − b, e, λ²) of one configuration from the compiled law
        (task_space_compiled, used with the compiled dynamics backend), or None where it
        does not apply (not one configuration, non-finite input, no solution): then the
        NumPy law runs and says what is wrong."""
        n = self.robot.n_dofs
        if dynamics.backend() != "compiled" or np.ndim(q) != 1 or np.shape(q) != (n,) or np.shape(qd) != (n,):
            return None
        kernel, table, modified, base, tool, rows = self._kernel_parts()
        try:
            q, qd, Td, Vd, Ad = (x if type(x) is np.ndarray and x.dtype == np.float64 and x.flags.c_contiguous
                                 else np.ascontiguousarray(x, dtype=float)
                                 for x in (q, qd, getattr(pose_d, "mat", pose_d), twist_d, accel_d))
        except (TypeError, ValueError):
            return None
        if Td.shape != (4, 4) or Vd.shape != (6,) or Ad.shape != (6,):
            return None
        if self.posture is None:
            qdd0 = np.zeros(n)
        elif joints is None:
            qdd0 = self.kp * (self.posture - q) - self.kd * qd
        else:  # the kernel checks that these are finite
            try:
                q_d, qd_d, qdd_d = joints
            except (TypeError, ValueError):
                return None
            if not (np.shape(q_d) == np.shape(qd_d) == np.shape(qdd_d) == (n,)):
                return None
            qdd0 = qdd_d + self.kp * (q_d - q) + self.kd * (qd_d - qd)
        qdd, task, e = np.empty(n), np.empty(n), np.empty(rows.shape[0])
        M = dynamics.mass_matrix(self.robot, q)
        lam = kernel(table, modified, base, tool, rows, self.weights, q, qd, Td, Vd, Ad, M, qdd0,
                     self.kp, self.kd, lam2, self.eps_inertia, qdd, task, e)
        return None if math.isnan(lam) else (qdd, task, e, lam)

    def torque(
        self, q: ArrayLike, qd: ArrayLike, pose_d: ArrayLike, twist_d: ArrayLike, accel_d: ArrayLike, joints: Any = None
    ) -> FloatArray:  # type: ignore[override]
        fast = self._compiled(q, qd, pose_d, twist_d, accel_d, joints, -1.0)
        if fast is not None:
            self._qdd, task, self.error, lam2 = fast
            self._lam2 = np.array([lam2])
            return task + dynamics.bias_torque(self.robot, q, qd)
        single, Q, QD = _batch(self.robot, q, qd)
        qdd, M, e = self._law(Q, QD, *_desired(pose_d, twist_d, accel_d, Q.shape[0]), joints, None)
        task = _mv(M, qdd)
        if single:
            self.error, self._qdd = e[0], qdd[0]
            return task[0] + dynamics.bias_torque(self.robot, Q[0], QD[0])
        self.error, self._qdd = e, qdd
        return task + dynamics.bias_torque(self.robot, Q, QD)

    def acceleration(
        self, q: ArrayLike, qd: ArrayLike, pose_d: ArrayLike, twist_d: ArrayLike, accel_d: ArrayLike, joints: Any = None
    ) -> FloatArray:
        """The closed-loop q̈ (no bias call: q̈ = M⁻¹ (τ − b) does not need b), with the
        singularity damping of the last :meth:`torque` call (the step's start) when it was
        for as many configurations."""
        if self._lam2 is not None and self._lam2.shape[0] == 1:
            fast = self._compiled(q, qd, pose_d, twist_d, accel_d, joints, float(self._lam2[0]))
            if fast is not None:
                return fast[0]
        single, Q, QD = _batch(self.robot, q, qd)
        lam2 = self._lam2 if self._lam2 is not None and self._lam2.shape[0] == Q.shape[0] else None
        qdd = self._law(Q, QD, *_desired(pose_d, twist_d, accel_d, Q.shape[0]), joints, lam2)[0]
        return qdd[0] if single else qdd

    def _law(
        self, Q: FloatArray, QD: FloatArray, Td: FloatArray, Vd: FloatArray, Ad: FloatArray, joints: Any,
        lam2: FloatArray | None,
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(q̈, M, e): (N, n), (N, n, n), (N, m); λ² (N,) chosen here when None."""
        T, J, jd = self._kinematics(Q, QD)
        twist = _mv(J, QD)
        e, R_e = self._errors(T, Td)
        rows = self.take
        accel = Ad[:, rows] + self.kd * (Vd - twist)[:, rows] + self.kp * e
        if R_e is not None:
            accel[:, 3:] = rotation_command(R_e, e[:, 3:], twist[:, 3:], Vd[:, 3:], Ad[:, 3:], self.kp, self.kd)[1]
        Jr = J[:, rows]
        M = self._mass(Q)
        if lam2 is None:
            lam2 = self._lam2 = damping(np.matmul(Jr, np.linalg.solve(M, Jr.transpose(0, 2, 1))), self.weights,
                                        self.eps_inertia)
        N, n = Q.shape[0], self.robot.n_dofs
        kkt = np.empty((N, *self._kkt_shape))
        kkt[:, :n, :n] = M
        kkt[:, :n, n:] = -Jr.transpose(0, 2, 1)
        kkt[:, n:, :n] = Jr
        kkt[:, n:, n:] = lam2[:, None, None] * self._inv_w2
        rhs = np.empty((N, self._kkt_shape[0]))
        qdd0 = self._posture_accel(Q, QD, joints)
        rhs[:, :n] = 0.0 if qdd0 is None else _mv(M, qdd0)
        rhs[:, n:] = accel - jd[:, rows]
        return np.linalg.solve(kkt, rhs[..., None])[:, :n, 0], M, e


def _cartesian_matrix(name: str, value: Any, units: str) -> FloatArray:
    """A 6×6 symmetric positive semi-definite matrix from a scalar (all axes), a pair
    (translational, rotational), six diagonal values or a 6×6 matrix."""
    arr = np.asarray(value, dtype=float) if not isinstance(value, bool) else np.array(np.nan)
    if arr.shape == ():
        arr = np.full(6, float(arr))
    elif arr.shape == (2,):
        arr = np.repeat(arr, 3)
    if arr.shape == (6,):
        arr = np.diag(arr)
    ok = arr.shape == (6, 6) and np.isfinite(arr).all() and np.allclose(arr, arr.T)
    if ok and np.linalg.eigvalsh(arr)[0] < -1e-12 * max(1.0, np.abs(arr).max()):
        ok = False
    if not ok:
        raise ValueError(
            f"{name} must be a number, a (translational, rotational) pair, six values or a symmetric positive "
            f"semi-definite 6x6 matrix [{units}], got {clip_repr(value)}"
        )
    return arr


class Impedance(TaskSpaceController):
    """Cartesian impedance: a spring K and damper D between the tool and its desired pose.

    ``stiffness`` K [N/m; N·m/rad] and ``damping`` D [N·s/m; N·m·s/rad]: a number (every
    axis), a (translational, rotational) pair, six diagonal values or a 6×6 symmetric
    positive semi-definite matrix in the world frame ([force; moment] from [position;
    rotation] error).  Defaults: K = ω² λ and D = 2ζ √(K λ) per axis group, λ the mean
    translational (rotational) diagonal of Λ at home, so the tool at home rings at the
    bandwidth, critically damped for ζ = 1.
    """

    mode = "impedance"

    def __init__(
        self, robot: RobotParams, gains: Gains, *, stiffness: Any = None, damping: Any = None, null_space: Any = "home"
    ) -> None:
        super().__init__(robot, gains, null_space)
        K = _cartesian_matrix("stiffness", stiffness, "N/m, N·m/rad") if stiffness is not None else None
        D = _cartesian_matrix("damping", damping, "N·s/m, N·m·s/rad") if damping is not None else None
        if K is None or D is None:
            lam = self._home_inertia()
            if K is None:
                K = np.diag(self.omega**2 * lam)
            if D is None:
                D = np.diag(2.0 * self.zeta * np.sqrt(np.diag(K) * lam))
        self.K = K[np.ix_(self.rows, self.rows)]
        self.D = D[np.ix_(self.rows, self.rows)]

    def _home_inertia(self) -> FloatArray:
        """(6,) task inertia at home: the mean translational and rotational diagonal of Λ."""
        home = np.asarray(self.robot.q_home, dtype=float)[None]
        _, J, _ = self._kinematics(home, np.zeros_like(home))
        Jr = J[:, self.take]
        Lam = damped_inverse(np.matmul(Jr, np.linalg.solve(self._mass(home), Jr.transpose(0, 2, 1))), self.weights, self.eps_inertia)
        diag = np.diagonal(Lam[0])
        lam = np.empty(6)
        trans = self.rows < 3
        lam[:3] = diag[trans].mean()
        lam[3:] = diag[~trans].mean() if (~trans).any() else lam[0]
        return lam

    def torque(
        self, q: ArrayLike, qd: ArrayLike, pose_d: ArrayLike, twist_d: ArrayLike, accel_d: ArrayLike, joints: Any = None
    ) -> FloatArray:  # type: ignore[override]
        single, Q, QD = _batch(self.robot, q, qd)
        task, M, e = self._law(Q, QD, *_desired(pose_d, twist_d, accel_d, Q.shape[0])[:2], joints)
        arg = (Q[0], QD[0]) if single else (Q, QD)
        friction = dynamics.friction_torque(self.robot, arg[1])
        tau = task + dynamics.gravity_torque(self.robot, arg[0]) + friction
        self._qdd = self._closed_loop(M, task, arg, friction)
        if single:
            self.error, self._qdd = e[0], self._qdd[0]
            return tau[0]
        self.error = e
        return tau

    def acceleration(
        self, q: ArrayLike, qd: ArrayLike, pose_d: ArrayLike, twist_d: ArrayLike, accel_d: ArrayLike, joints: Any = None
    ) -> FloatArray:
        # q̈ = M⁻¹ (τ − b) = M⁻¹ (Jᵀ(Ke + Dė) + Nᵀτ₀ − C q̇): gravity cancels, no call for it.
        single, Q, QD = _batch(self.robot, q, qd)
        task, M, _ = self._law(Q, QD, *_desired(pose_d, twist_d, accel_d, Q.shape[0])[:2], joints)
        arg = (Q[0], QD[0]) if single else (Q, QD)
        qdd = self._closed_loop(M, task, arg, dynamics.friction_torque(self.robot, arg[1]))
        return qdd[0] if single else qdd

    def _closed_loop(self, M: FloatArray, task: FloatArray, arg: tuple, friction: FloatArray) -> FloatArray:
        """q̈ (N, n) = M⁻¹ (task − C q̇), C q̇ = (bias without gravity) − friction."""
        coriolis = dynamics.bias_torque(self.robot, *arg, gravity=(0.0, 0.0, 0.0)) - friction
        return np.linalg.solve(M, (task - coriolis)[..., None])[..., 0]

    def _law(
        self, Q: FloatArray, QD: FloatArray, Td: FloatArray, Vd: FloatArray, joints: Any
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """(Jᵀ (K e + D ė) + Nᵀ τ₀, M, e): the law's torque without gravity and friction."""
        T, J, _ = self._kinematics(Q, QD)
        twist = _mv(J, QD)
        e, _ = self._errors(T, Td)
        Jr = J[:, self.take]
        wrench = e @ self.K.T + (Vd - twist)[:, self.take] @ self.D.T
        task = _mv(Jr.transpose(0, 2, 1), wrench)
        M = self._mass(Q)
        qdd0 = self._posture_accel(Q, QD, joints)
        if qdd0 is not None:  # Nᵀ M q̈₀ = M q̈₀ − Jᵀ Λ J q̈₀
            Lam = damped_inverse(np.matmul(Jr, np.linalg.solve(M, Jr.transpose(0, 2, 1))), self.weights, self.eps_inertia)
            task += _mv(M, qdd0) - _mv(Jr.transpose(0, 2, 1), _mv(Lam, _mv(Jr, qdd0)))
        return task, M, e


class ResolvedRate(TaskSpaceController):
    """Resolved-rate motion control at torque level (see the module docstring).

    ``gain`` K [1/s] of the Cartesian error (default ω); the posture rate gain k₀ is the
    same.  Joint-space computed torque with ``gains`` tracks (q_d, q̇_d, q̈_d), with
    ``q̈_d = J⁺ (ẍ_d + K (ẋ_d − J q̇_d) − J̇ q̇_d)``.  Each :meth:`torque` call is one
    control period ``dt`` (set by :meth:`reset`, 1 ms before it): it first moves q_d on by
    ``dt q̇_d + dt²/2 q̈_d`` of the previous call.
    """

    mode = "resolved_rate"
    continuous = False

    def __init__(self, robot: RobotParams, gains: Gains, *, gain: float | None = None, null_space: Any = "home") -> None:
        super().__init__(robot, gains, null_space)
        if gain is not None and (isinstance(gain, bool) or not isinstance(gain, (int, float)) or not (0 < gain < math.inf)):
            raise ValueError(f"gain must be a positive finite number [1/s], got {gain!r}")
        self.gain = float(gain) if gain is not None else gains.omega
        self.joint = ComputedTorque(robot, gains)
        self.dt = 1e-3
        self.q_des: FloatArray | None = None
        self.qd_des: FloatArray | None = None
        self.qdd_des: FloatArray | None = None

    def reset(self, q: ArrayLike, dt: float) -> None:
        """Start at rest at joint values ``q`` (n,) or (N, n), control period ``dt`` [s]."""
        self.q_des = np.array(q, dtype=float)
        self.qd_des = self.qdd_des = None
        self.dt = float(dt)

    def torque(
        self, q: ArrayLike, qd: ArrayLike, pose_d: ArrayLike, twist_d: ArrayLike, accel_d: ArrayLike, joints: Any = None
    ) -> FloatArray:  # type: ignore[override]
        single, Q, QD = _batch(self.robot, q, qd)
        if self.q_des is None or np.shape(self.q_des) != np.shape(q):
            self.reset(q, self.dt)
        elif self.qd_des is not None:
            self.q_des = self.q_des + self.dt * self.qd_des + 0.5 * self.dt**2 * self.qdd_des
        Td, Vd, Ad = _desired(pose_d, twist_d, accel_d, Q.shape[0])
        Qd = np.atleast_2d(self.q_des)
        T, J, _ = self._kinematics(Qd, np.zeros_like(Qd))
        e, _ = self._errors(T, Td)
        Jr = J[:, self.take]
        pinv = np.matmul(Jr.transpose(0, 2, 1), damped_inverse(np.matmul(Jr, Jr.transpose(0, 2, 1)), self.weights, self.eps_jacobian))
        qd_des = _mv(pinv, Vd[:, self.take] + self.gain * e)
        if self.posture is not None:
            rest = self.gain * ((self.posture if joints is None else np.asarray(joints[0], dtype=float)) - Qd)
            qd_des += rest - _mv(pinv, _mv(Jr, rest))
        _, _, jd = self._kinematics(Qd, qd_des)
        twist_error = Vd[:, self.take] - _mv(Jr, qd_des)
        qdd_des = _mv(pinv, Ad[:, self.take] + self.gain * twist_error - jd[:, self.take])
        self.qd_des, self.qdd_des = (qd_des[0], qdd_des[0]) if single else (qd_des, qdd_des)
        self.error = e[0] if single else e
        args = (Q, QD, Qd, qd_des, qdd_des)
        tau = self.joint.torque(*(a[0] for a in args)) if single else self.joint.torque(*args)
        self._qdd = self.joint.commanded_acceleration()
        return tau


def make_task_controller(mode: str, robot: RobotParams, gains: Gains | None = None, **options: Any) -> TaskSpaceController:
    """Task-space controller of ``mode`` (:data:`TASK_MODES`) for ``robot``.

    ``gains`` (or, without them, ``bandwidth`` [Hz] and — for osc and resolved rate —
    ``damping`` ζ, through :func:`controllers.control_gains`) set ω and ζ.  Other options:
    ``null_space`` (all), ``stiffness``/``damping`` (impedance: K and D; ``K``/``D`` are the
    same), ``gain`` (resolved rate).  ValueError for an unknown mode or option, naming it.
    """
    if mode not in TASK_MODES:
        raise ValueError(f"mode must be one of {', '.join(TASK_MODES)}, got {mode!r}")
    allowed = {"osc": {"bandwidth", "damping", "null_space"},
               "impedance": {"bandwidth", "stiffness", "damping", "K", "D", "null_space"},
               "resolved_rate": {"bandwidth", "damping", "gain", "null_space"}}[mode]
    unknown = sorted(set(options) - allowed)
    if unknown:
        raise ValueError(f"{mode} takes the options {', '.join(sorted(allowed))}, got {', '.join(unknown)}")
    for short, long in (("K", "stiffness"), ("D", "damping")):
        if short in options:
            if options.get(long) is not None:
                raise ValueError(f"give {long} or {short}, not both")
            options[long] = options.pop(short)
    bandwidth = options.pop("bandwidth", None)
    zeta = None if mode == "impedance" else options.pop("damping", None)
    if gains is None:
        gains = control_gains(robot, bandwidth=bandwidth, damping=zeta)
    elif bandwidth is not None or zeta is not None:
        raise ValueError("give gains or bandwidth/damping, not both")
    kinds = {"osc": OperationalSpace, "impedance": Impedance, "resolved_rate": ResolvedRate}
    return kinds[mode](robot, gains, **options)
