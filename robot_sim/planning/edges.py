"""Straight joint-space edges and sampled paths checked at the collision checker's
continuous resolution, in compiled code.

The checker's lever arms r_j bound the motion of every point of the arm: at most
Σ_j r_j |Δq_j| for a joint step Δq.  ``checker.path_is_free`` checks configurations no
more than its resolution apart in that bound; an edge this module calls free is free for
it too.  Between those configurations, :mod:`robot_sim.collision.certify` asks only
what the clearances of the checked pairs cannot prove free (each group of pairs with its
own motion bound: :class:`robot_sim.collision.groups.PairGroups`), so nothing called
free would be called colliding by checking every configuration at the resolution.
Joint values in rad or m; no Qt, no OpenGL.
"""
from __future__ import annotations

from typing import Protocol

import numpy as np
from numpy.typing import NDArray

from robot_sim.collision.groups import PairGroups
from robot_sim.planning.spline import JointSpline

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]
IntArray = NDArray[np.int64]


class Checker(Protocol):
    """What the planner uses of a collision checker: a ``robot_sim.collision.CollisionChecker``,
    or a ``robot_sim.planning.carrying.CheckerGroup`` of them (``members``)."""

    padding: float  # m: a configuration closer than this to collision counts as colliding

    def in_collision(self, q: FloatArray) -> BoolArray | bool: ...

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
    """A checker's continuous checks of edges and sampled paths, counted
    (``PathResult.checks``: configurations asked)."""

    def __init__(self, checker: Checker, lo: FloatArray, hi: FloatArray) -> None:
        self.checker = checker
        self.radii, self.resolution = motion_bound(checker, lo, hi)
        self.groups = PairGroups(getattr(checker, "members", None) or (checker,), lo, hi)
        self.count = 0

    def colliding(self, Q: FloatArray) -> BoolArray:
        """(M,) bool: which rows of ``Q`` (M, n) are in collision (one batched call)."""
        if Q.shape[0] == 0:
            return np.zeros(0, dtype=bool)
        self.count += Q.shape[0]
        return np.asarray(self.checker.in_collision(Q), dtype=bool).reshape(-1)

    def steps(self, dq: FloatArray) -> IntArray:
        """Number of equal steps (>= 1) for joint displacements ``dq`` (..., n)."""
        sweep = np.abs(dq) @ self.radii
        return np.maximum(1, np.ceil(sweep / self.resolution - 1e-12)).astype(np.int64)

    def _hits(self, P: FloatArray, steps: IntArray, C: FloatArray, first_only: bool, until_free: bool = False,
              curvature: FloatArray | None = None, lengths: FloatArray | None = None) -> IntArray:
        """Per two-point path (P[2e], P[2e + 1]) with steps[2e] rows and closing C[2e + 1]
        (C[2e] = 0): its first colliding row (``first_only``) or some colliding row, -1 when
        free (with ``until_free``, -2 after the first free path: not checked); a spline
        span with ``curvature`` and ``lengths`` (:meth:`PairGroups.first_hits`)."""
        hits, asked = self.groups.first_hits(P, steps, C, np.arange(0, P.shape[0] + 1, 2), first_only, until_free,
                                             curvature, lengths)
        self.count += asked
        return hits

    def _edges(self, QA: FloatArray, QB: FloatArray, first_only: bool,
               until_free: bool = False) -> tuple[IntArray, IntArray]:
        """The edges QA[e] → QB[e] (E, n) as two-point paths: (their hit rows as
        :meth:`_hits` gives them, their step counts)."""
        m = self.steps(QB - QA)
        return self._hits(*_pairs(QA, QB, m, self.groups.closing(QB - QA)), first_only, until_free), m

    def free_fraction(self, qa: FloatArray, qb: FloatArray) -> float:
        """How far along the edge ``qa`` → ``qb`` it is free: the fraction in [0, 1] of the
        last configuration before the first collision (1 when the edge is free)."""
        hits, m = self._edges(qa[None], qb[None], first_only=True)
        first = int(hits[0])
        if first < 0:
            return 1.0
        return float((first - 1) / m[0]) if first > 0 else 0.0

    def edges_free(self, QA: FloatArray, QB: FloatArray) -> BoolArray:
        """(E,) bool: which edges ``QA[e]`` → ``QB[e]`` (E, n) are free, both ends included."""
        return self._edges(QA, QB, first_only=False)[0] < 0

    def first_free(self, qa: FloatArray, QB: FloatArray) -> int:
        """The first k (in order) whose edge ``qa`` → ``QB[k]`` (K, n) is free, or -1;
        the edges after it are not checked."""
        hits = self._edges(np.repeat(qa[None], QB.shape[0], axis=0), QB, first_only=False, until_free=True)[0]
        free = np.flatnonzero(hits == -1)
        return int(free[0]) if free.size else -1

    def spans_colliding(self, spline: JointSpline) -> BoolArray:
        """(K - 1,) bool: which knot spans of ``spline`` collide somewhere.  Each span is
        stepped evenly in its parameter, no point of the arm moving more than the
        resolution per step (from each joint's largest speed on the span, which also
        bounds how much each group of pairs can close)."""
        motion = spline.span_speed() * np.diff(spline.knots)[:, None]  # (K - 1, n) bound on |Δq| per span
        m = np.maximum(1, np.ceil(motion @ self.radii / self.resolution - 1e-12)).astype(np.int64)
        P, steps, C = _pairs(spline.waypoints[:-1], spline.waypoints[1:], m, self.groups.closing(motion))
        curvature = _interleave(spline.curvature[:-1], spline.curvature[1:])
        lengths = np.repeat(np.diff(spline.knots), 2)
        return self._hits(P, steps, C, first_only=False, curvature=curvature, lengths=lengths) >= 0


def _interleave(A: FloatArray, B: FloatArray) -> FloatArray:
    """Rows A[0], B[0], A[1], B[1], ... (2E, ...)."""
    out = np.empty((2 * A.shape[0],) + A.shape[1:])
    out[0::2], out[1::2] = A, B
    return out


def _pairs(QA: FloatArray, QB: FloatArray, m: IntArray, closing: FloatArray) -> tuple[FloatArray, IntArray, FloatArray]:
    """Two-point paths QA[e] → QB[e] with m[e] steps and total closing[e] (E, G): points
    (2E, n), steps (2E,) and cumulative closing (2E, G) for :meth:`CheckCounter._hits`."""
    steps = np.ones(2 * QA.shape[0], dtype=np.int64)
    steps[0::2] = m
    return _interleave(QA, QB), steps, _interleave(np.zeros_like(closing), closing)
