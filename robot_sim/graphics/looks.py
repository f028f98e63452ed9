"""How a robot is drawn (pure, no GL): its DH segments (``dh``), rounded capsules with
joint housings (``solid``), its own visual shapes (``mesh``), or the meshes translucent
over the DH segments (``both``).  Robots without visuals have the first two only."""
from __future__ import annotations

from robot_sim.model.params import RobotParams

LOOKS = ("dh", "solid", "mesh", "both")  # how a robot is drawn; "both": meshes translucent over the DH look


def has_visuals(robot: RobotParams) -> bool:
    """True when ``robot`` carries any visual shape (base link or links)."""
    return bool(robot.base_visuals) or any(robot.visuals)


def looks_of(robot: RobotParams) -> tuple[str, ...]:
    """The looks ``robot`` can be drawn in, in the order a key cycles them: meshes, DH,
    both, solid for a robot with visuals; DH and solid otherwise."""
    return ("mesh", "dh", "both", "solid") if has_visuals(robot) else ("dh", "solid")


def look_for(robot: RobotParams, requested: str | None) -> str:
    """The look ``robot`` is drawn in when ``requested`` (one of :data:`LOOKS`, or None
    for the default: its meshes if it has any, else DH); a mesh look asked of a robot
    without visuals falls back to DH."""
    available = looks_of(robot)
    return requested if requested in available else available[0] if requested is None else "dh"
