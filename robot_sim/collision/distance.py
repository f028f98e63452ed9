"""Signed distance between two shapes, and the result type of every distance query.

World frame (or any common frame), metres; negative distances are penetration depths.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.collision.narrow import pair_distance
from robot_sim.collision.pack import pack
from robot_sim.model.shapes import Shape

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class DistanceResult:
    """The closest checked pair at one configuration.

    ``distance`` [m], signed (negative: penetration depth; inf when nothing is checked);
    ``pair`` the two names (link or obstacle; None when nothing is checked); ``points``
    (2, 3) the witness points in the world, on the first and on the second; ``normal``
    (3,) the unit direction from the first toward the second, with
    ``points[1] = points[0] + distance * normal``.
    """

    distance: float
    pair: tuple[str, str] | None
    points: FloatArray
    normal: FloatArray

    @property
    def in_collision(self) -> bool:
        return self.distance < 0.0



def shape_distance(a: Shape, b: Shape) -> DistanceResult:
    """Signed distance between shapes ``a`` and ``b`` posed in one frame (``pair`` None).
    Exact for spheres, capsules, boxes (with each other and with half-spaces) and spheres
    with cylinders; GJK/EPA otherwise (exact for polytopes, to 1e-10 m for curved
    shapes); meshes count as their convex hulls.  Two half-spaces: inf."""
    packed = pack([a, b])
    d, pa, pb, n = pair_distance(packed.kinds[0], packed.recs[0], packed.kinds[1], packed.recs[1], packed.verts,
                                 math.inf)
    return DistanceResult(float(d), None, np.array([pa, pb]), np.array(n))
