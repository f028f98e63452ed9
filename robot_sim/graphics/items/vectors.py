"""Arrows from a point along a world vector (1 m per unit): the endeffector's velocities
and the mouse pull spring; drawn over the scene."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.arrows import arrow_placements
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.item import Item, around
from robot_sim.graphics.robot_parts import robot_reach
from robot_sim.graphics.scene import GraphicsOptions, Scene, Vector
from robot_sim.graphics.vector_clip import shown_vectors


class VectorsItem(Item):
    """``scene.vectors`` ((origin, vector, rgba) triples) when ``options.show_vectors``,
    sized for the robot's reach: none shorter than its head, each shortened to the view
    (vector_clip.shown_vectors)."""

    layer = "overlay"
    order = 20.0

    def __init__(self) -> None:
        super().__init__()
        self.vectors: list[Vector] = []
        self.reach = 1.0

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        self.vectors = list(scene.vectors) if options.show_vectors else []
        self.reach = robot_reach(scene.kinematics.robot)
        self.visible = bool(self.vectors)

    def bounds(self) -> NDArray[np.float64]:
        ends = np.array([end for origin, vec, _ in self.vectors for end in (origin, np.add(origin, vec))]).reshape(-1, 3)
        return around(ends, self.reach * gd.VECTOR_HEAD_RADIUS_FRAC)

    def paint(self, frame: Frame) -> None:
        frame.lit(markers=True)
        head = self.reach * gd.VECTOR_HEAD_LENGTH_FRAC
        for origin, vec, rgba in shown_vectors(self.vectors, frame.camera, frame.width, frame.height, head):
            frame.add_obstacle([origin, origin + vec])  # no label on an arrow
            shafts, heads = arrow_placements(origin, vec, self.reach * gd.VECTOR_SHAFT_RADIUS_FRAC,
                                             self.reach * gd.VECTOR_HEAD_RADIUS_FRAC,
                                             self.reach * gd.VECTOR_HEAD_LENGTH_FRAC)
            frame.instances("cylinder", shafts, rgba)
            frame.instances("cone", heads, rgba)


ITEM = VectorsItem
