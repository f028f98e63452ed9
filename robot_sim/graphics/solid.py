"""The ``solid`` look of a DH robot (pure NumPy, no GL): every DH segment a rounded
capsule, every revolute joint a housing on its axis, prismatic joints as in the DH look,
and a base plate.

Sizes follow the DH look's part sizing (``robot_parts.robot_look``): a capsule's radius
is ``SOLID_LINK_RATIO`` times the smaller joint radius at its ends, a housing
``SOLID_HOUSING_RATIO`` times its joint's radius.  Capsules are drawn as a cylinder and
a sphere at each end.  World frame, metres.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.placements import along, spheres
from robot_sim.graphics.robot_parts import Part, dh_segments, robot_look, robot_parts
from robot_sim.kinematics import Kinematics
from robot_sim.model.params import JTYPE_PRISMATIC, RobotParams


def capsule_segments(robot: RobotParams, frames: NDArray[np.float64],
                     endeff: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The solid look's capsules at world ``frames`` (n+1, 4, 4) and tool pose ``endeff``:
    start points (k, 3), end points (k, 3) and radii (k,) of every revolute axis segment,
    every offset segment and the tool segment that is longer than ``MIN_LINK_LENGTH``."""
    look = robot_look(robot)
    seg = dh_segments(frames, robot.is_modified)
    rev = robot.jtype != JTYPE_PRISMATIC
    joint_r = look.joint_radius
    ends = np.r_[joint_r, look.endeff_radius]
    link_r = np.maximum(gd.SOLID_LINK_RATIO * np.minimum(ends[:-1], ends[1:]), look.link_radius[:-1])
    tool_r = max(gd.SOLID_LINK_RATIO * look.endeff_radius, float(look.link_radius[-1]))
    starts = np.vstack([seg.axis_start[rev], seg.offset_start, frames[-1:, :3, 3]])
    stops = np.vstack([seg.axis_end[rev], seg.offset_end, endeff[None, :3, 3]])
    radii = np.r_[link_r[rev], link_r, tool_r]
    keep = np.linalg.norm(stops - starts, axis=1) >= gd.MIN_LINK_LENGTH
    return starts[keep], stops[keep], radii[keep]


def solid_parts(robot: RobotParams, frames: NDArray[np.float64], endeff: NDArray[np.float64]) -> list[Part]:
    """Everything the solid look draws for ``robot`` at world ``frames`` (n+1, 4, 4) with
    tool pose ``endeff`` (4, 4): base plate, capsules, housings, prismatic sleeves and
    rods and the endeffector sphere."""
    dh = robot_parts(robot, frames, endeff)
    base, rods, housings, sleeves, endeff_sphere = dh[0], dh[2], dh[3], dh[4], dh[5]
    starts, stops, radii = capsule_segments(robot, frames, endeff)
    lengths = np.linalg.norm(stops - starts, axis=1)
    housing = housings.placements.copy()
    housing[:, :3, :2] *= gd.SOLID_HOUSING_RATIO  # wider about the same axis
    parts = [
        Part("joint", gd.BASE_COLOR, base.placements),
        Part("cylinder", gd.SOLID_LINK_COLOR, along(starts, stops - starts, radii, lengths)),
        Part("sphere", gd.SOLID_LINK_COLOR, spheres(np.vstack([starts, stops]), np.r_[radii, radii])),
        Part("cylinder", gd.SOLID_LINK_COLOR, rods.placements),
        Part("joint", gd.SOLID_HOUSING_COLOR, housing),
        Part("box", gd.SOLID_HOUSING_COLOR, sleeves.placements),
        Part("sphere", gd.ENDEFF_COLOR, endeff_sphere.placements),
    ]
    return parts


def posed_parts(kin: Kinematics, look: str, show_com: bool) -> list[Part]:
    """The parts of the arm posed by ``kin`` in ``look`` ("solid", else the DH look),
    with the centres of mass when ``show_com`` (DH look)."""
    if look == "solid":
        return solid_parts(kin.robot, kin.frames, kin.endeff_tf.mat)
    return robot_parts(kin.robot, kin.frames, kin.endeff_tf.mat, kin.link_com if show_com else None)
