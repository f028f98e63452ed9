"""Coordinate frames as RGB axes (x red, y green, z blue) with cone tips, and their
labels (pure NumPy, no GL; drawn by items/frames.py and the browser view).

Where axes coincide nothing z-fights: a frame sharing its origin with k earlier ones is
drawn ``1 + k * FRAME_STACK_LENGTH_STEP`` times longer and thinner (its tips show beyond
the others), and shaft radii differ slightly from frame to frame
(``FRAME_STACK_RADIUS_STEPS``) so axes along one line never share a surface.  World
frame, metres.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.kinematics import Kinematics

AXIS_COLORS = (gd.AXIS_X_COLOR, gd.AXIS_Y_COLOR, gd.AXIS_Z_COLOR)


def stack_ranks(origins: NDArray[np.float64], tol: float) -> NDArray[np.int64]:
    """For each of ``origins`` (N, 3), how many earlier ones lie within ``tol`` of it."""
    gaps = np.linalg.norm(origins[:, None] - origins[None], axis=-1) <= tol
    return np.tril(gaps, k=-1).sum(axis=1)


def axis_lengths(frames: NDArray[np.float64], length: float) -> NDArray[np.float64]:
    """Axis length (N,) of each of world ``frames`` (N, 4, 4) drawn ``length`` long."""
    ranks = stack_ranks(frames[:, :3, 3], gd.MIN_LINK_LENGTH)
    return length * (1.0 + gd.FRAME_STACK_LENGTH_STEP * ranks)


def axes_placements(frames: NDArray[np.float64], length: float) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Placements of the unit cylinder (shafts) and cone (heads) drawing the x, y and z
    axes of world ``frames`` (N, 4, 4) drawn ``length`` long, with their colours (3N, 4)
    each; and each frame's axis length (N,).  An axis arrow's rotation is its frame's
    with the columns turned so that the arrow's z is that axis (no trigonometry)."""
    lengths = axis_lengths(frames, length)
    steps = np.asarray(gd.FRAME_STACK_RADIUS_STEPS)
    ranks = np.rint((lengths / length - 1.0) / gd.FRAME_STACK_LENGTH_STEP).astype(int)
    thin = steps[np.arange(len(lengths)) % len(steps)] * np.maximum(1.0 - gd.FRAME_STACK_THINNING * ranks, 0.4)
    shaft_r, head_r = length * gd.FRAME_SHAFT_RADIUS_FRAC * thin, length * gd.FRAME_HEAD_RADIUS_FRAC * thin
    heads = np.minimum(lengths * gd.FRAME_HEAD_LENGTH_FRAC, 0.5 * lengths)
    rot, origin = frames[:, :3, :3], frames[:, :3, 3]
    shafts, cones, colors = [], [], []
    for axis, color in enumerate(AXIS_COLORS):
        turned = rot[:, :, [(axis + 1) % 3, (axis + 2) % 3, axis]]  # a cyclic turn: still a rotation
        for out, radius, start, extent in ((shafts, shaft_r, 0.0, lengths - heads), (cones, head_r, lengths - heads, heads)):
            mats = np.zeros((len(frames), 4, 4))
            mats[:, :3, :3] = turned * np.stack([radius, radius, extent], axis=-1)[:, None, :]
            mats[:, :3, 3] = origin + rot[:, :, axis] * np.broadcast_to(start, lengths.shape)[:, None]
            mats[:, 3, 3] = 1.0
            out.append(mats)
        colors.append(np.tile(color, (len(frames), 1)))
    return np.concatenate(shafts), np.concatenate(cones), np.concatenate(colors), lengths


def frames_and_names(kinematics: Kinematics, show_frames: list[bool],
                     show_endeff: bool) -> tuple[NDArray[np.float64], list[str]]:
    """World poses (N, 4, 4) of the frames to draw, ``h_tf[i]`` for each ``show_frames[i]``
    (indices past the robot's frames ignored) then ``endeff_tf`` when ``show_endeff``,
    and their names: the DH frame number, "E" for the endeffector."""
    index = np.flatnonzero(show_frames[: len(kinematics.frames)])
    shown, names = kinematics.frames[index], [str(i) for i in index]
    if show_endeff:
        shown, names = np.concatenate([shown, kinematics.endeff_tf.mat[None]]), names + ["E"]
    return shown, names


def frame_poses(kinematics: Kinematics, show_frames: list[bool], show_endeff: bool) -> NDArray[np.float64]:
    """World poses (N, 4, 4) of the frames to draw (see :func:`frames_and_names`)."""
    return frames_and_names(kinematics, show_frames, show_endeff)[0]


def frame_labels(frames: NDArray[np.float64], names: list[str], lengths: NDArray[np.float64]) -> list[tuple[NDArray, str]]:
    """One label per distinct origin among ``frames`` (N, 4, 4): the names of the frames
    there joined by commas ("4,5"), anchored a little along the bisector of the x and y
    axes of the first one, at ``FRAME_LABEL_FRAC`` of its axis ``lengths`` (N,)."""
    labels: list[tuple[NDArray, str]] = []
    origins = frames[:, :3, 3]
    taken = np.zeros(len(frames), dtype=bool)
    for i in range(len(frames)):
        if taken[i]:
            continue
        here = np.linalg.norm(origins - origins[i], axis=1) <= gd.MIN_LINK_LENGTH
        taken |= here
        anchor = origins[i] + gd.FRAME_LABEL_FRAC * lengths[i] * (frames[i, :3, 0] + frames[i, :3, 1]) / np.sqrt(2.0)
        labels.append((anchor, ",".join(n for n, h in zip(names, here) if h)))
    return labels
