"""Simulated calibration studies: a robot with random parameter errors (the arm on the
bench) and what an instrument would measure on it.  Used by the docs' study, the tests and
the benchmarks."""
from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import NDArray

from robot_sim.kinematics import forward_kinematics
from robot_sim.model.calibration_data import CalibrationData
from robot_sim.model.params import RobotParams
from robot_sim.transforms import HomogeneousTransform

#: The errors of the issue's study: lengths 0.5 mm, angles and joint offsets 0.05°, base
#: and tool 1 mm and 0.1° (standard deviations).
LENGTH_SIGMA, ANGLE_SIGMA = 0.5e-3, np.deg2rad(0.05)
FRAME_SIGMA, FRAME_ANGLE_SIGMA = 1e-3, np.deg2rad(0.1)


def perturbed(robot: RobotParams, rng: np.random.Generator, scale: float = 1.0) -> RobotParams:
    """``robot`` with Gaussian errors of ``scale`` times the standard deviations above on
    every a, d [m], α and θ [rad], and on the base and tool (xyz [m], then roll-pitch-yaw
    [rad] applied in their own frames)."""
    n = robot.n_dofs

    def frame(tf: HomogeneousTransform) -> HomogeneousTransform:
        return tf @ HomogeneousTransform.from_xyz_rpy(rng.normal(0, scale * FRAME_SIGMA, 3),
                                                      rng.normal(0, scale * FRAME_ANGLE_SIGMA, 3))

    length, angle = scale * LENGTH_SIGMA, scale * ANGLE_SIGMA
    return dataclasses.replace(
        robot, dh_a=robot.dh_a + rng.normal(0, length, n), dh_d=robot.dh_d + rng.normal(0, length, n),
        dh_alpha=robot.dh_alpha + rng.normal(0, angle, n), dh_th=robot.dh_th + rng.normal(0, angle, n),
        base_tf=frame(robot.base_tf), tool_tf=frame(robot.tool_tf))


def measured(robot: RobotParams, q: NDArray[np.float64], noise: NDArray[np.float64],
             poses: bool = False) -> CalibrationData:
    """What an instrument reads on ``robot`` at q (N, n): tool positions (or full poses when
    ``poses``) with ``noise`` (N, 3) [m] added to the positions."""
    T = forward_kinematics(robot, q)
    T[:, :3, 3] += noise
    return CalibrationData(q, poses=T) if poses else CalibrationData(q, positions=T[:, :3, 3])
