"""Small robots with known contact answers: carriages of prismatic joints carrying a sphere;
a UR5 over a box to drop onto it; a Panda whose links are pushed into each other."""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from kin_helpers import robot
from robot_sim.collision import Box, CollisionChecker, World

from robot_sim.model.inertials import LinkInertials
from robot_sim.model.params import JTYPE_PRISMATIC, RobotParams
from robot_sim.model.shapes import Sphere
from robot_sim.transforms import HomogeneousTransform

RADIUS = 0.05
MASS = 2.0


def _inertials(masses: list[float]) -> LinkInertials:
    return LinkInertials.from_arrays(mass=masses, com=[[0.0, 0.0, 0.0]] * len(masses),
                                     inertia=[np.eye(3) * 1e-3 * m for m in masses])


def vertical_slider() -> RobotParams:
    """One prismatic joint along world z; q is the height [m] of a sphere of radius
    :data:`RADIUS` and mass :data:`MASS` (frame 1's origin is its centre)."""
    return RobotParams.from_arrays("slider", [0.0], [0.0], [0.0], [0.0], [JTYPE_PRISMATIC],
                                   inertials=_inertials([MASS]), collisions=((Sphere(RADIUS),),))


def planar_carriage() -> RobotParams:
    """Two prismatic joints, q1 along world x and q2 along world z, carrying a sphere at
    frame 2's origin: a block of mass :data:`MASS` sliding in the x-z plane (the first
    carriage weighs 1e-6 of it, so the mass matrix is MASS·I)."""
    base = HomogeneousTransform.from_xyz_rpy([0.0, 0.0, 0.0], [0.0, math.pi / 2, 0.0])  # z0 = world x
    return RobotParams.from_arrays("carriage", [0.0, 0.0], [-math.pi / 2, 0.0], [0.0, 0.0], [math.pi / 2, 0.0],
                                   [JTYPE_PRISMATIC, JTYPE_PRISMATIC], base_tf=base,
                                   inertials=_inertials([1e-6 * MASS, MASS]),
                                   collisions=((), (Sphere(RADIUS),)))


def ur5_over_box() -> tuple:
    """A UR5 raised 0.4 m at home, and a box under its forearm and wrist whose top is 0.3 m
    below the arm's lowest shape point."""
    rob = dataclasses.replace(robot("ur5"), base_tf=HomogeneousTransform.from_xyz_rpy([0, 0, 0.4], [0, 0, 0]))
    shapes = CollisionChecker(rob).shapes(rob.q_home)
    lowest = min(s.pose[2, 3] - s.radius - s.length / 2 * abs(s.pose[2, 2]) for _, s in shapes)
    top = lowest - 0.3
    box = Box([0.6, 0.6, top], np.array(HomogeneousTransform.from_xyz_rpy([-0.55, -0.1, top / 2], [0, 0, 0]).mat))
    return rob, World({"box": box})


def panda_in_self_contact() -> tuple:
    """The Panda, its checker of its own links (no floor) and a configuration where two of
    its links overlap by 2 to 10 mm."""
    rob = robot("panda")
    checker = CollisionChecker(rob, World(floor=False))
    rng = np.random.default_rng(0)
    Q = rob.q_home + rng.uniform(-2.5, 2.5, (4000, rob.n_dofs))
    d = checker.distance(Q)
    return rob, checker, Q[np.flatnonzero((d < -0.002) & (d > -0.01))[0]]
