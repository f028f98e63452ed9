"""The workspace cloud's colour scale, drawn in the picture (window and ``--screenshot``
alike): a bar through ``WORKSPACE_COLORMAP`` in the bottom-right corner, the lowest and
highest manipulability of the cloud under its ends and what it measures above it.

:func:`color_scale_layout` is the pure geometry (pixels, x right, y down from the top
row); :class:`ColorScaleItem` paints it in the text layer.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.font import text_size
from robot_sim.graphics.frame import Frame
from robot_sim.graphics.gl import GL
from robot_sim.graphics.item import Item
from robot_sim.graphics.scene import GraphicsOptions, Scene

#: Bar width (at least; wider when its texts need it) and height (pixels), and its distance from the picture's right and bottom edges.
BAR_SIZE_PX = (160, 12)
MARGIN_PX = 8
#: Gap between the bar and its texts (pixels).
TEXT_GAP_PX = 4
TITLE = "manipulability √det(J Jᵀ)"


def value_texts(lo: float, hi: float) -> tuple[str, str]:
    """The values written at the bar's ends, in fixed point with the decimals that give
    the larger one 3 significant digits (no exponent: 2e-08 reads as 0.000 next to 0.118)."""
    top = max(abs(lo), abs(hi))
    decimals = max(0, 2 - math.floor(math.log10(top))) if top > 0.0 and math.isfinite(top) else 0
    return f"{lo + 0.0:.{decimals}f}", f"{hi + 0.0:.{decimals}f}"


@dataclass(frozen=True)
class ColorScale:
    """Where the scale goes: ``bar`` (left, top, right, bottom) and ``texts`` as
    (text, box (left, top, right, bottom)) for the low value, the high value, the title."""

    bar: NDArray[np.float64]
    texts: list[tuple[str, NDArray[np.float64]]]

    def boxes(self) -> NDArray[np.float64]:
        """Everything the scale covers (4, 4): its texts' boxes and the bar."""
        return np.array([box for _, box in self.texts] + [self.bar])


def color_scale_layout(lo: float, hi: float, width: int, height: int) -> ColorScale:
    """The scale of values ``lo`` .. ``hi`` in a ``width`` x ``height`` picture."""
    low, high = value_texts(lo, hi)
    (low_w, low_h), (high_w, high_h), (title_w, title_h) = (text_size(t) for t in (low, high, TITLE))
    bar_w = max(BAR_SIZE_PX[0], title_w, low_w + high_w + 2 * TEXT_GAP_PX)  # the texts never touch
    bar_h = BAR_SIZE_PX[1]
    text_h = max(low_h, high_h, title_h)
    right = float(width - MARGIN_PX)
    bottom = float(height - MARGIN_PX - text_h - TEXT_GAP_PX)
    bar = np.array([right - bar_w, bottom - bar_h, right, bottom])
    under = bottom + TEXT_GAP_PX
    centre = 0.5 * (bar[0] + bar[2])
    texts = [
        (low, np.array([bar[0], under, bar[0] + low_w, under + low_h])),
        (high, np.array([right - high_w, under, right, under + high_h])),
        (TITLE, np.array([centre - 0.5 * title_w, bar[1] - TEXT_GAP_PX - title_h,
                          centre + 0.5 * title_w, bar[1] - TEXT_GAP_PX])),
    ]
    return ColorScale(bar, texts)


class ColorScaleItem(Item):
    """The colour scale of ``scene.workspace`` while ``options.show_workspace``: its bar
    through the colour map with a frame, and its texts (written by the text layer at
    their places; labels keep clear of them)."""

    layer = "text"
    order = -1.0  # before the labels, which keep clear of the scale's texts

    def __init__(self) -> None:
        super().__init__()
        self.range = (0.0, 1.0)

    def update(self, scene: Scene, options: GraphicsOptions) -> None:
        cloud = scene.workspace if options.show_workspace else None
        self.visible = cloud is not None and len(cloud.values) > 0
        if self.visible:
            values = np.asarray(cloud.values, dtype=float)
            self.range = (float(np.nanmin(values)), float(np.nanmax(values)))

    def paint(self, frame: Frame) -> None:
        scale = color_scale_layout(*self.range, frame.width, frame.height)
        left, top, right, bottom = scale.bar
        stops = np.asarray(gd.WORKSPACE_COLORMAP, dtype=float)
        xs = left + stops[:, 0] * (right - left)
        rgba = np.c_[stops[:, 1:], np.ones(len(stops))]
        quads = [(np.array([[x0, top], [x1, top], [x1, bottom], [x0, top], [x1, bottom], [x0, bottom]]),
                  np.array([c0, c1, c1, c0, c1, c0]))
                 for x0, x1, c0, c1 in zip(xs[:-1], xs[1:], rgba[:-1], rgba[1:])]
        frame.pixel_shapes(np.vstack([q for q, _ in quads]), np.vstack([c for _, c in quads]), GL.GL_TRIANGLES)
        corners = np.array([[left, top], [right, top], [right, top], [right, bottom],
                            [right, bottom], [left, bottom], [left, bottom], [left, top]]) + 0.5
        frame.pixel_shapes(corners, np.tile(frame.theme.label, (len(corners), 1)), GL.GL_LINES)
        for text, box in scale.texts:
            frame.add_text(box, text)


ITEM = ColorScaleItem
