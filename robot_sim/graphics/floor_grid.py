"""The floor square under the robot and its grid lines (pure NumPy, no GL; drawn by
items/floor.py and the browser view).  World frame, metres, z = 0."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd

RGBA = tuple[float, float, float, float]


@dataclass(frozen=True)
class FloorGrid:
    """The floor square: ``half_extent`` metres either side of ``centre_xy`` (2,), grid
    lines every ``step`` metres on world-aligned lines."""

    half_extent: float
    step: float
    centre_xy: NDArray[np.float64]

    @classmethod
    def for_reach(cls, reach: float, centre_xy: ArrayLike = (0.0, 0.0)) -> FloorGrid:
        """The floor of a robot of ``reach`` metres standing at world ``centre_xy``:
        about ``GRID_LINES_PER_HALF`` cells of the first ``GRID_STEPS`` entry that is
        large enough from the centre to an edge of ``GROUND_EXTENT_FRAC`` * reach."""
        half = reach * gd.GROUND_EXTENT_FRAC
        wanted = half / gd.GRID_LINES_PER_HALF
        step = next((s for s in gd.GRID_STEPS if s >= wanted), gd.GRID_STEPS[-1])
        centre = np.round(np.asarray(centre_xy, dtype=float).reshape(2) / step) * step
        return cls(math.ceil(half / step) * step, float(step), centre)

    def triangles(self, rgba: RGBA) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Triangle corners (30, 3) and their colours (30, 4) of the square in ``rgba``:
        full alpha inside ``FLOOR_FADE_START`` of the half extent, fading to 0 at the edge."""
        (x0, y0), h = self.centre_xy, self.half_extent
        inner, outer = floor_square(x0, y0, gd.FLOOR_FADE_START * h), floor_square(x0, y0, h)
        solid, clear = np.asarray(rgba, dtype=float), np.asarray(rgba, dtype=float) * (1, 1, 1, 0)
        points = [inner[[0, 1, 2]], inner[[0, 2, 3]]]
        colors = [np.tile(solid, (6, 1))]
        for k in range(4):  # the ring: one trapezoid per side
            a, b = inner[k], inner[(k + 1) % 4]
            c, d = outer[(k + 1) % 4], outer[k]
            points += [np.array([a, b, c]), np.array([a, c, d])]
            colors.append(np.array([solid, solid, clear, solid, clear, clear]))
        return np.vstack(points), np.vstack(colors)

    def lines(self, rgba: RGBA) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Segment ends (M, 3) and colours (M, 4) of the grid lines in ``rgba``, each line
        in three pieces so that it fades out with the square."""
        (x0, y0), h = self.centre_xy, self.half_extent
        ticks = np.arange(-h, h + 0.5 * self.step, self.step)
        cuts = np.array([-h, -gd.FLOOR_FADE_START * h, gd.FLOOR_FADE_START * h, h])
        alphas = np.array([0.0, 1.0, 1.0, 0.0])
        pairs = [(0, 1), (1, 2), (2, 3)]
        points, colors = [], []
        for t in ticks:
            for i, j in pairs:
                points += [[x0 + t, y0 + cuts[i], 0.0], [x0 + t, y0 + cuts[j], 0.0],
                           [x0 + cuts[i], y0 + t, 0.0], [x0 + cuts[j], y0 + t, 0.0]]
                colors += [alphas[i], alphas[j], alphas[i], alphas[j]]
        fade = np.asarray(colors)[:, None] * np.array([0.0, 0.0, 0.0, rgba[3]]) + np.array([*rgba[:3], 0.0])
        return np.array(points), fade


def floor_square(x0: float, y0: float, h: float) -> NDArray[np.float64]:
    """Corners (4, 3) of the square of half side ``h`` about (x0, y0) on the floor,
    counter-clockwise seen from above."""
    return np.array([[x0 - h, y0 - h, 0.0], [x0 + h, y0 - h, 0.0], [x0 + h, y0 + h, 0.0], [x0 - h, y0 + h, 0.0]])
