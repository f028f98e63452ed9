"""Kinematics of DH manipulators: forward (single and batched), differential and inverse.

One job per file: ``chain`` (the per-robot chain model and the walks of the chain; frames
and units are stated there), ``frames`` (frames, tool pose, Jacobian, J̇q̇, manipulability),
``state`` (the :class:`Kinematics` of one joint state), ``workspace`` (sampling),
``ik`` (numerical and differential inverse kinematics) and ``checks``.  The public names
are re-exported here: ``from robot_sim.kinematics import solve_ik`` keeps working.
Imports neither OpenGL nor Qt.
"""
from robot_sim.kinematics.chain import CHUNK, cos_sin_half
from robot_sim.kinematics.frames import (
    characteristic_length, forward_kinematics, jacobian, jacobian_dot_qd, manipulability, task_rows, tool_kinematics,
)
from robot_sim.kinematics.ik import CollisionQuery, IKResult, diff_ik_velocity, ik_position_only_required, solve_ik
from robot_sim.kinematics.state import Kinematics
from robot_sim.kinematics.workspace import (
    WorkspaceCancelled, available_memory, max_workspace_samples, random_configurations, sampling_bounds,
    workspace_points,
)

__all__ = [
    "CHUNK", "CollisionQuery", "IKResult", "Kinematics", "WorkspaceCancelled", "available_memory",
    "characteristic_length", "cos_sin_half", "diff_ik_velocity", "forward_kinematics", "ik_position_only_required",
    "jacobian", "jacobian_dot_qd", "manipulability", "max_workspace_samples", "random_configurations",
    "sampling_bounds", "solve_ik", "task_rows", "tool_kinematics", "workspace_points",
]
