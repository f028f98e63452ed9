"""The one entry point that builds any controller by its mode name.

Joint-space modes live in :mod:`robot_sim.control.controllers`, task-space modes in
:mod:`robot_sim.control.task_space` (which builds on the former); this module sits on top
of both.  No Qt, no OpenGL.
"""
from __future__ import annotations

from typing import Any

from robot_sim.control.controllers import PD, ComputedTorque, Controller, Gains, Passive, PDGravity, control_gains
from robot_sim.control.task_space import TASK_MODES, make_task_controller
from robot_sim.model.params import RobotParams

#: Keyword options of the joint-space modes (those of control_gains).
JOINT_OPTIONS = ("bandwidth", "damping")


def make_controller(mode: str, robot: RobotParams, gains: Gains | None = None, **options: Any) -> Controller:
    """Controller of ``mode``: joint space (``passive``, ``pd``, ``pdg``, ``ct``; gains
    default to :func:`~robot_sim.control.controllers.control_gains` of the robot, with the
    options ``bandwidth`` [Hz] and ``damping`` (ζ) as the task-space modes take them) or task
    space (``osc``, ``impedance``, ``resolved_rate``, with the keyword ``options`` of
    :func:`~robot_sim.control.task_space.make_task_controller`, e.g. ``bandwidth``,
    ``damping``, ``null_space``).  ValueError for another mode or an option a mode does
    not take."""
    if mode in TASK_MODES:
        return make_task_controller(mode, robot, gains, **options)
    kinds = {"passive": Passive, "pd": PD, "pdg": PDGravity, "ct": ComputedTorque}
    if mode not in kinds:
        raise ValueError(f"mode must be one of {', '.join([*kinds, *TASK_MODES])}, got {mode!r}")
    extra = sorted(set(options) - set(JOINT_OPTIONS)) if mode != "passive" else sorted(options)
    if extra:
        takes = "no options" if mode == "passive" else f"only {' and '.join(JOINT_OPTIONS)}"
        raise ValueError(f"the {mode} controller takes {takes}, got {', '.join(extra)}")
    if gains is not None and options:
        raise ValueError(f"give gains or {', '.join(sorted(options))}, not both")
    if mode == "passive":
        return Passive(robot)
    return kinds[mode](robot, gains if gains is not None else control_gains(robot, **options))
