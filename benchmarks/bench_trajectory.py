"""Trajectory rows of ``make bench`` and their baseline, measured in the same run.

A Cartesian line of 1 s sampled at 1 kHz is followed through IK (``cartesian_line``:
each sample solved from the previous solution continued by the last joint step, no
restarts); the baseline solves every sample with ``solve_ik`` from the previous sample's
solution at the same tolerances, without the prediction.  Also: planning the whole
default pick task, and evaluating a trajectory at 10⁵ times (batched Hermite).
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from robot_sim.planning.cartesian import FOLLOW_MAX_ITER, FOLLOW_TOL
from robot_sim.kinematics import forward_kinematics, solve_ik
from robot_sim.planning.pick_task import default_plan, plan_pick
from robot_sim.model.params import RobotParams
from robot_sim.planning.scaling import cartesian_line

LINE_DURATION = 1.0
N_EVALUATE = 10**5


def bench_trajectory(table, robot: RobotParams, rng: np.random.Generator, measure: Callable, median_iqr: Callable,
                     ms: Callable, us: Callable) -> None:
    q0 = robot.q_home + np.linspace(0.2, -0.3, robot.n_dofs)
    T0 = forward_kinematics(robot, q0)
    T1 = T0.copy()
    T1[:3, 3] += [0.08, -0.05, -0.12]
    line = cartesian_line(robot, T0, T1, LINE_DURATION, q0)
    n = line.n_samples

    def baseline() -> None:
        q = q0
        for pose in line.poses:
            q = solve_ik(robot, pose, q, max_restarts=0, max_iter=FOLLOW_MAX_ITER, tol_pos=FOLLOW_TOL, tol_rot=FOLLOW_TOL).q

    med, iqr = median_iqr(measure(lambda: cartesian_line(robot, T0, T1, LINE_DURATION, q0), repeats=5))
    base, _ = median_iqr(measure(baseline, repeats=3))
    table.add(f"`cartesian_line` {robot.name}, {n} samples (IK per sample)", us(med / n) + "/sample",
              us(iqr / n), f"IK from the last sample: {us(base / n)}/sample", f"{base / med:.1f}×")
    plan = default_plan(robot)
    med, iqr = median_iqr(measure(lambda: plan_pick(robot, plan.spec), repeats=3))
    table.add(f"`plan_pick` {robot.name} default task ({plan.trajectory.n_samples} samples)", ms(med), ms(iqr))
    times = rng.uniform(0.0, plan.duration, N_EVALUATE)
    med, iqr = median_iqr(measure(lambda: plan.trajectory.evaluate(times), repeats=10))
    table.add(f"`Trajectory.evaluate` at {N_EVALUATE:,} times", us(med / N_EVALUATE * 1e3) + "/1000", us(iqr / N_EVALUATE * 1e3))
