"""Collision: signed distances between shapes, the robot's allowed pairs, batched
configuration checks and continuous path checks (penalty contact, which uses them, is
the physics loop's: robot_sim/sim/contact.py).

World frame, metres; signed distances are negative in penetration.  Imports neither
graphics, Qt nor OpenGL.
"""
from robot_sim.model.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Sphere
from robot_sim.model.world import World

from robot_sim.collision.checker import CollisionChecker, DistanceResult, PairContact

__all__ = ["Box", "Capsule", "CollisionChecker", "Cylinder", "DistanceResult",
           "HalfSpace", "Mesh", "PairContact", "Sphere", "World"]
