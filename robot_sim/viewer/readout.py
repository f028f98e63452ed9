"""The endeffector readout of the window and the browser view: world pose as xyz,
roll-pitch-yaw and a unit quaternion, Yoshikawa's manipulability, the tracking error and
the collision display's minimum distance (no Qt)."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from robot_sim.kinematics import manipulability
from robot_sim.transforms import HomogeneousTransform, quaternion_from_rot, rpy_from_rot
from robot_sim.viewer import settings as vs

if TYPE_CHECKING:
    from robot_sim.viewer.session import ViewerSession


def pose_readout(
    endeff_tf: HomogeneousTransform, manipulability: float, tracking: tuple[float, float] | None = None
) -> str:
    """Multi-line text of the endeffector pose in the world: position in metres, URDF
    roll-pitch-yaw in degrees, quaternion (w, x, y, z), and the manipulability √det(J Jᵀ);
    with ``tracking`` (position error [m], rotation error [rad] from the desired pose) a
    line of the Cartesian tracking error in mm and degrees."""
    x, y, z = endeff_tf.t()
    roll, pitch, yaw = (math.degrees(v) for v in rpy_from_rot(endeff_tf.R()))
    qw, qx, qy, qz = quaternion_from_rot(endeff_tf.R())
    values = dict(x=x, y=y, z=z, roll=roll, pitch=pitch, yaw=yaw, qw=qw, qx=qx, qy=qy, qz=qz)
    # rounding noise of exact zeros would print as "-0.0000"
    clean = {key: round(float(v), 9) + 0.0 for key, v in values.items()}
    text = vs.READOUT_FORMAT.format(m=manipulability, **clean)
    if tracking is not None:
        text += vs.READOUT_TRACKING_FORMAT.format(mm=1e3 * tracking[0], deg=math.degrees(tracking[1]))
    return text


def session_readout(session: ViewerSession) -> str:
    """The readout of what ``session`` shows: :func:`pose_readout` of its endeffector
    (manipulability NaN where an arm under 6 joints has an unlimited joint without a
    range to probe), the tracking error in a physical mode, and the minimum distance
    while the collision display is shown."""
    q = session.state.q()
    try:
        measure = manipulability(session.robot, q, session.kin.jacobian)
    except ValueError:
        measure = math.nan
    text = pose_readout(session.kin.endeff_tf, measure, session.tracking_error())
    collision = session.collision_readout()
    return text if collision is None else text + "\n" + collision
