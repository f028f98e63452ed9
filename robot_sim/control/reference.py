"""What a simulation's controller follows: a joint reference, a task (tool) reference, or both.

* A **joint reference** gives ``(q_des, qd_des, qdd_des)`` (n,) each at time t [s].
* A **task reference** gives ``(pose_d, twist_d, accel_d)``: the tool's desired world pose
  (4, 4) [m] (or a ``HomogeneousTransform``), twist (6,) [m/s; rad/s] and acceleration (6,)
  [m/s²; rad/s²]; one made from joints adds them as a fourth value (q, q̇, q̈).

:class:`Reference` wraps what a user passes as ``Simulation(reference=...)``: a callable
of either kind (told apart by what it returns at t = 0) or a ``Trajectory``, which is a
joint reference and, when it carries ``poses``, also a task reference (:class:`PoseTrack`).
A task-space controller given only a joint reference follows the tool motion of the
desired joints (:func:`task_from_joints`); a joint-space controller cannot follow a pose.

No Qt, no OpenGL.
"""
from __future__ import annotations

from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from robot_sim.control.task_error import rotation_logs
from robot_sim.kinematics import tool_kinematics
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotParams
from robot_sim.transforms import rot_from_angle_axis

FloatArray = NDArray[np.float64]
#: Desired values: (q, qd, qdd), (pose, twist, accel), or (pose, twist, accel, (q, qd, qdd)).
Desired = tuple


def task_from_joints(robot: RobotParams, q: FloatArray, qd: FloatArray, qdd: FloatArray) -> tuple:
    """The tool motion of the joint motion (q, q̇, q̈) (n,) or (N, n): pose T(q), twist J q̇
    and acceleration J q̈ + J̇ q̇ (world frame; (4, 4), (6,), (6,) or one per row), followed
    by the joint motion itself (the posture a task-space controller then tracks in its
    null space)."""
    T, J, jd = tool_kinematics(robot, q, qd)
    twist = np.matmul(J, qd[..., None])[..., 0]
    return T, twist, np.matmul(J, qdd[..., None])[..., 0] + jd, (q, qd, qdd)


def is_task(values: tuple, n: int) -> bool:
    """True if ``values`` (three arrays, one or N of each) are task values (pose
    (..., 4, 4), twist, acceleration) rather than joint values (q, q̇, q̈) (..., n) of an
    n-joint arm: by the pose's shape, and for n = 4, where N joint rows of 4 look like a
    pose, by the twist's 6 values."""
    pose_like = np.shape(getattr(values[0], "mat", values[0]))[-2:] == (4, 4)
    return pose_like and (n != 4 or np.shape(values[1])[-1:] != (4,))


def fixed_pose(pose: Any) -> Callable[[float], Desired]:
    """The task reference that holds the world pose ``pose`` (4, 4) at rest."""
    held = np.array(getattr(pose, "mat", pose), dtype=float)
    rest = np.zeros(6)
    return lambda _time: (held, rest, rest)


def _as_task(value: Any) -> Desired:
    """A task triple as arrays; ValueError naming what is wrong."""
    pose, twist, accel = value
    pose = np.asarray(getattr(pose, "mat", pose), dtype=float)
    twist, accel = np.asarray(twist, dtype=float), np.asarray(accel, dtype=float)
    if pose.shape != (4, 4) or twist.shape != (6,) or accel.shape != (6,):
        raise ValueError(
            f"a task reference returns (pose (4, 4), twist (6,), acceleration (6,)), got shapes "
            f"{pose.shape}, {twist.shape}, {accel.shape}"
        )
    return pose, twist, accel


class PoseTrack:
    """The task reference of sampled tool poses ``poses`` (K, 4, 4) at times ``t`` (K,) [s].

    Velocities and accelerations at the samples come from central differences of the
    samples (one-sided at the ends).  Between samples the position is the cubic Hermite
    interpolant of positions and velocities, the rotation turns at constant rate from one
    sample to the next, and the twist's angular part and the acceleration are linear in
    time.  Before the first and after the last sample the pose holds, at rest.
    """

    def __init__(self, t: FloatArray, poses: FloatArray) -> None:
        self.t = np.asarray(t, dtype=float)
        self.p = np.asarray(poses, dtype=float)[:, :3, 3]
        self.R = np.asarray(poses, dtype=float)[:, :3, :3]
        K = self.t.shape[0]
        self.v = np.zeros((K, 3))
        self.w = np.zeros((K, 3))
        self.a = np.zeros((K, 6))
        if K > 1:
            self.v = np.gradient(self.p, self.t, axis=0)
            step = rotation_logs(np.matmul(self.R[1:], self.R[:-1].transpose(0, 2, 1)))  # (K-1, 3)
            rate = step / np.diff(self.t)[:, None]
            self.w = np.concatenate([rate[:1], 0.5 * (rate[1:] + rate[:-1]), rate[-1:]])
            self.step = step
            self.a = np.gradient(np.concatenate([self.v, self.w], axis=1), self.t, axis=0)

    def __call__(self, time: float) -> Desired:
        t, K = self.t, self.t.shape[0]
        pose = np.eye(4)
        if K == 1 or time <= t[0] or time >= t[-1]:
            i = 0 if (K == 1 or time <= t[0]) else K - 1
            pose[:3, :3], pose[:3, 3] = self.R[i], self.p[i]
            return pose, np.zeros(6), np.zeros(6)
        i = min(int(np.searchsorted(t, time, side="right")) - 1, K - 2)
        h = t[i + 1] - t[i]
        s = (time - t[i]) / h
        p0, p1, v0, v1 = self.p[i], self.p[i + 1], self.v[i] * h, self.v[i + 1] * h
        s2, s3 = s * s, s * s * s
        pose[:3, 3] = (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * v0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * v1
        vel = ((6 * s2 - 6 * s) * (p0 - p1) + (3 * s2 - 4 * s + 1) * v0 + (3 * s2 - 2 * s) * v1) / h
        turn = self.step[i] * s
        angle = float(np.linalg.norm(turn))
        rot = rot_from_angle_axis(angle, turn / angle) if angle > 0.0 else np.eye(3)
        pose[:3, :3] = rot @ self.R[i]
        twist = np.concatenate([vel, (1 - s) * self.w[i] + s * self.w[i + 1]])
        return pose, twist, (1 - s) * self.a[i] + s * self.a[i + 1]


class Reference:
    """A simulation's reference: :attr:`joint` and/or :attr:`task` callables of time [s].

    ``source`` is a callable (joint or task, by what it returns at t = 0) or a trajectory
    (an object with ``evaluate(t)`` and ``t``/``poses`` like ``Trajectory``).  ValueError,
    naming what was expected, for anything else or a callable whose values have the wrong
    shapes.
    """

    def __init__(self, robot: RobotParams, source: Any) -> None:
        self.robot = robot
        self.joint: Callable[[float], Desired] | None = None
        self.task: Callable[[float], Desired] | None = None
        n = robot.n_dofs
        if hasattr(source, "evaluate") and hasattr(source, "poses"):
            if source.q.shape[1] != n:
                raise ValueError(f"reference trajectory has {source.q.shape[1]} joints, the robot {n}")
            self.joint = source.evaluate
            if source.poses is not None:
                self.task = PoseTrack(source.t, source.poses)
            return
        if not callable(source):
            raise ValueError(f"reference must be a callable of time or a Trajectory, got {clip_repr(source)}")
        first = source(0.0)
        try:
            items = tuple(first)
        except TypeError:
            items = ()
        if len(items) != 3:
            raise ValueError(f"reference(t) must return three values (q, qd, qdd) or (pose, twist, accel), got {clip_repr(first)}")
        if np.shape(getattr(items[0], "mat", items[0])) == (4, 4):
            _as_task(items)
            self.task = lambda time: _as_task(source(time))
        else:
            shapes = [np.shape(x) for x in items]
            if shapes != [(n,)] * 3:
                raise ValueError(f"a joint reference returns (q, qd, qdd) of shape ({n},) each, got shapes {shapes}")
            self.joint = source

    def for_space(self, space: str) -> Callable[[float], Desired]:
        """The reference for a controller of ``space`` ("joint" or "task"); a task
        controller given only joints follows their tool motion.  ValueError if a joint
        controller is given only a task reference."""
        if space == "task":
            if self.task is not None:
                return self.task
            joint = self.joint
            assert joint is not None
            return lambda time: task_from_joints(self.robot, *joint(time))
        if self.joint is None:
            raise ValueError(
                "a task-space reference (tool poses) needs a task-space controller (osc, impedance, resolved_rate)"
            )
        return self.joint
