"""The desired state ("ghost"): the arm's parts at the desired pose, translucent in
``GHOST_COLOR``, drawn only where they differ from the arm's and behind any arm surface
they touch, so the ghost never recolours the arm.  The IK target's branches drawn at once
(``scene.branches``, key Shift+B) are ghosts too, each labelled with its posture name at
its middle joint (``branch_label_point``)."""
from __future__ import annotations

import numpy as np

from robot_sim.graphics import defs as gd
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.solid import posed_parts
from robot_sim.graphics.robot_parts import Part, branch_label_point, differing
from robot_sim.graphics.scene import GraphicsOptions, Scene
from robot_sim.graphics.looks import look_for


class GhostItem(Item):
    """``scene.ghost`` and ``scene.branches`` when ``options.show_ghost``, in the arm's look
    (DH for a mesh look)."""

    layer = "translucent"
    order = 20.0

    def __init__(self) -> None:
        super().__init__()
        self.parts: list[Part] = []
        self.wireframe = False
        self.labels: list[tuple[np.ndarray, str]] = []

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        ghosts = ([] if scene.ghost is None else [scene.ghost]) + [kin for kin, _ in scene.branches]
        self.visible = options.show_ghost and bool(ghosts)
        if not self.visible:
            return
        arm = scene.kinematics
        look = "solid" if look_for(arm.robot, options.look) == "solid" else "dh"
        reference = posed_parts(arm, look, options.show_com)
        parts = [part for ghost in ghosts for part in differing(posed_parts(ghost, look, options.show_com), reference)]
        if scene.task is not None:  # the gripper is the endeffector
            parts = [p for p in parts if p.color != gd.ENDEFF_COLOR]
        self.parts, self.wireframe = parts, options.wireframe
        self.labels = [(branch_label_point(kin), name) for kin, name in scene.branches]

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
        for point, name in self.labels:
            frame.add_label(point, name)


ITEM = GhostItem
