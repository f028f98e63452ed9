"""readout: the endeffector pose text of the window."""
from __future__ import annotations

import math

from robot_sim.viewer.readout import pose_readout
from robot_sim.transforms import HomogeneousTransform


def test_pose_readout_worked_example():
    # yaw 90 deg about z: quaternion (cos 45°, 0, 0, sin 45°)
    tf = HomogeneousTransform.from_xyz_rpy([0.5, -0.25, 1.0], [0.0, 0.0, math.pi / 2])
    assert pose_readout(tf, 0.0123456).splitlines() == [
        "xyz [m]   +0.5000 -0.2500 +1.0000",
        "rpy [deg] +0.00 +0.00 +90.00",
        "quat wxyz +0.7071 +0.0000 +0.0000 +0.7071",
        "manipulability 0.01235",
    ]
