"""Optional oracle: ``toppra`` (``pip install toppra``; never a dependency of the suite)
against ``retime`` on 50 random paths per robot, same geometry (the not-a-knot cubic
spline through the waypoints by chord length) and the same speed and acceleration
limits; and with effort limits through our inverse dynamics (toppra's torque
constraint), on Panda and UR5e, whose drives give effort limits and no friction, with
acceleration limits EFFORT_ACCEL times the defaults so that effort binds.
Prints the duration ratio (ours / toppra): within 2 % is the target.

    PYOPENGL_PLATFORM=osmesa .venv/bin/python benchmarks/oracle_toppra.py [--paths 50]
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import toppra as ta

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from robot_sim.dynamics import inverse_dynamics  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.planning.cartesian import qd_limits, qdd_limits  # noqa: E402
from robot_sim.planning.retime import retime  # noqa: E402
from robot_sim.planning.spline import JointSpline  # noqa: E402

GRIDPOINTS = 2000
EFFORT_ACCEL = 8.0


def random_path(robot, rng: np.random.Generator, k: int = 5, step: float = 0.5) -> np.ndarray:
    mid = (robot.q_min + robot.q_max) / 2
    width = np.minimum(robot.q_max - robot.q_min, 2 * np.pi)
    q0 = mid + (rng.random(robot.n_dofs) - 0.5) * width * 0.5
    P = np.cumsum(np.vstack([q0, rng.normal(size=(k - 1, robot.n_dofs)) * step]), axis=0)
    return np.clip(P, robot.q_min, robot.q_max)


def toppra_duration(robot, path: np.ndarray, effort: bool, a: np.ndarray) -> float:
    spline = JointSpline.through(path)
    geometry = ta.SplineInterpolator(spline.knots, spline.waypoints, bc_type="not-a-knot")
    v = qd_limits(robot)
    constraints = [ta.constraint.JointVelocityConstraint(np.stack([-v, v], axis=1)),
                   ta.constraint.JointAccelerationConstraint(np.stack([-a, a], axis=1))]
    if effort:
        tau = np.asarray(robot.drives.effort_limit, dtype=float)
        constraints.append(ta.constraint.JointTorqueConstraint(
            lambda q, qd, qdd: inverse_dynamics(robot, q, qd, qdd), np.stack([-tau, tau], axis=1),
            np.zeros(robot.n_dofs)))
    grid = np.linspace(0.0, spline.length, GRIDPOINTS + 1)
    solver = ta.algorithm.TOPPRA(constraints, geometry, gridpoints=grid, parametrizer="ParametrizeConstAccel")
    traj = solver.compute_trajectory(0.0, 0.0)
    return float(traj.duration)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--paths", type=int, default=50)
    args = parser.parse_args()
    for name, effort in (("panda", False), ("ur5", False), ("humanoid7", False), ("panda", True), ("ur5e", True)):
        robot = load_robot(name)
        rng = np.random.default_rng(11)
        ratios, binding = [], []
        for _ in range(args.paths):
            path = random_path(robot, rng)
            a = qdd_limits(robot) * (EFFORT_ACCEL if effort else 1.0)
            ours = retime(robot, path, a_max=a, effort=effort)
            ratios.append(ours.duration / toppra_duration(robot, path, effort, a))
            if effort:
                tau = np.abs(inverse_dynamics(robot, ours.q, ours.qd, ours.qdd)) / robot.drives.effort_limit
                binding.append(tau.max())
        r = np.array(ratios)
        print(f"{name} ({'speed, acceleration, effort' if effort else 'speed, acceleration'}): duration ours/toppra "
              f"median {np.median(r):.4f}, range [{r.min():.4f}, {r.max():.4f}], "
              f"within 2 %: {np.mean(np.abs(r - 1) <= 0.02) * 100:.0f} % of {len(r)}"
              + (f"; effort binds (max |τ|/limit >= 0.999) on {np.mean(np.array(binding) >= 0.999) * 100:.0f} %"
                 if effort else ""), flush=True)


if __name__ == "__main__":
    main()
