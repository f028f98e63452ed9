"""Benchmark suite: one table of medians, spreads and, where it applies, a baseline.

Run with ``make bench`` (or ``PYOPENGL_PLATFORM=osmesa .venv/bin/python benchmarks/bench.py``).
Every figure is the median over repeated runs with the interquartile range as spread.
The kinematics rows carry, measured in the same run, a straightforward per-link NumPy
baseline implemented here (build each 4×4 DH matrix, multiply along the chain, one
configuration at a time) and the speed-up over it.  Timing lives here, never in tests.
"""
from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import time
import tracemalloc
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("PYOPENGL_PLATFORM", "osmesa")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as simulator.py sets it for the renderer

import numpy as np  # noqa: E402

from robot_sim.kinematics import (
    Kinematics,
    forward_kinematics,
    jacobian,
    random_configurations,
    solve_ik,
)
from bench_dynamics import bench_dynamics  # noqa: E402
from bench_ik_analytic import bench_ik_analytic  # noqa: E402
from bench_ik_general import bench_ik_general  # noqa: E402
from bench_planning import bench_planning  # noqa: E402
from bench_trajectory import bench_trajectory  # noqa: E402
from robot_sim.model.convert import to_modified, to_standard  # noqa: E402
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.io.robot_file import available_robots, load_robot  # noqa: E402
from robot_sim.model.state import RobotState  # noqa: E402
import bench_render  # noqa: E402  (benchmarks/ is on sys.path when bench.py runs)
import bench_sim  # noqa: E402
from bench_collision import bench_collision  # noqa: E402
from bench_task_space import bench_task_space  # noqa: E402
from bench_contact import bench_contact  # noqa: E402
from bench_calibration import bench_calibration  # noqa: E402
from timing import Table, measure, median_iqr, ms, us  # noqa: E402

ROBOT = "humanoid7"
IK_TARGETS = 200


# ----------------------------------------------------------------------------- baseline


def naive_dh(theta: float, d: float, a: float, alpha: float) -> np.ndarray:
    """One standard DH matrix, written out as a literal."""
    ct, st, ca, sa = math.cos(theta), math.sin(theta), math.cos(alpha), math.sin(alpha)
    return np.array([
        [ct, -st * ca, st * sa, a * ct],
        [st, ct * ca, -ct * sa, a * st],
        [0.0, sa, ca, d],
        [0.0, 0.0, 0.0, 1.0],
    ])


def naive_fk(robot: RobotParams, q: np.ndarray) -> list[np.ndarray]:
    """Per-link baseline: world frames 0..n and the endeffector for one configuration."""
    frames = [robot.base_tf.mat]
    for i in range(robot.n_dofs):
        revolute = robot.jtype[i] == JTYPE_REVOLUTE
        theta = robot.dh_th[i] + (q[i] if revolute else 0.0)
        d = robot.dh_d[i] + (0.0 if revolute else q[i])
        frames.append(frames[-1] @ naive_dh(theta, d, robot.dh_a[i], robot.dh_alpha[i]))
    frames.append(frames[-1] @ robot.tool_tf.mat)
    return frames


def naive_jacobian(robot: RobotParams, q: np.ndarray) -> np.ndarray:
    """Per-link baseline Jacobian (6, n) with np.cross, one configuration."""
    frames = naive_fk(robot, q)
    p_e = frames[-1][:3, 3]
    columns = []
    for i in range(robot.n_dofs):
        z, p = frames[i][:3, 2], frames[i][:3, 3]
        if robot.jtype[i] == JTYPE_REVOLUTE:
            columns.append(np.concatenate([np.cross(z, p_e - p), z]))
        else:
            columns.append(np.concatenate([z, np.zeros(3)]))
    return np.array(columns).T


def naive_ik(robot: RobotParams, target: np.ndarray, iters: int = 100) -> bool:
    """Baseline IK: undamped pseudo-inverse Newton from home, ignoring joint limits (an
    easier problem than ours), no restarts."""
    q = np.array(robot.q_home)
    for _ in range(iters):
        frames = naive_fk(robot, q)
        ee = frames[-1]
        dR = target[:3, :3] @ ee[:3, :3].T
        err = np.concatenate([target[:3, 3] - ee[:3, 3], 0.5 * np.array([dR[2, 1] - dR[1, 2], dR[0, 2] - dR[2, 0], dR[1, 0] - dR[0, 1]])])
        if np.linalg.norm(err[:3]) < 1e-6 and np.linalg.norm(err[3:]) < 1e-6:
            return True
        q = q + np.linalg.pinv(naive_jacobian(robot, q)) @ err
    return False


# ----------------------------------------------------------------------------- rows


def bench_fk(table: Table, robot: RobotParams, rng: np.random.Generator) -> None:
    base_q = random_configurations(robot, 2000, rng)
    base_med, _ = median_iqr(measure(lambda: [naive_fk(robot, q) for q in base_q], repeats=5))
    base_per = base_med / len(base_q)
    for n in (10**3, 10**5, 10**6):
        Q = random_configurations(robot, n, rng)
        med, iqr = median_iqr(measure(lambda: forward_kinematics(robot, Q), repeats=7 if n > 10**5 else 15))
        per = med / n
        target = "≤ 0.2 µs/config" if n == 10**6 else "—"
        table.add(
            f"batched FK, {robot.name}, N = {n:.0e} (µs/config; configs/s)",
            f"{per * 1e6:.3f} µs; {1 / per:.3g}/s",
            f"{iqr / n * 1e6:.3f} µs",
            f"{base_per * 1e6:.1f} µs",
            f"{base_per / per:.0f}×",
            target,
        )
    Q = random_configurations(robot, 10**6, rng)
    tracemalloc.start()
    forward_kinematics(robot, Q)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    table.add(
        "batched FK peak memory at N = 1e6 / output size",
        f"{peak / 2**20:.0f} MiB / {Q.shape[0] * 128 / 2**20:.0f} MiB",
        "0",
        target="≤ 2× output",
    )


def bench_update(table: Table, robot: RobotParams, rng: np.random.Generator) -> None:
    state = RobotState(robot)
    state.set_q(random_configurations(robot, 1, rng)[0])
    state.set_qd(rng.normal(size=robot.n_dofs))
    kin = Kinematics(robot)
    q = state.q()
    base_med, base_iqr = median_iqr(measure(lambda: naive_jacobian(robot, q), repeats=7, number=500))
    med, iqr = median_iqr(measure(lambda: kin.update(state.joint_state), repeats=7, number=2000))
    table.add(
        f"Kinematics.update, {robot.name} (frames, COMs, Jacobian)",
        us(med), us(iqr), f"{us(base_med)} (frames + Jacobian)", f"{base_med / med:.1f}×", "≤ 30 µs",
    )

    def update_all() -> None:
        kin.update(state.joint_state)
        kin.h_tf, kin.link_vel  # noqa: B018 - force the on-demand parts

    med, iqr = median_iqr(measure(update_all, repeats=7, number=2000))
    table.add(f"Kinematics.update + h_tf + velocities, {robot.name}", us(med), us(iqr))


def bench_jacobian(table: Table, robot: RobotParams, rng: np.random.Generator) -> None:
    base_q = random_configurations(robot, 1000, rng)
    base_med, _ = median_iqr(measure(lambda: [naive_jacobian(robot, q) for q in base_q], repeats=5))
    base_per = base_med / len(base_q)
    n = 10**5
    Q = random_configurations(robot, n, rng)
    med, iqr = median_iqr(measure(lambda: jacobian(robot, Q), repeats=7))
    table.add(
        f"batched Jacobian, {robot.name}, N = 1e5 (µs/config)",
        f"{med / n * 1e6:.3f} µs", f"{iqr / n * 1e6:.3f} µs", f"{base_per * 1e6:.1f} µs", f"{base_per / (med / n):.0f}×",
    )


def bench_conventions(table: Table, robot: RobotParams, rng: np.random.Generator) -> None:
    """The same arm as a modified (Craig) table against its standard table, same run: the
    baseline column holds the standard median, the ratio is standard / modified."""
    modified, robot = to_modified(robot), to_standard(robot)
    n = 10**5
    Q = random_configurations(robot, n, rng)
    for what, fn in (("batched FK", forward_kinematics), ("batched Jacobian", jacobian)):
        std_runs, mod_runs = [], []
        for _ in range(15):  # alternated, so a change of machine load hits both alike
            std_runs += measure(lambda: fn(robot, Q), repeats=1)
            mod_runs += measure(lambda: fn(modified, Q), repeats=1)
        std_med, _ = median_iqr(std_runs)
        med, iqr = median_iqr(mod_runs)
        table.add(
            f"{what}, {robot.name} as modified DH, N = 1e5 (µs/config; baseline: standard DH)",
            f"{med / n * 1e6:.3f} µs", f"{iqr / n * 1e6:.3f} µs", f"{std_med / n * 1e6:.3f} µs (standard)",
            f"{std_med / med:.2f}×", "≈ 1×",
        )


def limited_humanoid() -> RobotParams:
    h = load_robot("humanoid7")
    return RobotParams.from_arrays(
        "humanoid7 with ±90° limits", h.dh_a, h.dh_alpha, h.dh_d, h.dh_th, h.jtype,
        q_min=np.full(7, -np.pi / 2), q_max=np.full(7, np.pi / 2), base_tf=h.base_tf, tool_tf=h.tool_tf,
    )


IK_BAR = {"puma560": "RTB ikine_LM: 100 %, 2.2 ms", "humanoid7 with ±90° limits": "RTB ikine_LM: 98.5 %, 2.4 ms"}


def bench_ik(table: Table, robots: list[RobotParams], rng: np.random.Generator) -> None:
    for robot in robots:
        targets = forward_kinematics(robot, random_configurations(robot, IK_TARGETS, rng))
        position_only = robot.n_dofs < 6
        times, ok = [], 0
        for t in targets:
            start = time.perf_counter()
            ok += solve_ik(robot, t, position_only=position_only).success
            times.append(time.perf_counter() - start)
        med, iqr = median_iqr(times)
        baseline = "—"
        if not position_only:
            base_ok = sum(naive_ik(robot, t) for t in targets[:50])
            baseline = f"pinv Newton, no limits: {100 * base_ok / 50:.0f} % of 50"
        key = robot.name if robot.name in IK_BAR else Path(robot.source).stem
        table.add(
            f"IK {robot.name}{' (position only)' if position_only else ''}: median solve time, success",
            f"{ms(med)}, {100 * ok / len(targets):.1f} %", ms(iqr), baseline, "—", IK_BAR.get(key, "—"),
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-render", action="store_true", help="kinematics rows only")
    args = parser.parse_args()
    rng = np.random.default_rng(0)
    robot = load_robot(ROBOT)
    table = Table()
    bench_fk(table, robot, rng)
    bench_update(table, robot, rng)
    bench_jacobian(table, robot, rng)
    for name in (ROBOT, "panda"):  # a standard table and, once shipped, Franka's modified one
        if name in available_robots():
            bench_conventions(table, load_robot(name), rng)
    bench_dynamics(table, robot, rng, measure, median_iqr, us)
    ik_robots = [load_robot(n) for n in available_robots()] + [limited_humanoid()]
    bench_ik(table, ik_robots, rng)
    bench_ik_analytic(table, median_iqr, ms, us)
    bench_ik_general(table, median_iqr, ms, us)
    bench_trajectory(table, load_robot("ur5"), rng, measure, median_iqr, ms, us)
    bench_planning(table)
    bench_sim.bench_simulation(table, measure, median_iqr, us)
    bench_collision(table, measure, median_iqr, us)
    bench_task_space(table, us)
    bench_contact(table, measure, median_iqr, us)
    bench_calibration(table)
    if not args.skip_render:
        bench_render.bench_frames(table)
        bench_render.bench_screenshot(table)
    cpu = next((l.split(":", 1)[1].strip() for l in Path("/proc/cpuinfo").read_text().splitlines() if l.startswith("model name")), platform.processor())
    print(f"\nMachine: {cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, NumPy {np.__version__}\n")
    table.print()


if __name__ == "__main__":
    main()
