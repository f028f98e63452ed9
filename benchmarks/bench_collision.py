"""Collision rows of ``make bench``: a 7-joint capsule arm (Panda's DH capsules, self pairs
included) among 10 primitive obstacles (boxes, spheres, cylinders, capsules).

* batched ``in_collision`` and ``distance`` at N = 10⁵, µs per configuration (targets 2 and 5);
* one configuration through the public API (target 50 µs);
* the broad phase: the share of (pair, configuration) tests it skips;
* the baseline, when ``coal`` is installed (never a dependency): coal's ``collide`` called
  pair by pair on the same shapes at the same configurations, in the same run (target:
  ours at least 10x faster).

Run alone: ``python benchmarks/bench_collision.py``.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from robot_sim.collision import Box, Capsule, CollisionChecker, Cylinder, Sphere, World  # noqa: E402
from robot_sim.collision.allowed import sample_configurations  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402

N_BATCH = 10**5
N_SINGLE = 2000
N_COAL = 2000


def scene(seed: int = 1) -> CollisionChecker:
    """Panda among 10 obstacles around its workspace (no floor: primitives only)."""
    rng = np.random.default_rng(seed)
    items = {}
    for k in range(10):
        pose = np.eye(4)
        pose[:3, 3] = rng.uniform([-0.8, -0.8, 0.0], [0.8, 0.8, 1.0])
        kind = k % 4
        items[f"o{k}"] = (Box(rng.uniform(0.05, 0.2, 3), pose) if kind == 0 else
                          Sphere(rng.uniform(0.03, 0.1), pose[:3, 3]) if kind == 1 else
                          Cylinder(rng.uniform(0.03, 0.1), rng.uniform(0.05, 0.3), pose) if kind == 2 else
                          Capsule(rng.uniform(0.03, 0.1), rng.uniform(0.05, 0.3), pose))
    return CollisionChecker(load_robot("panda"), World(items, floor=False))


def _coal_objects(checker: CollisionChecker, q: np.ndarray):
    import coal

    def geom(shape):
        if isinstance(shape, Sphere):
            return coal.Sphere(shape.radius), np.eye(3), shape.center
        if isinstance(shape, Box):
            g = coal.Box(*shape.size)
        elif isinstance(shape, Cylinder):
            g = coal.Cylinder(shape.radius, shape.length)
        else:
            g = coal.Capsule(shape.radius, shape.length)
        return g, shape.pose[:3, :3], shape.pose[:3, 3]

    robot = [(name, geom(s)) for name, s in checker.shapes(q)]
    world = [(name, geom(s)) for name, s in checker.world.obstacles]
    return robot + world


def coal_in_collision(checker: CollisionChecker, Q: np.ndarray) -> tuple[np.ndarray, float]:
    """coal's verdict per configuration (pair by pair, stopping at the first hit), and its
    seconds per configuration (shape placement not counted)."""
    import coal

    owner_pairs = set(checker.checked_pairs)
    req = coal.CollisionRequest()
    out = np.zeros(len(Q), dtype=bool)
    spent = 0.0
    for k, q in enumerate(Q):
        objs = _coal_objects(checker, q)
        tfs = [coal.Transform3s(R, t) for _, (g, R, t) in objs]
        pairs = [(i, j) for i in range(len(objs)) for j in range(i + 1, len(objs))
                 if (objs[i][0], objs[j][0]) in owner_pairs]
        start = time.perf_counter()
        for i, j in pairs:
            res = coal.CollisionResult()
            if coal.collide(objs[i][1][0], tfs[i], objs[j][1][0], tfs[j], req, res):
                out[k] = True
                break
        spent += time.perf_counter() - start
    return out, spent / len(Q)


def bench_collision(table, measure, median_iqr, us) -> None:
    checker = scene()
    Q = sample_configurations(checker.robot, N_BATCH, seed=3)
    checker.in_collision(Q[:10])
    checker.distance(Q[:10])
    med, iqr = median_iqr(measure(lambda: checker.in_collision(Q), 3))
    table.add(f"collision: in_collision, panda + 10 obstacles, N={N_BATCH:.0e} (per config)", us(med / N_BATCH),
              us(iqr / N_BATCH), target="≤ 2 µs")
    ours_batched = med / N_BATCH
    med, iqr = median_iqr(measure(lambda: checker.distance(Q), 3))
    table.add(f"collision: distance, N={N_BATCH:.0e} (per config)", us(med / N_BATCH), us(iqr / N_BATCH),
              target="≤ 5 µs")
    single = Q[:N_SINGLE]
    med, iqr = median_iqr(measure(lambda: [checker.in_collision(q) for q in single], 3))
    table.add("collision: in_collision, one configuration", us(med / N_SINGLE), us(iqr / N_SINGLE), target="≤ 50 µs")
    med, iqr = median_iqr(measure(lambda: [checker.distance(q) for q in single], 3))
    table.add("collision: distance with witness points, one configuration", us(med / N_SINGLE), us(iqr / N_SINGLE))
    checker.stats[:] = 0
    hits = checker.in_collision(Q)
    looked, skipped = (int(x) for x in checker.stats)
    table.add("collision: broad phase, pair tests skipped", f"{skipped / max(looked, 1):.1%} of {looked}",
              "—", ratio=f"{hits.mean():.0%} of configs in collision")
    try:
        import coal  # noqa: F401
    except ImportError:
        table.add("collision: coal pair by pair (baseline)", "coal not installed", "—")
        return
    verdict, per_config = coal_in_collision(checker, Q[:N_COAL])
    agree = float(np.mean(verdict == hits[:N_COAL]))
    table.add("collision: coal collide pair by pair (per config)", us(per_config), "—",
              baseline=us(per_config), ratio=f"{per_config / ours_batched:.0f}x (ours batched); agree {agree:.1%}",
              target="≥ 10x")


if __name__ == "__main__":
    from timing import Table, measure, median_iqr, us

    t = Table()
    bench_collision(t, measure, median_iqr, us)
    t.print()
