"""Continuous collision checks of joint paths.

Between consecutive waypoints the path is the straight line in joint space.  Each segment
is cut into steps short enough that no point of any link shape moves more than ``step``
metres between two checked configurations (``step`` = the checker's padding, or
``DEFAULT_STEP`` without padding).  The bound comes from link lengths: joint j swings
every point it moves by at most |Δq_j| times its lever arm R_j, the largest distance from
joint j's origin to a shape beyond it along the chain (the √(a² + d²) of the rows in
between, a and d being perpendicular in either DH convention, plus each shape's bounding
sphere), and a prismatic joint moves them by |Δq_j|.
With padding p > 0 and steps of p, a path whose checked configurations are all farther
than p from collision is free everywhere in between.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.model.params import JTYPE_REVOLUTE
from robot_sim.model.state import check_joint_vector

FloatArray = NDArray[np.float64]

DEFAULT_STEP = 1e-3  # m: largest motion of any point between checks without padding
CHUNK = 8192  # configurations checked per call, in path order (the first hit ends the check)


@dataclass(frozen=True)
class PathCheck:
    """Outcome of :meth:`CollisionChecker.path_is_free`; true when the path is free.

    ``time``: where the first collision is, in seconds for a Trajectory or given times,
    else in waypoints (segment index + fraction); ``pair`` the closest pair there and
    ``q`` the configuration (None when free); ``checks``: configurations checked;
    ``step`` [m] the motion bound between checks.
    """

    free: bool
    time: float | None
    pair: tuple[str, str] | None
    q: FloatArray | None
    checks: int
    step: float

    def __bool__(self) -> bool:
        return self.free


def link_lever_arms(checker, Qa: FloatArray, Qb: FloatArray) -> FloatArray:  # noqa: ANN001
    """Per segment, link and joint (M, n + 1, n): how far a point of link l's shapes moves
    per unit of joint j's motion (m/rad for revolute joints, 1 for prismatic ones; 0 for
    the links before the joint), valid along the segments from Qa to Qb (M, n).  Summed
    over the joints between two links it bounds how much that pair can close."""
    robot, scene = checker.robot, checker.scene
    n = robot.n_dofs
    revolute = robot.jtype == JTYPE_REVOLUTE
    reach = np.zeros(n + 1)  # per link: farthest shape point from the link frame's origin
    for s in range(scene.n_robot):
        k = scene.link[s]
        reach[k] = max(reach[k], float(np.linalg.norm(scene.bc[s]) + scene.br[s]))
    d = np.abs(robot.dh_d) + np.where(revolute, 0.0, np.maximum(np.abs(Qa), np.abs(Qb)))
    row = np.hypot(robot.dh_a, d)  # (M, n): row m's translation bound (a and d are perpendicular)
    cum = np.concatenate([np.zeros((row.shape[0], 1)), np.cumsum(row, axis=1)], axis=1)  # cum[:, k] = rows 1..k
    arms = np.zeros((row.shape[0], n + 1, n))
    for j in range(n):
        if revolute[j]:
            # joint j + 1 sits at frame j's origin (standard; modified: frame j + 1's, closer)
            arms[:, j + 1:, j] = cum[:, j + 1:] - cum[:, j:j + 1] + reach[j + 1:]
        else:
            arms[:, j + 1:, j] = 1.0
    return arms


def lever_arms(checker, Qa: FloatArray, Qb: FloatArray) -> FloatArray:  # noqa: ANN001
    """Per segment and joint (M, n): how far a point of the shapes moves per unit of joint
    motion (m/rad for revolute joints, 1 for prismatic ones), valid along the segments
    from Qa to Qb (M, n): the largest of :func:`link_lever_arms` over the links."""
    return np.max(link_lever_arms(checker, Qa, Qb), axis=1)


def check_path(checker, q_path, times: ArrayLike | None = None) -> PathCheck:  # noqa: ANN001
    """Whether the path through waypoints ``q_path`` ((K, n), or a Trajectory, whose
    samples ``q`` at times ``t`` are used) is free of collision, checked continuously
    (module docstring).  ``times`` (K,) increasing gives the waypoints' times."""
    if hasattr(q_path, "t") and hasattr(q_path, "q"):
        times = q_path.t if times is None else times
        q_path = q_path.q
    Q = check_joint_vector(q_path, checker.robot.n_dofs, "q_path")
    if Q.ndim == 1:
        Q = Q[None]
    if len(Q) == 0:
        raise ValueError(f"path_is_free: q_path holds no configuration; expected (K, {checker.robot.n_dofs}) "
                         "waypoints with K >= 1")
    t = np.arange(len(Q), dtype=float) if times is None else np.asarray(times, dtype=float)
    if t.shape != (len(Q),) or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0.0):
        raise ValueError(f"path_is_free: times must be {len(Q)} finite, strictly increasing values, got {t!r}")
    step = checker.padding if checker.padding > 0.0 else DEFAULT_STEP
    if len(Q) == 1:
        counts = np.zeros(0, dtype=np.int64)
    else:
        Qa, Qb = Q[:-1], Q[1:]
        bound = np.sum(np.abs(Qb - Qa) * lever_arms(checker, Qa, Qb), axis=1)
        counts = np.maximum(1, np.ceil(bound / step)).astype(np.int64)
    # every checked configuration as (segment, fraction), in path order, the last waypoint last
    seg = np.repeat(np.arange(len(counts)), counts)
    start = np.repeat(np.cumsum(counts) - counts, counts)
    frac = (np.arange(seg.size) - start) / np.repeat(counts, counts) if seg.size else np.zeros(0)
    seg = np.append(seg, max(len(Q) - 2, 0))
    frac = np.append(frac, 1.0 if len(Q) > 1 else 0.0)
    total = seg.size
    for s in range(0, total, CHUNK):
        sg, fr = seg[s:s + CHUNK], frac[s:s + CHUNK]
        if len(Q) > 1:
            configs = Q[sg] + fr[:, None] * (Q[np.minimum(sg + 1, len(Q) - 1)] - Q[sg])
        else:
            configs = Q[np.zeros(len(sg), dtype=np.int64)]
        hits = np.flatnonzero(checker.in_collision(configs))
        if hits.size:
            k = int(hits[0])
            q_hit = configs[k].copy()
            i = int(sg[k])
            time = float(t[i] + fr[k] * (t[min(i + 1, len(t) - 1)] - t[i]))
            return PathCheck(False, time, checker.distance(q_hit).pair, q_hit, s + k + 1, step)
    return PathCheck(True, None, None, None, total, step)
