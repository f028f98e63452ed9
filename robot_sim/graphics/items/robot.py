"""The arm drawn from its DH table: the DH look (links as their d and a segments) or the
solid look (rounded capsules and joint housings), with a base plate.  Hidden when the
robot's meshes are shown alone (look ``mesh``)."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.frame import Drawing, Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.robot_parts import Part, part_corners
from robot_sim.graphics.scene import GraphicsOptions, Scene
from robot_sim.graphics.solid import posed_parts
from robot_sim.graphics.looks import look_for
from robot_sim.kinematics import Kinematics


class RobotItem(Item):
    """The arm of ``scene.kinematics`` as parts (:func:`posed_parts`), lit and casting
    shadows; translucent when ``options.alpha`` < 1; no endeffector sphere while the
    pick task draws a gripper there."""

    layer = "opaque"
    order = 10.0
    casts_shadow = True

    def __init__(self) -> None:
        super().__init__()
        self.kinematics: Kinematics | None = None
        self.look = "dh"
        self.alpha, self.wireframe, self.show_com, self.endeff_marker = 1.0, False, False, True
        self._posed: tuple[NDArray[np.float64], str, bool, list[Part]] | None = None

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        self.kinematics = scene.kinematics
        self.look = look_for(scene.kinematics.robot, options.look)
        self.visible = self.look != "mesh"
        self.alpha, self.wireframe, self.show_com = float(options.alpha), options.wireframe, options.show_com
        self.endeff_marker = scene.task is None
        self.layer = "translucent" if self.alpha < 1.0 else "opaque"  # type: ignore[misc]

    def parts(self) -> list[Part]:
        """The parts of the current pose (computed once per pose and look)."""
        kin = self.kinematics
        assert kin is not None
        posed = self._posed
        if posed is None or posed[0] is not kin.frames or posed[1] != self.look or posed[2] != self.show_com:
            posed = self._posed = (kin.frames, self.look, self.show_com, posed_parts(kin, self.look, self.show_com))
        parts = posed[3]
        return parts if self.endeff_marker else [p for p in parts if p.color != gd.ENDEFF_COLOR]

    def paint(self, frame: Frame) -> None:
        frame.lit(self.alpha)
        if self.wireframe:
            GL.glPolygonMode(GL.GL_FRONT_AND_BACK, GL.GL_LINE)
            frame.culling = False  # a wireframe shows the edges of the back faces too
        for part in self.parts():
            frame.instances(part.mesh, part.placements, part.color)
        GL.glPolygonMode(GL.GL_FRONT_AND_BACK, GL.GL_FILL)

    def paint_depth(self, drawing: Drawing) -> None:
        for part in self.parts():
            drawing.instances(part.mesh, part.placements, part.color)

    def shadow_key(self) -> object:
        kin = self.kinematics
        return None if kin is None else (kin.frames.tobytes(), self.look, self.show_com, self.endeff_marker)

    def bounds(self) -> NDArray[np.float64]:
        return part_corners(self.parts())


ITEM = RobotItem
