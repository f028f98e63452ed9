"""Joint-space plans: quintic polynomial, trapezoidal velocity, via points with blends.

Private helper of :mod:`trajectory` (import from there).  All inputs in SI units (rad or m,
per second, per second squared); every plan is a :class:`Trajectory` sampled at ``times``
(1 kHz from 0 to the end when None).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from robot_sim.planning.trajectory import FloatArray, Trajectory, check_times, sample_times
from robot_sim.model.params import RobotParams


def joint_vector(name: str, value: ArrayLike, n: int | None = None) -> FloatArray:
    """``value`` as a finite (n,) float vector; a scalar is broadcast when n is given."""
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0 and n is not None:
        arr = np.full(n, float(arr))
    if arr.ndim != 1 or (n is not None and arr.shape[0] != n) or arr.size == 0:
        want = f"({n},)" if n is not None else "(n,)"
        raise ValueError(f"{name} must be a vector of shape {want}, got shape {arr.shape}")
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise ValueError(f"{name}[{bad[0]}] is {float(arr[bad[0]])!r}; expected a finite number")
    return arr


def positive_vector(name: str, value: ArrayLike, n: int) -> FloatArray:
    """A finite, strictly positive (n,) vector (scalar broadcast); ValueError otherwise."""
    arr = joint_vector(name, value, n)
    bad = np.flatnonzero(arr <= 0.0)
    if bad.size:
        raise ValueError(f"{name}[{bad[0]}] is {float(arr[bad[0]])!r}; expected a positive number")
    return arr


def check_duration(duration: float) -> float:
    """A finite positive duration [s]; ValueError otherwise."""
    d = float(duration)
    if not (np.isfinite(d) and d > 0.0):
        raise ValueError(f"duration must be a positive finite number of seconds, got {duration!r}")
    return d


def plan_times(times: ArrayLike | None, duration: float) -> FloatArray:
    """``times`` checked to be strictly increasing within [0, duration]; 1 kHz when None."""
    if times is None:
        return sample_times(duration)
    t = check_times(times)
    if t[0] < 0.0 or t[-1] > duration * (1 + 1e-12):
        raise ValueError(f"times must lie within [0, {duration!r}] s, got [{float(t[0])!r}, {float(t[-1])!r}]")
    return t


def check_in_limits(robot: RobotParams | None, q: FloatArray, what: str) -> None:
    """ValueError naming the configuration, the joint, its value and the limits if any q
    (n,) or (M, n) lies outside the robot's joint limits."""
    if robot is None:
        return
    Q = np.atleast_2d(q)
    if Q.shape[1] != robot.n_dofs:
        raise ValueError(f"{what} has {Q.shape[1]} joint values, {robot.name} has {robot.n_dofs} joints")
    out = (Q < robot.q_min - 1e-12) | (Q > robot.q_max + 1e-12)
    if out.any():
        k, j = (int(v) for v in np.argwhere(out)[0])
        where = f"{what}[{k}]" if q.ndim == 2 else what
        raise ValueError(
            f"{where}: joint {j + 1} = {Q[k, j]:.6g} is outside its limits "
            f"[{robot.q_min[j]:.6g}, {robot.q_max[j]:.6g}]"
        )


def quintic(
    q0: ArrayLike,
    q1: ArrayLike,
    duration: float,
    times: ArrayLike | None = None,
    *,
    qd0: ArrayLike = 0.0,
    qd1: ArrayLike = 0.0,
    qdd0: ArrayLike = 0.0,
    qdd1: ArrayLike = 0.0,
    robot: RobotParams | None = None,
) -> Trajectory:
    """Quintic polynomial from ``q0`` to ``q1`` in ``duration`` seconds (RTB's ``jtraj``).

    Each joint follows q(τ) = Σ c_k τ^k, k = 0..5, meeting position, velocity (``qd0``,
    ``qd1``) and acceleration (``qdd0``, ``qdd1``) at both ends (zero by default; scalars
    broadcast).  ``times`` must lie within [0, duration].  With ``robot`` the end points are
    checked against its joint limits.  ValueError for bad shapes, NaN, a non-positive
    duration or non-increasing times.
    """
    a = joint_vector("q0", q0)
    n = a.shape[0]
    b = joint_vector("q1", q1, n)
    v0, v1 = joint_vector("qd0", qd0, n), joint_vector("qd1", qd1, n)
    a0, a1 = joint_vector("qdd0", qdd0, n), joint_vector("qdd1", qdd1, n)
    T = check_duration(duration)
    check_in_limits(robot, a, "q0")
    check_in_limits(robot, b, "q1")
    t = plan_times(times, T)
    dq = b - a
    c = np.stack(
        [
            a,
            v0,
            a0 / 2,
            (20 * dq - (8 * v1 + 12 * v0) * T - (3 * a0 - a1) * T**2) / (2 * T**3),
            (-30 * dq + (14 * v1 + 16 * v0) * T + (3 * a0 - 2 * a1) * T**2) / (2 * T**4),
            (12 * dq - 6 * (v1 + v0) * T + (a1 - a0) * T**2) / (2 * T**5),
        ]
    )  # (6, n)
    P = t[:, None] ** np.arange(6)  # (N, 6)
    k = np.arange(6)
    q = P @ c
    qd = P[:, :5] @ (c[1:] * k[1:, None])
    qdd = P[:, :4] @ (c[2:] * (k[2:] * (k[2:] - 1))[:, None])
    return Trajectory(t, q, qd, qdd)


def _parabolic(
    q0: FloatArray, durations: FloatArray, accels: FloatArray, times: ArrayLike | None
) -> Trajectory:
    """Motion from rest at ``q0`` (n,) through phases of constant acceleration ``accels``
    (K, n) lasting ``durations`` (K,) s; sampled at ``times`` (1 kHz when None); times past
    the end hold the final state.  Knot times are marked."""
    knots = np.concatenate([[0.0], np.cumsum(durations)])
    n = q0.shape[0]
    qk, vk = np.empty((len(knots), n)), np.empty((len(knots), n))
    qk[0], vk[0] = q0, 0.0
    for k, (h, acc) in enumerate(zip(durations, accels)):
        qk[k + 1] = qk[k] + vk[k] * h + 0.5 * acc * h * h
        vk[k + 1] = vk[k] + acc * h
    t = sample_times(knots[-1]) if times is None else check_times(times)
    if t[0] < 0.0:
        raise ValueError(f"times must not be negative, got times[0] = {float(t[0])!r}")
    tc = np.minimum(t, knots[-1])
    i = np.clip(np.searchsorted(knots, tc, side="right") - 1, 0, len(durations) - 1)
    dt = (tc - knots[i])[:, None]
    acc = np.where((t <= knots[-1])[:, None], accels[i], 0.0)
    q = qk[i] + vk[i] * dt + 0.5 * accels[i] * dt * dt
    qd = vk[i] + accels[i] * dt
    return Trajectory(t, q, qd, acc)


def hold(q: ArrayLike, duration: float = 0.0, times: ArrayLike | None = None) -> Trajectory:
    """The arm at rest at ``q`` for ``duration`` seconds (a single sample when 0)."""
    a = joint_vector("q", q)
    if times is None:
        times = sample_times(check_duration(duration)) if duration else np.zeros(1)
    t = check_times(times)
    zeros = np.zeros((t.shape[0], a.shape[0]))
    return Trajectory(t, zeros + a, zeros, zeros)


def trapezoidal(
    q0: ArrayLike,
    q1: ArrayLike,
    v_max: ArrayLike,
    a_max: ArrayLike,
    times: ArrayLike | None = None,
    *,
    robot: RobotParams | None = None,
) -> Trajectory:
    """Trapezoidal velocity profile (linear segment with parabolic blends) from ``q0`` to
    ``q1``, as fast as the per-joint limits ``v_max`` [rad/s or m/s] and ``a_max`` [/s²]
    allow (scalars broadcast).

    All joints move along the straight line q0 + s (q1 − q0) with one time law s(t), so
    they start, cruise and finish together; the limit of each joint bounds s', s'' and the
    tightest one is met exactly (a triangle when there is no room to cruise).  ``times``
    past the end hold q1 at rest; None samples the motion at 1 kHz.  With ``robot`` the end
    points are checked against its joint limits.
    """
    a = joint_vector("q0", q0)
    n = a.shape[0]
    b = joint_vector("q1", q1, n)
    vmax, amax = positive_vector("v_max", v_max, n), positive_vector("a_max", a_max, n)
    check_in_limits(robot, a, "q0")
    check_in_limits(robot, b, "q1")
    dq = b - a
    dist = np.abs(dq)
    if not dist.any():
        return hold(a, times=times)
    moving = dist > 0
    vs = float(np.min(vmax[moving] / dist[moving]))  # s' limit
    as_ = float(np.min(amax[moving] / dist[moving]))  # s'' limit
    if vs * vs / as_ >= 1.0:  # no room to reach vs: triangle
        tb = float(np.sqrt(1.0 / as_))
        durations, svals = np.array([tb, tb]), np.array([as_, -as_])
    else:
        tb = vs / as_
        durations, svals = np.array([tb, 1.0 / vs - tb, tb]), np.array([as_, 0.0, -as_])
    return _parabolic(a, durations, svals[:, None] * dq, times)


def via_points(
    qs: ArrayLike,
    v_max: ArrayLike,
    a_max: ArrayLike,
    blend: float | None = None,
    times: ArrayLike | None = None,
    *,
    robot: RobotParams | None = None,
) -> Trajectory:
    """Multi-segment path from ``qs[0]`` through every via point to ``qs[-1]``, passing
    **through** each via point exactly (unlike RTB's ``mstraj``, whose blends cut corners).

    Each segment arrives at its via point at constant velocity; the blend to the next
    segment's velocity (constant acceleration over ``blend`` seconds) starts there, and the
    next segment's cruise velocity is chosen so that it reaches its own via point on time.
    The path starts and ends at rest.  Nominal segment durations come from ``v_max`` (the
    slowest joint at full speed) and the blend from ``a_max`` (time to reach full speed)
    unless given; the whole motion is then slowed uniformly, if needed, until no joint
    exceeds ``v_max`` or ``a_max``.  The times each via point is passed are in ``marks``
    ("via 1", ...) and are samples of the default time grid.

    ``qs`` is (M, n), M >= 2.  With ``robot`` every via point is checked against its joint
    limits (ValueError naming the via point and joint).
    """
    Q = np.asarray(qs, dtype=float)
    if Q.ndim != 2 or Q.shape[0] < 2:
        raise ValueError(f"qs must have shape (M >= 2, n), got {Q.shape}")
    bad = np.argwhere(~np.isfinite(Q))
    if bad.size:
        raise ValueError(f"qs[{bad[0][0]}] joint {bad[0][1] + 1} is {float(Q[tuple(bad[0])])!r}; expected a finite number")
    n = Q.shape[1]
    vmax, amax = positive_vector("v_max", v_max, n), positive_vector("a_max", a_max, n)
    check_in_limits(robot, Q, "qs")
    if blend is None:
        tb = float(np.max(vmax / amax))
    else:
        tb = float(blend)
        if not (np.isfinite(tb) and tb > 0.0):
            raise ValueError(f"blend must be a positive number of seconds, got {blend!r}")
    deltas = np.diff(Q, axis=0)  # (S, n)
    n_seg = deltas.shape[0]
    seg_T = np.maximum(np.max(np.abs(deltas) / vmax, axis=1) + tb / 2, tb)
    seg_T[-1] = max(seg_T[-1] + tb / 2, 2 * tb)
    durations, accels, u = [], [], np.zeros(n)
    for k in range(n_seg):
        last = k == n_seg - 1
        cruise_T = seg_T[k] - (2 * tb if last else tb)
        c = (deltas[k] - u * tb / 2) / (seg_T[k] - (tb if last else tb / 2))
        durations += [tb, cruise_T]
        accels += [(c - u) / tb, np.zeros(n)]
        if last:
            durations.append(tb)
            accels.append(-c / tb)
        u = c
    durations, accels = np.array(durations), np.array(accels)
    # Peak speed is at a knot (velocity is piecewise linear); slow down uniformly if needed.
    vel = np.cumsum(accels * durations[:, None], axis=0)
    scale = max(1.0, float(np.max(np.abs(vel) / vmax)), float(np.sqrt(np.max(np.abs(accels) / amax))))
    durations, accels = durations * scale, accels / scale**2
    via_t = np.cumsum(seg_T * scale)[:-1]
    if times is None:
        total = float(np.sum(durations))
        times = np.union1d(sample_times(total), via_t)
        times = times[np.concatenate([[True], np.diff(times) > 1e-9])]
    traj = _parabolic(Q[0], durations, accels, times)
    marks = tuple((float(tm), f"via {k + 1}") for k, tm in enumerate(via_t))
    return Trajectory(traj.t, traj.q, traj.qd, traj.qdd, None, marks)
