"""Optional oracle: OMPL's RRT-Connect (``pip install ompl``; never a dependency of the
suite) on the scenes of ``bench_planning.py``, with the same CollisionChecker: states
checked with ``in_collision``, motions with OMPL's discrete motion validator at the
checker's continuous resolution (the same step bound ``path_is_free`` uses), then
OMPL's own path simplification.  Prints success rates, median planning times and the
ratio to ``plan_path``.

    PYOPENGL_PLATFORM=osmesa .venv/bin/python benchmarks/oracle_ompl.py [--scenes 10]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from ompl import base as ob  # noqa: E402
from ompl import geometric as og  # noqa: E402
from ompl import util as ou  # noqa: E402

from planning_scenes import ROBOTS, make_scene  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.kinematics import sampling_bounds  # noqa: E402
from robot_sim.planning.edges import motion_bound  # noqa: E402
from robot_sim.planning.rrt import plan_path  # noqa: E402

TIME_LIMIT = 1.0


def ompl_plan(robot, scene, time_limit: float = TIME_LIMIT) -> tuple[bool, float, float]:
    """(solved, wall seconds of the search, wall seconds with OMPL's path simplification)
    of OMPL RRT-Connect on ``scene``."""
    n = robot.n_dofs
    lo, hi = sampling_bounds(robot)
    lo, hi = np.minimum(lo, np.minimum(scene.q_start, scene.q_goal)), np.maximum(hi, np.maximum(scene.q_start, scene.q_goal))
    radii, resolution = motion_bound(scene.checker, lo, hi)
    space = ob.RealVectorStateSpace(n)
    bounds = ob.RealVectorBounds(n)
    for j in range(n):
        bounds.setLow(j, float(lo[j]))
        bounds.setHigh(j, float(hi[j]))
    space.setBounds(bounds)
    # the motion validator's step is a fraction of the space's extent; pick it so that a
    # step along the worst joint moves no point more than the checker's resolution
    space.setLongestValidSegmentFraction(float(resolution / radii.max() / space.getMaximumExtent()))
    setup = og.SimpleSetup(space)
    checker = scene.checker

    def valid(state) -> bool:
        return not checker.in_collision(np.array([state[j] for j in range(n)]))

    setup.setStateValidityChecker(valid)
    start, goal = space.allocState(), space.allocState()
    for j in range(n):
        start[j], goal[j] = float(scene.q_start[j]), float(scene.q_goal[j])
    setup.setStartAndGoalStates(start, goal)
    setup.setPlanner(og.RRTConnect(setup.getSpaceInformation()))
    t0 = time.perf_counter()
    solved = setup.solve(time_limit)
    searched = time.perf_counter() - t0
    ok = bool(solved) and setup.haveExactSolutionPath()
    if ok:
        setup.simplifySolution()
    return ok, searched, time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=10)
    args = parser.parse_args()
    ou.setLogLevel(ou.LOG_WARN)
    for name in ROBOTS:
        robot = load_robot(name)
        rng = np.random.default_rng(7)
        ours, theirs = [], []
        for k in range(args.scenes):
            scene = make_scene(robot, rng)
            res = plan_path(robot, scene.q_start, scene.q_goal, scene.checker, seed=k)
            ours.append((res.success, res.planning_time))
            theirs.append(ompl_plan(robot, scene))
        mine = statistics.median(t for ok, t in ours if ok) if any(ok for ok, _ in ours) else float("nan")
        solved = [run for run in theirs if run[0]]
        search = statistics.median(run[1] for run in solved) if solved else float("nan")
        total = statistics.median(run[2] for run in solved) if solved else float("nan")
        print(f"{name}: plan_path {sum(ok for ok, _ in ours)}/{args.scenes} solved in {TIME_LIMIT:g} s, median "
              f"{mine * 1e3:.1f} ms (search, shortcutting and smoothing); OMPL RRT-Connect {len(solved)}/"
              f"{args.scenes}, median {search * 1e3:.1f} ms search, {total * 1e3:.1f} ms with its simplification; "
              f"ratio OMPL search / ours {search / mine:.2f}", flush=True)

if __name__ == "__main__":
    main()
