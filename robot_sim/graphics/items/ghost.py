"""The desired state ("ghost"): the arm's parts at the desired pose, translucent in
``GHOST_COLOR``, drawn only where they differ from the arm's and behind any arm surface
they touch, so the ghost never recolours the arm."""
from __future__ import annotations

from robot_sim.graphics import defs as gd
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.solid import posed_parts
from robot_sim.graphics.robot_parts import Part, differing
from robot_sim.graphics.scene import GraphicsOptions, Scene
from robot_sim.graphics.looks import look_for


class GhostItem(Item):
    """``scene.ghost`` when ``options.show_ghost``, in the arm's look (DH for a mesh look)."""

    layer = "translucent"
    order = 20.0

    def __init__(self) -> None:
        super().__init__()
        self.parts: list[Part] = []
        self.wireframe = False

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        self.visible = options.show_ghost and scene.ghost is not None
        if not self.visible:
            return
        assert scene.ghost is not None
        arm = scene.kinematics
        look = "solid" if look_for(arm.robot, options.look) == "solid" else "dh"
        reference = posed_parts(arm, look, options.show_com)
        parts = differing(posed_parts(scene.ghost, look, options.show_com), reference)
        if scene.task is not None:  # the gripper is the endeffector
            parts = [p for p in parts if p.color != gd.ENDEFF_COLOR]
        self.parts, self.wireframe = parts, options.wireframe

    def paint(self, frame: Frame) -> None:
        frame.lit()
        GL.glDepthFunc(GL.GL_LESS)
        GL.glEnable(GL.GL_POLYGON_OFFSET_FILL)
        GL.glPolygonOffset(*gd.GHOST_POLYGON_OFFSET)
        if self.wireframe:
            GL.glPolygonMode(GL.GL_FRONT_AND_BACK, GL.GL_LINE)
        for part in self.parts:
            frame.instances(part.mesh, part.placements, gd.GHOST_COLOR)
        GL.glPolygonMode(GL.GL_FRONT_AND_BACK, GL.GL_FILL)
        GL.glDisable(GL.GL_POLYGON_OFFSET_FILL)
        GL.glDepthFunc(GL.GL_LEQUAL)


ITEM = GhostItem
