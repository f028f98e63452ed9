"""A small collision checker for the planning tests, written independently of
robot_sim.collision: the arm as balls along its DH segments (frame i-1 → the DH corner →
frame i, then frame n → tool), obstacles as axis-aligned boxes and balls.

It offers what the planner uses of a checker: batched ``in_collision``, ``path_is_free``
at a resolution, ``sweep_radii`` (a bound on how far any ball centre moves per unit of
joint motion, from the DH lengths) and ``resolution``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from robot_sim.kinematics import forward_kinematics
from robot_sim.model.params import RobotParams

BALL_RADIUS = 0.04


@dataclass
class BallArmChecker:
    robot: RobotParams
    boxes: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)  # (lo (3,), hi (3,)) world
    balls: list[tuple[np.ndarray, float]] = field(default_factory=list)  # (centre (3,), radius)
    radius: float = BALL_RADIUS
    resolution: float = 1e-3
    skip_links: int = 1  # the first segments (at the base) are not checked

    def __post_init__(self) -> None:
        r = self.robot
        lengths = np.abs(r.dh_a) + np.abs(r.dh_d)
        lengths = np.where(r.is_revolute, lengths, np.abs(r.dh_a) + np.maximum(np.abs(r.q_min), np.abs(r.q_max)))
        tool = float(np.linalg.norm(r.tool_tf.t()))
        beyond = np.cumsum(lengths[::-1])[::-1] + tool + self.radius
        self.sweep_radii = np.where(r.is_revolute, beyond, 1.0)

    def centres(self, Q: np.ndarray) -> np.ndarray:
        """(N, P, 3) ball centres at configurations Q (N, n)."""
        F = forward_kinematics(self.robot, Q, all_frames=True)
        o, z = F[:, :, :3, 3], F[:, :, :3, 2]
        n = self.robot.n_dofs
        pts = []
        for i in range(1, n + 2):
            a, b = o[:, i - 1], o[:, i]
            if i <= n:
                if self.robot.is_modified:
                    corner = b - z[:, i] * np.sum((b - a) * z[:, i], axis=1, keepdims=True)
                else:
                    corner = a + z[:, i - 1] * np.sum((b - a) * z[:, i - 1], axis=1, keepdims=True)
                legs = [(a, corner), (corner, b)]
            else:
                legs = [(a, b)]
            if i <= self.skip_links:
                continue
            for p0, p1 in legs:
                m = int(np.ceil(np.max(np.linalg.norm(p1 - p0, axis=1)) / self.radius)) + 1
                f = np.linspace(0.0, 1.0, m)
                pts.append(p0[:, None] + f[None, :, None] * (p1 - p0)[:, None])
        return np.concatenate(pts, axis=1)

    def clearance(self, Q: np.ndarray) -> np.ndarray:
        """(N,) smallest signed distance between the arm's balls and the obstacles [m]."""
        Q = np.atleast_2d(Q)
        C = self.centres(Q)
        best = np.full(Q.shape[0], np.inf)
        for lo, hi in self.boxes:
            d = np.linalg.norm(C - np.clip(C, lo, hi), axis=2)
            inside = np.all((C > lo) & (C < hi), axis=2)
            depth = np.min(np.minimum(C - lo, hi - C), axis=2)
            best = np.minimum(best, np.min(np.where(inside, -depth, d), axis=1))
        for c, rad in self.balls:
            best = np.minimum(best, np.min(np.linalg.norm(C - c, axis=2), axis=1) - rad)
        return best - self.radius

    def distance(self, q):
        Q = np.asarray(q, dtype=float)
        d = self.clearance(Q)
        return float(d[0]) if Q.ndim == 1 else d

    def in_collision(self, q):
        Q = np.asarray(q, dtype=float)
        hit = self.clearance(Q) < 0.0
        return bool(hit[0]) if Q.ndim == 1 else hit

    def dense(self, path: np.ndarray) -> np.ndarray:
        """Every configuration ``path_is_free`` checks along the polyline ``path`` (K, n)."""
        P = np.asarray(path, dtype=float)
        out = [P[:1]]
        for a, b in zip(P[:-1], P[1:]):
            m = max(1, int(np.ceil(np.abs(b - a) @ self.sweep_radii / self.resolution)))
            out.append(a + (np.arange(1, m + 1) / m)[:, None] * (b - a))
        return np.concatenate(out)

    def path_is_free(self, q_path) -> bool:
        return not bool(np.any(self.in_collision(self.dense(q_path))))
