"""The robot's own visual shapes (meshes and primitives from its file or URDF), drawn at
the links' poses: opaque in the ``mesh`` look, translucent over the DH segments in the
``both`` look.  Mesh buffers are uploaded once per robot and context."""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.frame import Drawing, Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.scene import GraphicsOptions, Scene
from robot_sim.graphics.looks import look_for
from robot_sim.graphics.buffers import StaticMesh
from robot_sim.graphics.visuals import VisualPiece, piece_corners, vertex_normals, visual_pieces
from robot_sim.kinematics import Kinematics
from robot_sim.model.params import RobotParams


def mesh_buffers(piece: VisualPiece) -> StaticMesh:
    """The (not yet uploaded) buffers of a mesh piece, with smooth vertex normals."""
    if piece.vertices is None or piece.faces is None:
        raise ValueError(f"mesh_buffers: piece of frame {piece.frame} is the unit mesh {piece.unit!r}, not a mesh")
    return StaticMesh(piece.vertices, vertex_normals(piece.vertices, piece.faces), piece.faces)


class RobotMeshItem(Item):
    """The visuals of ``scene.kinematics.robot`` at its current frames."""

    layer = "opaque"
    order = 11.0
    casts_shadow = True

    def __init__(self) -> None:
        super().__init__()
        self.kinematics: Kinematics | None = None
        self.alpha, self.wireframe = 1.0, False
        self._robot: RobotParams | None = None
        self._pieces: list[VisualPiece] = []
        self._buffers: list[StaticMesh | None] = []  # per piece: a mesh's buffers
        self._dead: list[StaticMesh] = []  # of a robot no longer shown: deleted at the next paint

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        kin = self.kinematics = scene.kinematics
        look = look_for(kin.robot, options.look)
        self.visible = look in ("mesh", "both")
        if not self.visible:
            return
        if kin.robot is not self._robot:
            self._dead += [b for b in self._buffers if b is not None]
            self._robot, self._pieces = kin.robot, visual_pieces(kin.robot)
            self._buffers = [None if p.vertices is None else mesh_buffers(p) for p in self._pieces]
        self.alpha = gd.MESH_OVER_DH_ALPHA if look == "both" else float(options.alpha)
        self.wireframe = options.wireframe
        self.layer = "translucent" if self.alpha < 1.0 else "opaque"  # type: ignore[misc]

    def _draw(self, frame: Drawing) -> None:
        assert self.kinematics is not None
        frames = self.kinematics.frames
        units: dict[str, tuple[list[NDArray], list[tuple[float, ...]]]] = {}
        for piece, buffers in zip(self._pieces, self._buffers):
            placement = frames[piece.frame] @ piece.local
            if buffers is not None:
                frame.mesh(buffers, placement, piece.color)
            else:
                mats, colors = units.setdefault(piece.unit or "box", ([], []))
                mats.append(placement)
                colors.append(piece.color)
        for unit, (mats, colors) in units.items():
            frame.instances(unit, np.array(mats), np.array(colors))

    def paint(self, frame: Frame) -> None:
        for buffers in self._dead:
            buffers.delete()
        self._dead.clear()
        frame.lit(self.alpha)
        if self.wireframe:
            GL.glPolygonMode(GL.GL_FRONT_AND_BACK, GL.GL_LINE)
            frame.culling = False  # a wireframe shows the edges of the back faces too
        self._draw(frame)
        GL.glPolygonMode(GL.GL_FRONT_AND_BACK, GL.GL_FILL)

    def paint_depth(self, drawing: Drawing) -> None:
        self._draw(drawing)

    def shadow_key(self) -> object:
        kin = self.kinematics
        return None if kin is None else (id(self._robot), kin.frames.tobytes())

    def bounds(self) -> NDArray[np.float64]:
        return piece_corners(self._pieces, self.kinematics.frames) if self.kinematics is not None else np.zeros((0, 3))

    def release(self, current: bool) -> None:
        for buffers in [b for b in self._buffers if b is not None] + self._dead:
            (buffers.delete if current else buffers.forget)()
        self._dead.clear()


ITEM = RobotMeshItem
