"""The public dynamics functions (conventions: :mod:`robot_sim.dynamics`) and the choice of
implementation (:func:`set_backend`): the compiled kernels (``robot_sim.dynamics.compiled``)
or the reference recursion (``robot_sim.dynamics.recursion``).  Imports neither Qt nor
OpenGL."""
from __future__ import annotations

import math
import os
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from robot_sim.dynamics.algebra import FloatArray, Scalar
from robot_sim.dynamics.recursion import (
    _check_gravity, _crba_terms, _DynModel, _model, _rnea_terms,
)
from robot_sim.kernels.model import kernel_array
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.params import RobotParams

GRAVITY = (0.0, 0.0, -9.81)
#: Configurations per chunk of the batched kernels (work arrays stay in cache).
CHUNK = 2048
#: The implementations: "compiled" (numba kernels of dynamics.compiled, the default) and
#: "reference" (the readable recursion of this module).  The environment variable
#: ``ROBOT_SIM_DYNAMICS`` picks one at import, :func:`set_backend` at run time.
BACKENDS = ("compiled", "reference")
BACKEND_ENV = "ROBOT_SIM_DYNAMICS"


def _checked_backend(name: object, where: str) -> str:
    if name not in BACKENDS:
        raise ValueError(f"{where} must be one of {', '.join(BACKENDS)}, got {name!r}")
    return str(name)


_backend = _checked_backend(os.environ.get(BACKEND_ENV, "compiled"), f"environment variable {BACKEND_ENV}")


def set_backend(name: str) -> None:
    """Run the dynamics through ``name``: ``"compiled"`` (numba kernels compiled once per
    machine and cached) or ``"reference"`` (the readable recursion, for debugging and as
    the tests' reference).  Results agree to round-off (about 1e-12 relative)."""
    global _backend
    _backend = _checked_backend(name, "backend")


def backend() -> str:
    """The implementation in use, one of :data:`BACKENDS`."""
    return _backend


def _solve_spd(A: FloatArray, b: FloatArray) -> FloatArray:
    """x (n, M) with A x = b for symmetric positive definite A (n, n, M): Cholesky
    factorisation and two triangular solves, looping over joints only."""
    n = A.shape[0]
    L = [[None] * n for _ in range(n)]
    for j in range(n):
        diag = A[j, j].copy()
        for k in range(j):
            diag -= L[j][k] * L[j][k]
        L[j][j] = np.sqrt(diag)
        inv = 1.0 / L[j][j]
        for i in range(j + 1, n):
            acc = A[i, j].copy()
            for k in range(j):
                acc -= L[i][k] * L[j][k]
            acc *= inv
            L[i][j] = acc
    y = [None] * n
    for i in range(n):
        acc = b[i].copy()
        for k in range(i):
            acc -= L[i][k] * y[k]
        y[i] = acc / L[i][i]
    x = np.empty_like(b)
    for i in range(n - 1, -1, -1):
        acc = y[i].copy()
        for k in range(i + 1, n):
            acc -= L[k][i] * x[k]
        x[i] = acc / L[i][i]
    return x


# ------------------------------------------------------------------ arguments


def _joint_array(
    robot: RobotParams, value: ArrayLike, name: str, like: FloatArray | None = None, finite: bool = True
) -> FloatArray:
    n = robot.n_dofs
    if type(value) is np.ndarray and value.dtype == np.float64:
        arr = value  # the common case, without the cost of a conversion
    else:
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be an array of shape ({n},) or (N, {n}), got {type(value).__name__}") from None
    if like is None:
        if arr.ndim not in (1, 2) or arr.shape[-1] != n:
            raise ValueError(f"{name} must have shape ({n},) or (N, {n}), got shape {arr.shape}")
    elif arr.shape != like.shape:
        raise ValueError(f"{name} must have the shape of q, {like.shape}, got shape {arr.shape}")
    if finite and not np.isfinite(arr).all():
        raise ValueError(f"{name} must be finite, got NaN or inf in {name}")
    return arr


_NO_WRENCH = np.zeros((1, 6))  # the compiled kernels' placeholder for "no tool wrench"


def _tool_wrench_in_last_frame(robot: RobotParams, Q: FloatArray, f_tool: ArrayLike) -> FloatArray:
    """(N, 6) [force; moment about frame n's origin] in frame n from the world wrench at the tool origin."""
    f = np.asarray(f_tool, dtype=float)
    if f.shape not in ((6,), (Q.shape[0], 6)) or not np.isfinite(f).all():
        raise ValueError(
            f"f_tool must be a finite (6,) wrench [force; moment] or one per configuration ({Q.shape[0]}, 6), "
            f"got shape {f.shape}"
        )
    f = np.broadcast_to(f, (Q.shape[0], 6))
    frames = forward_kinematics(robot, Q, all_frames=True)
    n = robot.n_dofs
    R, origin, tool = frames[:, n, :3, :3], frames[:, n, :3, 3], frames[:, n + 1, :3, 3]
    moment = f[:, 3:] + np.cross(tool - origin, f[:, :3])
    out = np.empty((Q.shape[0], 6))
    out[:, :3] = np.einsum("nji,nj->ni", R, f[:, :3])
    out[:, 3:] = np.einsum("nji,nj->ni", R, moment)
    return out


def _drive_torque(model: _DynModel, QDT: FloatArray | None, QDDT: FloatArray | None) -> FloatArray | None:
    """G²·Jm·q̈ + G²·B·q̇ + |G|·Tc± (by the sign of q̇, 0 at rest), (n, N); None if nothing."""
    out = None
    if QDDT is not None and np.any(model.reflected):
        out = QDDT * model.reflected[:, None]
    if QDT is not None and model.has_friction:
        coulomb = np.where(QDT > 0.0, model.coulomb_pos[:, None], np.where(QDT < 0.0, model.coulomb_neg[:, None], 0.0))
        friction = QDT * model.viscous[:, None] + coulomb
        out = friction if out is None else out + friction
    return out


def _rows(X: FloatArray | None) -> FloatArray | None:
    """(N, n) → (n, N) contiguous: each joint's values of all configurations in one row."""
    return None if X is None else np.ascontiguousarray(X.T)


def _joint_inputs(model: _DynModel, QT: FloatArray) -> tuple[list[Scalar], list[Scalar], FloatArray | list[float]]:
    """cos θ, sin θ and q per joint for a chunk (n, M): arrays, or Python floats when M = 1
    (one configuration: float arithmetic costs far less than NumPy calls on 1-arrays)."""
    if QT.shape[1] != 1:
        return (*model.cos_sin(QT), QT)
    q = QT[:, 0].tolist()
    cos, sin = list(model.ct), list(model.st)
    for j in model.rev_index:
        cos[j], sin[j] = math.cos(model.th[j] + q[j]), math.sin(model.th[j] + q[j])
    return cos, sin, q


def _rate_inputs(X: FloatArray | None) -> list[float] | None:
    """Rates of one configuration (n, 1) as Python floats."""
    return None if X is None else X[:, 0].tolist()


def _rnea(
    robot: RobotParams,
    Q: FloatArray,
    QD: FloatArray | None,
    QDD: FloatArray | None,
    gravity: ArrayLike,
    f_tool: ArrayLike | None,
) -> FloatArray:
    """τ (n, N) by RNEA, drive terms included, for Q etc. of shape (N, n) (None: zero)."""
    model = _model(robot)
    if _backend == "compiled":
        kernels, table = model.compiled()
        zero = None if QD is not None and QDD is not None else np.zeros(Q.shape)
        ext = _NO_WRENCH if f_tool is None else _tool_wrench_in_last_frame(robot, Q, f_tool)
        tau = np.empty(Q.shape)
        finite = kernels.rnea_batch(
            table, Q, zero if QD is None else QD, zero if QDD is None else QDD,
            model.gravity_array(robot, gravity), ext, f_tool is not None, tau,
        )
        if not finite:
            _arguments(robot, Q, qd=Q if QD is None else QD, qdd=Q if QDD is None else QDD)  # raises
        return tau.T
    g0 = model.gravity_in_frame0(robot, gravity)
    wrench = None if f_tool is None else _rows(_tool_wrench_in_last_frame(robot, Q, f_tool))
    QT, QDT, QDDT = _rows(Q), _rows(QD), _rows(QDD)
    if QT.shape[1] == 1:  # one configuration: Python floats throughout
        cos, sin, q = _joint_inputs(model, QT)
        ext = None if wrench is None else _rate_inputs(wrench)
        ext = None if ext is None else (tuple(ext[:3]), tuple(ext[3:]))
        tau = np.array(_rnea_terms(model, cos, sin, q, _rate_inputs(QDT), _rate_inputs(QDDT), g0, ext), dtype=float)[:, None]
    else:
        tau = np.empty(QT.shape)
        for s in range(0, QT.shape[1], CHUNK):
            sl = slice(s, s + CHUNK)
            cos, sin, q = _joint_inputs(model, QT[:, sl])
            rates = [None if X is None else X[:, sl] for X in (QDT, QDDT)]
            ext = None if wrench is None else (tuple(wrench[:3, sl]), tuple(wrench[3:, sl]))
            for j, value in enumerate(_rnea_terms(model, cos, sin, q, rates[0], rates[1], g0, ext)):
                tau[j, sl] = value
    drive = _drive_torque(model, QDT, QDDT)
    if drive is not None:
        tau += drive
    return tau


def _crba(model: _DynModel, QT: FloatArray) -> FloatArray:
    """Mass matrices (n, n, M) of a chunk (n, M)."""
    n = model.n
    cos, sin, q = _joint_inputs(model, QT)
    values = _crba_terms(model, cos, sin, q)
    if QT.shape[1] == 1:
        return np.array(values, dtype=float).reshape(n, n, 1)
    out = np.empty((n, n, QT.shape[1]))
    for k, value in enumerate(values):
        out[k // n, k % n] = value
    return out


def _arguments(robot: RobotParams, q: ArrayLike, finite: bool = True, **rates: ArrayLike) -> tuple[bool, list[FloatArray]]:
    """Checked joint arrays as (N, n): q first, then ``rates`` (each the shape of q), and
    whether q was a single configuration.  ``finite=False`` leaves the test for NaN/inf
    to the caller (the compiled kernels test their inputs at no cost and report it: then
    the arguments are checked again with the test, which raises naming the culprit)."""
    q_arr = _joint_array(robot, q, "q", finite=finite)
    arrays = [q_arr] + [_joint_array(robot, value, name, q_arr, finite) for name, value in rates.items()]
    # C-contiguous and writeable, whatever was given (a robot's read-only q_home, a strided
    # column): numba compiles a kernel again for each other layout or flag
    if q_arr.ndim == 1:
        return True, [kernel_array(a)[None] for a in arrays]
    return False, [kernel_array(a) for a in arrays]


# ------------------------------------------------------------------ public API


def inverse_dynamics(
    robot: RobotParams,
    q: ArrayLike,
    qd: ArrayLike,
    qdd: ArrayLike,
    gravity: ArrayLike = GRAVITY,
    f_tool: ArrayLike | None = None,
) -> FloatArray:
    """Joint torques/forces τ [N·m or N] that produce accelerations ``qdd`` at ``q``, ``qd``
    (recursive Newton–Euler), including reflected motor inertia and friction when the
    robot has drives: τ = M q̈ + C q̇ + g + τ_f − Jᵀ f_tool.

    q, qd, qdd: (n,) or (N, n) [rad, m; per s; per s²]; result of the same shape.
    ``gravity`` [m/s²] in the world; ``f_tool`` (6,) or (N, 6) wrench [N; N·m] applied by
    the environment at the tool frame origin, world frame.  ValueError for wrong shapes,
    NaN/inf, or a robot without inertial data.
    """
    if f_tool is None and _backend == "compiled":  # one configuration of float64 vectors: fast
        model = _model(robot)
        kernels, table = model.compiled()
        tau = np.empty(model.n)
        try:
            if kernels.rnea_vec(table, q, qd, qdd, model.gravity_array(robot, gravity), tau):
                return tau
        except TypeError:  # not C-contiguous float64 vectors: the checked way below
            pass
    single, (Q, QD, QDD) = _arguments(robot, q, _backend != "compiled", qd=qd, qdd=qdd)
    tau = _rnea(robot, Q, QD, QDD, gravity, f_tool).T
    return tau[0] if single else tau


def computed_torque(
    robot: RobotParams,
    q: ArrayLike,
    qd: ArrayLike,
    q_des: ArrayLike,
    qd_des: ArrayLike,
    qdd_des: ArrayLike,
    kp: float | ArrayLike,
    kd: float | ArrayLike,
    gravity: ArrayLike = GRAVITY,
) -> tuple[FloatArray, FloatArray]:
    """(τ, q̈_ref): the inverse dynamics τ = ID(q, q̇, q̈_ref) [N·m or N] at the reference
    acceleration q̈_ref = q̈_des + kp (q_des − q) + kd (q̇_des − q̇) [rad/s² or m/s²], in one
    call (computed torque's law).  Joint arrays (n,) or (N, n); ``kp`` [1/s²] and ``kd``
    [1/s] numbers, or (N, 1) one per configuration.  ValueError as inverse_dynamics."""
    if _backend == "compiled" and isinstance(kp, float) and isinstance(kd, float):  # one configuration: fast
        model = _model(robot)
        kernels, table = model.compiled()
        tau, qdd_ref = np.empty(model.n), np.empty(model.n)
        try:
            if kernels.ct_vec(table, q, qd, q_des, qd_des, qdd_des, kp, kd, model.gravity_array(robot, gravity), tau, qdd_ref):
                return tau, qdd_ref
        except TypeError:  # not C-contiguous float64 vectors: the checked way below
            pass
    single, (Q, QD, QDES, QDDES, QDDDES) = _arguments(robot, q, qd=qd, q_des=q_des, qd_des=qd_des, qdd_des=qdd_des)
    gains = [np.broadcast_to(np.asarray(g, dtype=float), (Q.shape[0], 1)) for g in (kp, kd)]
    for name, g in zip(("kp", "kd"), gains):
        if not np.isfinite(g).all():
            raise ValueError(f"{name} must be finite, got {g!r}")
    if _backend == "compiled":
        model = _model(robot)
        kernels, table = model.compiled()
        tau, qdd_ref = np.empty(Q.shape), np.empty(Q.shape)
        KP, KD = (kernel_array(g[:, 0]) for g in gains)  # a column of a broadcast is read-only
        kernels.ct_batch(table, Q, QD, QDES, QDDES, QDDDES, KP, KD, model.gravity_array(robot, gravity), tau, qdd_ref)
    else:
        qdd_ref = QDDDES + gains[0] * (QDES - Q) + gains[1] * (QDDES - QD)
        tau = _rnea(robot, Q, QD, qdd_ref, gravity, None).T
    return (tau[0], qdd_ref[0]) if single else (tau, qdd_ref)


def gravity_torque(robot: RobotParams, q: ArrayLike, gravity: ArrayLike = GRAVITY) -> FloatArray:
    """g(q): joint torques [N·m or N] that hold the arm still against gravity, (n,) or (N, n)."""
    if _backend == "compiled":  # one configuration of a float64 vector: fast
        model = _model(robot)
        kernels, table = model.compiled()
        tau = np.empty(model.n)
        try:
            if kernels.rnea_vec(table, q, model.zero, model.zero, model.gravity_array(robot, gravity), tau):
                return tau
        except TypeError:  # not a C-contiguous float64 vector: the checked way below
            pass
    single, (Q,) = _arguments(robot, q, _backend != "compiled")
    tau = _rnea(robot, Q, None, None, gravity, None).T
    return tau[0] if single else tau


def bias_torque(
    robot: RobotParams, q: ArrayLike, qd: ArrayLike, gravity: ArrayLike = GRAVITY, f_tool: ArrayLike | None = None
) -> FloatArray:
    """C(q, q̇) q̇ + g(q) + τ_f(q̇) (− Jᵀ f_tool when given): inverse dynamics at q̈ = 0."""
    single, (Q, QD) = _arguments(robot, q, _backend != "compiled", qd=qd)
    tau = _rnea(robot, Q, QD, None, gravity, f_tool).T
    return tau[0] if single else tau


def compiled_kernels(robot: RobotParams, gravity: ArrayLike = GRAVITY) -> tuple[Any, FloatArray, FloatArray]:
    """(the compiled kernels module, ``robot``'s parameter table, gravity in frame 0 (3,)):
    for other compiled code built on these kernels (the operational-space step passes
    ``crba_batch`` and ``rnea_batch`` into its own kernel).  Imports numba."""
    model = _model(robot)
    kernels, table = model.compiled()
    return kernels, table, model.gravity_array(robot, gravity)


def friction_torque(robot: RobotParams, qd: ArrayLike) -> FloatArray:
    """τ_f(q̇) = G²·B·q̇ + |G|·Tc± [N·m or N], (n,) or (N, n): what the drives spend on
    friction at joint rates ``qd`` (Tc+ when q̇ > 0, Tc− when q̇ < 0, none at rest); zero
    without drives.  Included in :func:`inverse_dynamics` and :func:`bias_torque`."""
    qd_arr = _joint_array(robot, qd, "qd")
    single, QD = qd_arr.ndim == 1, np.atleast_2d(qd_arr)
    friction = _drive_torque(_model(robot), _rows(QD), None)
    tau = np.zeros(QD.shape) if friction is None else friction.T
    return tau[0] if single else tau


def mass_matrix(robot: RobotParams, q: ArrayLike) -> FloatArray:
    """Joint-space inertia matrix M(q) (n, n) or (N, n, n) [kg·m², kg], symmetric positive
    definite, reflected motor inertia G²·Jm on the diagonal (composite rigid bodies)."""
    single, (Q,) = _arguments(robot, q, _backend != "compiled")
    model = _model(robot)
    if _backend == "compiled":
        kernels, table = model.compiled()
        M = np.empty((Q.shape[0], model.n, model.n))
        if not kernels.crba_batch(table, Q, M):
            _arguments(robot, q)  # raises
        return M[0] if single else M
    QT = _rows(Q)
    out = np.empty((robot.n_dofs, robot.n_dofs, QT.shape[1]))
    for s in range(0, QT.shape[1], CHUNK):
        out[:, :, s : s + CHUNK] = _crba(model, QT[:, s : s + CHUNK])
    out = out.transpose(2, 0, 1)
    return out[0].copy() if single else out


def forward_dynamics(
    robot: RobotParams,
    q: ArrayLike,
    qd: ArrayLike,
    tau: ArrayLike,
    gravity: ArrayLike = GRAVITY,
    f_tool: ArrayLike | None = None,
) -> FloatArray:
    """Joint accelerations q̈ = M⁻¹ (τ − C q̇ − g − τ_f + Jᵀ f_tool), (n,) or (N, n), by a
    batched Cholesky solve of the composite-rigid-body M (see the README for why)."""
    if f_tool is None and _backend == "compiled":  # as in inverse_dynamics
        model = _model(robot)
        kernels, table = model.compiled()
        qdd = np.empty(model.n)
        try:
            if kernels.fd_vec(table, q, qd, tau, model.gravity_array(robot, gravity), qdd):
                return qdd
        except TypeError:
            pass
    single, (Q, QD, TAU) = _arguments(robot, q, _backend != "compiled", qd=qd, tau=tau)
    model = _model(robot)
    if _backend == "compiled":
        kernels, table = model.compiled()
        ext = _NO_WRENCH if f_tool is None else _tool_wrench_in_last_frame(robot, Q, f_tool)
        qdd = np.empty(Q.shape)
        g0 = model.gravity_array(robot, gravity)
        if not kernels.fd_batch(table, Q, QD, TAU, g0, ext, f_tool is not None, qdd):
            _arguments(robot, q, qd=qd, tau=tau)  # raises
        return qdd[0] if single else qdd
    rhs = _rows(TAU) - _rnea(robot, Q, QD, None, gravity, f_tool)
    QT = _rows(Q)
    if single:
        return np.linalg.solve(_crba(model, QT)[:, :, 0], rhs[:, 0])
    out = np.empty(QT.shape)
    for s in range(0, QT.shape[1], CHUNK):
        sl = slice(s, s + CHUNK)
        out[:, sl] = _solve_spd(_crba(model, QT[:, sl]), rhs[:, sl])
    return out.T


def constrained_forward_dynamics(
    robot: RobotParams,
    q: ArrayLike,
    qd: ArrayLike,
    tau: ArrayLike,
    held: ArrayLike,
    gravity: ArrayLike = GRAVITY,
    f_tool: ArrayLike | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Forward dynamics with the ``held`` joints locked (by joint stops): (q̈, λ), each
    (n,) or (N, n).  ``held`` is bool, (n,) for every configuration or the shape of q.

    M q̈ = τ − C q̇ − g − τ_f + Jᵀ f_tool + λ with q̈ exactly zero on the held joints and λ
    zero on the others: the free joints solve their rows and columns of M (the held rows
    and columns replaced by the identity's), and λ [N·m or N] is the torque the
    constraint exerts on each held joint (its reaction).  The held joints' velocities
    should be zero (a held joint does not move)."""
    single, (Q, QD, TAU) = _arguments(robot, q, qd=qd, tau=tau)
    n = robot.n_dofs
    mask = np.asarray(held)
    if mask.dtype != np.bool_ or mask.shape not in ((n,), np.shape(q)):
        raise ValueError(
            f"held must be a bool array of shape ({n},) or of the shape of q, {np.shape(q)}, "
            f"got {mask.dtype} of shape {mask.shape}"
        )
    if single:  # plain (n, n) algebra: a batch of one costs far more in NumPy's stacked calls
        M1 = mass_matrix(robot, Q[0])
        rhs1 = TAU[0] - bias_torque(robot, Q[0], QD[0], gravity, f_tool)
        A1 = M1.copy()
        A1[mask] = 0.0
        A1[:, mask] = 0.0
        A1[mask, mask] = 1.0
        qdd1 = np.linalg.solve(A1, np.where(mask, 0.0, rhs1))
        qdd1[mask] = 0.0
        return qdd1, (M1 @ qdd1 - rhs1) * mask
    H = np.broadcast_to(mask, Q.shape)
    M = mass_matrix(robot, Q)
    rhs = TAU - bias_torque(robot, Q, QD, gravity, f_tool)
    A = np.where(H[:, :, None] | H[:, None, :], 0.0, M)
    A[:, np.arange(n), np.arange(n)] += H
    qdd = np.where(H, 0.0, np.linalg.solve(A, np.where(H, 0.0, rhs)[..., None])[..., 0])
    reaction = np.where(H, np.einsum("nij,nj->ni", M, qdd) - rhs, 0.0)
    return qdd, reaction


def _link_jacobians(robot: RobotParams, Q: FloatArray, QD: FloatArray) -> dict[str, FloatArray]:
    """World-frame per-link quantities (N configurations, k = link, j = joint): COM
    Jacobians ``Jv``, ``Jw`` (N, k, 3, j) and their time derivatives ``Jv_dot``, ``Jw_dot``
    along q̇, link angular velocities ``omega`` (N, k, 3), world inertias ``inertia``
    (N, k, 3, 3) about the COMs, and ``com`` (N, k, 3)."""
    model = _model(robot)
    li = robot.inertials
    n = robot.n_dofs
    frames = forward_kinematics(robot, Q, all_frames=True)[:, : n + 1]
    axis_frames = frames[:, 1:] if model.modified else frames[:, :-1]
    a, p = axis_frames[..., :3, 2], axis_frames[..., :3, 3]  # (N, j, 3)
    rev = np.asarray(model.revolute)
    R = frames[:, 1:, :3, :3]
    com = frames[:, 1:, :3, 3] + np.einsum("nkab,kb->nka", R, li.com)
    w_joint = a * (QD * rev)[..., None]
    omega = np.cumsum(w_joint, axis=1)
    omega_before = np.concatenate([np.zeros_like(omega[:, :1]), omega[:, :-1]], axis=1)
    a_dot = np.cross(omega_before, a)
    slide = a * (QD * ~rev)[..., None]

    def velocity(x: FloatArray, mask: FloatArray) -> FloatArray:
        """Velocity of points x (N, k, 3), point k moved by the joints j with mask[k, j]."""
        contrib = np.cross(w_joint[:, None], x[:, :, None] - p[:, None]) + slide[:, None]
        return np.einsum("kj,nkja->nka", mask, contrib)

    lower = np.tril(np.ones((n, n)))
    com_vel = velocity(com, lower)
    p_vel = velocity(p, np.tril(np.ones((n, n)), -1))  # axis point as a point of the link before
    lever = com[:, :, None] - p[:, None]  # (N, k, j, 3)
    Jv = np.where(rev[None, None, :, None], np.cross(a[:, None], lever), a[:, None])
    Jv_dot = np.where(
        rev[None, None, :, None],
        np.cross(a_dot[:, None], lever) + np.cross(a[:, None], com_vel[:, :, None] - p_vel[:, None]),
        a_dot[:, None],
    )
    mask = (lower[None, :, :, None] * rev[None, None, :, None])
    Jw = a[:, None] * mask
    Jw_dot = a_dot[:, None] * mask
    Jv, Jv_dot = Jv * lower[None, :, :, None], Jv_dot * lower[None, :, :, None]
    inertia = np.einsum("nkab,kbc,nkdc->nkad", R, li.inertia, R)
    return {
        "Jv": Jv.transpose(0, 1, 3, 2), "Jw": Jw.transpose(0, 1, 3, 2),
        "Jv_dot": Jv_dot.transpose(0, 1, 3, 2), "Jw_dot": Jw_dot.transpose(0, 1, 3, 2),
        "omega": omega, "inertia": inertia, "com": com,
    }


def coriolis_matrix(robot: RobotParams, q: ArrayLike, qd: ArrayLike) -> FloatArray:
    """C(q, q̇) (n, n) or (N, n, n) with C q̇ the Coriolis and centrifugal torques and
    Ṁ − 2C skew-symmetric: Σ_k m_k J_vᵀ J̇_v + J_ωᵀ I_k J̇_ω + J_ωᵀ [ω_k]ₓ I_k J_ω over the
    links (COM Jacobians and inertias in the world frame).  Motor inertia adds nothing."""
    single, (Q, QD) = _arguments(robot, q, qd=qd)
    _model(robot)  # refuses a robot without inertial data
    mass = np.asarray(robot.inertials.mass)
    parts = _link_jacobians(robot, Q, QD)
    Jv, Jw, Jv_dot, Jw_dot = parts["Jv"], parts["Jw"], parts["Jv_dot"], parts["Jw_dot"]
    inertia, omega = parts["inertia"], parts["omega"]
    spin = np.cross(omega[:, :, :, None], inertia, axis=2)  # [ω]ₓ I, column by column
    C = np.einsum("k,nkai,nkaj->nij", mass, Jv, Jv_dot)
    C += np.einsum("nkai,nkab,nkbj->nij", Jw, inertia, Jw_dot)
    C += np.einsum("nkai,nkab,nkbj->nij", Jw, spin, Jw)
    return C[0] if single else C


def energy(
    robot: RobotParams, q: ArrayLike, qd: ArrayLike, gravity: ArrayLike = GRAVITY
) -> tuple[FloatArray | float, FloatArray | float]:
    """(kinetic, potential) energy [J]: ½ q̇ᵀ M q̇ (motor inertia included) and
    −Σ m_k g·c_k with the COMs c_k in the world (zero at the world origin's height)."""
    single, (Q, QD) = _arguments(robot, q, qd=qd)
    g = _check_gravity(gravity)
    M = mass_matrix(robot, Q)
    kinetic = 0.5 * np.einsum("ni,nij,nj->n", QD, M, QD)
    n = robot.n_dofs
    frames = forward_kinematics(robot, Q, all_frames=True)[:, 1 : n + 1]
    com = frames[..., :3, 3] + np.einsum("nkab,kb->nka", frames[..., :3, :3], robot.inertials.com)
    potential = -np.einsum("k,nka,a->n", np.asarray(robot.inertials.mass), com, g)
    if single:
        return float(kinetic[0]), float(potential[0])
    return kinetic, potential
