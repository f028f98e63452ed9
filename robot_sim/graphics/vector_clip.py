"""Which arrows a picture shows, and how much of them (pure NumPy, no GL).

An arrow shorter than its head would be drawn as a flat cone: at rest a simulated arm's
velocity of a few millimetres per second showed as a flickering disc on the tool.  Such
arrows are left out.  An arrow whose tip leaves the view is shortened to where it leaves
(less a margin), so its head, which says where it points, is always in the picture.

World frame, metres; the view is a :class:`~robot_sim.graphics.camera.Camera` seeing a
``width`` x ``height`` picture.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics.camera import Camera

#: Fraction of the picture's half-width and half-height kept free at its edges.
VIEW_MARGIN = 0.04


def visible_fraction(camera: Camera, width: int, height: int, origin: NDArray[np.float64],
                     vector: NDArray[np.float64]) -> float:
    """The largest t in [0, 1] with ``origin + t * vector`` inside the view (less
    VIEW_MARGIN); 1 when the origin itself is outside (the arrow is left as it is)."""
    clip = camera.projection_matrix(width / height) @ camera.view_matrix()
    c0 = clip @ np.r_[origin, 1.0]
    dc = clip @ np.r_[vector, 0.0]
    keep = 1.0 - VIEW_MARGIN
    # each bound is linear in t: f(t) = f0 + t df >= 0 (|x|, |y| <= keep w; w > 0)
    bounds = [(keep * c0[3] - c0[0], keep * dc[3] - dc[0]), (keep * c0[3] + c0[0], keep * dc[3] + dc[0]),
              (keep * c0[3] - c0[1], keep * dc[3] - dc[1]), (keep * c0[3] + c0[1], keep * dc[3] + dc[1]),
              (c0[3], dc[3])]
    if any(f0 < 0.0 for f0, _ in bounds):
        return 1.0
    t = 1.0
    for f0, df in bounds:
        if f0 + df < 0.0:
            t = min(t, f0 / (f0 - (f0 + df)))
    return t


def shown_vectors(vectors: Sequence[tuple], camera: Camera, width: int, height: int,
                  head_length: float) -> list[tuple]:
    """The (origin, vector, rgba) arrows of ``vectors`` to draw: none shorter than
    ``head_length`` (metres), each shortened so its tip stays in the view."""
    out = []
    for origin, vector, rgba in vectors:
        origin, vector = np.asarray(origin, dtype=float), np.asarray(vector, dtype=float)
        if np.linalg.norm(vector) < head_length:
            continue
        shortened = vector * visible_fraction(camera, width, height, origin, vector)
        if np.linalg.norm(shortened) >= head_length:
            out.append((origin, shortened, rgba))
    return out
