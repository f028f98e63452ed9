"""Small robots with known contact answers: carriages of prismatic joints carrying a sphere."""
from __future__ import annotations

import math

import numpy as np

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
