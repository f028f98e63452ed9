"""Labels in the 3D view: text in an anti-aliased vector font (:mod:`..font`, FreeType)
drawn as textured quads at pixel positions, the same in the Qt widget and offscreen.

Each label is written with a halo in the theme's halo colour, so it reads over light
and dark parts alike.  Labels are placed clear of each other, of the arrows and lines the
frame's items registered (:meth:`Frame.add_obstacle`) and of the texts written at fixed
places (:meth:`Frame.add_text`), with a leader line where one had to move
(:func:`~robot_sim.graphics.label_layout.place_labels`).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.font import GlyphAtlas, atlas, text_size
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.label_layout import LabelPlacement, place_labels, polyline_segments
from robot_sim.graphics.shaders import COLOR, NORMAL, POSITION

__all__ = ["LabelsItem", "text_size"]

#: Width of the leader line from a moved label's point to its text (pixels).
LEADER_WIDTH_PX = 1.0


class LabelsItem(Item):
    """Every label the frame's items added (:meth:`Frame.add_label`), in the label font
    with a halo in the theme's colour, ``LABEL_OFFSET_PX`` right of and above its point's
    pixel where that place is free, else at the nearest free place with a leader line
    (``place_labels``); and the frame's fixed texts.  ``labels`` and ``placement`` keep
    what the last frame wrote where (the boxes, for tests and hosts)."""

    layer = "text"
    order = 0.0

    def __init__(self) -> None:
        super().__init__()
        self._texture = 0
        self._version = -1
        self.labels: list[tuple[NDArray[np.float64], str, tuple[float, ...]]] = []
        self.placement = place_labels(np.zeros((0, 2)), [], (1, 1))

    def _bind_atlas(self, glyphs: GlyphAtlas) -> None:
        if not self._texture:
            self._texture = int(GL.glGenTextures(1))
            self._version = -1
        GL.glActiveTexture(GL.GL_TEXTURE0)
        GL.glBindTexture(GL.GL_TEXTURE_2D, self._texture)
        if self._version != glyphs.version:
            GL.glPixelStorei(GL.GL_UNPACK_ALIGNMENT, 1)
            h, w = glyphs.image.shape[:2]
            GL.glTexImage2D(GL.GL_TEXTURE_2D, 0, GL.GL_RG8, w, h, 0, GL.GL_RG, GL.GL_UNSIGNED_BYTE, glyphs.image)
            for key in (GL.GL_TEXTURE_MIN_FILTER, GL.GL_TEXTURE_MAG_FILTER):
                GL.glTexParameteri(GL.GL_TEXTURE_2D, key, GL.GL_NEAREST)
            self._version = glyphs.version

    def paint(self, frame: Frame) -> None:
        glyphs = atlas()
        self.labels = list(frame.labels)
        self.placement = self.place(frame, glyphs)
        quads, colors = [], []
        written = [(box, text, rgba) for box, (_, text, rgba) in zip(self.placement.boxes, self.labels)] + frame.texts
        for box, text, rgba in written:
            if np.all(np.isfinite(box)):
                quads.append(glyphs.layout(text, box[0], box[1]))
                colors.append(np.tile(rgba, (len(quads[-1]), 1)))
        self._paint_leaders(frame)
        if not quads or not sum(len(q) for q in quads):
            return
        # two triangles a glyph, each corner: (x, y, 0), (u, v, 0), colour
        corners = np.concatenate(quads)[:, [0, 1, 2, 0, 2, 3]].reshape(-1, 4)
        rows = np.zeros((len(corners), 10), dtype=np.float32)
        rows[:, [0, 1, 3, 4]] = corners
        rows[:, 6:] = np.repeat(np.concatenate(colors), 6, axis=0)
        self._bind_atlas(glyphs)
        program = frame.resources.programs["text"].use()
        program.set("u_viewport", (float(frame.width), float(frame.height))).set("u_atlas", 0)
        program.set("u_halo_color", frame.theme.halo)
        n = frame.resources.stream.attributes(rows, ((POSITION, 3), (NORMAL, 3), (COLOR, 4)))
        GL.glDrawArrays(GL.GL_TRIANGLES, 0, n)
        GL.glDisableVertexAttribArray(NORMAL)
        GL.glDisableVertexAttribArray(COLOR)

    @staticmethod
    def place(frame: Frame, glyphs: GlyphAtlas) -> LabelPlacement:
        """Where the frame's labels go: clear of each other, its obstacles and its texts."""
        if not frame.labels:
            return place_labels(np.zeros((0, 2)), [], (frame.width, frame.height))
        # every anchor and obstacle point projected at once
        points = [np.array([p for p, _, _ in frame.labels]), *frame.obstacles]
        pixels = frame.camera.project(np.concatenate(points), frame.width, frame.height)
        anchors, *lines = np.split(pixels, np.cumsum([len(p) for p in points])[:-1])
        lines = polyline_segments(lines)
        taken = np.array([box for box, _, _ in frame.texts]).reshape(-1, 4)
        return place_labels(anchors, [glyphs.text_size(text) for _, text, _ in frame.labels],
                            (frame.width, frame.height), lines, taken)

    def _paint_leaders(self, frame: Frame) -> None:
        """A thin line from each moved label's point to its text, in the label's colour."""
        moved = np.flatnonzero(self.placement.moved)
        if len(moved):
            points = np.concatenate([self.placement.leaders[k] for k in moved])
            colors = np.repeat([self.labels[k][2] for k in moved], 2, axis=0)
            frame.pixel_shapes(points + 0.5, colors, GL.GL_LINES, LEADER_WIDTH_PX)

    def release(self, current: bool) -> None:
        if current and self._texture:
            GL.glDeleteTextures([self._texture])
        self._texture = 0


ITEM = LabelsItem
