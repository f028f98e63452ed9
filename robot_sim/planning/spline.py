"""The geometry :func:`retime` gives a joint path: a cubic spline through its waypoints.

Waypoints (K, n) are parameterised by their cumulative chord length s (the Euclidean
joint-space distance, rad or m) and joined by the not-a-knot cubic spline (the third
derivative is continuous at the second and the second-to-last waypoint; three waypoints
give one parabola, two a straight line), as ``scipy.interpolate.CubicSpline`` and
``toppra.SplineInterpolator`` build it.  Repeated waypoints are dropped.  No Qt, no OpenGL.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

#: Waypoints closer than this (joint-space distance, rad or m) count as one.
DUPLICATE_TOL = 1e-12


def _second_derivatives(s: FloatArray, Y: FloatArray) -> FloatArray:
    """Second derivatives (K, n) at the knots of the not-a-knot spline through (s, Y)."""
    K = s.shape[0]
    if K == 2:
        return np.zeros_like(Y)
    h = np.diff(s)
    slope = np.diff(Y, axis=0) / h[:, None]
    A = np.zeros((K, K))
    rhs = np.zeros_like(Y)
    i = np.arange(1, K - 1)
    A[i, i - 1], A[i, i], A[i, i + 1] = h[:-1], 2.0 * (h[:-1] + h[1:]), h[1:]
    rhs[1:-1] = 6.0 * np.diff(slope, axis=0)
    if K == 3:  # one parabola: constant second derivative
        A[0, :2], A[2, 1:] = (1.0, -1.0), (1.0, -1.0)
    else:  # third derivative continuous across knots 1 and K-2
        A[0, :3] = h[1], -(h[0] + h[1]), h[0]
        A[-1, -3:] = h[-1], -(h[-2] + h[-1]), h[-2]
    return np.linalg.solve(A, rhs)


def _value(h: FloatArray, a: FloatArray, b: FloatArray, m0: FloatArray, m1: FloatArray, y0: FloatArray,
           y1: FloatArray) -> FloatArray:
    """q on a knot span of length h, a and b from its two ends (a + b = h), with
    curvatures m0, m1 and waypoints y0, y1 at its ends (arrays that broadcast)."""
    return (m0 * a**3 + m1 * b**3) / (6 * h) + (y0 / h - m0 * h / 6) * a + (y1 / h - m1 * h / 6) * b


def _slope(h: FloatArray, a: FloatArray, b: FloatArray, m0: FloatArray, m1: FloatArray, y0: FloatArray,
           y1: FloatArray) -> FloatArray:
    """dq/ds there (as :func:`_value`)."""
    return (-m0 * a**2 + m1 * b**2) / (2 * h) + (y1 - y0) / h - (m1 - m0) * h / 6


@dataclass(frozen=True, eq=False)
class JointSpline:
    """Not-a-knot cubic spline through joint waypoints, by chord length.

    ``knots`` (K,) path parameter s at the waypoints [rad or m of joint-space distance],
    ``waypoints`` (K, n), ``curvature`` (K, n) the second derivatives d²q/ds² at the knots.
    """

    knots: FloatArray
    waypoints: FloatArray
    curvature: FloatArray

    @classmethod
    def through(cls, path: ArrayLike) -> "JointSpline":
        """The spline through ``path`` (K, n), K >= 1; ValueError for NaN or a bad shape."""
        P = np.asarray(path, dtype=float)
        if P.ndim != 2 or P.shape[0] == 0 or P.shape[1] == 0:
            raise ValueError(f"path must be (K, n) joint waypoints, got shape {P.shape}")
        bad = np.argwhere(~np.isfinite(P))
        if bad.size:
            k, j = bad[0]
            raise ValueError(f"path[{k}] joint {j + 1} is {P[k, j]!r}; expected a finite number")
        step = np.linalg.norm(np.diff(P, axis=0), axis=1)
        keep = np.concatenate([[True], step > DUPLICATE_TOL])
        P = P[keep]
        s = np.concatenate([[0.0], np.cumsum(step[keep[1:]])])
        curv = _second_derivatives(s, P) if P.shape[0] > 1 else np.zeros_like(P)
        for arr in (s, P, curv):
            arr.setflags(write=False)
        return cls(s, P, curv)

    @property
    def length(self) -> float:
        """Total chord length of the path [rad or m]."""
        return float(self.knots[-1])

    def _pieces(self, s: ArrayLike) -> tuple[FloatArray, ...]:
        """Per parameter (``s`` clamped to [0, length]): the knot span's length h, the
        distances a, b to its ends, its curvatures m0, m1 and waypoints y0, y1."""
        sq = np.clip(np.asarray(s, dtype=float).reshape(-1), 0.0, self.length)
        P, M, t = self.waypoints, self.curvature, self.knots
        i = np.clip(np.searchsorted(t, sq, side="right") - 1, 0, t.shape[0] - 2)
        h = (t[i + 1] - t[i])[:, None]
        return h, t[i + 1, None] - sq[:, None], sq[:, None] - t[i, None], M[i], M[i + 1], P[i], P[i + 1]

    def positions(self, s: ArrayLike) -> FloatArray:
        """q(s) (M, n) at path parameters ``s`` (M,), clamped to [0, length]."""
        if self.waypoints.shape[0] == 1:
            return np.zeros((np.size(s), self.waypoints.shape[1])) + self.waypoints[0]
        return _value(*self._pieces(s))

    def evaluate(self, s: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """q(s), dq/ds and d²q/ds² at path parameters ``s`` (M,) → three (M, n) arrays;
        ``s`` is clamped to [0, length]."""
        if self.waypoints.shape[0] == 1:
            q = self.positions(s)
            return q, np.zeros_like(q), np.zeros_like(q)
        pieces = self._pieces(s)
        h, a, b, m0, m1, _, _ = pieces
        return _value(*pieces), _slope(*pieces), (m0 * a + m1 * b) / h

    def _span_points(self, b: FloatArray) -> tuple[FloatArray, FloatArray]:
        """q and dq/ds (K - 1, n) at offsets ``b`` (K - 1, n) into each span, per joint."""
        h, m0, m1, y0, y1 = self._spans()
        pieces = (h, h - b, b, m0, m1, y0, y1)
        return _value(*pieces), _slope(*pieces)

    def _spans(self) -> tuple[FloatArray, ...]:
        """Per knot span (K - 1, 1 or n): its length h, curvatures m0, m1 and waypoints y0, y1."""
        t, P, M = self.knots, self.waypoints, self.curvature
        return np.diff(t)[:, None], M[:-1], M[1:], P[:-1], P[1:]

    def span_speed(self) -> FloatArray:
        """(K - 1, n): the largest |dq/ds| of each joint over each knot span (exact: at the
        span's ends or where d²q/ds² = 0 inside it)."""
        h, m0, m1, _, _ = self._spans()
        with np.errstate(divide="ignore", invalid="ignore"):
            inner = np.nan_to_num(np.clip(m0 * h / (m0 - m1), 0.0, h), nan=0.0, posinf=0.0, neginf=0.0)
        zeros = np.zeros_like(m0)
        return np.max([np.abs(self._span_points(b)[1]) for b in (zeros, zeros + h, inner)], axis=0)

    def span_range(self) -> tuple[FloatArray, FloatArray]:
        """(lowest, highest) value (K - 1, n) of each joint over each knot span (exact: at
        the span's ends or where dq/ds = 0 inside it)."""
        h, m0, m1, _, _ = self._spans()
        zeros = np.zeros_like(m0)
        _, c = self._span_points(zeros)  # dq/ds = A b² + B b + c on the span, b from its start
        A, B = (m1 - m0) / (2 * h), m0
        with np.errstate(divide="ignore", invalid="ignore"):
            root = np.sqrt(np.maximum(B * B - 4 * A * c, 0.0))
            linear = np.abs(A) <= 1e-12 * (np.abs(B) + np.abs(c) / h)
            b1 = np.where(linear, -c / B, (-B + root) / (2 * A))
            b2 = np.where(linear, -c / B, (-B - root) / (2 * A))
        candidates = [zeros, zeros + h] + [np.nan_to_num(np.clip(b, 0.0, h), nan=0.0) for b in (b1, b2)]
        values = np.array([self._span_points(b)[0] for b in candidates])
        return values.min(axis=0), values.max(axis=0)
