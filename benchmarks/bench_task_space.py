"""Benchmark rows of task-space control (called by bench.py; runnable alone for a quick look).

One 1 kHz RK4 step of humanoid7 under operational-space control against the same step
under computed torque, both toward a set point away from the start.  OSC is a
continuous-time law, evaluated at each of the four RK4 stages (its own closed-loop
acceleration, so no forward dynamics); computed torque is evaluated once and needs three
forward dynamics.  Medians of samples taken alternately (OSC, computed torque, OSC, ...), so
both see the same machine load; the ratio is also given as the median of the pairs'
ratios, which a load change between samples disturbs least.  Also the batched evaluation of the OSC law on 1000
configurations, per configuration, and one BatchSimulation step of 100 arms under OSC
(the law at every RK4 stage, batched), per arm.
"""
from __future__ import annotations

import os
import sys
import time
from pathlib import Path
from typing import Any, Callable

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from robot_sim.sim.batch import BatchSimulation  # noqa: E402
from robot_sim.control.factory import make_controller  # noqa: E402
from robot_sim.sim.simulation import Simulation  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.kinematics import forward_kinematics  # noqa: E402

STEPS = 10  # steps per sample (a short sample is rarely hit by another process's time slice)
SAMPLES = 200  # samples of each, alternated, so a pair sees the same load
BATCH = 1000
ARMS = 100  # arms of the BatchSimulation row


def _simulation(robot: Any, mode: str) -> Simulation:
    sim = Simulation(robot, controller=make_controller(mode, robot), integrator="rk4", dt=1e-3)
    sim.state.set_q_des(robot.q_home + 0.3)  # a set point away from the start: the arm moves
    return sim


def _alternated(runs: dict[str, Callable[[], object]]) -> dict[str, list[float]]:
    """Seconds per call of each run, sampled in turn SAMPLES times."""
    for run in runs.values():
        run()  # warm up
    samples: dict[str, list[float]] = {key: [] for key in runs}
    for _ in range(SAMPLES):
        for key, run in runs.items():
            start = time.perf_counter()
            run()
            samples[key].append(time.perf_counter() - start)
    return samples


def bench_task_space(table: Any, us: Callable[[float], str]) -> None:
    robot = load_robot("humanoid7")
    osc, ct = _simulation(robot, "osc"), _simulation(robot, "ct")
    samples = _alternated({"osc": lambda: osc.step(STEPS), "ct": lambda: ct.step(STEPS)})
    med = {key: float(np.median(v)) / STEPS for key, v in samples.items()}
    iqr = float(np.subtract(*np.percentile(samples["osc"], [75, 25]))) / STEPS
    ratio = np.array(samples["osc"]) / np.array(samples["ct"])  # each OSC sample over the CT sample after it
    table.add("simulation step, humanoid7, 1 kHz, RK4 + operational space (4 law evaluations)",
              us(med["osc"]), us(iqr), us(med["ct"]) + " (computed torque)",
              f"{med['osc'] / med['ct']:.2f}× computed torque (pairs: {np.median(ratio):.2f}×)", "≤ 1.5× computed torque")
    controller = make_controller("osc", robot)
    rng = np.random.default_rng(0)
    Q = robot.q_home + rng.uniform(-0.3, 0.3, (BATCH, robot.n_dofs))
    QD = rng.uniform(-0.5, 0.5, (BATCH, robot.n_dofs))
    pose, zero = forward_kinematics(robot, robot.q_home), np.zeros(6)
    batch = _alternated({"batch": lambda: controller.torque(Q, QD, pose, zero, zero),
                         "single": lambda: controller.torque(Q[0], QD[0], pose, zero, zero)})
    per = float(np.median(batch["batch"])) / BATCH
    table.add(f"operational-space torque, humanoid7, batched over {BATCH} configurations, per configuration",
              us(per), us(float(np.subtract(*np.percentile(batch["batch"], [75, 25]))) / BATCH),
              us(float(np.median(batch["single"]))) + " (one call)", f"{np.median(batch['single']) / per:.1f}×")

    arms = BatchSimulation(robot, ARMS, "osc")
    arms.set_state(Q[:ARMS])
    arms.set_reference(q=robot.q_home + 0.3)
    stepped = _alternated({"batch": lambda: arms.step(5)})["batch"]
    table.add(f"BatchSimulation step, humanoid7, {ARMS} arms under operational space, RK4, per arm",
              us(float(np.median(stepped)) / (5 * ARMS)), us(float(np.subtract(*np.percentile(stepped, [75, 25]))) / (5 * ARMS)),
              us(med["osc"]) + " (Simulation, one arm)", f"{med['osc'] / (float(np.median(stepped)) / (5 * ARMS)):.1f}×")


if __name__ == "__main__":
    from timing import Table, us as fmt

    rows = Table()
    bench_task_space(rows, fmt)
    rows.print()
