"""The DH parameters of one joint drawn in the 3D view (the geometry is
``robot_sim.graphics.annotation_geometry``): lines over the scene and labels."""
from __future__ import annotations

from robot_sim.graphics import defs as gd
from robot_sim.graphics.annotation_geometry import Annotation, dh_annotation
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.robot_parts import robot_look
from robot_sim.graphics.scene import GraphicsOptions, Scene


class AnnotationItem(Item):
    """The DH annotation of ``options.annotate_joint`` (a joint of the robot shown, else
    nothing): its lines, unlit, ``ANNOTATION_LINE_WIDTH`` pixels wide (extension lines and
    spokes dashed), drawn over the scene and the frames, and its labels (through the
    text layer)."""

    layer = "overlay"
    order = 30.0

    def __init__(self) -> None:
        super().__init__()
        self.annotation = Annotation()

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        kin, joint = scene.kinematics, options.annotate_joint
        self.visible = joint is not None and 1 <= joint <= kin.robot.n_dofs  # a joint left from another robot: none
        if self.visible:
            assert joint is not None
            self.annotation = dh_annotation(kin.frames, joint, kin.robot.is_modified, robot_look(kin.robot).frame_length)

    def paint(self, frame: Frame) -> None:
        GL.glDisable(GL.GL_DEPTH_TEST)  # over the frames' axes too
        for points, rgba, dashed in self.annotation.lines:
            if dashed:
                GL.glEnable(GL.GL_LINE_STIPPLE)
                GL.glLineStipple(*gd.ANNOTATION_DASH)
            frame.lines(points, rgba, GL.GL_LINE_STRIP, gd.ANNOTATION_LINE_WIDTH)
            GL.glDisable(GL.GL_LINE_STIPPLE)
            frame.add_obstacle(points)  # no label on a dimension or an arc
        GL.glEnable(GL.GL_DEPTH_TEST)
        for anchor, text, rgba in self.annotation.labels:
            frame.add_label(anchor, text, rgba)


ITEM = AnnotationItem
