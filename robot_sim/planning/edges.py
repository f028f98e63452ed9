"""Straight joint-space edges and sampled paths checked at the collision checker's
continuous resolution.

The checker's lever arms r_j bound the motion of every point of the arm: at most
Σ_j r_j |Δq_j| for a joint step Δq.  ``checker.path_is_free`` checks configurations no
more than its resolution apart in that bound; an edge this module calls free is free for
it too.

Configurations are asked for their signed distances in batches: first every
``COARSE_STRIDE``-th of an edge, then, level by level (one batched call per level), the
middle of every stretch between two asked configurations that their clearances do not
prove free.  A stretch is proven free when, for the arm against the world, the
clearances at its ends add up to more than the motion bound between them (no point can
close the gap), and, for the arm against itself, to more than the bound of the joints
between the two links of each checked pair (their relative motion).  Nothing called free
would be called colliding by checking every configuration at the resolution.  Joint
values in rad or m; no Qt, no OpenGL.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Protocol

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
Rows = NDArray[np.int64]

#: Configurations between two first distance queries along an edge or a sampled path.
COARSE_STRIDE = 64


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


@dataclass(frozen=True)
class _Part:
    """One group of checked pairs: its batched distance and the bound on how much its
    pairs can close for joint steps (M, n) -> (M,)."""

    distance: Callable[[FloatArray], FloatArray]
    closing: Callable[[FloatArray], FloatArray]


def _parts(checker: Checker, radii: FloatArray, bounds: tuple[FloatArray, FloatArray]) -> list[_Part]:
    """The arm against the world (each point moves at most its bound) and, for a
    CollisionChecker that checks self-collision, the arm against itself (a pair of links
    i < j closes at most by joints i+1..j times their lever arms for link j's shapes), each asked of a checker of its
    own kind; a checker with ``members`` as the groups of its members; another checker as
    one group whose pairs may close by twice the bound."""
    def world(dq: FloatArray) -> FloatArray:
        return np.abs(dq) @ radii

    members = getattr(checker, "members", None)
    if members is not None:  # a checker made of checkers (robot_sim.planning.carrying)
        return [part for member in members for part in _parts(member, radii, bounds)]
    if not all(hasattr(checker, key) for key in ("robot", "world", "self_collision")):
        return [_Part(checker.distance, lambda dq: 2.0 * world(dq))]
    robot, make = checker.robot, type(checker)
    outer = make(robot, checker.world, self_collision=False, padding=checker.padding)
    parts = [_Part(outer.distance, world)]
    if checker.self_collision:
        from robot_sim.collision.path import link_lever_arms

        own = make(robot, type(checker.world)(floor=False), self_collision=True, padding=checker.padding)
        index = {name: k for k, name in enumerate(robot.link_names)}
        pairs = sorted({tuple(sorted((index[a], index[b]))) for a, b in own.checked_pairs})
        if pairs:
            lo, hi = bounds
            arms = link_lever_arms(own, np.asarray(lo, dtype=float)[None], np.asarray(hi, dtype=float)[None])[0]
            # pair (i, j), i < j: link j moves against link i by the joints i+1..j only
            A = np.array([np.where(np.arange(robot.n_dofs) >= i, arms[j], 0.0) for i, j in pairs])

            def relative(dq: FloatArray) -> FloatArray:
                return np.max(np.abs(dq) @ A.T, axis=1)

            parts.append(_Part(own.distance, relative))
    return parts


class CheckCounter:
    """A checker's batched queries, counted (``PathResult.checks``: configurations asked)."""

    def __init__(self, checker: Checker, lo: FloatArray, hi: FloatArray) -> None:
        self.checker = checker
        self.radii, self.resolution = motion_bound(checker, lo, hi)
        self.padding = float(getattr(checker, "padding", 0.0))
        self.parts = _parts(checker, self.radii, (lo, hi))
        self.count = 0

    def colliding(self, Q: FloatArray) -> BoolArray:
        """(M,) bool: which rows of ``Q`` (M, n) are in collision (one batched call)."""
        if Q.shape[0] == 0:
            return np.zeros(0, dtype=bool)
        self.count += Q.shape[0]
        return np.asarray(self.checker.in_collision(Q), dtype=bool).reshape(-1)

    def clearance(self, Q: FloatArray) -> FloatArray:
        """(M, P) signed distance beyond the padding of the rows of ``Q`` (M, n) [m], one
        column per group of pairs."""
        self.count += Q.shape[0]
        if Q.shape[0] == 0:
            return np.zeros((0, len(self.parts)))
        return np.stack([np.asarray(p.distance(Q), dtype=float).reshape(-1) for p in self.parts], axis=1) - self.padding

    def closing(self, dq: FloatArray) -> FloatArray:
        """(M, P): how much the pairs of each group can close over joint steps ``dq`` (M, n)."""
        return np.stack([p.closing(dq) for p in self.parts], axis=1)

    def steps(self, dq: FloatArray) -> NDArray[np.int64]:
        """Number of equal steps (>= 1) for joint displacements ``dq`` (..., n)."""
        sweep = np.abs(dq) @ self.radii
        return np.maximum(1, np.ceil(sweep / self.resolution - 1e-12)).astype(np.int64)

    def along(self, rows: "_Rows", first_only: bool = False) -> BoolArray:
        """(M,) bool: collisions along sampled paths of M configurations (``rows``),
        consecutive ones at most the resolution apart, every path starting and ending at a
        knot row.

        The knots are asked first; a stretch between two asked rows is proven free (module
        docstring) or its middle row is asked, level by level, until every stretch is
        proven free or has no row inside.  Rows of a path known to collide, or with
        ``first_only`` beyond its first collision, are not asked (False)."""
        M = rows.count
        hit = np.zeros(M, dtype=bool)
        limit = np.full(rows.paths, M)  # per path: rows from here on are not asked
        d = np.full((M, len(self.parts)), np.nan)
        closing = np.full((M, len(self.parts)), np.nan)

        def mark(hits: Rows) -> None:
            hit[hits] = True
            if first_only:
                np.minimum.at(limit, rows.path(hits), hits)
            else:
                limit[rows.path(hits)] = -1

        def ask(asked: Rows) -> None:
            d[asked] = self.clearance(rows.config(asked))
            closing[asked] = rows.closing(asked)
            mark(asked[np.any(d[asked] < 0.0, axis=1)])

        kn = rows.knots
        ask(kn)
        a, b = kn[:-1], kn[1:]
        while a.size:
            pa = rows.path(a)
            keep = (b - a > 1) & (pa == rows.path(b)) & np.all(d[a] >= 0.0, axis=1) & (a < limit[pa])
            keep &= np.any(d[a] + d[b] <= closing[b] - closing[a], axis=1)
            a, b = a[keep], b[keep]
            if not a.size:
                break
            mid = (a + b) // 2
            ask(mid)
            a, b = np.concatenate([a, mid]), np.concatenate([mid, b])
        return hit

    def _edge_rows(self, QA: FloatArray, QB: FloatArray) -> "_Rows":
        """The configurations of the edges QA[e] → QB[e] (E, n) at most the resolution
        apart, both ends included (path e), built only when asked."""
        return _EdgeRows(QA, QB, self.steps(QB - QA), self.closing(QB - QA))

    def free_fraction(self, qa: FloatArray, qb: FloatArray) -> float:
        """How far along the edge ``qa`` → ``qb`` it is free: the fraction in [0, 1] of the
        last configuration before the first collision (1 when the edge is free)."""
        rows = self._edge_rows(qa[None], qb[None])
        first = np.flatnonzero(self.along(rows, first_only=True))
        if not first.size:
            return 1.0
        return float((first[0] - 1) / (rows.count - 1)) if first[0] > 0 else 0.0

    def edges_free(self, QA: FloatArray, QB: FloatArray) -> BoolArray:
        """(E,) bool: which edges ``QA[e]`` → ``QB[e]`` (E, n) are free, both ends included."""
        free = np.ones(QA.shape[0], dtype=bool)
        rows = self._edge_rows(QA, QB)
        free[rows.path(np.flatnonzero(self.along(rows)))] = False
        return free

    def samples_colliding(self, Q: FloatArray) -> BoolArray:
        """(M,) bool: collisions along the sampled path ``Q`` (M, n), consecutive rows at
        most the resolution apart (see :meth:`along`)."""
        closing = np.concatenate([np.zeros((1, len(self.parts))), np.cumsum(self.closing(np.diff(Q, axis=0)), axis=0)])
        return self.along(_SampleRows(Q, closing))


class _Rows(Protocol):
    """Configurations numbered 0..count-1 along ``paths`` sampled paths."""

    count: int
    paths: int
    knots: Rows  # the rows asked first, in order: every COARSE_STRIDE-th and each path's ends

    def config(self, rows: Rows) -> FloatArray: ...  # (k, n)

    def closing(self, rows: Rows) -> FloatArray: ...  # (k, P) bound from the path's start

    def path(self, rows: Rows) -> Rows: ...


class _EdgeRows:
    """The rows of straight edges QA[e] → QB[e], m_e steps each (m_e + 1 rows)."""

    def __init__(self, QA: FloatArray, QB: FloatArray, m: NDArray[np.int64], closing: FloatArray) -> None:
        self.QA, self.dQ, self.m, self.total = QA, QB - QA, m, closing
        self.start = np.concatenate([[0], np.cumsum(m + 1)[:-1]])
        self.count, self.paths = int(np.sum(m + 1)), QA.shape[0]
        self.knots = np.concatenate([np.append(np.arange(0, mi, COARSE_STRIDE), mi) + s
                                     for mi, s in zip(m.tolist(), self.start.tolist())])

    def path(self, rows: Rows) -> Rows:
        return np.searchsorted(self.start, rows, side="right") - 1

    def _frac(self, rows: Rows) -> tuple[Rows, FloatArray]:
        e = self.path(rows)
        return e, (rows - self.start[e]) / self.m[e]

    def config(self, rows: Rows) -> FloatArray:
        e, f = self._frac(rows)
        return self.QA[e] + f[:, None] * self.dQ[e]

    def closing(self, rows: Rows) -> FloatArray:
        e, f = self._frac(rows)
        return f[:, None] * self.total[e]


class _SampleRows:
    """The rows of one sampled path ``Q`` (M, n) with its cumulative ``closing`` (M, P)."""

    def __init__(self, Q: FloatArray, closing: FloatArray) -> None:
        self.Q, self.cum = Q, closing
        self.count, self.paths = Q.shape[0], 1
        self.knots = np.append(np.arange(0, self.count - 1, COARSE_STRIDE), self.count - 1)

    def path(self, rows: Rows) -> Rows:
        return np.zeros(len(rows), dtype=np.int64)

    def config(self, rows: Rows) -> FloatArray:
        return self.Q[rows]

    def closing(self, rows: Rows) -> FloatArray:
        return self.cum[rows]
