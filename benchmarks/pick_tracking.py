"""The pick task under a simulated controller: how well it tracks, and how long a run takes.

    .venv/bin/python benchmarks/pick_tracking.py [--mode ct] [--repeats 3] [ROBOT ...]

For each robot (default: the four of docs/trajectories.md) the default pick task is
planned once (``default_plan``), then run ``--repeats`` times by the simulated controller
of ``--mode`` (``robot_sim.sim.pick_run.simulate_pick``, 1 ms steps).  Prints one row
per robot: the largest tool tracking error [mm], how far from its place pose the object
was let go [mm] (both the same in every run: the simulation is deterministic), the
task's length [s] and the median wall time of a run [s] with its spread.  The figures of
docs/trajectories.md ("Measured: ...") come from this script.
"""
from __future__ import annotations

import argparse
import os
import time

import numpy as np

from robot_sim.sim.pick_run import simulate_pick
from robot_sim.io.robot_file import load_robot
from robot_sim.planning.pick_task import default_plan

ROBOTS = ("ur5", "humanoid7", "panda", "puma560")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("robots", nargs="*", default=list(ROBOTS))
    parser.add_argument("--mode", default="ct", help="controller (ct, pd, pdg)")
    parser.add_argument("--repeats", type=int, default=3, help="timed runs per robot")
    args = parser.parse_args()
    print(f"load average at start: {', '.join(f'{v:.2f}' for v in os.getloadavg())}")
    print("| robot | tool error [mm] | placed from target [mm] | task [s] | run [s] (median, min..max) |")
    print("|---|---|---|---|---|")
    for name in args.robots:
        plan = default_plan(load_robot(name))
        times, run = [], None
        for _ in range(args.repeats):
            start = time.perf_counter()
            run = simulate_pick(plan, args.mode)
            times.append(time.perf_counter() - start)
        assert run is not None
        placed = 1e3 * float(np.linalg.norm(run.placed_pose[:3, 3] - plan.spec.place[:3, 3]))
        note = f" ({run.stopped})" if run.stopped else ""
        print(f"| {plan.robot.name} | {1e3 * run.tool_error:.3g} | {placed:.3g} | {plan.duration:.1f} | "
              f"{np.median(times):.1f} ({min(times):.1f}..{max(times):.1f}){note} |", flush=True)
    print(f"load average at end: {', '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
