"""The endeffector readout of the window: world pose as xyz, roll-pitch-yaw and a unit
quaternion, and Yoshikawa's manipulability (no Qt)."""
from __future__ import annotations

import math

from robot_sim.viewer import settings as vs
from robot_sim.transforms import HomogeneousTransform, quaternion_from_rot, rpy_from_rot


def pose_readout(endeff_tf: HomogeneousTransform, manipulability: float) -> str:
    """Multi-line text of the endeffector pose in the world: position in metres, URDF
    roll-pitch-yaw in degrees, quaternion (w, x, y, z), and the manipulability √det(J Jᵀ)."""
    x, y, z = endeff_tf.t()
    roll, pitch, yaw = (math.degrees(v) for v in rpy_from_rot(endeff_tf.R()))
    qw, qx, qy, qz = quaternion_from_rot(endeff_tf.R())
    values = dict(x=x, y=y, z=z, roll=roll, pitch=pitch, yaw=yaw, qw=qw, qx=qx, qy=qy, qz=qz)
    # rounding noise of exact zeros would print as "-0.0000"
    clean = {key: round(float(v), 9) + 0.0 for key, v in values.items()}
    return vs.READOUT_FORMAT.format(m=manipulability, **clean)
