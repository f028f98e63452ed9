"""``CollisionChecker``: is a configuration in collision, how far is it from it, and which
pair is closest, for one configuration or a batch of them.

World frame, metres, signed distances (negative: penetration depth).  The robot stands
at its ``base_tf``; its links collide with each other (unless ``self_collision=False``)
and with the world's obstacles (the floor by default).  Which pairs are checked:
:mod:`.allowed`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.kernels.model import kernel_array
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotParams
from robot_sim.model.shapes import Shape
from robot_sim.model.state import check_joint_vector
from robot_sim.model.world import World

from robot_sim.collision import batch
from robot_sim.collision.allowed import PairSet, analyse
from robot_sim.collision.distance import DistanceResult
from robot_sim.collision.scene import Scene, build_scene, frames

FloatArray = NDArray[np.float64]

#: Configurations per compiled call of a large batch (bounds the temporary arrays).
CHUNK = 65536


@dataclass(frozen=True)
class PairContact:
    """One checked pair at one configuration: names, shape rows of the scene, signed
    distance [m], witness points (2, 3) and normal (3,) as in :class:`DistanceResult`."""

    pair: tuple[str, str]
    rows: tuple[int, int]
    distance: float
    points: FloatArray
    normal: FloatArray


class CollisionChecker:
    """Collision queries of ``robot`` among its links and against ``world``'s obstacles.

    ``world`` None means ``World()``: the floor only.  ``padding`` [m] >= 0 is a safety
    margin: a configuration is in collision when a checked pair is closer than
    ``padding`` (distances themselves stay geometric).  The allowed pairs are computed
    here (cached per robot for its own pairs).
    """

    def __init__(self, robot: RobotParams, world: World | None = None, *, self_collision: bool = True,
                 padding: float = 0.0) -> None:
        if not isinstance(robot, RobotParams):
            raise ValueError(f"CollisionChecker: robot must be a RobotParams, got {type(robot).__name__}")
        if world is None:
            world = World()
        if not isinstance(world, World):
            raise ValueError(f"CollisionChecker: world must be a World or None, got {type(world).__name__}")
        if not isinstance(self_collision, bool):
            raise ValueError(f"CollisionChecker: self_collision must be True or False, got {clip_repr(self_collision)}")
        if isinstance(padding, bool) or not isinstance(padding, (int, float)) or not (0.0 <= padding < math.inf):
            raise ValueError(f"CollisionChecker: padding must be a finite number of metres >= 0, got {clip_repr(padding)}")
        self.robot = robot
        self.world = world
        self.self_collision = self_collision
        self.padding = float(padding)
        self._scene = build_scene(robot, world)
        allowed, rows = analyse(self._scene, self.padding, self_collision, robot.collision_allow)
        if not self_collision:
            names = robot.link_names
            allowed = PairSet(set(allowed) | {(a, b) for i, a in enumerate(names) for b in names[i + 1:]})
        self._allowed = allowed
        self._pairs = np.ascontiguousarray(rows)
        self.stats = np.zeros(2, dtype=np.int64)

    # ------------------------------------------------------------------ what is checked
    @property
    def allowed(self) -> PairSet:
        """Name pairs never checked (membership ignores the order)."""
        return self._allowed

    @property
    def checked_pairs(self) -> tuple[tuple[str, str], ...]:
        """The name pairs that are checked, each once, in order."""
        seen: dict[tuple[str, str], None] = {}
        for i, j in self._pairs:
            seen[(self._scene.owner[i], self._scene.owner[j])] = None
        return tuple(seen)

    @property
    def link_names(self) -> tuple[str, ...]:
        return self.robot.link_names

    @property
    def scene(self) -> Scene:
        return self._scene

    @property
    def pairs(self) -> NDArray[np.int64]:
        """(P, 2) rows of the scene's shapes checked against each other."""
        return self._pairs

    def _configs(self, q: ArrayLike) -> tuple[FloatArray, bool]:
        Q = check_joint_vector(q, self.robot.n_dofs)
        # C-contiguous and writeable (numba compiles the kernels again for read-only arrays)
        return kernel_array(Q.reshape(-1, self.robot.n_dofs)), Q.ndim == 1

    # ------------------------------------------------------------------ queries
    def in_collision(self, q: ArrayLike) -> bool | NDArray[np.bool_]:
        """Whether q (n,) is in collision (a bool), or each row of q (N, n) (an (N,) array):
        some checked pair closer than ``padding``."""
        Q, single = self._configs(q)
        out = np.empty(Q.shape[0], dtype=np.bool_)
        args = self._scene.args()
        for s in range(0, Q.shape[0], CHUNK):
            batch.in_collision_batch(Q[s:s + CHUNK], *args, self._pairs, self._scene.verts, self.padding,
                                     out[s:s + CHUNK], self.stats)
        return bool(out[0]) if single else out

    def distance(self, q: ArrayLike) -> DistanceResult | FloatArray:
        """The closest checked pair at q (n,) as a :class:`DistanceResult`, or the smallest
        signed distance [m] of each row of q (N, n) as an (N,) array."""
        Q, single = self._configs(q)
        N = Q.shape[0]
        out_d = np.empty(N)
        out_pair = np.empty(N, dtype=np.int64)
        out_pts = np.empty((N, 2, 3))
        args = self._scene.args()
        for s in range(0, N, CHUNK):
            batch.distance_batch(Q[s:s + CHUNK], *args, self._pairs, self._scene.verts, out_d[s:s + CHUNK],
                                 out_pair[s:s + CHUNK], out_pts[s:s + CHUNK])
        if not single:
            return out_d
        if out_pair[0] < 0:
            return DistanceResult(math.inf, None, np.full((2, 3), np.nan), np.full(3, np.nan))
        contact = self._pair_contact(Q[0], int(out_pair[0]))
        return DistanceResult(float(out_d[0]), contact.pair, contact.points, contact.normal)

    def contacts(self, q: ArrayLike, within: float = 0.0) -> list[PairContact]:
        """Every checked shape pair closer than ``within`` [m] at q (n,), closest first."""
        Q, single = self._configs(q)
        if not single:
            raise ValueError(f"contacts takes one configuration of shape ({self.robot.n_dofs},), got {Q.shape}")
        d, pts, nrm = self._evaluate(Q[0], within, self._pairs)
        order = np.argsort(d, kind="stable")
        return [self._contact(self._pairs, int(p), d, pts, nrm) for p in order if d[p] < within]

    def shapes(self, q: ArrayLike) -> list[tuple[str, Shape]]:
        """The robot's collision shapes at q (n,) as (link name, shape posed in the world)."""
        Q, single = self._configs(q)
        if not single:
            raise ValueError(f"shapes takes one configuration of shape ({self.robot.n_dofs},), got {Q.shape}")
        F = frames(self._scene, Q[0])
        scene = self._scene
        return [(scene.owner[s], scene.shapes[s].moved(F[scene.link[s]])) for s in range(scene.n_robot)]

    def path_is_free(self, q_path: ArrayLike, times: ArrayLike | None = None):  # noqa: ANN201
        """Continuous check of a joint path; see :func:`.path.check_path`."""
        from robot_sim.collision.path import check_path

        return check_path(self, q_path, times)

    # ------------------------------------------------------------------ helpers
    def _evaluate(self, q: FloatArray, threshold: float, pairs: NDArray[np.int64]
                  ) -> tuple[FloatArray, FloatArray, FloatArray]:
        P = pairs.shape[0]
        d, pts, nrm = np.empty(P), np.zeros((P, 2, 3)), np.zeros((P, 3))
        recs = np.empty_like(self._scene.recs0)
        batch.pair_results(kernel_array(q), *self._scene.args(), np.ascontiguousarray(pairs),
                           self._scene.verts, threshold, d, pts, nrm, recs)
        return d, pts, nrm

    def _contact(self, rows: NDArray[np.int64], p: int, d: FloatArray, pts: FloatArray, nrm: FloatArray) -> PairContact:
        i, j = (int(x) for x in rows[p])
        owner = self._scene.owner
        return PairContact((owner[i], owner[j]), (i, j), float(d[p]), pts[p].copy(), nrm[p].copy())

    def _pair_contact(self, q: FloatArray, p: int) -> PairContact:
        rows = self._pairs[p:p + 1]
        return self._contact(rows, 0, *self._evaluate(q, math.inf, rows))

    def __repr__(self) -> str:
        return (f"CollisionChecker({self.robot.name}, {self.world!r}, {len(self.checked_pairs)} pairs checked, "
                f"{len(self._allowed)} allowed, padding={self.padding:g} m)")
