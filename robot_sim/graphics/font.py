"""Anti-aliased text from a vector font: glyphs rasterised by FreeType (``freetype-py``)
into one atlas image, and strings laid out as textured quads (pure NumPy, no GL).

The font is DejaVu Sans from Debian's ``fonts-dejavu-core`` (the Makefile installs it).
The atlas has two channels: the glyphs' coverage, and that coverage grown by
``HALO_PX`` pixels, so text is drawn with a halo in the background's colour and reads
over light and dark parts alike.  Glyphs are added on first use, so any character the
font has can be written.  Pixel coordinates: x right, y down.
"""
from __future__ import annotations

import functools
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

FONT_PACKAGE = "fonts-dejavu-core"
FONT_DIRS = ("/usr/share/fonts/truetype/dejavu", "/usr/share/fonts/dejavu", "/usr/local/share/fonts")
FONT_FILE = "DejaVuSans.ttf"
FONT_ENV = "ROBOT_SIM_FONT"     # a .ttf to use instead
LABEL_FONT_PX = 15              # labels' pixel size (the em height)
HALO_PX = 2                     # halo width around each glyph
ATLAS_WIDTH = 512
_PRELOAD = "".join(chr(c) for c in range(32, 127)) + "θαβγδφψω°±−·√²ᵀ"


def font_path() -> Path:
    """The font file: ``$ROBOT_SIM_FONT`` if set, else DejaVu Sans from ``FONT_DIRS``.
    Raises FileNotFoundError naming the Debian package when there is none."""
    override = os.environ.get(FONT_ENV)
    if override:
        if not Path(override).is_file():
            raise FileNotFoundError(f"{FONT_ENV}={override}: no such font file")
        return Path(override)
    for folder in FONT_DIRS:
        candidate = Path(folder) / FONT_FILE
        if candidate.is_file():
            return candidate
    raise FileNotFoundError(
        f"font {FONT_FILE} not found in {', '.join(FONT_DIRS)}; install the Debian package {FONT_PACKAGE} "
        f"(apt-get install {FONT_PACKAGE}) or set {FONT_ENV} to a .ttf file")


@dataclass(frozen=True)
class Glyph:
    """One glyph's cell in the atlas (halo padding included) and its metrics, pixels:
    ``x``, ``y``, ``width``, ``height`` of the cell; ``left``/``top`` from the pen
    position on the baseline to the cell's top-left corner (y down); ``advance``."""

    x: int
    y: int
    width: int
    height: int
    left: int
    top: int
    advance: float


def _grow(coverage: NDArray[np.uint8], radius: int) -> NDArray[np.uint8]:
    """``coverage`` (h, w) dilated by a disc of ``radius`` pixels (same shape)."""
    out = coverage.copy()
    h, w = coverage.shape
    for dy in range(-radius, radius + 1):
        for dx in range(-radius, radius + 1):
            if dx * dx + dy * dy > radius * radius or (dx == 0 and dy == 0):
                continue
            src = coverage[max(0, -dy):h - max(0, dy), max(0, -dx):w - max(0, dx)]
            dst = out[max(0, dy):h - max(0, -dy), max(0, dx):w - max(0, -dx)]
            np.maximum(dst, src, out=dst)
    return out


class GlyphAtlas:
    """Glyphs of one font at one pixel size packed into an image (H, ``ATLAS_WIDTH``, 2)
    uint8: channel 0 coverage, channel 1 the halo.  ``version`` counts changes of
    :attr:`image` (a GL texture is re-uploaded when it differs)."""

    def __init__(self, path: str | os.PathLike[str], pixel_size: int, halo: int = HALO_PX) -> None:
        import freetype  # freetype-py: FreeType bindings with the library in the wheel

        self.face = freetype.Face(str(path))
        self.face.set_pixel_sizes(0, int(pixel_size))
        self.pixel_size, self.halo = int(pixel_size), int(halo)
        metrics = self.face.size
        self.ascender, self.descender = metrics.ascender / 64.0, metrics.descender / 64.0
        self.image = np.zeros((64, ATLAS_WIDTH, 2), dtype=np.uint8)
        self.version = 0
        self._glyphs: dict[str, Glyph] = {}
        self._shelf = (0, 0, 0)  # x, y, height of the row being filled
        for char in _PRELOAD:
            self.glyph(char)

    @property
    def line_height(self) -> int:
        """Pixels from the top of the tallest glyph to the bottom of the lowest."""
        return int(round(self.ascender - self.descender))

    def glyph(self, char: str) -> Glyph:
        """The glyph of ``char``, rasterised and packed on first use (a character the
        font lacks gets its replacement glyph)."""
        found = self._glyphs.get(char)
        if found is not None:
            return found
        import freetype

        self.face.load_char(char, freetype.FT_LOAD_RENDER | freetype.FT_LOAD_TARGET_NORMAL)
        slot = self.face.glyph
        bitmap, pad = slot.bitmap, self.halo + 1
        ink = np.array(bitmap.buffer, dtype=np.uint8).reshape(bitmap.rows, bitmap.pitch)[:, :bitmap.width] \
            if bitmap.rows and bitmap.width else np.zeros((0, 0), dtype=np.uint8)
        cell = np.zeros((ink.shape[0] + 2 * pad, ink.shape[1] + 2 * pad), dtype=np.uint8)
        cell[pad:pad + ink.shape[0], pad:pad + ink.shape[1]] = ink
        x, y = self._place(*cell.shape)
        self.image[y:y + cell.shape[0], x:x + cell.shape[1], 0] = cell
        self.image[y:y + cell.shape[0], x:x + cell.shape[1], 1] = _grow(cell, self.halo)
        found = self._glyphs[char] = Glyph(x, y, cell.shape[1], cell.shape[0], slot.bitmap_left - pad,
                                           -slot.bitmap_top - pad, slot.advance.x / 64.0)
        self.version += 1
        return found

    def _place(self, height: int, width: int) -> tuple[int, int]:
        """Top-left corner of a free ``width`` x ``height`` cell (shelf packing; the
        image grows downwards when full)."""
        x, y, row = self._shelf
        if x + width > ATLAS_WIDTH:
            x, y, row = 0, y + row, 0
        while y + height > self.image.shape[0]:
            self.image = np.concatenate([self.image, np.zeros_like(self.image)])
        self._shelf = (x + width, y, max(row, height))
        return x, y

    def text_size(self, text: str) -> tuple[int, int]:
        """Width and height in pixels of ``text`` on one line (height: :attr:`line_height`)."""
        width = sum(self.glyph(c).advance for c in text)
        return int(round(width)), self.line_height

    def layout(self, text: str, x: float, y: float) -> NDArray[np.float32]:
        """Quads (k, 4, 4) of ``text``'s visible glyphs written with the top-left corner
        of its line box at pixel (``x``, ``y``): per corner (px, py, u, v), corners in
        the order top-left, top-right, bottom-right, bottom-left; u, v in 0..1 of the
        atlas as it is after the call."""
        pen, baseline = float(round(x)), float(round(y + self.ascender))
        cells = []
        for char in text:
            g = self.glyph(char)
            if g.width > 2 * (self.halo + 1):
                cells.append((pen + g.left, baseline + g.top, g))
            pen += g.advance
        # per glyph: x, y on the picture, x, y in the atlas, width, height (pixels)
        cell = np.array([(cx, cy, g.x, g.y, g.width, g.height) for cx, cy, g in cells], dtype=float).reshape(-1, 6)
        right = np.array([0.0, 1.0, 1.0, 0.0])  # corners' share of the width, then of the height
        down = np.array([0.0, 0.0, 1.0, 1.0])
        h, w = self.image.shape[:2]
        quads = np.empty((len(cells), 4, 4), dtype=np.float32)
        quads[..., 0] = cell[:, :1] + cell[:, 4:5] * right
        quads[..., 1] = cell[:, 1:2] + cell[:, 5:6] * down
        quads[..., 2] = (cell[:, 2:3] + cell[:, 4:5] * right) / w
        quads[..., 3] = (cell[:, 3:4] + cell[:, 5:6] * down) / h
        return quads


@functools.lru_cache(maxsize=4)
def atlas(pixel_size: int = LABEL_FONT_PX) -> GlyphAtlas:
    """The shared atlas of the label font at ``pixel_size`` (font data, no GL objects)."""
    return GlyphAtlas(font_path(), pixel_size)


def text_size(text: str, pixel_size: int = LABEL_FONT_PX) -> tuple[int, int]:
    """Width and height in pixels of a label ``text`` in the label font."""
    return atlas(pixel_size).text_size(text)
