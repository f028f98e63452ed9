"""Shortcutting and smoothing of a free joint-space polyline, keeping it free.

* :func:`shortcut` removes waypoints whose neighbours see each other and replaces random
  stretches by straight edges (Hauser & Ng-Thow-Hing's random shortcutting), each new
  edge checked at the checker's continuous resolution.
* :func:`smooth` makes the path one that :func:`retime` can follow without stopping: the
  cubic spline through the waypoints (:class:`JointSpline`) is checked at the same
  resolution; where it collides or leaves the joint limits, waypoints are added on the
  polyline (pulling the spline onto it), and a span that still fails becomes a straight
  edge with a stop at both ends (a repeated waypoint).

Joint values in rad or m.  No Qt, no OpenGL.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.model.params import RobotParams
from robot_sim.planning.edges import CheckCounter
from robot_sim.planning.spline import JointSpline

FloatArray = NDArray[np.float64]

#: Random shortcut attempts (a fixed count, so a seed gives one path).
SHORTCUT_ATTEMPTS = 12
#: Waypoints whose edges turn by less than this (1 − cos) are on a straight line.
COLLINEAR_TOL = 1e-9
#: Rounds of adding waypoints to a colliding spline span before it becomes a straight edge.
SMOOTH_ROUNDS = 4
#: Round-off allowed beyond a joint limit at a span's extreme [rad or m].
LIMIT_TOL = 1e-12


def _corners(P: FloatArray) -> FloatArray:
    """``P`` without the waypoints that lie on the straight line between their neighbours
    (the tree's chains along one connection), which changes no edge."""
    P = P[np.concatenate([[True], np.linalg.norm(np.diff(P, axis=0), axis=1) > 0.0])]  # repeats go first
    if P.shape[0] < 3:
        return P
    d0, d1 = P[1:-1] - P[:-2], P[2:] - P[1:-1]
    n0, n1 = np.linalg.norm(d0, axis=1), np.linalg.norm(d1, axis=1)
    straight = np.einsum("ij,ij->i", d0, d1) >= (1.0 - COLLINEAR_TOL) * n0 * n1
    return P[np.concatenate([[True], ~straight, [True]])]


def _prune(counter: CheckCounter, P: FloatArray) -> FloatArray:
    """Greedy vertex removal: from each kept waypoint, jump to the farthest one in sight."""
    keep, i = [0], 0
    while i < P.shape[0] - 1:
        far = np.arange(P.shape[0] - 1, i + 1, -1)
        k = counter.first_free(P[i], P[far]) if far.size else -1
        i = int(far[k]) if k >= 0 else i + 1
        keep.append(i)
    return P[keep]


def shortcut(counter: CheckCounter, path: FloatArray, rng: np.random.Generator,
             attempts: int = SHORTCUT_ATTEMPTS) -> FloatArray:
    """``path`` (K, n), a free polyline, made shorter: waypoints pruned, then ``attempts``
    random shortcuts between two points on different edges, then pruned again."""
    P = _prune(counter, _corners(path))
    for _ in range(attempts):
        if P.shape[0] < 3:
            break
        cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])
        ta, tb = np.sort(rng.random(2) * cum[-1])
        ia = min(int(np.searchsorted(cum, ta, side="right")) - 1, P.shape[0] - 2)
        ib = min(int(np.searchsorted(cum, tb, side="right")) - 1, P.shape[0] - 2)
        if ia == ib:
            continue
        pa = P[ia] + (P[ia + 1] - P[ia]) * ((ta - cum[ia]) / (cum[ia + 1] - cum[ia]))
        pb = P[ib] + (P[ib + 1] - P[ib]) * ((tb - cum[ib]) / (cum[ib + 1] - cum[ib]))
        if counter.edges_free(pa[None], pb[None])[0]:
            P = np.concatenate([P[: ia + 1], pa[None], pb[None], P[ib + 1 :]])
    return _prune(counter, P)


def _failing_spans(counter: CheckCounter, robot: RobotParams, spline: JointSpline) -> NDArray[np.int64]:
    """Knot spans (indices) of ``spline`` where it leaves the joint limits (exact extremes
    of each span's cubic, LIMIT_TOL allowed) or, when it stays within them, where it
    collides."""
    lo, hi = spline.span_range()
    outside = np.any((lo < robot.q_min - LIMIT_TOL) | (hi > robot.q_max + LIMIT_TOL), axis=1)
    if outside.any():
        return np.flatnonzero(outside)
    return np.flatnonzero(counter.spans_colliding(spline))


def _refined(P: FloatArray, spans: NDArray[np.int64]) -> FloatArray:
    """``P`` with the points at 1/4 and 3/4 of each listed span inserted (on the polyline)."""
    rows = []
    for k in range(P.shape[0]):
        rows.append(P[k])
        if k in spans:
            d = P[k + 1] - P[k]
            rows += [P[k] + 0.25 * d, P[k] + 0.75 * d]
    return np.array(rows)


def smooth(counter: CheckCounter, robot: RobotParams, path: FloatArray) -> FloatArray:
    """Waypoints (K', n) whose spline (:class:`JointSpline`, cut at repeated waypoints) is
    free and within the limits; the polyline through them is ``path``'s (a free polyline)."""
    queue: list[tuple[FloatArray, int]] = [(np.asarray(path, dtype=float), 0)]  # (piece, rounds), in order
    done: list[FloatArray] = []
    while queue:
        piece, tries = queue.pop(0)
        spans = _failing_spans(counter, robot, JointSpline.through(piece)) if piece.shape[0] > 2 else ()
        if not len(spans):
            done.append(piece)
        elif tries < SMOOTH_ROUNDS:
            queue.insert(0, (_refined(piece, spans), tries + 1))
        else:  # still failing: cut at both ends of every failing span (straight, free edges)
            cuts = sorted({0, piece.shape[0] - 1} | set(spans.tolist()) | set((spans + 1).tolist()))
            queue[:0] = [(piece[a : b + 1], tries) for a, b in zip(cuts[:-1], cuts[1:])]
    return np.concatenate(done)
