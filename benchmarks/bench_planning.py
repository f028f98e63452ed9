"""Planning benchmark (``make bench`` rows, or standalone): ``plan_path`` on random
scenes (``planning_scenes.py``: a table, 3–8 boxes and cylinders, start and goal that
they separate) for Panda, UR5 and humanoid7.

Per robot: success rate within 1 s, median planning time (wall, and the process's CPU
time, which a loaded machine inflates less) and configurations checked;
every returned path is checked at 1 mm of measured motion (forward kinematics, not the
planner's bound) with the checker's batched ``in_collision``, and the first
``--coal`` of them, independently, with coal's distances (``coal_check.py``; skipped
where the optional ``coal`` is not installed).  Also
``retime`` of the planned paths (median time and trajectory duration).

    PYOPENGL_PLATFORM=osmesa .venv/bin/python benchmarks/bench_planning.py [--scenes 100] [--coal 10]
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

import coal_check  # noqa: E402
from planning_scenes import ROBOTS, make_scene  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.planning.retime import retime  # noqa: E402
from robot_sim.planning.rrt import plan_path  # noqa: E402

TIME_LIMIT = 1.0


def run(name: str, scenes: int, coal_paths: int, seed: int = 7) -> dict:
    """Plan ``scenes`` random problems for robot ``name``; the figures as a dict."""
    robot = load_robot(name)
    rng = np.random.default_rng(seed)
    times, cpu, checks, ok, fine_bad, coal_bad, coal_done, rt_times, durations = [], [], [], 0, 0, 0, 0, [], []
    for k in range(scenes):
        scene = make_scene(robot, rng)
        c0 = time.process_time()
        res = plan_path(robot, scene.q_start, scene.q_goal, scene.checker, time_limit=TIME_LIMIT, seed=k)
        cpu.append(time.process_time() - c0)
        times.append(res.planning_time)
        checks.append(res.checks)
        if not res.success:
            continue
        ok += 1
        coal = coal_check.CoalCheck(scene.checker)
        dense = coal.dense(res.path)
        fine_bad += bool(np.any(scene.checker.in_collision(dense)))
        if coal_check.coal is not None and coal_done < coal_paths:
            coal_done += 1
            coal_bad += not coal.path_free(res.path)[0]
        t0 = time.perf_counter()
        traj = retime(robot, res.path)
        rt_times.append(time.perf_counter() - t0)
        durations.append(traj.duration)
    return {
        "robot": name, "scenes": scenes, "solved": ok, "median_ms": statistics.median(times) * 1e3,
        "p90_ms": float(np.percentile(times, 90)) * 1e3, "cpu_median_ms": statistics.median(cpu) * 1e3,
        "median_checks": statistics.median(checks),
        "colliding_at_1mm": fine_bad, "coal_checked": coal_done, "coal_colliding": coal_bad,
        "retime_median_ms": statistics.median(rt_times) * 1e3 if rt_times else float("nan"),
        "duration_median_s": statistics.median(durations) if durations else float("nan"),
    }


def describe(r: dict) -> str:
    return (f"{r['robot']}: {r['solved']}/{r['scenes']} solved within {TIME_LIMIT:g} s "
            f"({100 * r['solved'] / r['scenes']:.1f} %), planning time median {r['median_ms']:.1f} ms "
            f"(p90 {r['p90_ms']:.1f} ms; CPU time median {r['cpu_median_ms']:.1f} ms), "
            f"{r['median_checks']:.0f} configurations checked (median); "
            f"paths colliding at 1 mm: {r['colliding_at_1mm']} (checker), {r['coal_colliding']}/{r['coal_checked']} "
            f"(coal); retime {r['retime_median_ms']:.0f} ms, trajectory {r['duration_median_s']:.2f} s (medians)")


def bench_planning(table, scenes: int = 30, coal_paths: int = 3) -> None:
    """Rows of ``make bench``."""
    for name in ROBOTS:
        r = run(name, scenes, coal_paths)
        table.add(f"`plan_path` {name}, {scenes} random table scenes (median)", f"{r['median_ms']:.1f} ms",
                  f"p90 {r['p90_ms']:.1f} ms", f"CPU median {r['cpu_median_ms']:.1f} ms; solved {r['solved']}/{scenes} in 1 s; free at 1 mm: "
                  f"{r['solved'] - r['colliding_at_1mm']}/{r['solved']}", target="≤ 20 ms, ≥ 99 %")
        table.add(f"`retime` of those paths, {name} (TOPP-RA, effort limits)", f"{r['retime_median_ms']:.0f} ms", "—",
                  f"trajectory {r['duration_median_s']:.2f} s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=100)
    parser.add_argument("--coal", type=int, default=10, help="paths per robot checked with coal")
    parser.add_argument("--robots", nargs="*", default=list(ROBOTS))
    args = parser.parse_args()
    for name in args.robots:
        print(describe(run(name, args.scenes, args.coal)), flush=True)


if __name__ == "__main__":
    main()
