"""The collision display (key C): collision shapes, red where in contact, obstacles, and
the closest pair's line labelled with its distance (``collision_scene``)."""
from __future__ import annotations

from robot_sim.graphics import defs as gd
from robot_sim.graphics.collision_scene import CollisionScene, closest_marks, collision_parts
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.scene import GraphicsOptions, Scene


class CollisionItem(Item):
    """``scene.collision`` when given: the shapes translucent over the arm, the closest
    pair's witness points as cyan dots joined by a line, its signed distance as a label."""

    layer = "translucent"
    order = 30.0

    def __init__(self) -> None:
        super().__init__()
        self.collision: CollisionScene | None = None

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        self.collision = scene.collision
        self.visible = scene.collision is not None

    def paint(self, frame: Frame) -> None:
        collision = self.collision
        assert collision is not None
        frame.lit()
        for unit, colours, placements in collision_parts(collision):
            frame.instances(unit, placements, colours)
        marks = closest_marks(collision)
        if marks is None:
            return
        points, dots = marks
        frame.instances("sphere", dots, gd.CLOSEST_COLOR)
        frame.lines(points, gd.CLOSEST_COLOR, GL.GL_LINES, gd.CLOSEST_WIDTH_PX)
        frame.add_obstacle(points)
        frame.add_label(points.mean(axis=0), collision.distance_text(), gd.CLOSEST_COLOR)


ITEM = CollisionItem
