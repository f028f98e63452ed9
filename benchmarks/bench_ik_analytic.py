"""Rows of ``make bench`` for the analytic IK (issue 29), each floor of the issue with a
baseline measured in the same run, alternated, and whether the floor is met:

* one pose from Python (at most 10 µs on UR5, PUMA 560 and KR 6), against EAIK and
  ik-geo on the same arm's bare DH table when they are installed
  (``benchmarks/compare_analytic_ik.py``; oracles, never dependencies);
* a batch of 10⁵ poses (at most 1 µs of wall time per pose, on one thread per core:
  :mod:`robot_sim.ik.threads`), against the same poses solved one at a time from Python;
* ``solve_ik`` (at least 50× faster than its numerical path) and the default UR5 pick
  task (at most a quarter of the time; Panda's beside it, no floor), against the same
  code with the closed form switched off (``answers`` and ``follows`` patched to False)."""
from __future__ import annotations

import time
from contextlib import contextmanager
from typing import Callable, Iterator

import numpy as np

import robot_sim.ik.nearest as nearest
import robot_sim.planning.pose_goal as pose_goal
from robot_sim.ik.solutions import ik_solutions
from robot_sim.ik.threads import cores
from robot_sim.io.robot_file import load_robot
from robot_sim.kinematics import forward_kinematics, random_configurations, solve_ik
from robot_sim.planning.pick_task import default_task, plan_pick

ONE_POSE = ("ur5", "puma560", "kr6_r900")
BATCH = 100_000
POSES = 300


@contextmanager
def numerical_only() -> Iterator[None]:
    """The package as before the closed form: every IK question answered numerically."""
    saved = nearest.answers, pose_goal.answers, nearest.follows
    nearest.answers = pose_goal.answers = lambda robot, position_only: False
    nearest.follows = lambda robot: False
    try:
        yield
    finally:
        nearest.answers, pose_goal.answers, nearest.follows = saved


def _per_call(fn: Callable[[np.ndarray], object], targets: np.ndarray) -> list[float]:
    times = []
    for t in targets:
        start = time.perf_counter()
        fn(t)
        times.append(time.perf_counter() - start)
    return times


def verdict(met: bool) -> str:
    return "met" if met else "NOT met"


def _oracle_baseline(name: str, rng: np.random.Generator, ours: Callable[[np.ndarray], object],
                     ours_targets: np.ndarray, us) -> tuple[list[float], str]:  # noqa: ANN001
    """Ours per pose, alternated per pose with EAIK and ik-geo on the bare arm (medians),
    where they are installed."""
    try:
        from compare_analytic_ik import oracles

        bare, eaik_ik, geo_ik = oracles(name)
    except ImportError:
        return _per_call(ours, ours_targets), "EAIK, ik-geo not installed"
    targets = forward_kinematics(bare, rng.uniform(-np.pi, np.pi, (len(ours_targets), 6)))
    eaik_ik(targets[0])
    geo_ik(targets[0])
    mine, theirs, geos = [], [], []
    for t, u in zip(ours_targets, targets):
        for fn, pose, into in ((ours, t, mine), (eaik_ik, u, theirs), (geo_ik, u, geos)):
            start = time.perf_counter()
            fn(pose)
            into.append(time.perf_counter() - start)
    return mine, f"EAIK {us(float(np.median(theirs)))}, ik-geo {us(float(np.median(geos)))}"


def bench_ik_analytic(table, median_iqr, ms, us) -> None:  # noqa: ANN001
    rng = np.random.default_rng(29)
    for name in ONE_POSE:
        robot = load_robot(name)
        targets = forward_kinematics(robot, random_configurations(robot, POSES, rng))
        for within in (False, True):
            def ours(t: np.ndarray, within: bool = within) -> object:
                return ik_solutions(robot, t, within_limits=within)

            ours(targets[0])
            times, baseline = _oracle_baseline(name, rng, ours, targets, us)
            count = np.mean([len(ours(t)) for t in targets[:50]])
            med, iqr = median_iqr(times)
            what = "every turn inside the limits" if within else "raw branches"
            table.add(f"analytic IK {name}, one pose from Python ({what}, {count:.1f} solutions)",
                      us(med), us(iqr), baseline, "—", f"≤ 10 µs: {verdict(med <= 10e-6)}")
    # every arm's raw branches, and within the limits where a batch of 10^5 fits in the output
    # (UR5's ±2π joints give 512 solutions a pose: 3·10^8 joint values, over MAX_VALUES)
    for name, within in (("puma560", True), ("kr6_r900", True), ("puma560", False), ("kr6_r900", False),
                         ("ur5", False)):
        robot = load_robot(name)
        T = forward_kinematics(robot, random_configurations(robot, BATCH, rng))
        ik_solutions(robot, T, within_limits=within)  # compiled, and the process's first 10^8 bytes mapped
        walls, cpus, singles = [], [], []
        for _ in range(5):  # alternated: the batch, then a share of its poses one at a time
            start, cpu = time.perf_counter(), time.process_time()
            ik_solutions(robot, T, within_limits=within)
            walls.append((time.perf_counter() - start) / BATCH)
            cpus.append((time.process_time() - cpu) / BATCH)
            singles += _per_call(lambda t: ik_solutions(robot, t, within_limits=within), T[:1000])
        med, iqr = median_iqr(walls)
        single = float(np.median(singles))
        table.add(f"analytic IK {name}, batch of 10^5 poses ({'within limits' if within else 'raw branches'}), "
                  f"wall per pose on {cores()} threads (CPU of all threads {us(median_iqr(cpus)[0])})",
                  us(med), us(iqr), f"one at a time {us(single)}", f"{single / med:.1f}×",
                  f"≤ 1 µs: {verdict(med <= 1e-6)}")
    for name in ONE_POSE:
        robot = load_robot(name)
        targets = forward_kinematics(robot, random_configurations(robot, 60, rng))
        ok = sum(solve_ik(robot, t).success for t in targets)
        (f, fi), (s, _) = alternated([lambda t=t: solve_ik(robot, t) for t in targets], median_iqr)
        table.add(f"solve_ik {name}: analytic (success {100 * ok / len(targets):.0f} %) vs numerical path",
                  us(f), us(fi), f"numerical {ms(s)}", f"{s / f:.0f}×", f"≥ 50×: {verdict(s / f >= 50)}")
    for name in ("ur5", "panda"):  # Panda: a 7-joint arm, its lines on the closed form with the free joint held
        robot = load_robot(name)
        spec = default_task(robot)
        (f, fi), (s, _) = alternated([lambda: plan_pick(robot, spec)], median_iqr, time.process_time)
        floor = f"≥ 4×: {verdict(s / f >= 4)}" if name == "ur5" else "—"
        table.add(f"default {robot.name} pick task planned (CPU): analytic IK vs numerical", ms(f), ms(fi),
                  f"numerical {ms(s)}", f"{s / f:.1f}×", floor)


def alternated(calls: list[Callable[[], object]], median_iqr, clock: Callable[[], float] = time.perf_counter,
               rounds: int = 3) -> tuple:  # noqa: ANN001
    """(median, IQR) of each call with the closed form, then without: ``rounds`` times the
    block of every call with it, then the block without it (a call's time includes what a
    user's repeated calls would see, not the caches the other path left behind)."""
    fast, slow = [], []
    for _ in range(rounds):
        for call in calls:
            start = clock()
            call()
            fast.append(clock() - start)
        with numerical_only():
            for call in calls:
                start = clock()
                call()
                slow.append(clock() - start)
    return median_iqr(fast), median_iqr(slow)
