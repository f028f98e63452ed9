"""Calibration against robotkinecal and pybotics on the same simulated measurements.

Optional, not part of the suite.  Both peers pin NumPy below 2, so they live in their own
environment beside the project's (robot_sim runs there too, from the checkout):

    python3 -m venv .venv-calib
    .venv-calib/bin/pip install "numpy>=1.26,<2" "scipy==1.13.1" --only-binary=scipy,numpy pybotics robotkinecal tomlkit
    PYTHONPATH=. .venv-calib/bin/python benchmarks/compare_calibration.py

Each arm is perturbed as in docs/calibration.md (lengths σ 0.5 mm, angles σ 0.05°, base and
tool σ 1 mm and 0.1°), measured at the 50 poses of ``rs.calibration_poses`` with 20 µm noise
per axis; every library fits the same four fifths (robot_sim's seeded split) from the
nominal model and predicts the held-out fifth.  robotkinecal (Li et al., IEEE T-RO 2016:
product of exponentials, 4 parameters per joint plus the tool point) gets the arm as a
Robotics Toolbox model of ``rs.to_urdf``; pybotics fits its modified DH table, tool
position and world frame with SciPy's Levenberg–Marquardt on per-pose distance errors, as
its documentation does.  Times are medians of 3 runs on the same machine, same run.
"""
from __future__ import annotations

import os
import tempfile
import time
import warnings

import numpy as np

import robot_sim as rs
from robot_sim.calibration.simulate import measured, perturbed

NOISE, POSES = 20e-6, 50
REPEATS = int(os.environ.get("REPEATS", "3"))
ARM_NAMES = os.environ.get("ARMS", "")
ARMS = ("ur5", "puma560", "kr6_r900", "panda")


def _median_time(fn, repeats=REPEATS):
    times, result = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times)), result


def robotkinecal_fit(robot, q_train, p_train, q_test):
    import roboticstoolbox as rtb
    from robotkinecal import SerialRobotKineCal

    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "arm.urdf")
        with open(path, "w") as out:
            out.write(rs.to_urdf(robot, path))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            from roboticstoolbox.models.URDF.URDFRobot import URDF_read

            links, name, _ = URDF_read(path)
    model = rtb.Robot(links, name=name)
    ee = "tool0"  # rs.to_urdf's endeffector link

    def fit():
        cal = SerialRobotKineCal(model, ee_name=ee)
        cal.set_observations(list(q_train), [p.copy() for p in p_train])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            cal.solve()
        return np.array([cal.forward_kinematics(cal.N_JOINTS + 1, q).t for q in q_test])

    return _median_time(fit)


def pybotics_fit(robot, q_train, p_train, q_test):
    from pybotics.kinematic_chain import MDHKinematicChain
    from pybotics.optimization import OptimizationHandler, optimize_accuracy
    from pybotics.robot import Robot
    from pybotics.tool import Tool
    from scipy.optimize import least_squares

    mod = rs.to_modified(robot)
    mdh = np.column_stack([mod.dh_alpha, mod.dh_a, mod.dh_th, mod.dh_d])

    def fit():
        nominal = Robot(MDHKinematicChain.from_parameters(mdh), tool=Tool(matrix=mod.tool_tf.mat.copy()),
                        world_frame=mod.base_tf.mat.copy())
        nominal.joint_limits = np.array([[-np.inf] * robot.n_dofs, [np.inf] * robot.n_dofs])
        handler = OptimizationHandler(robot=nominal, kinematic_chain_mask=True,
                                      tool_mask=[True, True, True, False, False, False], world_mask=True)
        x0 = handler.generate_optimization_vector()
        least_squares(optimize_accuracy, x0, args=(handler, q_train, p_train), method="lm")
        return np.array([handler.robot.fk(q)[:3, 3] for q in q_test])

    return _median_time(fit)


def main() -> None:
    print("| arm | library | held-out RMS | held-out max | fit time |")
    print("|---|---|---|---|---|")
    for name in ARM_NAMES.split(",") if ARM_NAMES else ARMS:
        rng = np.random.default_rng(0)
        robot = rs.load_robot(name)
        truth = perturbed(robot, rng)
        q = rs.calibration_poses(robot, POSES, seed=0)
        data = measured(truth, q, rng.normal(0, NOISE, (POSES, 3)))
        seconds, res = _median_time(lambda: rs.calibrate(robot, data))
        held = res.holdout.poses
        train = np.setdiff1d(np.arange(POSES), held)
        rows = [("robot_sim", res.holdout.position, seconds / 2)]  # calibrate fits twice: the split, then all
        for label, fn in (("robotkinecal", robotkinecal_fit), ("pybotics", pybotics_fit)):
            try:
                t, predicted = fn(robot, q[train], data.positions[train], q[held])
                rows.append((label, np.linalg.norm(predicted - data.positions[held], axis=1), t))
            except Exception as exc:  # a peer that cannot take this arm says why
                print(f"| {name} | {label} | failed: {type(exc).__name__}: {str(exc)[:80]} | | |")
        for label, err, t in rows:
            print(f"| {name} | {label} | {np.sqrt(np.mean(err**2)) * 1e6:.1f} µm | {err.max() * 1e6:.1f} µm | "
                  f"{t * 1e3:.0f} ms |", flush=True)


if __name__ == "__main__":
    main()
