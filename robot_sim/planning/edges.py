"""Straight joint-space edges and sampled paths checked at the collision checker's
continuous resolution.

An edge from ``qa`` to ``qb`` (n,) is cut into ``m`` equal steps, the smallest count for
which no point of the arm moves more than the checker's resolution between two checked
configurations (the checker's per-joint sweep radii bound the motion:
|Δx| <= Σ_j r_j |Δq_j|).  That is the resolution of ``checker.path_is_free``, so an edge
this module calls free is free for it too.

The interpolated configurations of all edges asked about go to the checker in batched
calls: every ``COARSE_STRIDE``-th configuration is asked for its signed distance first
(one call), and the
configurations between two asked ones whose clearances add up to more than twice the
sweep between them are known free without being checked (no point of the arm, and no
pair of points, can close that gap); the others are bisected, a batched call per level
(see :meth:`CheckCounter.along`).  Nothing called free would be called colliding by
checking every configuration.  Joint values in rad or m; no Qt, no OpenGL.
"""
from __future__ import annotations

from typing import Protocol

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: Configurations between two first distance queries along an edge or a sampled path.
COARSE_STRIDE = 32


class Checker(Protocol):
    """What the planner uses of a collision checker (robot_sim.collision.CollisionChecker)."""

    padding: float  # m: a configuration closer than this to collision counts as colliding

    def in_collision(self, q: FloatArray) -> BoolArray | bool: ...

    def distance(self, q: FloatArray) -> FloatArray | object: ...

    def path_is_free(self, q_path: FloatArray) -> object: ...


def motion_bound(checker: Checker, lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, float]:
    """(r (n,), resolution [m]): no point of the arm moves more than Σ_j r_j |Δq_j| for a
    joint step Δq within [lo, hi], and ``checker.path_is_free`` checks configurations at
    most the resolution apart in that bound.  A checker may give both (``sweep_radii``,
    ``resolution``); a :class:`~robot_sim.collision.CollisionChecker` has them from its
    lever arms and its padding (or the default step without padding)."""
    radii = getattr(checker, "sweep_radii", None)
    if radii is not None:
        return np.asarray(radii, dtype=float), float(checker.resolution)
    from robot_sim.collision.path import DEFAULT_STEP, lever_arms

    arms = lever_arms(checker, np.asarray(lo, dtype=float)[None], np.asarray(hi, dtype=float)[None])[0]
    return arms, float(checker.padding) if checker.padding > 0.0 else DEFAULT_STEP


class CheckCounter:
    """A checker's batched queries, counted (``PathResult.checks``: configurations asked)."""

    def __init__(self, checker: Checker, lo: FloatArray, hi: FloatArray) -> None:
        self.checker = checker
        self.radii, self.resolution = motion_bound(checker, lo, hi)
        self.padding = float(getattr(checker, "padding", 0.0))
        self.count = 0

    def colliding(self, Q: FloatArray) -> BoolArray:
        """(M,) bool: which rows of ``Q`` (M, n) are in collision (one batched call)."""
        if Q.shape[0] == 0:
            return np.zeros(0, dtype=bool)
        self.count += Q.shape[0]
        return np.asarray(self.checker.in_collision(Q), dtype=bool).reshape(-1)

    def clearance(self, Q: FloatArray) -> FloatArray:
        """(M,) signed distance beyond the padding of the rows of ``Q`` (M, n) [m]."""
        if Q.shape[0] == 0:
            return np.zeros(0)
        self.count += Q.shape[0]
        d = np.asarray(self.checker.distance(Q), dtype=float).reshape(-1)
        return d - self.padding

    def steps(self, dq: FloatArray) -> NDArray[np.int64]:
        """Number of equal steps (>= 1) for joint displacements ``dq`` (..., n)."""
        sweep = np.abs(dq) @ self.radii
        return np.maximum(1, np.ceil(sweep / self.resolution - 1e-12)).astype(np.int64)

    def along(self, Q: FloatArray, knot: BoolArray, path: NDArray[np.int64] | None = None,
              first_only: bool = False) -> BoolArray:
        """(M,) bool: collisions along sampled paths ``Q`` (M, n), consecutive rows at most
        the resolution apart; ``path`` (M,) numbers the paths (one path when None), each
        starting and ending at a ``knot`` row.

        The knots are asked for their distances first; an
        interval between two asked rows is free if their clearances add up to more than
        twice the sweep between them (the gap cannot close: every point moves at most
        the sweep, every pair of points closes by at most twice it), otherwise its middle
        row is asked, level by level (one batched call per level), until every interval
        is proven free or has no row inside.  Rows of a path known to collide, or with
        ``first_only`` beyond its first collision, are not asked (False)."""
        hit = np.zeros(Q.shape[0], dtype=bool)
        path = np.zeros(Q.shape[0], dtype=np.int64) if path is None else path
        limit = np.full(int(path[-1]) + 1, Q.shape[0])  # per path: rows from here on are not asked
        sweep = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(Q, axis=0)) @ self.radii)])
        d = np.full(Q.shape[0], np.nan)

        def ask(rows: NDArray[np.int64]) -> None:
            d[rows] = self.clearance(Q[rows])
            hits = rows[d[rows] < 0.0]
            hit[hits] = True
            if first_only:
                np.minimum.at(limit, path[hits], hits)
            else:
                limit[path[hits]] = -1

        kn = np.flatnonzero(knot)
        ask(kn)
        a, b = kn[:-1], kn[1:]
        while a.size:
            keep = (b - a > 1) & (d[a] >= 0.0) & (a < limit[path[a]])
            keep &= d[a] + d[b] <= 2.0 * (sweep[b] - sweep[a])
            a, b = a[keep], b[keep]
            if not a.size:
                break
            mid = (a + b) // 2
            ask(mid)
            a, b = np.concatenate([a, mid]), np.concatenate([mid, b])
        return hit

    def _edge_rows(self, QA: FloatArray, QB: FloatArray) -> tuple[FloatArray, NDArray[np.int64], BoolArray]:
        """Configurations of the edges QA[e] → QB[e] (E, n), both ends included: (M, n),
        the edge of each row, and the knot rows (every COARSE_STRIDE-th and the ends)."""
        m = self.steps(QB - QA)
        edge = np.repeat(np.arange(QA.shape[0]), m + 1)
        start = np.concatenate([[0], np.cumsum(m + 1)[:-1]])
        k = np.arange(edge.shape[0]) - start[edge]
        frac = k / m[edge]
        knot = (k % COARSE_STRIDE == 0) | (k == m[edge])
        return QA[edge] + frac[:, None] * (QB[edge] - QA[edge]), edge, knot

    def first_collision(self, qa: FloatArray, qb: FloatArray) -> float | None:
        """Fraction in [0, 1] of the edge ``qa`` → ``qb`` at which its first colliding
        configuration sits, or None if the edge is free."""
        Q, _, knot = self._edge_rows(qa[None], qb[None])
        hit = np.flatnonzero(self.along(Q, knot, first_only=True))
        return float(hit[0] / (Q.shape[0] - 1)) if hit.size else None

    def edges_free(self, QA: FloatArray, QB: FloatArray) -> BoolArray:
        """(E,) bool: which edges ``QA[e]`` → ``QB[e]`` (E, n) are free, both ends included."""
        Q, edge, knot = self._edge_rows(QA, QB)
        free = np.ones(QA.shape[0], dtype=bool)
        free[edge[self.along(Q, knot, edge)]] = False
        return free
