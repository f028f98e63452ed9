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
from numpy.typing import ArrayLike

from _cartesian_path import (
    SCALINGS,
    CartesianPathError,
    cartesian_arc,
    cartesian_line,
    follow_poses,
    qd_limits,
    time_scaling,
    tool_poses,
)
from _joint_profiles import check_in_limits, hold, quintic, trapezoidal, via_points
from _traj_value import DEFAULT_RATE, Trajectory, check_times, sample_times
from robot_defs import RobotParams

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
    torques of :func:`dynamics.inverse_dynamics` stay within the robot's effort limits.

    Limits (n,) or scalars; None means the robot's (``qd_limits`` for speed, drive limits
    for effort) or no limit.  The torque τ(λ) = g + (τ − g)/λ² (gravity does not scale), so
    λ follows in closed form per sample; a pose whose gravity torque alone exceeds a limit
    raises ValueError naming the sample and the joint.  The path and the samples are the
    same; only their times change.
    """
    n = traj.n_dofs
    lam2 = 1.0
    if qd_max is None and robot is not None:
        qd_max = qd_limits(robot)
    if qd_max is not None:
        vmax = np.broadcast_to(np.asarray(qd_max, dtype=float), (n,))
        lam2 = max(lam2, float(np.max(np.abs(traj.qd) / vmax)) ** 2)
    if qdd_max is not None:
        amax = np.broadcast_to(np.asarray(qdd_max, dtype=float), (n,))
        lam2 = max(lam2, float(np.max(np.abs(traj.qdd) / amax)))
    if effort:
        lam2 = max(lam2, _effort_scale(traj, robot))
    lam = float(np.sqrt(lam2))
    t = traj.t[0] + (traj.t - traj.t[0]) * lam
    marks = tuple((traj.t[0] + (tm - traj.t[0]) * lam, m) for tm, m in traj.marks)
    return Trajectory(t, traj.q, traj.qd / lam, traj.qdd / lam2, traj.poses, marks)


def _effort_scale(traj: Trajectory, robot: RobotParams | None) -> float:
    """Smallest λ² that keeps inverse-dynamics torques within the effort limits."""
    if robot is None:
        raise ValueError("effort=True needs the robot (its dynamics and effort limits)")
    import dynamics  # only needed here; absent until the dynamics module exists

    drives = getattr(robot, "drives", None)
    limit = np.full(traj.n_dofs, np.inf) if drives is None else np.asarray(drives.effort_limit, dtype=float)
    zeros = np.zeros_like(traj.q)
    tau = dynamics.inverse_dynamics(robot, traj.q, traj.qd, traj.qdd)
    g = dynamics.inverse_dynamics(robot, traj.q, zeros, zeros)
    over = np.abs(g) > limit
    if over.any():
        k, j = (int(v) for v in np.argwhere(over)[0])
        raise ValueError(
            f"sample {k} (t = {traj.t[k]:.4f} s): gravity alone needs {g[k, j]:.4g} N·m at joint {j + 1}, "
            f"above its effort limit {limit[j]:.4g}; no time scaling can fix that"
        )
    r = tau - g
    with np.errstate(divide="ignore", invalid="ignore"):
        need = np.where(r > 0, r / (limit - g), np.where(r < 0, -r / (limit + g), 0.0))
    need = np.where(np.isfinite(limit), need, 0.0)
    return float(np.max(need, initial=1.0))
