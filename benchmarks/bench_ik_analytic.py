"""Rows of ``make bench`` for the analytic IK (issue 29): one pose from Python, a batch of
10⁵ poses, solve_ik against its numerical path, and the default UR5 pick task planned
with and without the closed form.  "Without" runs the same code with the closed form
switched off (``answers`` patched to False), alternated with "with" in one run."""
from __future__ import annotations

import time
from contextlib import contextmanager
from typing import Callable, Iterator

import numpy as np

import robot_sim.ik.nearest as nearest
import robot_sim.planning.pose_goal as pose_goal
from robot_sim.ik.solutions import ik_solutions
from robot_sim.io.robot_file import load_robot
from robot_sim.kinematics import forward_kinematics, random_configurations, solve_ik
from robot_sim.planning.pick_task import default_task, plan_pick

ONE_POSE = ("ur5", "puma560", "kr6_r900")
BATCH = 100_000
POSES = 300


@contextmanager
def numerical_only() -> Iterator[None]:
    """The package as before the closed form: every IK question answered numerically."""
    saved = nearest.answers, pose_goal.answers
    nearest.answers = pose_goal.answers = lambda robot, position_only: False
    try:
        yield
    finally:
        nearest.answers, pose_goal.answers = saved


def _per_call(fn: Callable[[np.ndarray], object], targets: np.ndarray) -> list[float]:
    times = []
    for t in targets:
        start = time.perf_counter()
        fn(t)
        times.append(time.perf_counter() - start)
    return times


def bench_ik_analytic(table, median_iqr, ms, us) -> None:  # noqa: ANN001
    rng = np.random.default_rng(29)
    for name in ONE_POSE:
        robot = load_robot(name)
        targets = forward_kinematics(robot, random_configurations(robot, POSES, rng))
        for within in (False, True):
            ik_solutions(robot, targets[0], within_limits=within)
            times = _per_call(lambda t: ik_solutions(robot, t, within_limits=within), targets)
            count = np.mean([len(ik_solutions(robot, t, within_limits=within)) for t in targets[:50]])
            med, iqr = median_iqr(times)
            what = "every turn inside the limits" if within else "raw branches"
            table.add(f"analytic IK {name}, one pose from Python ({what}, {count:.1f} solutions)",
                      us(med), us(iqr), "—", "—", "≤ 10 µs (EAIK 5.0-6.0 µs, ik-geo 5.3-5.6 µs)")
    for name, within in (("puma560", True), ("ur5", False)):
        robot = load_robot(name)
        T = forward_kinematics(robot, random_configurations(robot, BATCH, rng))
        ik_solutions(robot, T[:10], within_limits=within)
        runs = []
        for _ in range(3):  # CPU time: on a shared machine a second-long run's wall time counts the others
            start = time.process_time()
            ik_solutions(robot, T, within_limits=within)
            runs.append((time.process_time() - start) / BATCH)
        med, iqr = median_iqr(runs)
        table.add(f"analytic IK {name}, batch of 10^5 poses ({'within limits' if within else 'raw branches'}), "
                  "CPU per pose",
                  us(med), us(iqr), "—", "—", "≤ 1 µs")
    for name in ONE_POSE:
        robot = load_robot(name)
        targets = forward_kinematics(robot, random_configurations(robot, 60, rng))
        ok = sum(solve_ik(robot, t).success for t in targets)
        (f, fi), (s, _) = alternated([lambda t=t: solve_ik(robot, t) for t in targets], median_iqr)
        table.add(f"solve_ik {name}: analytic (success {100 * ok / len(targets):.0f} %) vs numerical path",
                  us(f), us(fi), f"numerical {ms(s)}", f"{s / f:.0f}×", "≥ 50×")
    robot = load_robot("ur5")
    spec = default_task(robot)
    (f, fi), (s, _) = alternated([lambda: plan_pick(robot, spec)] * 3, median_iqr, time.process_time)
    table.add("default UR5 pick task planned (CPU): analytic IK vs numerical", ms(f), ms(fi), f"numerical {ms(s)}",
              f"{s / f:.1f}×", "≥ 4×")


def alternated(calls: list[Callable[[], object]], median_iqr, clock: Callable[[], float] = time.perf_counter) -> tuple:  # noqa: ANN001,E501
    """(median, IQR) of each call with the closed form, then without, alternated per call."""
    fast, slow = [], []
    for call in calls:
        start = clock()
        call()
        fast.append(clock() - start)
        with numerical_only():
            start = clock()
            call()
            slow.append(clock() - start)
    return median_iqr(fast), median_iqr(slow)
