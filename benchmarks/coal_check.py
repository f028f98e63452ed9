"""Independent check of planned paths with coal (the FCL fork Pinocchio uses; a
benchmark-only oracle, never a dependency of the suite).

A joint path is sampled so finely that no point of any link shape moves more than
STEP metres between two samples, measured from the link frames' actual motion
(forward kinematics: origin displacement plus rotation angle times the shape's
farthest point), not from the planner's bound; at every sample, coal's distance between
every pair the CollisionChecker checks (the arm's shapes from ``checker.shapes(q)``,
the world's obstacles as coal shapes) must be at least the checker's padding.
"""
from __future__ import annotations

import numpy as np

try:
    import coal
except ImportError:  # an optional oracle: without it only the dense sampling works
    coal = None

from robot_sim.kinematics import forward_kinematics
from robot_sim.model.shapes import Box, Capsule, Cylinder, HalfSpace, Sphere

STEP = 1e-3  # m


def _geometry(shape):
    if isinstance(shape, Box):
        return coal.Box(*np.asarray(shape.size, dtype=float))
    if isinstance(shape, Sphere):
        return coal.Sphere(float(shape.radius))
    if isinstance(shape, Cylinder):
        return coal.Cylinder(float(shape.radius), float(shape.length))
    if isinstance(shape, Capsule):
        return coal.Capsule(float(shape.radius), float(shape.length))
    if isinstance(shape, HalfSpace):
        return coal.Halfspace(np.asarray(shape.normal, dtype=float), float(shape.offset))
    raise TypeError(f"coal check: no coal shape for {type(shape).__name__}")


def _transform(shape) -> coal.Transform3s:
    if isinstance(shape, HalfSpace):
        return coal.Transform3s(np.eye(3), np.zeros(3))
    T = np.asarray(shape.pose, dtype=float)
    return coal.Transform3s(T[:3, :3].copy(), T[:3, 3].copy())


def _extent(shape) -> float:
    """Distance from the shape's pose origin to its farthest point [m]."""
    if isinstance(shape, Box):
        return float(np.linalg.norm(shape.size) / 2)
    if isinstance(shape, Sphere):
        return float(shape.radius)
    if isinstance(shape, Cylinder):
        return float(np.hypot(shape.radius, shape.length / 2))
    return float(shape.radius + shape.length / 2)


class CoalCheck:
    """Minimum coal distance over the checker's pairs, and a 1 mm path check."""

    def __init__(self, checker) -> None:  # noqa: ANN001
        self.checker = checker
        self.robot = checker.robot
        index = {name: k for k, name in enumerate(self.robot.link_names)}
        q0 = np.asarray(self.robot.q_home, dtype=float)
        shapes = checker.shapes(q0)
        self.owner = [name for name, _ in shapes]
        self.link = np.array([index[name] for name in self.owner])
        frames = forward_kinematics(self.robot, q0, all_frames=True)
        # farthest shape point from its link frame's origin, per shape
        self.reach = np.array([
            np.linalg.norm(np.asarray(s.pose)[:3, 3] - frames[k][:3, 3]) + _extent(s)
            for k, (_, s) in zip(self.link, shapes)])
        if coal is None:
            return
        self.geom = [_geometry(s) for _, s in shapes]
        self.obstacles = [(name, _geometry(s), _transform(s)) for name, s in checker.world.obstacles]
        checked = {frozenset(p) for p in checker.checked_pairs}
        robot_names = set(self.owner)
        self.self_pairs = [(i, j) for i in range(len(shapes)) for j in range(i + 1, len(shapes))
                           if frozenset((self.owner[i], self.owner[j])) in checked]
        self.world_pairs = [(i, k) for i in range(len(shapes)) for k, (name, _, _) in enumerate(self.obstacles)
                            if name not in robot_names and frozenset((self.owner[i], name)) in checked]

    def min_distance(self, q: np.ndarray) -> float:
        shapes = self.checker.shapes(q)
        tf = [_transform(s) for _, s in shapes]
        best = np.inf
        req = coal.DistanceRequest()
        for i, j in self.self_pairs:
            res = coal.DistanceResult()
            best = min(best, coal.distance(self.geom[i], tf[i], self.geom[j], tf[j], req, res))
        for i, k in self.world_pairs:
            res = coal.DistanceResult()
            _, geom, T = self.obstacles[k]
            best = min(best, coal.distance(self.geom[i], tf[i], geom, T, req, res))
        return float(best)

    def dense(self, path: np.ndarray) -> np.ndarray:
        """The polyline through ``path`` (K, n) sampled so that no shape point moves more
        than STEP between samples (measured, not bounded)."""
        out = [path[:1]]
        for a, b in zip(path[:-1], path[1:]):
            m = 8
            while True:
                Q = a + (np.arange(m + 1) / m)[:, None] * (b - a)
                F = forward_kinematics(self.robot, Q, all_frames=True)[:, self.link]
                move = np.linalg.norm(np.diff(F[:, :, :3, 3], axis=0), axis=2)
                R0, R1 = F[:-1, :, :3, :3], F[1:, :, :3, :3]
                cos = (np.einsum("mkij,mkij->mk", R0, R1) - 1.0) / 2.0
                angle = np.arccos(np.clip(cos, -1.0, 1.0))
                if np.max(move + angle * self.reach) <= STEP:
                    break
                m *= 2
            out.append(Q[1:])
        return np.concatenate(out)

    def path_free(self, path: np.ndarray) -> tuple[bool, float]:
        """(free, smallest distance) along the polyline through ``path`` at 1 mm."""
        Q = self.dense(np.asarray(path, dtype=float))
        d = min(self.min_distance(q) for q in Q)
        return d >= self.checker.padding, d
