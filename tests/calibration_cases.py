"""Simulated calibration studies shared by the calibration tests: a shipped arm perturbed by
the issue's errors (lengths σ 0.5 mm, angles and joint offsets σ 0.05°, base and tool σ 1 mm
and 0.1°), measured at poses from calibration_poses with Gaussian noise."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

import robot_sim as rs
from robot_sim.transforms import HomogeneousTransform

LENGTH_SIGMA, ANGLE_SIGMA = 0.5e-3, np.deg2rad(0.05)
FRAME_SIGMA, FRAME_ANGLE_SIGMA = 1e-3, np.deg2rad(0.1)
NOISE = 20e-6
ARMS = [name for name in rs.available_robots() if rs.load_robot(name).n_dofs in (6, 7)]


def perturbed(robot: rs.RobotParams, rng: np.random.Generator) -> rs.RobotParams:
    """``robot`` with the issue's random errors (the arm on the bench)."""
    n = robot.n_dofs

    def frame(tf: HomogeneousTransform) -> HomogeneousTransform:
        return tf @ HomogeneousTransform.from_xyz_rpy(rng.normal(0, FRAME_SIGMA, 3), rng.normal(0, FRAME_ANGLE_SIGMA, 3))

    return dataclasses.replace(
        robot, dh_a=robot.dh_a + rng.normal(0, LENGTH_SIGMA, n), dh_d=robot.dh_d + rng.normal(0, LENGTH_SIGMA, n),
        dh_alpha=robot.dh_alpha + rng.normal(0, ANGLE_SIGMA, n), dh_th=robot.dh_th + rng.normal(0, ANGLE_SIGMA, n),
        base_tf=frame(robot.base_tf), tool_tf=frame(robot.tool_tf))


@dataclass
class Study:
    nominal: rs.RobotParams
    truth: rs.RobotParams
    q: np.ndarray
    noise: np.ndarray  # (N, 3) [m] added to the true positions
    exact: rs.CalibrationData
    noisy: rs.CalibrationData


def study(name: str, n_poses: int = 50, seed: int = 1, measurement: str = "position") -> Study:
    """The simulated study of arm ``name`` (deterministic for ``seed``)."""
    rng = np.random.default_rng(seed)
    nominal = rs.load_robot(name)
    truth = perturbed(nominal, rng)
    q = rs.calibration_poses(nominal, n_poses, measurement=measurement, seed=seed)
    poses = rs.forward_kinematics(truth, q)
    noise = rng.normal(0, NOISE, (n_poses, 3))
    if measurement == "position":
        return Study(nominal, truth, q, noise, rs.CalibrationData(q, positions=poses[:, :3, 3]),
                     rs.CalibrationData(q, positions=poses[:, :3, 3] + noise))
    noisy = poses.copy()
    noisy[:, :3, 3] += noise
    return Study(nominal, truth, q, noise, rs.CalibrationData(q, poses=poses), rs.CalibrationData(q, poses=noisy))
