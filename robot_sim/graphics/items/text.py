"""Labels in the 3D view: text in an anti-aliased vector font (:mod:`..font`, FreeType)
drawn as textured quads at pixel positions, the same in the Qt widget and offscreen.

Each label is written with a halo in the theme's halo colour, so it reads over light
and dark parts alike; labels that would overlap move down (:func:`spread`).
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.font import GlyphAtlas, atlas, text_size
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.shaders import COLOR, NORMAL, POSITION

__all__ = ["LabelsItem", "spread", "text_size"]


def spread(pixels: NDArray[np.float64], sizes: list[tuple[int, int]]) -> NDArray[np.float64]:
    """Label anchors (N, 2) (x right, y down) moved down, in order, by whole text lines
    until no text box (``sizes`` (w, h) each, drawn right of and above its anchor)
    overlaps an earlier one; anchors that project nowhere (NaN) stay put."""
    out = pixels.copy()
    boxes: list[tuple[float, float, float, float]] = []
    gap = gd.LABEL_GAP_PX
    for k, ((w, h), (x, y)) in enumerate(zip(sizes, pixels)):
        if not (np.isfinite(x) and np.isfinite(y)):
            continue
        for _ in range(len(sizes) + 1):
            box = (x, y - h - gap, x + w, y)
            if not any(box[0] < b[2] and b[0] < box[2] and box[1] < b[3] and b[1] < box[3] for b in boxes):
                break
            y += h + gap
        boxes.append(box)
        out[k] = (x, y)
    return out


class LabelsItem(Item):
    """Every label the frame's items added (:meth:`Frame.add_label`), in the label font
    with a halo in the theme's colour, ``LABEL_OFFSET_PX`` right of and above its point's
    pixel, moved down where it would overlap an earlier one (:func:`spread`)."""

    layer = "text"
    order = 0.0

    def __init__(self) -> None:
        super().__init__()
        self._texture = 0
        self._version = -1

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
        if not frame.labels:
            return
        glyphs = atlas()
        texts = [text for _, text, _ in frame.labels]
        pixels = spread(frame.camera.project(np.array([p for p, _, _ in frame.labels]), frame.width, frame.height),
                        [glyphs.text_size(t) for t in texts])
        dx, dy = gd.LABEL_OFFSET_PX
        rows = []
        for (_, text, rgba), (x, y) in zip(frame.labels, pixels):
            if not (np.isfinite(x) and np.isfinite(y)):
                continue
            quads = glyphs.layout(text, x + dx, y - dy - glyphs.line_height)
            for quad in quads:  # two triangles per glyph: position (x, y, 0), uv in the normal slot, colour
                corners = quad[[0, 1, 2, 0, 2, 3]]
                rows.append(np.c_[corners[:, :2], np.zeros(6), corners[:, 2:], np.zeros(6), np.tile(rgba, (6, 1))])
        if not rows:
            return
        self._bind_atlas(glyphs)
        program = frame.resources.programs["text"].use()
        program.set("u_viewport", (float(frame.width), float(frame.height))).set("u_atlas", 0)
        program.set("u_halo_color", frame.theme.halo)
        n = frame.resources.stream.attributes(np.vstack(rows), ((POSITION, 3), (NORMAL, 3), (COLOR, 4)))
        GL.glDrawArrays(GL.GL_TRIANGLES, 0, n)
        GL.glDisableVertexAttribArray(NORMAL)
        GL.glDisableVertexAttribArray(COLOR)

    def release(self, current: bool) -> None:
        if current and self._texture:
            GL.glDeleteTextures([self._texture])
        self._texture = 0


ITEM = LabelsItem
