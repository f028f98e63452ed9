"""The endeffector trail: a polyline through the points the endeffector passed."""
from __future__ import annotations

import numpy as np

from robot_sim.graphics import defs as gd
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.scene import GraphicsOptions, Scene


class TrailItem(Item):
    """``scene.trail`` (N, 3) world points in metres, oldest first, as an unlit line strip
    of ``TRAIL_COLOR``, ``TRAIL_WIDTH_PX`` wide; depth tested so the arm hides what is
    behind it."""

    layer = "translucent"
    order = 5.0

    def __init__(self) -> None:
        super().__init__()
        self.points = np.zeros((0, 3))

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        self.points = np.zeros((0, 3)) if scene.trail is None else np.asarray(scene.trail, dtype=float).reshape(-1, 3)
        self.visible = len(self.points) >= 2

    def paint(self, frame: Frame) -> None:
        frame.lines(self.points, gd.TRAIL_COLOR, GL.GL_LINE_STRIP, gd.TRAIL_WIDTH_PX)


ITEM = TrailItem
