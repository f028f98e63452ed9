"""Entry point of the checkout: re-exports the public names of :mod:`robot_sim.model.state`."""
from robot_sim.model.state import (  # noqa: F401
    check_joint_vector,
    JointState,
    RobotState,
)
__all__ = [
    "check_joint_vector",
    "JointState",
    "RobotState",
]
