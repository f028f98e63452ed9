"""The endeffector trail drawable: a polyline through the points the endeffector passed."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from robot_sim.graphics import defs as gd
from robot_sim.graphics.gl import GL, draw_arrays, set_color
from robot_sim.graphics.resources import Drawable


class TrailGraphics(Drawable):
    """Unlit line strip of ``TRAIL_COLOR``, ``TRAIL_WIDTH_PX`` wide, through world
    ``points`` (N, 3) in metres, oldest first; depth tested so the arm hides what is
    behind it."""

    gl_preset = "unlit"

    def __init__(self, points: ArrayLike) -> None:
        super().__init__()
        self.points = np.asarray(points, dtype=float).reshape(-1, 3)

    def paint(self) -> None:
        if len(self.points) < 2:
            return
        GL.glLineWidth(gd.TRAIL_WIDTH_PX)
        set_color(gd.TRAIL_COLOR)
        draw_arrays(GL.GL_LINE_STRIP, self.points)
        GL.glLineWidth(1.0)
