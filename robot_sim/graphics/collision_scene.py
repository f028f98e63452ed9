"""What the collision display (key C) draws, as plain data and unit-mesh placements (no
GL): the robot's collision shapes posed in the world, red for the links in contact, the
world's obstacles (not half-spaces: the floor is drawn already), and the closest checked
pair's witness points with the line between them.  World frame, metres."""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.placements import spheres
from robot_sim.graphics.visuals import shape_pieces
from robot_sim.model.shapes import HalfSpace, Mesh, Shape

if TYPE_CHECKING:  # the checker's module loads numba; drawing needs only its fields
    from robot_sim.collision.distance import DistanceResult

FloatArray = NDArray[np.float64]
RGBA = tuple[float, float, float, float]


@dataclass(frozen=True)
class CollisionScene:
    """``shapes``: (link name, shape posed in the world) of the robot; ``obstacles``:
    (name, shape) of the world; ``touching``: the names of links and obstacles in some
    checked pair closer than zero; ``closest``: the closest checked pair (None or
    ``pair`` None when nothing is checked)."""

    shapes: tuple[tuple[str, Shape], ...]
    obstacles: tuple[tuple[str, Shape], ...]
    touching: frozenset[str]
    closest: DistanceResult | None

    def distance_text(self) -> str:
        """The closest pair and its signed distance in millimetres (negative: penetration)."""
        if self.closest is None or self.closest.pair is None:
            return "no pair checked"
        first, second = self.closest.pair
        return f"{first} - {second} {self.closest.distance * 1000.0:+.1f} mm"


def collision_parts(scene: CollisionScene) -> list[tuple[str, FloatArray, FloatArray]]:
    """(unit mesh, colours (N, 4), placements (N, 4, 4)) to draw: every robot shape (red
    where its link touches something) and every obstacle but half-spaces and meshes
    (whose hulls have no unit mesh)."""
    groups: dict[str, tuple[list, list]] = {}
    drawn = [(shape, gd.COLLISION_CONTACT_COLOR if name in scene.touching else gd.COLLISION_SHAPE_COLOR)
             for name, shape in scene.shapes]
    drawn += [(shape, gd.COLLISION_OBSTACLE_COLOR) for _, shape in scene.obstacles]
    for shape, rgba in drawn:
        if isinstance(shape, (HalfSpace, Mesh)):
            continue
        for piece in shape_pieces(shape, 0):
            colours, placements = groups.setdefault(piece.unit, ([], []))
            colours.append(rgba)
            placements.append(piece.local)
    return [(unit, np.array(c, dtype=float), np.array(p, dtype=float)) for unit, (c, p) in groups.items()]


def closest_marks(scene: CollisionScene) -> tuple[FloatArray, FloatArray] | None:
    """The closest pair's witness points (2, 3) and the sphere placements (2, 4, 4)
    marking them, or None when nothing is checked."""
    if scene.closest is None or scene.closest.pair is None:
        return None
    points = np.asarray(scene.closest.points, dtype=float)
    return points, spheres(points, gd.CLOSEST_POINT_RADIUS_M)
