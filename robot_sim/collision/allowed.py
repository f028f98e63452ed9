"""Which pairs are never checked: the "adjacent / always" analysis of MoveIt's setup assistant.

* Adjacent links (the base and link 1, link i and link i+1) touch at their joint.
* Pairs that touch in every one of ``SAMPLES`` random configurations (seeded, inside the
  joint limits) would only ever report themselves: links joined through a link of zero
  length, a link that turns on the floor it stands on.
* The robot file's ``[collision] allow = [["link2", "link4"], ...]`` adds its own pairs.

The robot's own pairs are analysed once per robot and padding (cached); pairs with
obstacles once per checker.
"""
from __future__ import annotations

from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray

from robot_sim.kernels.model import per_robot
from robot_sim.kinematics import characteristic_length
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams

from robot_sim.collision import batch
from robot_sim.collision.scene import Scene

SAMPLES = 1000
SEED = 0

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
    rows, groups, names = _grouped(scene, world_rows)
    always = always_touching(scene, rows, groups, len(names), padding)
    allowed |= {name for name, hit in zip(names, always) if hit}
    allowed_set = PairSet(allowed)
    checked = (self_rows if self_collision else []) + world_rows
    keep = [(i, j) for i, j in checked if (scene.owner[i], scene.owner[j]) not in allowed_set]
    return allowed_set, np.array(keep, dtype=np.int64).reshape(-1, 2)
