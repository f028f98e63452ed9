"""Placements of the unit meshes (pure NumPy, no GL): the 4x4 world matrices that scale,
turn and move a unit mesh (``robot_sim.graphics.meshes``) into a drawn part.  Shared by the
OpenGL items and the browser view (robot_sim.web).  World frame, metres."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.transforms import rotations_z_onto


def along(origins: ArrayLike, vecs: ArrayLike, radii: ArrayLike, lengths: ArrayLike) -> NDArray[np.float64]:
    """World placements (N, 4, 4) of unit meshes modelled along +z from 0 to 1 with radius
    1: scaled to ``radii`` across and ``lengths`` along, starting at ``origins`` (N, 3)
    and pointing along ``vecs`` (N, 3)."""
    rot = rotations_z_onto(vecs)
    n = len(rot)
    mats = np.zeros((n, 4, 4))
    mats[:, :3, :3] = rot * np.stack(np.broadcast_arrays(radii, radii, lengths), axis=-1).reshape(n, 1, 3)
    mats[:, :3, 3] = origins
    mats[:, 3, 3] = 1.0
    return mats


def spheres(centres: ArrayLike, radius: ArrayLike) -> NDArray[np.float64]:
    """World placements (N, 4, 4) of the unit sphere scaled to ``radius`` (scalar or (N,))
    at ``centres`` (N, 3)."""
    centres = np.asarray(centres, dtype=float).reshape(-1, 3)
    mats = np.zeros((len(centres), 4, 4))
    mats[:, [0, 1, 2], [0, 1, 2]] = np.broadcast_to(np.asarray(radius, dtype=float).reshape(-1, 1), (len(centres), 3))
    mats[:, :3, 3] = centres
    mats[:, 3, 3] = 1.0
    return mats
