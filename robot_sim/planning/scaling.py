"""Trajectories: joint-space and Cartesian plans as sampled, evaluable values.

* :class:`Trajectory` — ``t`` (N,), ``q``/``qd``/``qdd`` (N, n), optional tool ``poses``
  (N, 4, 4); ``evaluate(times)`` at any time(s), batched; ``to_csv``/``from_csv``.
* Joint space: :func:`quintic` (RTB ``jtraj``), :func:`trapezoidal` (linear segment with
  parabolic blends, joints synchronised), :func:`via_points` (through via points, blended).
* Cartesian: :func:`cartesian_line` (straight line + SLERP, RTB ``ctraj``) and
  :func:`cartesian_arc`, followed by IK sample by sample (:func:`follow_poses`), which
  raises :class:`CartesianPathError` naming the sample, pose and reason where it fails.
* :func:`hold` keeps the arm at rest for a while (a gripper closing).
* :func:`scale_to_limits` slows a trajectory uniformly until it respects joint speed,
  acceleration and effort limits.

SI units: seconds, radians or metres per joint; ``times=None`` samples at 1 kHz.  No Qt,
no OpenGL.  Bad input raises ValueError naming the argument, where and what is accepted.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.planning.cartesian import (
    SCALINGS,
    CartesianPathError,
    cartesian_arc,
    cartesian_line,
    follow_poses,
    qd_limits,
    time_scaling,
    tool_poses,
)
from robot_sim.planning.profiles import check_in_limits, hold, quintic, trapezoidal, via_points
from robot_sim.planning.trajectory import DEFAULT_RATE, Trajectory, check_times, sample_times
from robot_sim.model.params import RobotParams

__all__ = [
    "DEFAULT_RATE", "SCALINGS", "CartesianPathError", "Trajectory", "cartesian_arc", "cartesian_line",
    "check_in_limits", "check_times", "follow_poses", "hold", "qd_limits", "quintic", "sample_times",
    "scale_to_limits", "time_scaling", "tool_poses", "trapezoidal", "via_points",
]


def scale_to_limits(
    traj: Trajectory,
    qd_max: ArrayLike | None = None,
    qdd_max: ArrayLike | None = None,
    *,
    robot: RobotParams | None = None,
    effort: bool = False,
) -> Trajectory:
    """``traj`` slowed uniformly (t → λt, q̇ → q̇/λ, q̈ → q̈/λ², λ >= 1, the smallest that
    works) so that |q̇| <= ``qd_max``, |q̈| <= ``qdd_max`` and, with ``effort``, the joint
    torques of :func:`dynamics.inverse_dynamics` (friction included) stay within the
    robot's drive effort limits.

    Limits (n,) or scalars; ``qd_max`` None means the robot's (:func:`qd_limits`) when a
    robot is given, else no limit.  Speed and acceleration give λ in closed form; effort
    is searched (doubling, then bisection to 1e-6 relative) because friction does not
    scale with 1/λ².  Poses whose torque stays above a limit however slow the motion
    (gravity, Coulomb friction) raise ValueError naming the sample and the joint.  The path
    and the samples stay; only their times change.
    """
    n = traj.n_dofs
    lam = 1.0
    if qd_max is None and robot is not None:
        qd_max = qd_limits(robot)
    if qd_max is not None:
        vmax = np.broadcast_to(np.asarray(qd_max, dtype=float), (n,))
        lam = max(lam, float(np.max(np.abs(traj.qd) / vmax)))
    if qdd_max is not None:
        amax = np.broadcast_to(np.asarray(qdd_max, dtype=float), (n,))
        lam = max(lam, float(np.sqrt(np.max(np.abs(traj.qdd) / amax))))
    if effort:
        lam = _effort_scale(traj, robot, lam)
    return _retimed(traj, lam)


def _retimed(traj: Trajectory, lam: float) -> Trajectory:
    t = traj.t[0] + (traj.t - traj.t[0]) * lam
    marks = tuple((traj.t[0] + (tm - traj.t[0]) * lam, m) for tm, m in traj.marks)
    return Trajectory(t, traj.q, traj.qd / lam, traj.qdd / lam**2, traj.poses, marks)


#: Slowest uniform time scaling the effort search tries before giving up.
MAX_EFFORT_SCALE = 1e3


def _effort_scale(traj: Trajectory, robot: RobotParams | None, lam: float) -> float:
    """Smallest λ >= ``lam`` whose inverse-dynamics torques stay within the effort limits."""
    if robot is None:
        raise ValueError("effort=True needs the robot (its dynamics and effort limits)")
    from robot_sim import dynamics  # imported only when effort limits are asked for

    drives = robot.drives
    limit = np.full(traj.n_dofs, np.inf) if drives is None else np.asarray(drives.effort_limit, dtype=float)

    def excess(scale: float) -> NDArray[np.float64]:
        return np.abs(dynamics.inverse_dynamics(robot, traj.q, traj.qd / scale, traj.qdd / scale**2)) / limit

    if np.max(excess(lam)) <= 1.0:
        return lam
    hi = lam
    while np.max(excess(hi)) > 1.0:
        if hi >= MAX_EFFORT_SCALE:
            k, j = (int(v) for v in np.unravel_index(np.argmax(excess(hi)), traj.q.shape))
            raise ValueError(
                f"sample {k} (t = {traj.t[k]:.4f} s): joint {j + 1} needs more than its effort limit "
                f"{limit[j]:.4g} even {MAX_EFFORT_SCALE:g} times slower (gravity or friction alone)"
            )
        hi *= 2.0
    lo = hi / 2.0 if hi > lam else lam
    while hi - lo > 1e-6 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if np.max(excess(mid)) <= 1.0 else (mid, hi)
    return hi
