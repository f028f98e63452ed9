"""Contact rows of ``make bench`` (called by bench.py; runnable alone).

* The issue's stability figures: a passive UR5 dropped onto a box from 0.3 m (its lowest
  shape point 0.3 m above the box's top, raised 0.4 m so that the fall has room): when
  it comes to rest (every joint rate below 1e-3 rad/s from then on), its deepest
  penetration over the whole run and at rest (targets: within 2 s, under 5 mm), and
  the most energy any step gained (kinetic + potential + springs).
* Every shipped robot with inertials dropped onto the floor from home (passive, 1.5 s):
  how many diverged (target none) and the deepest penetration among them.
* Cost: one 1 kHz RK4 step of that UR5 resting on the box (its contact points, the
  contact torque at every stage) against the free step of the same arm without a
  checker, and the free step of the arm 5 m above the floor with a checker (the
  active-pair check only); the three alternated, CPU time of this process.  The resting
  arm's samples follow each other (it stays at rest); the free arms swing from home
  again for each (``load_state``, which also forgets friction anchors: a resting arm
  reloaded would slide onto new ones).
"""
from __future__ import annotations

import dataclasses
import os
import sys
import time
from pathlib import Path
from typing import Any, Callable

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from robot_sim import dynamics  # noqa: E402
from robot_sim.collision import Box, CollisionChecker, World  # noqa: E402
from robot_sim.sim.simulation import Simulation  # noqa: E402
from robot_sim.io.robot_file import available_robots, load_robot  # noqa: E402
from robot_sim.transforms import HomogeneousTransform  # noqa: E402

DROP = 0.3  # m between the arm's lowest shape point and the box
REST_RATE = 1e-3  # rad/s: every joint slower than this is at rest
STEPS = 200


def ur5_drop() -> tuple[Simulation, CollisionChecker]:
    robot = dataclasses.replace(load_robot("ur5"), base_tf=HomogeneousTransform.from_xyz_rpy([0, 0, 0.4], [0, 0, 0]))
    lowest = min(s.pose[2, 3] - s.radius - s.length / 2 * abs(s.pose[2, 2])
                 for _, s in CollisionChecker(robot).shapes(robot.q_home))
    top = lowest - DROP
    box = np.eye(4)
    box[:3, 3] = [-0.55, -0.1, top / 2]
    checker = CollisionChecker(robot, World({"box": Box([0.6, 0.6, top], box)}))
    return Simulation(robot, checker=checker), checker


def _energy(sim: Simulation) -> float:
    return sum(dynamics.energy(sim.robot, sim.q, sim.qd)) + sim.contact.stored_energy(sim.q)


def bench_drop(table: Any) -> Simulation:
    sim, checker = ur5_drop()
    rest_at, deepest, gained, energy = None, 0.0, 0.0, _energy(sim)
    while sim.time < 3.0 - 1e-9:
        sim.step()
        now = _energy(sim)
        gained, energy = max(gained, now - energy), now
        deepest = max(deepest, -checker.distance(sim.q).distance)
        moving = np.abs(sim.qd).max() >= REST_RATE
        rest_at = None if moving else (sim.time if rest_at is None else rest_at)
    final = -checker.distance(sim.q).distance
    table.add("contact: passive UR5 dropped 0.3 m onto a box, at rest after",
              "never" if rest_at is None else f"{rest_at:.2f} s", "—", target="≤ 2 s")
    table.add("contact: that drop's deepest penetration (whole run / at rest)",
              f"{deepest * 1000:.2f} mm / {final * 1000:.2f} mm", "—", target="< 5 mm")
    table.add("contact: that drop, most energy gained by one RK4 step", f"{gained:.1e} J", "—", target="≤ 0")
    return sim


def bench_floor_drops(table: Any, seconds: float = 1.5) -> None:
    diverged, deepest, worst = [], 0.0, ""
    names = [name for name in available_robots() if load_robot(name).inertials is not None]
    for name in names:
        robot = load_robot(name)
        checker = CollisionChecker(robot)
        sim = Simulation(robot, checker=checker)
        sim.step(round(seconds / sim.dt))
        if sim.stopped is not None or not np.isfinite(sim.q).all():
            diverged.append(name)
            continue
        depth = -checker.distance(sim.q).distance
        if depth > deepest:
            deepest, worst = depth, name
    table.add(f"contact: {len(names)} shipped robots dropped onto the floor ({seconds:g} s passive), diverged",
              str(len(diverged)) + (f" ({', '.join(diverged)})" if diverged else ""), "—",
              ratio=f"deepest {deepest * 1000:.2f} mm ({worst})", target="0")


def bench_contact_step(table: Any, resting: Simulation, median_iqr: Callable, us: Callable[[float], str],
                       repeats: int = 11) -> None:
    q0, qd0 = resting.q.copy(), resting.qd.copy()
    free = Simulation(resting.robot)
    high = dataclasses.replace(resting.robot, base_tf=HomogeneousTransform.from_xyz_rpy([0, 0, 5.0], [0, 0, 0]))
    far = Simulation(high, checker=CollisionChecker(high))  # the floor 5 m below the base: never near
    samples: dict[Simulation, list[float]] = {resting: [], free: [], far: []}
    for _ in range(repeats + 1):  # the first round warms the kernels
        for sim in samples:
            if sim is not resting:  # the free arms swing from home again; the resting one stays at rest
                sim.state.set_q(sim.robot.q_home)
                sim.state.set_qd(np.zeros(sim.robot.n_dofs))
                sim.load_state()
            start = time.process_time()  # CPU time: on a shared machine, time descheduled would land on the
            sim.step(STEPS)  # longest samples (the resting ones) most often
            samples[sim].append((time.process_time() - start) / STEPS)
    (rest, iqr), (base, _), (check, check_iqr) = (median_iqr(samples[s][1:]) for s in (resting, free, far))
    table.add("contact: UR5 step resting on the box (RK4, contact torque at every stage)", us(rest), us(iqr),
              us(base), f"{rest / base:.1f}× the free step")
    table.add("contact: UR5 free step with a checker, no pair near contact", us(check), us(check_iqr), us(base),
              f"{check / base:.2f}× the free step")


def bench_contact(table: Any, measure: Callable[..., list[float]], median_iqr: Callable,
                  us: Callable[[float], str]) -> None:
    resting = bench_drop(table)
    bench_floor_drops(table)
    bench_contact_step(table, resting, median_iqr, us)


if __name__ == "__main__":
    import timing

    rows = timing.Table()
    bench_contact(rows, timing.measure, timing.median_iqr, timing.us)
    rows.print()
