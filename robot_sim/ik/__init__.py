"""Analytic inverse kinematics of DH arms: the closed-form family read from the joint
axes (:func:`ik_family`) and every solution of a pose or a batch of poses
(:func:`ik_solutions`).  Imports only ``model``, ``transforms`` and ``jit``."""
from __future__ import annotations

from pathlib import Path

from robot_sim.jit import drop_stale_cache

#: The modules holding compiled kernels (pipeline compiles the others into its code).
KERNEL_MODULES = ("subproblems", "position", "families", "finish", "pipeline", "nearest")

drop_stale_cache(Path(__file__).resolve().parent, KERNEL_MODULES, "ik-kernels.sha256", "pipeline.py")
