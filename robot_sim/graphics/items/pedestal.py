"""The pedestal of a raised base: a translucent column from the floor up to the base
plate, so the base's height reads at a glance while links hanging down beside or
through it still show."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.placements import along
from robot_sim.graphics.item import Item
from robot_sim.graphics.robot_parts import robot_look
from robot_sim.graphics.scene import GraphicsOptions, Scene
from robot_sim.model.params import RobotParams


def pedestal(robot: RobotParams, base: NDArray[np.float64]) -> NDArray[np.float64] | None:
    """Placement (1, 4, 4) of the unit closed cylinder standing from the floor up to the
    bottom of ``robot``'s base plate under world frame 0 ``base`` (4, 4) when that is
    raised above the floor, else None."""
    look = robot_look(robot)
    top = base[:3, 3] - base[:3, 2] * gd.BASE_PLATE_THICKNESS_RATIO * look.base_radius
    if top[2] <= gd.MIN_LINK_LENGTH:
        return None
    foot = top * (1.0, 1.0, 0.0)
    return along(foot[None], (top - foot)[None], gd.PEDESTAL_RADIUS_RATIO * look.base_radius, top[2])


class PedestalItem(Item):
    """The pedestal under ``scene.kinematics``' base when it is raised."""

    layer = "translucent"
    order = 1.0

    def __init__(self) -> None:
        super().__init__()
        self.column: NDArray[np.float64] | None = None

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        kin = scene.kinematics
        self.column = pedestal(kin.robot, kin.frames[0])
        self.visible = self.column is not None

    def paint(self, frame: Frame) -> None:
        frame.lit()
        frame.instances("joint", self.column, gd.PEDESTAL_COLOR)


ITEM = PedestalItem
