"""The pick task's item: table, obstacles, object and a two-finger gripper at the tool (lit,
casting shadows) and the planned endeffector path (``task_scene`` has the geometry)."""
from __future__ import annotations

import numpy as np

from robot_sim.graphics import defs as gd
from robot_sim.graphics.frame import Drawing, Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.scene import GraphicsOptions, Scene
from robot_sim.graphics.task_scene import FloatArray, TaskScene, task_parts, task_points


class TaskItem(Item):
    """``scene.task``: table, object and gripper, lit and casting shadows, and the planned
    endeffector path as an unlit line."""

    layer = "opaque"
    order = 20.0
    casts_shadow = True

    def __init__(self) -> None:
        super().__init__()
        self.task: TaskScene | None = None

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        self.task = scene.task
        self.visible = scene.task is not None

    def paint_depth(self, drawing: Drawing) -> None:
        assert self.task is not None
        for mesh, color, placements in task_parts(self.task):
            drawing.instances(mesh, placements, color)

    def paint(self, frame: Frame) -> None:
        task = self.task
        assert task is not None
        frame.lit()
        self.paint_depth(frame)
        if len(task.path) >= 2:
            frame.lines(task.path, gd.PATH_COLOR, GL.GL_LINE_STRIP, gd.PATH_LINE_WIDTH_PX)

    def shadow_key(self) -> object:
        task = self.task
        return None if task is None else (task.object_pose.tobytes(), task.tool_pose.tobytes(), task.gripper_opening)

    def bounds(self) -> FloatArray:
        return np.zeros((0, 3)) if self.task is None else task_points(self.task)


ITEM = TaskItem
