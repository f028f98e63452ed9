"""Cartesian plans: straight lines and circular arcs of the tool, followed through IK.

Private helper of :mod:`trajectory` (import from there).  Poses are tool frames in the
world (4×4), positions in metres, angles in radians, times in seconds.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.planning.profiles import _parabolic, check_duration, joint_vector, plan_times
from robot_sim.planning.trajectory import FloatArray, Trajectory
from robot_sim.ik.nearest import follow_branch
from robot_sim.kinematics import forward_kinematics, jacobian, solve_ik
from robot_sim.kinematics.ik import _target_matrix
from robot_sim.model.params import RobotParams
from robot_sim.transforms import rotation_log, rpy_from_rot

#: Joint speed assumed when the robot file gives no velocity limit [rad/s, m/s]; bounds the
#: joint step between two samples of a Cartesian path (a larger step is a branch flip or
#: a singularity).
DEFAULT_QD_MAX_REVOLUTE = np.pi
DEFAULT_QD_MAX_PRISMATIC = 1.0
#: Below this smallest singular value of the Jacobian a failure is reported as singular.
SINGULAR_SIGMA = 1e-3
#: IK tolerances when following a path [m, rad]: well inside the 1e-6 the tests demand.
FOLLOW_TOL = 1e-9
FOLLOW_MAX_ITER = 60
SCALINGS = ("quintic", "trapezoidal")
#: Default acceleration limit: a joint reaches its speed limit from rest in this time [s].
ACCEL_TIME = 0.2
#: A joint this close to a limit it was not at before has reached it [rad or m].
LIMIT_REACHED = 1e-9


class CartesianPathError(ValueError):
    """A Cartesian path cannot be followed.  ``sample`` is the first sample that fails,
    ``time`` its time [s], ``pose`` its target (4×4), ``reason`` why (out of reach, singular,
    a joint reaching its limit, a joint speed or acceleration above its limit), ``joint``
    the joint concerned (0-based; None when no single joint is), and ``trajectory`` the
    motion up to the last good sample (None if the first sample already fails)."""

    def __init__(self, message: str, sample: int, time: float, pose: FloatArray, reason: str,
                 trajectory: Trajectory | None, joint: int | None = None) -> None:
        super().__init__(message)
        self.sample, self.time, self.pose, self.reason, self.trajectory = sample, time, pose, reason, trajectory
        self.joint = joint


def time_scaling(kind: str, duration: float, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Path parameter s(t) from 0 to 1 over ``duration`` and its first two derivatives.

    "quintic": s = 10τ³ − 15τ⁴ + 6τ⁵ (τ = t/duration; zero speed and acceleration at both
    ends); "trapezoidal": constant acceleration for the first third, cruise at 1.5/duration,
    constant deceleration for the last third (RTB's ``trapezoidal`` default).
    """
    if kind == "quintic":
        tau = t / duration
        s = tau**3 * (10 - 15 * tau + 6 * tau**2)
        sd = 30 * tau**2 * (1 - tau) ** 2 / duration
        sdd = 60 * tau * (1 - tau) * (1 - 2 * tau) / duration**2
        return s, sd, sdd
    if kind == "trapezoidal":
        acc = 4.5 / duration**2
        prof = _parabolic(np.zeros(1), np.full(3, duration / 3), np.array([[acc], [0.0], [-acc]]), t)
        return prof.q[:, 0], prof.qd[:, 0], prof.qdd[:, 0]
    raise ValueError(f"scaling must be one of {', '.join(SCALINGS)}, got {kind!r}")


def _rotations(axis: FloatArray, angles: FloatArray) -> FloatArray:
    """Rotations (N, 3, 3) by ``angles`` (N,) about the unit ``axis`` (Rodrigues, batched)."""
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    s, c = np.sin(angles)[:, None, None], np.cos(angles)[:, None, None]
    return np.eye(3) + s * K + (1.0 - c) * (K @ K)


def qd_limits(robot: RobotParams) -> FloatArray:
    """Joint speed limits (n,): the robot's drive limits where known, else the defaults."""
    default = np.where(robot.is_revolute, DEFAULT_QD_MAX_REVOLUTE, DEFAULT_QD_MAX_PRISMATIC)
    drives = robot.drives
    limit = np.asarray(drives.velocity_limit, dtype=float) if drives is not None else default
    return np.where(np.isfinite(limit), limit, default)


def qdd_limits(robot: RobotParams) -> FloatArray:
    """Joint acceleration limits (n,) [rad/s² or m/s²]: each joint's speed limit
    (:func:`qd_limits`) reached from rest in ACCEL_TIME seconds (robot files give no
    acceleration limits)."""
    return qd_limits(robot) / ACCEL_TIME


def _describe(pose: FloatArray) -> str:
    rpy = np.degrees(rpy_from_rot(pose[:3, :3]))
    return f"tool at xyz [{', '.join(f'{v:.4f}' for v in pose[:3, 3])}] m, rpy [{', '.join(f'{v:.2f}' for v in rpy)}] deg"


def _why(robot: RobotParams, q_prev: FloatArray, result) -> tuple[str, int | None]:
    """Reason an IK step from ``q_prev`` failed (singular, joint limit or out of reach) and
    the joint concerned (None when no single joint is)."""
    rows = 3 if result.position_only else 6
    sigma = float(np.linalg.svd(jacobian(robot, q_prev)[:rows], compute_uv=False)[-1])
    if sigma < SINGULAR_SIGMA:
        return f"singular: smallest singular value of the Jacobian {sigma:.2e} < {SINGULAR_SIGMA:g}", None
    at_limit = np.flatnonzero((result.q <= robot.q_min + 1e-6) | (result.q >= robot.q_max - 1e-6))
    if at_limit.size:
        j = int(at_limit[0])
        return f"joint {j + 1} at its limit ({result.q[j]:.4g} in [{robot.q_min[j]:.4g}, {robot.q_max[j]:.4g}])", j
    return f"out of reach: IK position error {result.pos_err:.3g} m, rotation error {result.rot_err:.3g} rad", None


def _partial(t: FloatArray, q: FloatArray, poses: FloatArray) -> Trajectory:
    if t.shape[0] == 1:
        zeros = np.zeros_like(q)
        return Trajectory(t, q, zeros, zeros, poses)
    order = 2 if t.shape[0] > 2 else 1
    qd = np.gradient(q, t, axis=0, edge_order=order)
    qdd = np.gradient(qd, t, axis=0, edge_order=order)
    return Trajectory(t, q, qd, qdd, poses)


def follow_poses(robot: RobotParams, t: ArrayLike, poses: ArrayLike, q0: ArrayLike,
                 qd_max: ArrayLike | None = None, qdd_max: ArrayLike | None = None) -> Trajectory:
    """Joint motion that puts the tool at ``poses`` (N, 4, 4) at times ``t`` (N,).

    Where the arm has a closed form the samples are solved in one batch
    (:func:`robot_sim.ik.nearest.follow_branch`), each on the branch that continues the
    previous sample's (a 7-joint arm's free joint held at its value in ``q0``); otherwise (and from a sample that branch cannot reach) each sample
    is solved by :func:`kinematics.solve_ik` from the previous sample's solution continued
    by the last joint step (the first from ``q0``) without random restarts, so the joint
    path stays on one branch.  q̇ and q̈ are finite differences of
    q (second order).  Raises :class:`CartesianPathError`, naming the sample, its time and
    the joint, at the first sample whose IK fails (out of reach, singular), where a joint
    reaches one of its limits (the IK would hold it there while the others compensate: a
    stop within one sample), whose joint step exceeds ``qd_max`` [rad/s, m/s] × the time
    step (default :func:`qd_limits`: a branch flip or a singularity), or, once every sample
    is solved, where a joint accelerates beyond ``qdd_max`` [rad/s², m/s²] (default
    :func:`qdd_limits`); the error holds the motion up to the last good sample.
    """
    t = np.asarray(t, dtype=float)
    P = np.asarray(poses, dtype=float)
    q_prev = joint_vector("q0", q0, robot.n_dofs)
    vmax = qd_limits(robot) if qd_max is None else joint_vector("qd_max", qd_max, robot.n_dofs)
    amax = qdd_limits(robot) if qdd_max is None else joint_vector("qdd_max", qdd_max, robot.n_dofs)

    def fail(k: int, reason: str, joint: int | None, Q: FloatArray) -> CartesianPathError:
        partial = _partial(t[:k], Q[:k], P[:k]) if k > 0 else None
        stop = f"stopped at sample {k - 1}" if k > 0 else "nothing moved"
        return CartesianPathError(
            f"Cartesian path cannot be followed at sample {k} of {t.shape[0]} "
            f"(t = {t[k]:.4f} s, {_describe(P[k])}): {reason}; {stop}",
            k, float(t[k]), P[k].copy(), reason, partial, joint)

    def at_limit(q: FloatArray) -> NDArray[np.bool_]:
        return (q <= robot.q_min + LIMIT_REACHED) | (q >= robot.q_max - LIMIT_REACHED)

    Q = np.empty((t.shape[0], robot.n_dofs))
    was_at = at_limit(q_prev)
    branch = follow_branch(robot, P, q_prev)  # closed form: every sample at once, on one branch
    for k in range(t.shape[0]):
        q_k = None if branch is None else branch[k]
        if q_k is None or not np.isfinite(q_k).all():
            # predictor: continue the last joint step (fewer IK iterations); stays a seed only
            seed = q_prev if k < 2 else q_prev + (q_prev - Q[k - 2]) * ((t[k] - t[k - 1]) / (t[k - 1] - t[k - 2]))
            seed = np.clip(seed, robot.q_min, robot.q_max)
            res = solve_ik(robot, P[k], seed, max_restarts=0, max_iter=FOLLOW_MAX_ITER,
                           tol_pos=FOLLOW_TOL, tol_rot=FOLLOW_TOL)
            if not res.success:
                raise fail(k, *_why(robot, q_prev, res), Q)
            q_k = res.q
        reached = np.flatnonzero(at_limit(q_k) & ~was_at)
        if reached.size:
            j = int(reached[0])
            raise fail(k, f"joint {j + 1} reaches its limit ({q_k[j]:.6g} in "
                          f"[{robot.q_min[j]:.6g}, {robot.q_max[j]:.6g}])", j, Q)
        if k > 0:
            speed = np.abs(q_k - q_prev) / (t[k] - t[k - 1])
            j = int(np.argmax(speed / vmax))
            if speed[j] > vmax[j]:
                unit = "rad/s" if robot.is_revolute[j] else "m/s"
                raise fail(k, f"joint {j + 1} would move at {speed[j]:.3g} {unit}, above its limit "
                              f"{vmax[j]:.3g} {unit} (branch flip or singularity)", j, Q)
        Q[k] = q_prev = q_k
        was_at = at_limit(q_prev)
    traj = _partial(t, Q, P)
    over = np.argwhere(np.abs(traj.qdd) > amax)
    if over.size:
        k, j = (int(v) for v in over[0])
        unit = "rad/s²" if robot.is_revolute[j] else "m/s²"
        raise fail(k, f"joint {j + 1} would accelerate at {abs(traj.qdd[k, j]):.3g} {unit}, above its limit "
                      f"{amax[j]:.3g} {unit}", j, Q)
    return traj


def cartesian_line(robot: RobotParams, pose0: ArrayLike, pose1: ArrayLike, duration: float,
                   q0: ArrayLike, times: ArrayLike | None = None, scaling: str = "quintic",
                   *, qd_max: ArrayLike | None = None, qdd_max: ArrayLike | None = None) -> Trajectory:
    """Tool moves on the straight line from ``pose0`` to ``pose1`` (world frame, 4×4 or
    HomogeneousTransform) in ``duration`` s; orientation by SLERP, R(s) = R0 exp(s log(R0ᵀR1)),
    both along the same time law s(t) (``scaling`` "quintic" or "trapezoidal", see
    :func:`time_scaling`; RTB's ``ctraj``).  The joint motion is found by
    :func:`follow_poses` from ``q0``; ``poses`` holds the targets.  Raises ValueError for bad
    input and :class:`CartesianPathError` where the path cannot be followed.
    """
    T0, T1 = _target_matrix(pose0), _target_matrix(pose1)
    T = check_duration(duration)
    t = plan_times(times, T)
    s, _, _ = time_scaling(scaling, T, t)
    w = rotation_log(T0[:3, :3].T @ T1[:3, :3])
    angle = float(np.linalg.norm(w))
    axis = w / angle if angle > 0 else np.array([0.0, 0.0, 1.0])
    P = np.tile(np.eye(4), (t.shape[0], 1, 1))
    P[:, :3, :3] = T0[:3, :3] @ _rotations(axis, s * angle)
    P[:, :3, 3] = T0[:3, 3] + s[:, None] * (T1[:3, 3] - T0[:3, 3])
    return follow_poses(robot, t, P, q0, qd_max, qdd_max)


def cartesian_arc(robot: RobotParams, pose0: ArrayLike, centre: ArrayLike, axis: ArrayLike,
                  angle: float, duration: float, q0: ArrayLike, times: ArrayLike | None = None,
                  scaling: str = "quintic", *, turn_tool: bool = True,
                  qd_max: ArrayLike | None = None, qdd_max: ArrayLike | None = None) -> Trajectory:
    """Tool moves on the circular arc that turns ``pose0``'s position by ``angle`` rad about
    the line through ``centre`` (m, world) along ``axis`` (right hand), in ``duration`` s.
    With ``turn_tool`` the tool's orientation turns with the arc, else it stays that of
    ``pose0``.  Time law, IK following and errors as :func:`cartesian_line`.
    """
    T0 = _target_matrix(pose0)
    c = joint_vector("centre", centre, 3)
    k = joint_vector("axis", axis, 3)
    if np.linalg.norm(k) < 1e-12:
        raise ValueError(f"axis must be a non-zero vector, got {k!r}")
    k = k / np.linalg.norm(k)
    if not np.isfinite(angle) or angle == 0.0:
        raise ValueError(f"angle must be a non-zero finite number of radians, got {angle!r}")
    T = check_duration(duration)
    t = plan_times(times, T)
    s, _, _ = time_scaling(scaling, T, t)
    R = _rotations(k, s * angle)
    P = np.tile(np.eye(4), (t.shape[0], 1, 1))
    P[:, :3, :3] = R @ T0[:3, :3] if turn_tool else T0[:3, :3]
    P[:, :3, 3] = c + R @ (T0[:3, 3] - c)
    return follow_poses(robot, t, P, q0, qd_max, qdd_max)


def tool_poses(robot: RobotParams, traj: Trajectory) -> Trajectory:
    """``traj`` with ``poses`` set to the tool pose of every sample (forward kinematics)."""
    return Trajectory(traj.t, traj.q, traj.qd, traj.qdd, forward_kinematics(robot, traj.q), traj.marks)
