"""The workspace point cloud as data (pure NumPy, no GL): points coloured through a
colour map (``items.cloud`` draws it)."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd


def colormap(values: ArrayLike) -> NDArray[np.uint8]:
    """RGBA colours (N, 4) uint8 of ``values`` (N,) through ``WORKSPACE_COLORMAP``, scaled
    from the finite minimum (first stop) to the maximum (last stop); constant values take
    the middle colour, non-finite ones the first."""
    vals = np.asarray(values, dtype=float).ravel()
    finite = np.isfinite(vals)
    unit = np.zeros_like(vals)
    if finite.any():
        lo, hi = vals[finite].min(), vals[finite].max()
        unit[finite] = (vals[finite] - lo) / (hi - lo) if hi > lo else 0.5
    stops = np.asarray(gd.WORKSPACE_COLORMAP)
    rgba = np.full((len(vals), 4), 255, dtype=np.uint8)
    for channel in range(3):
        rgba[:, channel] = np.round(255.0 * np.interp(unit, stops[:, 0], stops[:, channel + 1]))
    return rgba


class WorkspaceCloud:
    """Points (N, 3) of a workspace (world, metres) coloured by ``values`` (N,)
    (e.g. height or manipulability) through ``WORKSPACE_COLORMAP``, min to max.
    Plain data: ``items.cloud.CloudItem`` draws it."""

    def __init__(self, points: ArrayLike, values: ArrayLike) -> None:
        pts = np.asarray(points, dtype=float)
        vals = np.asarray(values, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise ValueError(f"WorkspaceCloud: points must have shape (N, 3), got {pts.shape}")
        if vals.shape != (len(pts),):
            raise ValueError(f"WorkspaceCloud: values must have shape ({len(pts)},), got {vals.shape}")
        self.points: NDArray[np.float32] = np.ascontiguousarray(pts, dtype=np.float32)
        self.values: NDArray[np.float64] = vals
        self.colors: NDArray[np.uint8] = colormap(vals)

    def __len__(self) -> int:
        return len(self.points)
