"""Collision: signed distances between shapes, the robot's allowed pairs, batched
configuration checks, continuous path checks and penalty contact for simulation.

World frame, metres; signed distances are negative in penetration.  Imports neither
graphics, Qt nor OpenGL.
"""
from robot_sim.model.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Sphere
from robot_sim.model.world import World

from robot_sim.collision.checker import CollisionChecker, DistanceResult, PairContact
from robot_sim.collision.contact import ContactForce, ContactModel

__all__ = ["Box", "Capsule", "CollisionChecker", "ContactForce", "ContactModel", "Cylinder", "DistanceResult",
           "HalfSpace", "Mesh", "PairContact", "Sphere", "World"]
