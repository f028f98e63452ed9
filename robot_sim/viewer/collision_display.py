"""The viewer's collision state (no GL, no Qt): the checker of the shown robot and its
world, what the collision display (key C) draws at a configuration, the readout's
minimum distance and the status bar's flag for a configuration in collision.

The checker is built on first use (its allowed-pair analysis takes up to about a second
for a 7-joint arm).  World frame, metres.
"""
from __future__ import annotations

from numpy.typing import ArrayLike

from robot_sim.collision.checker import CollisionChecker
from robot_sim.graphics.collision_scene import CollisionScene
from robot_sim.model.params import RobotParams
from robot_sim.model.world import World


class CollisionDisplay:
    """Collision queries of ``robot`` in ``world`` (the floor when None) for a viewer."""

    def __init__(self, robot: RobotParams, world: World | None = None) -> None:
        self.robot = robot
        self.world = World() if world is None else world
        self._checker: CollisionChecker | None = None

    @property
    def checker(self) -> CollisionChecker:
        if self._checker is None:
            self._checker = CollisionChecker(self.robot, self.world)
        return self._checker

    def scene(self, q: ArrayLike) -> CollisionScene:
        """The collision display at q (n,): shapes, obstacles, who touches, the closest pair."""
        checker = self.checker
        touching = {name for contact in checker.contacts(q) for name in contact.pair}
        return CollisionScene(tuple(checker.shapes(q)), self.world.obstacles, frozenset(touching),
                              checker.distance(q))

    def readout(self, q: ArrayLike) -> str:
        """The readout's line: the minimum distance over the checked pairs and which pair."""
        result = self.checker.distance(q)
        if result.pair is None:
            return "min distance: no pair checked"
        return f"min distance {result.distance * 1000.0:+.1f} mm ({result.pair[0]} - {result.pair[1]})"

    def flag(self, q: ArrayLike) -> str:
        """The status bar's flag when q is in collision ("" when it is not)."""
        result = self.checker.distance(q)
        if not result.in_collision:
            return ""
        return f" | IN COLLISION: {result.pair[0]} - {result.pair[1]} ({-result.distance * 1000.0:.1f} mm deep)"
