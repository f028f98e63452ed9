"""Rows of ``make bench`` for general 6R arms (issue 29, item 3): every real solution of
one pose from Python, and solve_ik on such an arm against its numerical path (the
closed form switched off, alternated in one run)."""
from __future__ import annotations

import time

import numpy as np

from bench_ik_analytic import alternated
from robot_sim.ik.solutions import ik_solutions
from robot_sim.kinematics import forward_kinematics, solve_ik
from robot_sim.model.params import RobotParams

TABLES = 5
POSES = 100


def random_6r(rng: np.random.Generator) -> RobotParams:
    """A 6R table whose axes neither meet nor run parallel (no closed form)."""
    signs = lambda: rng.choice([-1.0, 1.0], 6)  # noqa: E731
    return RobotParams.from_arrays("bench 6R", rng.uniform(0.05, 0.5, 6) * signs(), rng.uniform(0.3, 2.8, 6) * signs(),
                                   rng.uniform(0.05, 0.4, 6) * signs(), rng.uniform(-np.pi, np.pi, 6), np.zeros(6),
                                   q_min=np.full(6, -np.pi), q_max=np.full(6, np.pi))


def bench_ik_general(table, median_iqr, ms, us) -> None:  # noqa: ANN001
    rng = np.random.default_rng(296)
    times, counts, solve_calls = [], [], []
    for _ in range(TABLES):
        robot = random_6r(rng)
        targets = forward_kinematics(robot, rng.uniform(-np.pi, np.pi, (POSES, 6)))
        ik_solutions(robot, targets[0])
        for t in targets:
            start = time.perf_counter()
            sols = ik_solutions(robot, t)
            times.append(time.perf_counter() - start)
            counts.append(sols.count)
        solve_calls += [lambda robot=robot, t=t: solve_ik(robot, t) for t in targets[:12]]
    med, iqr = median_iqr(times)
    table.add(f"general 6R pose: median µs with every real solution ({np.mean(counts):.1f} solutions, "
              f"up to {max(counts)})", us(med), us(iqr), "—", "—", "≤ 200 µs")
    (f, fi), (s, _) = alternated(solve_calls, median_iqr)
    table.add("solve_ik general 6R: every real solution, nearest taken, vs numerical path", us(f), us(fi),
              f"numerical {ms(s)}", f"{s / f:.0f}×", "faster")
