"""A checker's pairs in groups that move alike, each with its clearance and its bound on
how fast that clearance can shrink: what a continuous check certifies stretches with.

A pair of one link's shape and an obstacle closes at most by Σ_j r_kj |Δq_j| for a
joint step Δq, r_kj the lever arm of joint j for link k's shapes (0 for the joints after
link k); a pair of links i < j closes at most by joints i+1..j with link j's arms.  Pairs
with the same bound form one group: the world pairs of each link, the self pairs of each
link pair.  For a stretch between two configurations with clearances d_a, d_b (per
group), the stretch is free when d_a + d_b exceeds the group's bound for the step, for
every group (the clearance of a group cannot reach 0 from both ends).  Per group this is
tighter than one distance against the largest lever arm of the arm: a base link near the
table moves little.

Several checkers of one robot (a :class:`robot_sim.planning.carrying.CheckerGroup`'s
members: the arm, a carried object) are packed into one scene and checked together.
World frame, metres; joint steps in rad or m.  No Qt, no OpenGL.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from robot_sim.kernels.model import GEOMETRY

from robot_sim.collision import certify
from robot_sim.collision import layout as L
from robot_sim.collision.checker import CHUNK, CollisionChecker
from robot_sim.collision.path import link_lever_arms

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]

#: Rows between two knots of a checked path (see :mod:`.certify`).
KNOT_STRIDE = 64


def _merged(checkers: Sequence[CollisionChecker]) -> tuple[tuple, IntArray, IntArray, FloatArray]:
    """The scene arguments of :mod:`.batch` after the configurations (robot shapes of every
    checker first, then their obstacles), the pairs (P, 2) as rows of it, each pair's link
    pair key (P, 2: (-1, link) against the world, (link i, link j) i <= j against itself)
    and the shared vertex array."""
    first = checkers[0].scene
    for c in checkers[1:]:
        if c.robot.is_modified != first.robot.is_modified or not (
                np.array_equal(c.scene.dh[:, :GEOMETRY], first.dh[:, :GEOMETRY]) and np.array_equal(c.scene.world0, first.world0)):
            raise ValueError("checkers of different robots cannot be checked together")
    scenes = [c.scene for c in checkers]
    S = [s.n_robot for s in scenes]
    O = [s.recs0.shape[0] - s.n_robot for s in scenes]
    robot_at = np.cumsum([0] + S)
    obstacle_at = robot_at[-1] + np.cumsum([0] + O)
    vert_at = np.cumsum([0] + [s.verts.shape[0] for s in scenes])

    def rows(k: int, i: NDArray) -> NDArray:
        return np.where(i < S[k], robot_at[k] + i, obstacle_at[k] + i - S[k])

    def stack(field: str) -> NDArray:
        parts = [getattr(s, field) for s in scenes]
        robot = [p[:n] for p, n in zip(parts, S)]
        obstacles = [p[n:] for p, n in zip(parts, S)]
        return np.ascontiguousarray(np.concatenate(robot + obstacles))

    recs0 = stack("recs0")
    kinds = stack("kinds")
    for k, s in enumerate(scenes):  # convex shapes name their rows of the shared vertex array
        for i in np.flatnonzero(s.kinds == L.CONVEX):
            recs0[rows(k, np.array(i)), L.VSTART] += vert_at[k]
    local = np.ascontiguousarray(recs0[:robot_at[-1]])
    link = np.concatenate([s.link for s in scenes])
    args = (first.dh, first.robot.is_modified, first.world0, link, local, recs0, kinds, stack("bc"), stack("br"))
    pairs, keys = [], []
    for k, (c, s) in enumerate(zip(checkers, scenes)):
        P = np.sort(c.pairs, axis=1)
        pairs.append(rows(k, P))
        world = P[:, 1] >= s.n_robot
        li, lj = s.link[P[:, 0]], s.link[np.minimum(P[:, 1], s.n_robot - 1)]
        keys.append(np.column_stack([np.where(world, -1, li), np.where(world, li, lj)]))
    verts = np.ascontiguousarray(np.concatenate([s.verts for s in scenes]).reshape(-1, 3))
    return args, np.ascontiguousarray(np.concatenate(pairs), dtype=np.int64), np.concatenate(keys), verts


class PairGroups:
    """The checked pairs of ``checkers`` (CollisionCheckers of one robot, same padding
    assumed the largest) grouped by their motion bound over joint values in [lo, hi]
    (n,): :meth:`closing` bounds how much each group's clearance can shrink over joint
    steps, :meth:`clearance` gives each group's clearance, :meth:`first_hits` checks
    sampled paths continuously."""

    def __init__(self, checkers: Sequence[CollisionChecker], lo: FloatArray, hi: FloatArray) -> None:
        checkers = list(checkers)
        self.padding = max(c.padding for c in checkers)
        self._args, self._pairs, keys, self._verts = _merged(checkers)
        n = checkers[0].robot.n_dofs
        bounds = (np.asarray(lo, dtype=float)[None], np.asarray(hi, dtype=float)[None])
        arms = np.max([link_lever_arms(c, *bounds)[0] for c in checkers], axis=0)  # (n + 1, n)
        unique, group = np.unique(keys, axis=0, return_inverse=True)
        self._group = np.ascontiguousarray(group.reshape(-1), dtype=np.int64)
        #: (G, n): a group's clearance shrinks by at most |dq| @ bound[g] over a step dq.
        self.bound = np.array([np.where(np.arange(n) >= max(i, 0), arms[j], 0.0) for i, j in unique]).reshape(-1, n)

    @property
    def count(self) -> int:
        return int(self.bound.shape[0])

    def closing(self, dq: FloatArray) -> FloatArray:
        """(M, G): how much each group's clearance can shrink over joint steps dq (M, n)."""
        return np.abs(dq) @ self.bound.T

    def clearance(self, Q: FloatArray, limit: float = np.inf) -> FloatArray:
        """(M, G) signed distance minus the padding [m] of each group's closest pair at
        the rows of Q (M, n): exact below ``limit``, else a lower bound at least ``limit``;
        a row where a pair is closer than the padding holds that value (< 0) in every column."""
        Q = np.ascontiguousarray(Q, dtype=float)
        out = np.empty((Q.shape[0], self.count))
        for s in range(0, Q.shape[0], CHUNK):
            certify.clearance_batch(Q[s:s + CHUNK], *self._args, self._pairs, self._verts, self._group, self.padding,
                                    np.full(self.count, float(limit)), out[s:s + CHUNK])
        return out

    def first_hits(self, P: FloatArray, steps: IntArray, C: FloatArray, starts: IntArray, first_only: bool,
                   until_free: bool = False, curvature: FloatArray | None = None,
                   lengths: FloatArray | None = None) -> tuple[IntArray, int]:
        """Continuous check of sampled paths (:mod:`.certify`): path e runs through the
        points P[starts[e]:starts[e + 1]] (rad or m) with steps[k] rows from point k to
        k + 1 and cumulative closing C (K, G) from :meth:`closing`; straight between the
        points, or spline spans with second derivatives ``curvature`` (K, n) at the points
        over parameter ``lengths`` (K,).  Returns each path's first colliding row
        (``first_only``; else some colliding row), -1 when free (with ``until_free``, -2
        for the paths after the first free one: not checked), and the number of
        configurations asked."""
        K = P.shape[0]
        Mc = np.zeros_like(P) if curvature is None else curvature
        H = np.ones(K) if lengths is None else lengths
        out = np.empty(starts.shape[0] - 1, dtype=np.int64)
        arrays = (P, Mc, H, steps, C, starts)
        kinds = (float, float, float, np.int64, float, np.int64)
        asked = certify.first_hits(*(np.ascontiguousarray(a, dtype=t) for a, t in zip(arrays, kinds)), KNOT_STRIDE,
                                   first_only, until_free, *self._args, self._pairs, self._verts, self._group,
                                   self.padding, out)
        return out, int(asked)
