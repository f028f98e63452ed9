"""robot_sim: a simulator for fixed-base manipulators described by DH parameters or URDF.

``import robot_sim as rs`` is the flat public API; names are imported on first use, so
``import robot_sim`` itself loads nothing heavy (and never Qt or OpenGL):

>>> import robot_sim as rs
>>> robot = rs.load_robot("puma560")
>>> T = rs.forward_kinematics(robot, robot.q_home)  # the tool's pose in the world, 4x4
>>> T[:3, 3].round(3)  # its position [m]
array([ 0.737, -0.15 ,  0.957])
>>> frames = rs.forward_kinematics(robot, robot.q_home, all_frames=True)
>>> frames.shape  # frames 0..6, then the tool
(8, 4, 4)
>>> bool((frames[-1] == T).all())
True

(``tests/test_doctests.py`` runs these examples.)

The subpackages are the architecture (see docs/layout.md): ``model``, ``io``,
``kinematics``, ``dynamics``, ``control``, ``planning``, ``graphics``, ``viewer``, ``qt``, ``app``.
"""
from __future__ import annotations

import importlib
from typing import Any

#: Public name -> the module that defines it.
_EXPORTS = {
    # models and state
    "load_robot": "robot_sim.io.robot_file",
    "available_robots": "robot_sim.io.robot_file",
    "RobotParams": "robot_sim.model.params",
    "RobotDefinitionError": "robot_sim.model.params",
    "RobotState": "robot_sim.model.state",
    "JointState": "robot_sim.model.state",
    # kinematics
    "Kinematics": "robot_sim.kinematics",
    "forward_kinematics": "robot_sim.kinematics",
    "jacobian": "robot_sim.kinematics",
    "jacobian_dot_qd": "robot_sim.kinematics",
    "tool_kinematics": "robot_sim.kinematics",
    "manipulability": "robot_sim.kinematics",
    "solve_ik": "robot_sim.kinematics",
    "IKResult": "robot_sim.kinematics",
    "random_configurations": "robot_sim.kinematics",
    # analytic inverse kinematics
    "ik_family": "robot_sim.ik.family",
    "IKFamily": "robot_sim.ik.family",
    "ik_solutions": "robot_sim.ik.solutions",
    "IKSolutions": "robot_sim.ik.solutions",
    # dynamics
    "inverse_dynamics": "robot_sim.dynamics",
    "mass_matrix": "robot_sim.dynamics",
    "gravity_torque": "robot_sim.dynamics",
    "coriolis_matrix": "robot_sim.dynamics",
    "bias_torque": "robot_sim.dynamics",
    "friction_torque": "robot_sim.dynamics",
    "forward_dynamics": "robot_sim.dynamics",
    "constrained_forward_dynamics": "robot_sim.dynamics",
    "energy": "robot_sim.dynamics",
    # simulation and control
    "Simulation": "robot_sim.sim.simulation",
    "LimitEvent": "robot_sim.sim.stops",
    "make_controller": "robot_sim.control.factory",
    "control_gains": "robot_sim.control.controllers",
    "Gains": "robot_sim.control.controllers",
    "BatchSimulation": "robot_sim.sim.batch",
    "sweep": "robot_sim.sim.sweep",
    # conversion and files
    "to_standard": "robot_sim.model.convert",
    "to_modified": "robot_sim.model.convert",
    "to_urdf": "robot_sim.io.urdf_out",
    "load_urdf": "robot_sim.io.urdf_in",
    "to_toml": "robot_sim.io.robot_writer",
    "save_robot": "robot_sim.io.robot_writer",
    "MeshSkippedWarning": "robot_sim.io.meshes",
    # calibration
    "CalibrationData": "robot_sim.model.calibration_data",
    "CalibrationDataError": "robot_sim.model.calibration_data",
    "load_calibration_data": "robot_sim.io.calibration_csv",
    "calibrate": "robot_sim.calibration.calibrate",
    "CalibrationResult": "robot_sim.calibration.calibrate",
    "calibration_poses": "robot_sim.calibration.poses",
    # planning
    "Trajectory": "robot_sim.planning.trajectory",
    "quintic": "robot_sim.planning.profiles",
    "trapezoidal": "robot_sim.planning.profiles",
    "via_points": "robot_sim.planning.profiles",
    "hold": "robot_sim.planning.profiles",
    "cartesian_line": "robot_sim.planning.cartesian",
    "cartesian_arc": "robot_sim.planning.cartesian",
    "CartesianPathError": "robot_sim.planning.cartesian",
    "scale_to_limits": "robot_sim.planning.scaling",
    "plan_pick": "robot_sim.planning.pick_task",
    "plan_path": "robot_sim.planning.rrt",
    "PathResult": "robot_sim.planning.rrt",
    "plan_to_pose": "robot_sim.planning.pose_goal",
    "retime": "robot_sim.planning.retime",
    "InfeasiblePath": "robot_sim.planning.topp",
    "qd_limits": "robot_sim.planning.cartesian",
    "qdd_limits": "robot_sim.planning.cartesian",
    "load_task": "robot_sim.planning.task_file",
    # geometry and collision
    "Box": "robot_sim.model.shapes",
    "Sphere": "robot_sim.model.shapes",
    "Cylinder": "robot_sim.model.shapes",
    "Capsule": "robot_sim.model.shapes",
    "Mesh": "robot_sim.io.meshes",  # importing it installs the one mesh-file reader
    "HalfSpace": "robot_sim.model.shapes",
    "World": "robot_sim.model.world",
    "load_world": "robot_sim.io.world_file",
    "WorldDefinitionError": "robot_sim.io.world_file",
    "CollisionChecker": "robot_sim.collision.checker",
    "DistanceResult": "robot_sim.collision.distance",
    "shape_distance": "robot_sim.collision.distance",
    "ContactModel": "robot_sim.sim.contact",
    "ContactForce": "robot_sim.sim.contact",
    # viewing
    "Visualizer": "robot_sim.viewer.visualizer",
    "show": "robot_sim.viewer.visualizer",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'robot_sim' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
