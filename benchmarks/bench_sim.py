"""Benchmark rows of the physics loop (called by bench.py; runnable alone for a quick look).

* One simulation step at 1 kHz, RK4, on UR5, Panda and humanoid7: passive and with
  computed torque (per step of a run of :data:`STEPS`; the baseline column is the same
  step with the reference backend of ``dynamics``, the readable recursion), and one
  ``Simulation.step()`` call on its own (which also writes the state to the RobotState).
* ``BatchSimulation`` with computed torque on humanoid7: µs per arm-step at n_envs =
  10 … 10 000 (one core).
* A sweep of :data:`SWEEP_RUNS` runs (UR5, computed torque over kp, 0.1 s each): wall
  time on the local cores and, when dask.distributed is installed, on a LocalCluster of
  two worker processes.

MuJoCo's ``mj_step`` on the same arms, alternated in one run, is the optional
``benchmarks/compare_mujoco.py``.
"""
from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from bench_dynamics import using  # noqa: E402
from robot_sim import dynamics  # noqa: E402
from robot_sim.sim.batch import BatchSimulation  # noqa: E402
from robot_sim.control.controllers import ComputedTorque, control_gains  # noqa: E402
from robot_sim.sim.simulation import Simulation  # noqa: E402
from robot_sim.sim.sweep import sweep  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.model.params import RobotParams  # noqa: E402

STEPS = 200  # steps per sample
ROBOTS = ("ur5", "panda", "humanoid7")
N_ENVS = (10, 100, 1000, 10_000)
SWEEP_RUNS = 10_000
SWEEP_DURATION = 0.1


def _simulation(robot: RobotParams, ct: bool) -> Simulation:
    controller = ComputedTorque(robot, control_gains(robot)) if ct else None
    sim = Simulation(robot, controller=controller, integrator="rk4", dt=1e-3)
    sim.state.set_q_des(robot.q_home + 0.3)  # a set point away from the start: the arm moves
    return sim


def _run(sim: Simulation) -> None:
    sim.load_state()  # from the same start every sample
    sim.step(STEPS)


def _without_stops(robot: RobotParams) -> RobotParams:
    n = robot.n_dofs
    return dataclasses.replace(robot, q_min=np.full(n, -np.inf), q_max=np.full(n, np.inf))


def alternated(
    runs: dict[str, Callable[[], object]], repeats: int, clock: Callable[[], float] = time.process_time
) -> dict[str, list[float]]:
    """Seconds per call of each run, the runs alternated call by call (after one warm-up
    round), so that a machine whose speed drifts slows all of them alike.  By default the
    clock is this process's CPU time: on a machine shared with other jobs, time spent
    descheduled would otherwise land on whichever sample it hits."""
    samples: dict[str, list[float]] = {key: [] for key in runs}
    for round_ in range(repeats + 1):
        for key, fn in runs.items():
            start = clock()
            fn()
            if round_:
                samples[key].append(clock() - start)
    return samples


def bench_one_arm(table: Any, measure: Callable[..., list[float]], median_iqr: Callable, us: Callable[[float], str]) -> None:
    """Passive and computed-torque steps alternated in one run.  The passive arm falls, so
    with the shipped limits it reaches stops within the window (and its step then includes
    arrivals and resting): the ratio is taken against the passive arm without stops, and
    the shipped-limits figure is reported beside it (CPU time of this process)."""
    for name in ROBOTS:
        robot = load_robot(name)
        sims = {"passive": _simulation(_without_stops(robot), False), "limits": _simulation(robot, False),
                "ct": _simulation(robot, True)}
        samples = alternated({key: (lambda sim=sim: _run(sim)) for key, sim in sims.items()}, repeats=9)
        arrivals = {key: len(sim.take_events()) for key, sim in sims.items()}
        base = None
        if name == "humanoid7":
            with using("reference"):
                base = median_iqr(measure(lambda: _run(sims["ct"]), repeats=3))[0]
        med = {key: median_iqr(v) for key, v in samples.items()}
        table.add(f"simulation step, {name}, 1 kHz, RK4, passive (no stops reached)",
                  us(med["passive"][0] / STEPS), us(med["passive"][1] / STEPS), target="≤ 3 × mj_step")
        table.add(f"… same, shipped limits ({arrivals['limits']} stop arrivals in {9 + 1} runs of {STEPS} steps)",
                  us(med["limits"][0] / STEPS), us(med["limits"][1] / STEPS))
        table.add(f"simulation step, {name}, 1 kHz, RK4 + computed torque ({arrivals['ct']} stop arrivals)",
                  us(med["ct"][0] / STEPS), us(med["ct"][1] / STEPS),
                  "—" if base is None else us(base / STEPS) + " (reference)",
                  "—" if base is None else f"{base / med['ct'][0]:.0f}×", "≤ 1.2 × passive")
        ratio = float(np.median(np.array(samples["ct"]) / np.array(samples["passive"])))
        table.add(f"… computed torque / passive, {name} (median of the alternated pairs)", f"{ratio:.2f}", "—",
                  target="≤ 1.2")
    sim = _simulation(load_robot("humanoid7"), True)
    med, iqr = median_iqr(measure(sim.step, repeats=9, number=100))
    table.add("one `Simulation.step()` call, humanoid7, RK4 + CT (state written to the RobotState)", us(med), us(iqr))


def bench_batch(table: Any, measure: Callable[..., list[float]], median_iqr: Callable, us: Callable[[float], str]) -> None:
    robot = load_robot("humanoid7")
    for n_envs in N_ENVS:
        batch = BatchSimulation(robot, n_envs, controller="ct", integrator="rk4", dt=1e-3)
        batch.set_reference(q=robot.q_home + 0.3)
        steps = max(2, 20_000 // n_envs)
        med, iqr = median_iqr(measure(lambda: batch.step(steps), repeats=5))
        per = med / (steps * n_envs)
        table.add(f"BatchSimulation, humanoid7, RK4 + CT, n_envs = {n_envs} (µs per arm-step)",
                  us(per), us(iqr / (steps * n_envs)), target="≤ mj_step (n_envs = 1000)")


def bench_sweep(table: Any, seconds: Callable[[float], str]) -> None:
    robot = load_robot("ur5")
    grid = {"kp": np.linspace(100.0, 1000.0, SWEEP_RUNS)}
    start = time.perf_counter()
    local = sweep(robot, grid, "ct", duration=SWEEP_DURATION)
    wall = time.perf_counter() - start
    table.add(f"sweep of {SWEEP_RUNS} runs (UR5, CT, {SWEEP_DURATION} s each), local cores ({os.cpu_count()})",
              seconds(wall), "—")
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        return
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            Client(cluster) as client:
        sweep(robot, {"kp": [100.0, 200.0]}, "ct", duration=0.01, chunk_size=1, client=client)  # both workers warm
        start = time.perf_counter()
        remote = sweep(robot, grid, "ct", duration=SWEEP_DURATION, client=client)
        wall = time.perf_counter() - start
    assert remote.equals(local), "the cluster's table differs from the local one"
    table.add(f"same sweep on a dask LocalCluster of 2 workers (same table)", seconds(wall), "—")


def _resting_pair(robot: RobotParams) -> tuple[Simulation, Simulation, np.ndarray]:
    """Two passive simulations released at rest from home: one with joint 2 (index 1) on
    a stop that gravity presses it onto (held through every sample) and no other stop (so
    no other joint's arrival enters the samples), one without stops."""
    q0 = robot.q_home.copy()
    n = robot.n_dofs
    q_min, q_max = np.full(n, -np.inf), np.full(n, np.inf)
    falls_up = dynamics.forward_dynamics(robot, q0, np.zeros(n), np.zeros(n))[1] > 0
    (q_max if falls_up else q_min)[1] = q0[1]
    on_stop = dataclasses.replace(robot, q_min=q_min, q_max=q_max)
    free = dataclasses.replace(robot, q_min=np.full(n, -np.inf), q_max=np.full(n, np.inf))
    return Simulation(on_stop), Simulation(free), q0


def bench_resting_step(table: Any, median_iqr: Callable, us: Callable[[float], str], repeats: int = 41) -> None:
    """Step time with a joint resting on its stop (held: the constrained step and the
    reaction check) against the free step, passive humanoid7, 1 kHz RK4; the two are
    alternated sample by sample, each sample STEPS steps from the same rest state (CPU
    time of this process)."""
    held, free, q0 = _resting_pair(load_robot("humanoid7"))

    def run(sim: Simulation) -> None:
        sim.state.set_q(q0)
        sim.state.set_qd(np.zeros_like(q0))
        sim.load_state()
        sim.step(STEPS)
        if sim is held and (held.q[1] != q0[1] or held.take_events()):
            raise RuntimeError("the benchmark's resting joint left its stop")

    samples = alternated({"held": lambda: run(held), "free": lambda: run(free)}, repeats)
    (rest, iqr), (base, _) = (median_iqr([t / STEPS for t in samples[k]]) for k in ("held", "free"))
    ratio = float(np.median(np.array(samples["held"]) / np.array(samples["free"])))
    table.add(
        "simulation step, humanoid7 passive, joint 2 resting on its stop (vs free step; median of the alternated pairs)",
        us(rest), us(iqr), us(base), f"{ratio:.2f}× the free step", "≤ 1.3×",
    )


def bench_cold_start(table: Any, median_iqr: Callable, repeats: int = 3) -> None:
    """``simulator.py --motion ct --screenshot``, start to PNG, with the numba cache filled
    (what every run after the first loads) and empty (a fresh install's first run: every
    kernel it calls compiled), alternated; bytecode caches as a user's Python has them."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYOPENGL_PLATFORM"] = "osmesa"
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, str(ROOT / "simulator.py"), "--motion", "ct", "--screenshot", str(Path(tmp) / "s.png")]
        subprocess.run(cmd, check=True, env=env, cwd=ROOT)  # fills the package's cache
        runs = {
            "warm": lambda: subprocess.run(cmd, check=True, env=env, cwd=ROOT),
            "cold": lambda: subprocess.run(
                cmd, check=True, cwd=ROOT, env=dict(env, NUMBA_CACHE_DIR=tempfile.mkdtemp(dir=tmp))
            ),
        }
        samples = alternated(runs, repeats, time.perf_counter)  # wall time: the runs are child processes
    for key, what in (("warm", "numba cache filled"), ("cold", "empty numba cache, every kernel compiled")):
        med, iqr = median_iqr(samples[key])
        table.add(f"`simulator.py --motion ct --screenshot` start to PNG, {what}", f"{med:.2f} s", f"{iqr:.2f} s",
                  target="≤ 1.5 s" if key == "warm" else "—")


def bench_simulation(table: Any, measure: Callable[..., list[float]], median_iqr: Callable, us: Callable[[float], str]) -> None:
    bench_one_arm(table, measure, median_iqr, us)
    bench_resting_step(table, median_iqr, us)
    bench_cold_start(table, median_iqr)
    bench_batch(table, measure, median_iqr, us)
    bench_sweep(table, lambda s: f"{s:.2f} s")


if __name__ == "__main__":
    import timing

    rows = timing.Table()
    bench_simulation(rows, timing.measure, timing.median_iqr, timing.us)
    rows.print()
