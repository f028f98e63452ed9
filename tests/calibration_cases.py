"""Simulated calibration studies shared by the calibration tests: a shipped arm perturbed by
the issue's errors (robot_sim.calibration.simulate), measured at poses from
calibration_poses with 20 µm Gaussian noise."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import robot_sim as rs
from robot_sim.calibration.simulate import measured, perturbed

NOISE = 20e-6
ARMS = [name for name in rs.available_robots() if rs.load_robot(name).n_dofs in (6, 7)]


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
    noise = rng.normal(0, NOISE, (n_poses, 3))
    poses = measurement == "pose"
    return Study(nominal, truth, q, noise, measured(truth, q, np.zeros_like(noise), poses),
                 measured(truth, q, noise, poses))
