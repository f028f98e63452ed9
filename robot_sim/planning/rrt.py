"""Collision-free joint-space paths: :func:`plan_path` (bidirectional RRT-Connect, then
shortcutting and smoothing) and its :class:`PathResult`.

Every edge is a straight joint-space segment checked in compiled code at the continuous
resolution of ``checker.path_is_free`` (see :mod:`robot_sim.planning.edges`: clearances
prove stretches free, the rest is split), so a returned path is free between its
waypoints, not only at them.  Joint values in rad or
m, times in seconds.  No Qt, no OpenGL.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.kinematics import sampling_bounds
from robot_sim.model.params import RobotParams
from robot_sim.planning.edges import CheckCounter, Checker
from robot_sim.planning.profiles import joint_vector
from robot_sim.planning.smoothing import shortcut, smooth

FloatArray = NDArray[np.float64]

#: Longest RRT extension [rad or m of joint-space distance]: OMPL's default range, a fifth
#: of the sampling box's diagonal, capped so a step stays local.
RANGE_FRACTION = 0.2
MAX_STEP = 1.5
#: A blocked extension stops this far (motion bound, m) before the obstacle.
BACKOFF = 0.03
#: Tolerance on the joint limits for start and goal [rad or m].
LIMIT_TOL = 1e-9


@dataclass(frozen=True, eq=False)
class PathResult:
    """Outcome of :func:`plan_path`.

    ``success``; ``path`` (K, n) joint waypoints from start to goal (rad or m; the
    piecewise-linear path through them and the spline :func:`retime` follows through them
    are both collision-free; a waypoint given twice is a stop), empty (0, n) on failure;
    ``message`` one line; ``planning_time`` [s] of wall time; ``checks`` the number of
    configurations handed to the checker.
    """

    success: bool
    path: FloatArray
    message: str
    planning_time: float
    checks: int


class _Tree:
    """Nodes (grown array) and parent indices of one RRT tree rooted at ``root``."""

    def __init__(self, root: FloatArray) -> None:
        self.nodes = np.empty((64, root.shape[0]))
        self.parent = np.empty(64, dtype=np.int64)
        self.nodes[0], self.parent[0], self.size = root, -1, 1

    def nearest(self, q: FloatArray) -> int:
        d = self.nodes[: self.size] - q
        return int(np.argmin(np.einsum("ij,ij->i", d, d)))

    def add_chain(self, start: int, Q: FloatArray) -> int:
        """Append ``Q`` (M, n) as a chain hanging from node ``start``; index of the last."""
        m = Q.shape[0]
        if self.size + m > self.nodes.shape[0]:
            cap = max(2 * self.nodes.shape[0], self.size + m)
            self.nodes = np.concatenate([self.nodes, np.empty((cap - self.nodes.shape[0], Q.shape[1]))])
            self.parent = np.concatenate([self.parent, np.empty(cap - self.parent.shape[0], dtype=np.int64)])
        idx = np.arange(self.size, self.size + m)
        self.nodes[idx] = Q
        self.parent[idx] = np.concatenate([[start], idx[:-1]])
        self.size += m
        return int(idx[-1])

    def branch(self, i: int) -> FloatArray:
        """Nodes from ``i`` back to the root, in that order."""
        out = []
        while i >= 0:
            out.append(self.nodes[i])
            i = int(self.parent[i])
        return np.array(out)


def _outside_limits(robot: RobotParams, q: FloatArray, what: str) -> str | None:
    out = np.flatnonzero((q < robot.q_min - LIMIT_TOL) | (q > robot.q_max + LIMIT_TOL))
    if not out.size:
        return None
    j = int(out[0])
    return (f"{what} is outside the joint limits: joint {j + 1} = {q[j]:.6g} not in "
            f"[{robot.q_min[j]:.6g}, {robot.q_max[j]:.6g}]")


def _toward(counter: CheckCounter, tree: _Tree, target: FloatArray, step: float, connect: bool) -> tuple[int, bool]:
    """Grow ``tree`` from its nearest node toward ``target``: one step of at most ``step``
    (extend) or, with ``connect``, as far as the straight line is free, adding a node
    every ``step``.  Returns (index of the last node added or -1, target reached)."""
    near = tree.nearest(target)
    qa = tree.nodes[near]
    delta = target - qa
    dist = float(np.linalg.norm(delta))
    if dist == 0.0:
        return near, True
    reach = dist if connect else min(dist, step)
    frac = counter.free_fraction(qa, qa + delta * (reach / dist))
    free = reach * frac
    if frac < 1.0:  # stop short of the obstacle: a node at its surface blocks later growth
        free -= BACKOFF / (np.abs(delta / dist) @ counter.radii)
    if free <= 1e-12:
        return -1, False
    # nodes every `step` along the free part (the last one where the free part ends)
    marks = np.append(np.arange(step, free - 1e-9, step), free) if connect else np.array([free])
    last = tree.add_chain(near, qa + delta * (marks / dist)[:, None])
    return last, frac == 1.0 and reach == dist


def _rrt_connect(counter: CheckCounter, lo: FloatArray, hi: FloatArray, q0: FloatArray, q1: FloatArray,
                 rng: np.random.Generator, deadline: float) -> tuple[FloatArray | None, int]:
    """RRT-Connect (Kuffner & LaValle 2000) between q0 and q1; the path or None, and the
    number of nodes grown."""
    step = min(MAX_STEP, RANGE_FRACTION * float(np.linalg.norm(hi - lo)))
    trees = [_Tree(q0), _Tree(q1)]
    a = 0
    while time.perf_counter() < deadline:
        sample = lo + (hi - lo) * rng.random(lo.shape[0])
        ia, _ = _toward(counter, trees[a], sample, step, connect=False)
        if ia >= 0:
            ib, reached = _toward(counter, trees[1 - a], trees[a].nodes[ia], step, connect=True)
            if reached:
                ta, tb = (trees[a].branch(ia), trees[1 - a].branch(ib)) if a == 0 else \
                    (trees[1 - a].branch(ib), trees[a].branch(ia))
                return np.concatenate([ta[::-1], tb]), trees[0].size + trees[1].size
        a = 1 - a
    return None, trees[0].size + trees[1].size


def plan_path(robot: RobotParams, q_start: ArrayLike, q_goal: ArrayLike, checker: Checker, *,
              time_limit: float = 1.0, seed: int | None = 0) -> PathResult:
    """A collision-free joint path from ``q_start`` to ``q_goal`` (n,) within the joint
    limits, for ``checker`` (a ``robot_sim.collision.CollisionChecker`` of ``robot``).

    Bidirectional RRT-Connect samples uniformly inside the joint limits (unlimited revolute
    joints over [−π, π], widened to hold start and goal); each extension is one straight
    edge checked continuously at the resolution of ``checker.path_is_free``.  The path found is then shortcut and smoothed
    (:mod:`robot_sim.planning.smoothing`), keeping it free.  The same ``seed`` gives the
    same path (the search is stopped by ``time_limit`` [s] only when it fails; its clock
    starts after the checks of start, goal and the straight line).

    Start or goal outside the limits or in collision, or no path within ``time_limit``,
    give ``success=False`` with a message naming which; ValueError only for malformed
    arguments (wrong shape, NaN, a non-positive time limit).
    """
    t0 = time.perf_counter()
    n = robot.n_dofs
    qs = joint_vector("q_start", q_start, n)
    qg = joint_vector("q_goal", q_goal, n)
    limit = float(time_limit)
    if not (np.isfinite(limit) and limit > 0.0):
        raise ValueError(f"time_limit must be a positive number of seconds, got {time_limit!r}")
    lo, hi = sampling_bounds(robot)
    lo, hi = np.minimum(lo, np.minimum(qs, qg)), np.maximum(hi, np.maximum(qs, qg))
    counter = CheckCounter(checker, lo, hi)
    if counter.radii.shape != (n,):
        raise ValueError(f"checker has lever arms for {counter.radii.shape} joints, {robot.name} has {n}")

    def result(ok: bool, path: FloatArray | None, message: str) -> PathResult:
        P = np.array(path if path is not None else np.zeros((0, n)), dtype=float)
        P.setflags(write=False)
        return PathResult(ok, P, message, time.perf_counter() - t0, counter.count)

    for q, what in ((qs, "start"), (qg, "goal")):
        reason = _outside_limits(robot, q, what)
        if reason:
            return result(False, None, reason)
    hits = counter.colliding(np.stack([qs, qg]))
    if hits.any():
        which = " and ".join(w for w, h in zip(("start", "goal"), hits) if h)
        return result(False, None, f"{which} {'is' if hits.sum() == 1 else 'are'} in collision")
    if counter.edges_free(qs[None], qg[None])[0]:
        return result(True, np.stack([qs, qg]), "straight joint-space line is free")
    rng = np.random.default_rng(seed)
    # the search's clock starts here: the checks above compile the checker's kernels on a
    # process's first call, which must not eat the search's time
    raw, nodes = _rrt_connect(counter, lo, hi, qs, qg, rng, time.perf_counter() + limit)
    if raw is None:
        return result(False, None, f"no path found within {limit:g} s ({nodes} tree nodes)")
    short = shortcut(counter, raw, rng)
    path = smooth(counter, robot, short)
    return result(True, path, f"RRT-Connect: {nodes} tree nodes, {raw.shape[0]} waypoints shortcut to "
                              f"{short.shape[0]}, smoothed")
