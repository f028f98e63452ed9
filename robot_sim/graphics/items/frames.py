"""Coordinate frames drawn over the scene: the DH frames shown and the endeffector frame,
each labelled with its number ("E" for the tool); the geometry is
``robot_sim.graphics.frame_axes``."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics.frame import Frame
from robot_sim.graphics.frame_axes import axes_placements, axis_lengths, frame_labels, frames_and_names
from robot_sim.graphics.item import Item, around
from robot_sim.graphics.robot_parts import robot_look
from robot_sim.graphics.scene import GraphicsOptions, Scene

#: Bounds of a frame: a cube of half side this many axis lengths about its origin.
FRAME_BOUND_MARGIN = 1.25


def draw_axes(frame: Frame, frames: ArrayLike, length: float) -> NDArray[np.float64]:
    """Draw the axes of world ``frames`` (N, 4, 4), ``length`` metres long, with the lit
    program in use (labels keep clear of them); returns each frame's axis length (N,)."""
    poses = np.asarray(frames, dtype=float).reshape(-1, 4, 4)
    shafts, cones, colors, lengths = axes_placements(poses, length)
    frame.instances("cylinder", shafts, colors)
    frame.instances("cone", cones, colors)
    for pose, extent in zip(poses, lengths):  # labels keep clear of the arrows
        for axis in range(3):
            frame.add_obstacle([pose[:3, 3], pose[:3, 3] + extent * pose[:3, axis]])
    return lengths


class FramesItem(Item):
    """The frames ``options.show_frames`` and ``show_endeff_frame`` select, labelled when
    ``options.show_labels``, sized ``robot_look(robot).frame_length``."""

    layer = "overlay"
    order = 0.0

    def __init__(self) -> None:
        super().__init__()
        self.frames = np.zeros((0, 4, 4))
        self.names: list[str] = []
        self.length, self.labelled = 1.0, True

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        kin = scene.kinematics
        self.frames, self.names = frames_and_names(kin, options.show_frames, options.show_endeff_frame)
        self.length, self.labelled = robot_look(kin.robot).frame_length, options.show_labels
        self.visible = len(self.frames) > 0

    def bounds(self) -> NDArray[np.float64]:
        # an arrow of length L with its head stays within L of its origin; the margin
        # covers the head's radius
        return around(self.frames[:, :3, 3], FRAME_BOUND_MARGIN * axis_lengths(self.frames, self.length))

    def paint(self, frame: Frame) -> None:
        frame.lit(markers=True)
        lengths = draw_axes(frame, self.frames, self.length)
        if self.labelled:
            for point, text in frame_labels(self.frames, self.names, lengths):
                frame.add_label(point, text)


ITEM = FramesItem
