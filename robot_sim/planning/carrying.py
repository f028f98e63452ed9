"""Collision checkers for the pick task's phases, made of CollisionCheckers:
:class:`CheckerGroup`, and :func:`held_object`, which checks a grasped object (a shape
fixed to the last link) against a world: a CollisionChecker of the same robot whose only
link shape is the object.  The object against the arm's own links is not checked (it
hangs between the fingers, ahead of the tool frame).

World frame, metres.  No Qt, no OpenGL.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.collision import CollisionChecker, World
from robot_sim.collision.path import DEFAULT_STEP, lever_arms
from robot_sim.kinematics import sampling_bounds
from robot_sim.model.params import RobotParams
from robot_sim.model.shapes import Shape

FloatArray = NDArray[np.float64]


def held_object(robot: RobotParams, shape: Shape, world: World, padding: float = 0.0) -> CollisionChecker:
    """``shape`` (posed in the last link's frame n) against ``world``."""
    holder = replace(robot, base_collisions=(), collisions=((),) * (robot.n_dofs - 1) + ((shape,),),
                     collision_allow=())
    return CollisionChecker(holder, world, self_collision=False, padding=padding)


class CheckerGroup:
    """Checkers of one robot asked together: a configuration collides if it collides for
    any member.  Offers what the planner uses of a checker: batched ``in_collision``,
    ``path_is_free`` (the first member's failure), ``padding``, the members' largest lever
    arms (``sweep_radii``) with ``resolution``, and ``members`` (the planner checks their
    pairs together, each group of pairs with its own bound)."""

    def __init__(self, *members: CollisionChecker) -> None:
        self.members = members
        self.robot = members[0].robot
        self.padding = max(m.padding for m in members)
        lo, hi = sampling_bounds(self.robot)
        self.sweep_radii = np.max([lever_arms(m, lo[None], hi[None])[0] for m in members], axis=0)
        self.resolution = self.padding if self.padding > 0.0 else DEFAULT_STEP

    def in_collision(self, q: ArrayLike) -> bool | NDArray[np.bool_]:
        """Whether q (n,), or each row of q (N, n), collides for some member."""
        hits = [m.in_collision(q) for m in self.members]
        return any(hits) if isinstance(hits[0], bool) else np.logical_or.reduce(hits)

    def path_is_free(self, q_path: ArrayLike, times: ArrayLike | None = None):  # noqa: ANN201
        """The first member's continuous check that fails, else the last one's (free)."""
        for member in self.members:
            check = member.path_is_free(q_path, times)
            if not check:
                return check
        return check
