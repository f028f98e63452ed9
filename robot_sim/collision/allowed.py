"""Which pairs are never checked: the "adjacent / always" analysis of MoveIt's setup assistant.

* Adjacent links (the base and link 1, link i and link i+1) touch at their joint.
* The robot's own pairs that touch in every one of ``SAMPLES`` random configurations
  (seeded, inside the joint limits) would only ever report themselves: links joined
  through a link of zero length.
* A pair with an obstacle is never allowed by sampling (an obstacle that encloses the
  arm touches every link in every sample, and must be a collision).  It is allowed only
  where its distance cannot depend on q and it touches at home: the base with whatever
  it stands on, and a link that only turns about vertical axes (joints 1..k revolute
  about world z) with the floor it stands on.
* The robot file's ``[collision] allow = [["link2", "link4"], ...]`` adds its own pairs.

The robot's own pairs are analysed once per robot and padding (cached); pairs with
obstacles once per checker.
"""
from __future__ import annotations

from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray

from robot_sim.kernels.model import kernel_array, per_robot
from robot_sim.kinematics import characteristic_length
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.model.shapes import HalfSpace

from robot_sim.collision import batch
from robot_sim.collision.scene import Scene, frames

SAMPLES = 1000
SEED = 0
#: An axis within this of 1 in |z| is vertical (a floor's normal, a joint's axis).
VERTICAL_TOL = 1e-9

class PairSet(frozenset):
    """A frozen set of name pairs (tuples) whose membership ignores the order:
    ``("link4", "link2") in pairs`` when ``("link2", "link4")`` is held."""

    def __contains__(self, pair: object) -> bool:
        if isinstance(pair, (tuple, list)) and len(pair) == 2:
            a, b = pair
            return frozenset.__contains__(self, (a, b)) or frozenset.__contains__(self, (b, a))
        return False


def sample_configurations(robot: RobotParams, count: int, seed: int = SEED) -> NDArray[np.float64]:
    """(count, n) configurations uniform inside the limits; unlimited revolute joints over
    ±π, unlimited prismatic ones within one characteristic length of home."""
    span = characteristic_length(robot)
    revolute = robot.jtype == JTYPE_REVOLUTE
    lo = np.where(np.isfinite(robot.q_min), robot.q_min, np.where(revolute, -np.pi, robot.q_home - span))
    hi = np.where(np.isfinite(robot.q_max), robot.q_max, np.where(revolute, np.pi, robot.q_home + span))
    return lo + (hi - lo) * np.random.default_rng(seed).random((count, robot.n_dofs))


def adjacent_pairs(robot: RobotParams) -> set[tuple[str, str]]:
    names = robot.link_names
    return {(names[i], names[i + 1]) for i in range(robot.n_dofs)}


def always_touching(scene: Scene, rows: NDArray[np.int64], groups: NDArray[np.int64], n_groups: int,
                    padding: float) -> NDArray[np.bool_]:
    """For shape pairs ``rows`` (P, 2) of ``scene`` grouped into ``n_groups`` owner pairs
    (``groups`` (P,)): whether each group has a pair closer than ``padding`` in every
    sampled configuration."""
    if n_groups == 0:
        return np.zeros(0, dtype=bool)
    Q = sample_configurations(scene.robot, SAMPLES)
    touch = np.zeros((SAMPLES, len(rows)), dtype=np.bool_)
    batch.touching_batch(Q, *scene.args(), np.ascontiguousarray(rows), scene.verts, max(padding, 0.0) + 0.0, touch)
    by_group = np.zeros((SAMPLES, n_groups), dtype=bool)
    for g in range(n_groups):
        by_group[:, g] = touch[:, groups == g].any(axis=1)
    return by_group.all(axis=0)


def _turns_about_vertical(scene: Scene) -> NDArray[np.bool_]:
    """(n + 1,): for link k, whether joints 1..k are all revolute about world-vertical axes
    (at home; then at every q), so the link's height never changes (link 0: True)."""
    robot = scene.robot
    F = frames(scene, np.asarray(robot.q_home, dtype=float))
    axes = F[1:, :3, 2] if robot.is_modified else F[:-1, :3, 2]  # joint i turns about z_i or z_{i-1}
    vertical = (robot.jtype == JTYPE_REVOLUTE) & (np.abs(axes[:, 2]) > 1.0 - VERTICAL_TOL)
    return np.concatenate([[True], np.cumprod(vertical).astype(bool)])


def _q_independent(scene: Scene, level: NDArray[np.bool_], i: int, j: int) -> bool:
    """Whether robot shape row ``i`` keeps its distance to obstacle row ``j`` at every q:
    a base shape, or a link turning only about vertical axes (``level``, from
    :func:`_turns_about_vertical`) against a horizontal floor."""
    k = int(scene.link[i])
    if k == 0:
        return True
    obstacle = scene.shapes[j]
    if not isinstance(obstacle, HalfSpace) or abs(obstacle.normal[2]) < 1.0 - VERTICAL_TOL:
        return False
    return bool(level[k])


def _grouped(scene: Scene, rows: list[tuple[int, int]]) -> tuple[NDArray, NDArray, list[tuple[str, str]]]:
    keys: dict[tuple[str, str], int] = {}
    groups = []
    for i, j in rows:
        groups.append(keys.setdefault((scene.owner[i], scene.owner[j]), len(keys)))
    return (np.array(rows, dtype=np.int64).reshape(-1, 2), np.array(groups, dtype=np.int64), list(keys))


def analyse(scene: Scene, padding: float, self_collision: bool,
            file_pairs: Iterable[tuple[str, str]]) -> tuple[PairSet, NDArray[np.int64]]:
    """The allowed name pairs and the shape pairs (rows of the scene) left to check."""
    robot = scene.robot
    fixed = adjacent_pairs(robot) | {tuple(p) for p in file_pairs}
    fixed_set = PairSet(fixed)
    S, total = scene.n_robot, len(scene.owner)
    self_rows = [(i, j) for i in range(S) for j in range(i + 1, S)
                 if scene.link[i] != scene.link[j] and (scene.owner[i], scene.owner[j]) not in fixed_set]
    world_rows = [(i, j) for i in range(S) for j in range(S, total)
                  if (scene.owner[i], scene.owner[j]) not in fixed_set]
    allowed = set(fixed)
    if self_collision:
        always_self = per_robot(robot, "always_touching_self", lambda _robot: {})
        key = (padding, tuple(sorted(fixed)))
        if key not in always_self:
            rows, groups, names = _grouped(scene, self_rows)
            always = always_touching(scene, rows, groups, len(names), padding)
            always_self[key] = frozenset(name for name, hit in zip(names, always) if hit)
        allowed |= always_self[key]
    level = _turns_about_vertical(scene) if world_rows else None
    resting = [(i, j) for i, j in world_rows if _q_independent(scene, level, i, j)]
    if resting:  # touching at home is touching everywhere for these: no sampling
        rows = np.array(resting, dtype=np.int64)
        touch = np.zeros((1, len(rows)), dtype=np.bool_)
        batch.touching_batch(kernel_array(robot.q_home[None]), *scene.args(), rows, scene.verts,
                             max(padding, 0.0) + 0.0, touch)
        allowed |= {(scene.owner[i], scene.owner[j]) for (i, j), hit in zip(resting, touch[0]) if hit}
    allowed_set = PairSet(allowed)
    checked = (self_rows if self_collision else []) + world_rows
    keep = [(i, j) for i, j in checked if (scene.owner[i], scene.owner[j]) not in allowed_set]
    return allowed_set, np.array(keep, dtype=np.int64).reshape(-1, 2)
