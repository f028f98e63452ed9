"""The workspace point cloud's item: the points drawn from a vertex buffer uploaded
once per cloud (``workspace`` has the data)."""
from __future__ import annotations

from robot_sim.graphics import defs as gd
from robot_sim.graphics.buffers import StaticPoints
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.scene import GraphicsOptions, Scene
from robot_sim.graphics.workspace import WorkspaceCloud


class CloudItem(Item):
    """``scene.workspace`` when ``options.show_workspace``: unlit points of
    ``WORKSPACE_POINT_SIZE`` pixels, depth tested and written, from a vertex buffer
    uploaded once per cloud (the buffer of a cloud no longer shown is deleted)."""

    layer = "opaque"
    order = 0.0
    cached = True  # 200 000 points cost llvmpipe more than the rest of a frame

    def __init__(self) -> None:
        super().__init__()
        self.cloud: WorkspaceCloud | None = None
        self._buffer: StaticPoints | None = None
        self._dead: list[StaticPoints] = []
        self._version = 0  # counts the clouds shown

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        cloud = scene.workspace if options.show_workspace else None
        self.visible = cloud is not None and len(cloud) > 0
        if cloud is not None and cloud is not self.cloud:
            if self._buffer is not None:
                self._dead.append(self._buffer)
            self.cloud, self._buffer = cloud, StaticPoints(cloud.points, cloud.colors)
            self._version += 1

    def cache_key(self) -> object:
        return self._version

    def paint(self, frame: Frame) -> None:
        for buffer in self._dead:
            buffer.delete()
        self._dead.clear()
        assert self._buffer is not None
        frame.unlit()
        GL.glPointSize(gd.WORKSPACE_POINT_SIZE)
        self._buffer.draw(GL.GL_POINTS)
        GL.glPointSize(1.0)

    def release(self, current: bool) -> None:
        for buffer in self._dead + ([self._buffer] if self._buffer is not None else []):
            (buffer.delete if current else buffer.forget)()
        self._dead.clear()


ITEM = CloudItem
