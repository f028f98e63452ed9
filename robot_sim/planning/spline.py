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

    def evaluate(self, s: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """q(s), dq/ds and d²q/ds² at path parameters ``s`` (M,) → three (M, n) arrays;
        ``s`` is clamped to [0, length]."""
        sq = np.clip(np.asarray(s, dtype=float).reshape(-1), 0.0, self.length)
        P, M, t = self.waypoints, self.curvature, self.knots
        if P.shape[0] == 1:
            zeros = np.zeros((sq.shape[0], P.shape[1]))
            return zeros + P[0], zeros, zeros.copy()
        i = np.clip(np.searchsorted(t, sq, side="right") - 1, 0, t.shape[0] - 2)
        h = (t[i + 1] - t[i])[:, None]
        a, b = (t[i + 1, None] - sq[:, None]), (sq[:, None] - t[i, None])
        m0, m1, y0, y1 = M[i], M[i + 1], P[i], P[i + 1]
        q = (m0 * a**3 + m1 * b**3) / (6 * h) + (y0 / h - m0 * h / 6) * a + (y1 / h - m1 * h / 6) * b
        dq = (-m0 * a**2 + m1 * b**2) / (2 * h) + (y1 - y0) / h - (m1 - m0) * h / 6
        ddq = (m0 * a + m1 * b) / h
        return q, dq, ddq

    def samples(self, spacing: float) -> FloatArray:
        """Path parameters from 0 to ``length``, the knots included, at most ``spacing`` apart."""
        parts = [self.knots[:1]]
        for s0, s1 in zip(self.knots[:-1], self.knots[1:]):
            m = max(1, int(np.ceil((s1 - s0) / spacing - 1e-12)))
            parts.append(np.linspace(s0, s1, m + 1)[1:])
        return np.concatenate(parts)
