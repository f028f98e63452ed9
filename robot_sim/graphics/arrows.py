"""Arrows as placements of the unit cylinder (shaft) and cone (head) (pure NumPy): the
axes of frames, the IK target's frame and the velocity vectors.  World frame, metres."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.placements import along


def arrow_placements(origins: ArrayLike, vecs: ArrayLike, shaft_radius: ArrayLike, head_radius: ArrayLike,
                     head_length: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Placements (k, 4, 4) of the unit cylinder and of the unit cone drawing arrows from
    world ``origins`` (N, 3) to ``origins + vecs``; sizes scalars or (N,); a head is at
    most half its arrow; vectors shorter than ``MIN_LINK_LENGTH`` draw nothing."""
    origins = np.asarray(origins, dtype=float).reshape(-1, 3)
    vecs = np.asarray(vecs, dtype=float).reshape(-1, 3)
    n = len(origins)
    shaft, head_r, head_l = (np.broadcast_to(np.asarray(v, dtype=float), (n,)) for v in (shaft_radius, head_radius, head_length))
    lengths = np.linalg.norm(vecs, axis=1)
    keep = lengths >= gd.MIN_LINK_LENGTH
    origins, vecs, lengths, shaft, head_r, head_l = (v[keep] for v in (origins, vecs, lengths, shaft, head_r, head_l))
    heads = np.minimum(head_l, 0.5 * lengths)
    shaft_ends = origins + vecs * ((lengths - heads) / np.where(lengths > 0.0, lengths, 1.0))[:, None]
    return along(origins, vecs, shaft, lengths - heads), along(shaft_ends, vecs, head_r, heads)
