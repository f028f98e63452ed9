"""The IK target: a small frame and a marker sphere at its world pose, yellow, or magenta
when it is out of reach; drawn over the scene."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.placements import spheres
from robot_sim.graphics.item import Item, around
from robot_sim.graphics.items.frames import FRAME_BOUND_MARGIN, draw_axes
from robot_sim.graphics.robot_parts import robot_reach
from robot_sim.graphics.scene import GraphicsOptions, Scene


class TargetItem(Item):
    """``scene.target_tf`` when ``options.show_target``, sized for the robot's reach."""

    layer = "overlay"
    order = 10.0

    def __init__(self) -> None:
        super().__init__()
        self.pose, self.reach, self.reachable = np.eye(4), 1.0, True

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        self.visible = options.show_target and scene.target_tf is not None
        if self.visible:
            assert scene.target_tf is not None
            self.pose, self.reachable = scene.target_tf.mat, scene.target_reachable
            self.reach = robot_reach(scene.kinematics.robot)

    def bounds(self) -> NDArray[np.float64]:
        half = FRAME_BOUND_MARGIN * self.reach * max(gd.TARGET_FRAME_LENGTH_FRAC, gd.TARGET_MARKER_RADIUS_FRAC)
        return around(self.pose[:3, 3], half)

    def paint(self, frame: Frame) -> None:
        frame.lit(markers=True)
        draw_axes(frame, self.pose[None], self.reach * gd.TARGET_FRAME_LENGTH_FRAC)
        color = gd.TARGET_COLOR if self.reachable else gd.TARGET_UNREACHABLE_COLOR
        frame.instances("sphere", spheres(self.pose[:3, 3], self.reach * gd.TARGET_MARKER_RADIUS_FRAC), color)


ITEM = TargetItem
