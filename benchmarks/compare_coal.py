"""Oracle check (optional, never part of the test suite): our signed distances against coal
(the FCL fork Pinocchio uses) on random configurations of every shipped 6/7-joint arm
among random boxes, spheres, cylinders and capsules.

For every checked pair of every configuration both libraries compute the signed distance
of the same posed shapes (from ``CollisionChecker.shapes``); reported per pair kind: the
largest |ours - coal| apart and in penetration, and disagreements of in contact / not in
contact outside ±1e-6 m.  coal's EPA fails on some penetrating cylinder pairs (it returns
-DBL_MAX) and overestimates others; where coal reports a deeper penetration than ours, our
normal n is checked as an escape: the support h_{A-B}(n) of the Minkowski difference
equals our depth, so the true depth (the smallest such support) is at most ours, and
coal's larger value cannot be right ("coal deeper, ours certified").

``pip install coal`` into the venv, then ``python benchmarks/compare_coal.py [samples]``.
"""
from __future__ import annotations

import sys
from collections import defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import coal  # noqa: E402

from robot_sim.collision import Box, Capsule, CollisionChecker, Cylinder, Sphere, World  # noqa: E402
from robot_sim.collision.allowed import sample_configurations  # noqa: E402
from robot_sim.collision.distance import shape_distance  # noqa: E402
from robot_sim.collision.gjk import support  # noqa: E402
from robot_sim.collision.pack import pack  # noqa: E402
from robot_sim.io.robot_file import available_robots, load_robot  # noqa: E402

TOL = 1e-6


def coal_geom(shape):
    if isinstance(shape, Sphere):
        return coal.Sphere(shape.radius), coal.Transform3s(np.eye(3), shape.center)
    if isinstance(shape, Box):
        g = coal.Box(*shape.size)
    elif isinstance(shape, Cylinder):
        g = coal.Cylinder(shape.radius, shape.length)
    else:
        g = coal.Capsule(shape.radius, shape.length)
    return g, coal.Transform3s(shape.pose[:3, :3], shape.pose[:3, 3])


def escape_support(sa, sb, n: np.ndarray) -> float:
    """h_{A-B}(n) = h_A(n) + h_B(-n) of the full shapes (cores plus swept radii)."""
    p = pack([sa, sb])
    a = np.array(support(p.kinds[0], p.recs[0], p.verts, tuple(n))) + p.recs[0][12] * n
    b = np.array(support(p.kinds[1], p.recs[1], p.verts, tuple(-n))) - p.recs[1][12] * n
    return float(n @ (a - b))


def random_world(rng: np.random.Generator) -> World:
    items = {}
    for k in range(8):
        pose = np.eye(4)
        pose[:3, 3] = rng.uniform([-0.8, -0.8, 0.0], [0.8, 0.8, 1.0])
        kind = k % 4
        items[f"{('box', 'sphere', 'cylinder', 'capsule')[kind]}{k}"] = (
            Box(rng.uniform(0.05, 0.3, 3), pose) if kind == 0 else
            Sphere(rng.uniform(0.03, 0.15), pose[:3, 3]) if kind == 1 else
            Cylinder(rng.uniform(0.03, 0.12), rng.uniform(0.05, 0.4), pose) if kind == 2 else
            Capsule(rng.uniform(0.03, 0.12), rng.uniform(0.05, 0.4), pose))
    return World(items, floor=False)


def main() -> None:
    samples = int(sys.argv[1]) if len(sys.argv) > 1 else 50
    rng = np.random.default_rng(0)
    req = coal.DistanceRequest()
    req.enable_signed_distance = True
    req.gjk_tolerance = 1e-10  # the oracle at its tightest (default 1e-6 leaves micrometre errors on cylinders)
    req.epa_tolerance = 1e-10
    worst = defaultdict(float)
    counts = defaultdict(int)
    for name in available_robots():
        robot = load_robot(name)
        if robot.n_dofs not in (6, 7):
            continue
        checker = CollisionChecker(robot, random_world(rng))
        obstacles = dict(checker.world.obstacles)
        for q in sample_configurations(robot, samples, seed=int(rng.integers(1 << 30))):
            links = checker.shapes(q)
            by_name = defaultdict(list)
            for link, shape in links:
                by_name[link].append(shape)
            for a, b in checker.checked_pairs:
                for sa in by_name[a]:
                    for sb in (by_name[b] if b in by_name else [obstacles[b]]):
                        ours = shape_distance(sa, sb)
                        ga, ta = coal_geom(sa)
                        gb, tb = coal_geom(sb)
                        res = coal.DistanceResult()
                        theirs = coal.distance(ga, ta, gb, tb, req, res)
                        kind = f"{type(sa).__name__}-{type(sb).__name__}"
                        regime = "apart" if ours.distance > 0 else "penetrating"
                        counts[kind, regime] += 1
                        if theirs < -1e300:  # coal's EPA failed
                            counts[kind, "coal EPA failed"] += 1
                            continue
                        err = abs(ours.distance - theirs)
                        if regime == "penetrating" and theirs < ours.distance - TOL and \
                                abs(escape_support(sa, sb, ours.normal) + ours.distance) < 1e-9:
                            counts[kind, "coal deeper, ours certified"] += 1
                            continue
                        worst[kind, regime] = max(worst[kind, regime], err)
                        if (ours.distance < -TOL and theirs > TOL) or (ours.distance > TOL and theirs < -TOL):
                            counts[kind, "contact verdicts differ"] += 1
    print(f"{'pair':24s} {'regime':24s} {'pairs':>8s} {'max |ours - coal| (m)':>22s}")
    for (kind, regime), n in sorted(counts.items()):
        value = f"{worst[kind, regime]:.2e}" if (kind, regime) in worst else ""
        print(f"{kind:24s} {regime:24s} {n:8d} {value:>22s}")


if __name__ == "__main__":
    main()
