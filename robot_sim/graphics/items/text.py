"""Text in the 3D view without a GUI toolkit: a small bitmap font drawn with glBitmap at
window positions, so the Qt widget and the OSMesa renderer write the same labels.

Glyphs are 5 x 7 pixel cells (``FONT_5X7``), magnified ``LABEL_PIXEL_SCALE`` times and
compiled into one display list per character code per GL context; a string is drawn
with one glCallLists.  Characters outside the font are drawn as blanks.  Each label is
drawn twice, first in ``LABEL_SHADOW_COLOR`` one pixel down and right, so it reads over
light and dark parts alike.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.gl import GL, set_color
from robot_sim.graphics.resources import Drawable

# 5 x 7 glyphs, top row first, "#" = ink.  Greek and the degree sign are mapped to the
# control codes below so that a string is one byte per character.
FONT_5X7: dict[str, tuple[str, ...]] = {
    "0": (" ### ", "#   #", "#  ##", "# # #", "##  #", "#   #", " ### "),
    "1": ("  #  ", " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### "),
    "2": (" ### ", "#   #", "    #", "   # ", "  #  ", " #   ", "#####"),
    "3": ("#####", "   # ", "  #  ", "   # ", "    #", "#   #", " ### "),
    "4": ("   # ", "  ## ", " # # ", "#  # ", "#####", "   # ", "   # "),
    "5": ("#####", "#    ", "#### ", "    #", "    #", "#   #", " ### "),
    "6": ("  ## ", " #   ", "#    ", "#### ", "#   #", "#   #", " ### "),
    "7": ("#####", "    #", "   # ", "  #  ", " #   ", " #   ", " #   "),
    "8": (" ### ", "#   #", "#   #", " ### ", "#   #", "#   #", " ### "),
    "9": (" ### ", "#   #", "#   #", " ####", "    #", "   # ", " ##  "),
    "E": ("#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#####"),
    "d": ("    #", "    #", " ## #", "#  ##", "#   #", "#   #", " ####"),
    "a": ("     ", "     ", " ### ", "    #", " ####", "#   #", " ####"),
    "m": ("     ", "     ", "## # ", "# # #", "# # #", "#   #", "#   #"),
    ".": ("     ", "     ", "     ", "     ", "     ", " ##  ", " ##  "),
    ",": ("     ", "     ", "     ", "     ", " ##  ", "  #  ", " #   "),
    "-": ("     ", "     ", "     ", "#####", "     ", "     ", "     "),
    "+": ("     ", "  #  ", "  #  ", "#####", "  #  ", "  #  ", "     "),
    "=": ("     ", "     ", "#####", "     ", "#####", "     ", "     "),
    " ": ("     ", "     ", "     ", "     ", "     ", "     ", "     "),
    "θ": (" ### ", "#   #", "#   #", "#####", "#   #", "#   #", " ### "),
    "α": ("     ", "     ", " ## #", "#  # ", "#  # ", "#  # ", " ## #"),
    "°": (" ##  ", "#  # ", "#  # ", " ##  ", "     ", "     ", "     "),
}
_CODES = {"θ": 1, "α": 2, "°": 3}
GLYPH_W, GLYPH_H = 5, 7


def _code(char: str) -> int:
    return _CODES.get(char, ord(char) if len(char) == 1 and ord(char) < 128 else ord(" "))


def encode(text: str) -> bytes:
    """The display-list codes of ``text``'s characters (unknown ones become blanks)."""
    return bytes(_code(c) if c in FONT_5X7 else ord(" ") for c in text)


def glyph_bitmap(char: str, scale: int) -> NDArray[np.uint8]:
    """Ink (7 * scale, 5 * scale) of ``char``, top row first, 1 where drawn."""
    rows = np.array([[c == "#" for c in row] for row in FONT_5X7[char]], dtype=np.uint8)
    return np.kron(rows, np.ones((scale, scale), dtype=np.uint8))


def text_size(text: str, scale: int = gd.LABEL_PIXEL_SCALE) -> tuple[int, int]:
    """Width and height in pixels of ``text`` drawn at ``scale``."""
    return len(text) * (GLYPH_W + 1) * scale, GLYPH_H * scale


def spread(pixels: NDArray[np.float64], sizes: list[tuple[int, int]]) -> NDArray[np.float64]:
    """Label anchors (N, 2) (x right, y down) moved down, in order, by whole text lines
    until no text box (``sizes`` (w, h) each, drawn right of and above its anchor)
    overlaps an earlier one; anchors that project nowhere (NaN) stay put."""
    out = pixels.copy()
    boxes: list[tuple[float, float, float, float]] = []
    gap = gd.LABEL_PIXEL_SCALE
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


class TextGraphics(Drawable):
    """Labels at world points: ``labels`` holds (point (3,), text, rgba) triples; each
    text is drawn ``LABEL_OFFSET_PX`` right of and above the point's pixel, seen by the
    camera and viewport set with :meth:`place`.  Never hidden by the scene (overlay)."""

    gl_preset = "overlay"

    def __init__(self) -> None:
        super().__init__()
        self.labels: list[tuple[ArrayLike, str, Sequence[float]]] = []
        self._pixels = np.zeros((0, 2))
        self._height = 1

    def place(self, pixels: NDArray[np.float64], height: int) -> None:
        """Pixel positions (N, 2) (x right, y down from the top row) of the labels' points
        in a viewport ``height`` pixels tall (from ``Camera.project``); a label that would
        overlap an earlier one moves down until it does not (:func:`spread`)."""
        pixels = np.asarray(pixels, dtype=float).reshape(-1, 2)
        self._pixels = spread(pixels, [text_size(text) for _, text, _ in self.labels])
        self._height = int(height)

    def _compile_font(self) -> int:
        scale = gd.LABEL_PIXEL_SCALE
        base = int(GL.glGenLists(128))
        GL.glPixelStorei(GL.GL_UNPACK_ALIGNMENT, 1)
        for char in FONT_5X7:
            ink = glyph_bitmap(char, scale)[::-1]  # glBitmap rows run bottom to top
            data = np.packbits(ink, axis=1).tobytes()
            GL.glNewList(base + _code(char), GL.GL_COMPILE)
            GL.glBitmap(ink.shape[1], ink.shape[0], 0.0, 0.0, float((GLYPH_W + 1) * scale), 0.0, data)
            GL.glEndList()
        return base

    def paint(self) -> None:
        if not self.labels:
            return
        base = self.gl.get(self._compile_font)
        GL.glListBase(base)
        dx, dy = gd.LABEL_OFFSET_PX
        for (_, text, rgba), (x, y) in zip(self.labels, self._pixels):
            if not (np.isfinite(x) and np.isfinite(y)):
                continue
            codes = encode(text)
            wx, wy = x + dx, self._height - 1 - y + dy
            for color, shift in ((gd.LABEL_SHADOW_COLOR, (1, -1)), (rgba, (0, 0))):
                set_color(color)
                GL.glWindowPos2f(wx + shift[0], wy + shift[1])
                GL.glCallLists(len(codes), GL.GL_UNSIGNED_BYTE, codes)
        GL.glListBase(0)
