"""Benchmark rows of the physics loop (called by bench.py; runnable alone for a quick look).

One simulation step of humanoid7 at 1 kHz with RK4 and computed torque, and where its time
goes: three ``dynamics.forward_dynamics`` calls (RK4 stages 2–4; stage 1's acceleration
is computed torque's reference acceleration, exact on the model), one
``dynamics.inverse_dynamics`` (the controller) and the loop itself (control law, RK4
sums, limit and finiteness checks).  The baseline, measured in the same run, is the
same step with each stage's acceleration computed the textbook way,
``solve(mass_matrix(q), τ − bias_torque(q, q̇))`` (two dynamics calls and a solve).
"""
from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any, Callable

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

from robot_sim import dynamics  # noqa: E402
from robot_sim.control.controllers import ComputedTorque, control_gains  # noqa: E402
from robot_sim.model.params import RobotParams
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.control.simulation import Simulation  # noqa: E402

STEPS = 200  # steps per sample


class _TextbookStep(Simulation):
    """The same loop with q̈ = M⁻¹ (τ − b) from mass_matrix and bias_torque (the baseline)."""

    def _accel(self, q, qd, tau, f_tool):  # type: ignore[no-untyped-def]
        rhs = tau - dynamics.bias_torque(self.robot, q, qd)
        return np.linalg.solve(dynamics.mass_matrix(self.robot, q), rhs)


class _LoopOnly(Simulation):
    """The loop with the dynamics answered instantly (zero acceleration): its own cost."""

    def _accel(self, q, qd, tau, f_tool):  # type: ignore[no-untyped-def]
        return np.zeros_like(q)


class _PresetTorque(ComputedTorque):
    """Computed torque's control law with inverse dynamics answered instantly."""

    def torque(self, q, qd, q_des, qd_des, qdd_des):  # type: ignore[no-untyped-def]
        return qdd_des + self.kp * (q_des - q) + self.kd * (qd_des - qd)


def _simulation(robot: RobotParams, cls: type[Simulation]) -> Simulation:
    sim = cls(robot, controller=ComputedTorque(robot, control_gains(robot)), integrator="rk4", dt=1e-3)
    sim.state.set_q_des(robot.q_home + 0.3)  # a set point away from the start: the arm moves
    return sim


def bench_simulation(table: Any, measure: Callable[..., list[float]], median_iqr: Callable, us: Callable[[float], str]) -> None:
    robot = load_robot("humanoid7")
    sim, base = _simulation(robot, Simulation), _simulation(robot, _TextbookStep)
    base_med, _ = median_iqr(measure(lambda: base.step(STEPS), repeats=5))
    med, iqr = median_iqr(measure(lambda: sim.step(STEPS), repeats=9))
    step, base_step = med / STEPS, base_med / STEPS
    table.add(
        "simulation step, humanoid7, 1 kHz, RK4 + computed torque",
        f"{us(step)} (real-time factor {1e-3 / step:.1f})",
        us(iqr / STEPS),
        us(base_step),
        f"{base_step / step:.1f}×",
        "≤ 250 µs",
    )
    q, qd, tau = sim.q.copy(), sim.qd.copy(), sim.effort.copy()
    fd, _ = median_iqr(measure(lambda: dynamics.forward_dynamics(robot, q, qd, tau), repeats=9, number=200))
    inv, _ = median_iqr(measure(lambda: dynamics.inverse_dynamics(robot, q, qd, tau), repeats=9, number=200))
    table.add("… 3 × forward_dynamics (RK4 stages 2–4), one configuration", us(3 * fd), "—")
    table.add("… 1 × inverse_dynamics (computed torque), one configuration", us(inv), "—")
    loop = _LoopOnly(robot, controller=_PresetTorque(robot, control_gains(robot)), integrator="rk4", dt=1e-3)
    own, _ = median_iqr(measure(lambda: loop.step(STEPS), repeats=9))
    table.add("… the loop itself (control law, RK4 sums, limits, checks)", us(own / STEPS), "—")


if __name__ == "__main__":
    import timing

    rows = timing.Table()
    bench_simulation(rows, timing.measure, timing.median_iqr, timing.us)
    rows.print()
