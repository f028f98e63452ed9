"""Where labels go on the picture: a simple overlap-avoiding pass (pure NumPy, no GL).

Each label has an anchor pixel (the projected point it names) and a text box size.  Its
first candidate is the usual place, ``LABEL_OFFSET_PX`` right of and above the anchor;
the others ring the anchor at growing distances (eight directions a ring).  In the
labels' order each takes the nearest candidate whose box lies in the picture and meets
neither an earlier label's box nor an obstacle segment (the annotation's arrows and arcs,
the frames' axes); a label that cannot find one takes the candidate it overlaps least.
A label moved off its usual place gets a leader line from its anchor to its box.

Pixels: x right, y down from the top row (as ``Camera.project`` gives them).  A box is
(left, top, right, bottom).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics import defs as gd

#: Rings of candidate places tried around an anchor, beyond the usual place.
RINGS = 6
#: Distance between rings, in text-line heights.
RING_STEP_LINES = 1.2
#: Directions (dx, dy) of the candidates on a ring: right-up first, then around.
_DIRECTIONS = np.array([(1, -1), (-1, -1), (1, 1), (-1, 1), (0, -1), (0, 1), (1, 0), (-1, 0)], dtype=float)


@dataclass(frozen=True)
class LabelPlacement:
    """Placed labels: ``boxes`` (N, 4) as (left, top, right, bottom) in pixels, NaN for a
    label whose anchor projects nowhere; ``moved`` (N,) True where a label left its usual
    place; ``leaders`` (N, 2, 2) the leader line from the anchor to the nearest point of
    the box (NaN where not moved)."""

    boxes: NDArray[np.float64]
    moved: NDArray[np.bool_]
    leaders: NDArray[np.float64]

    @property
    def origins(self) -> NDArray[np.float64]:
        """Bottom-left pixel (N, 2) of each text box: where its text starts."""
        return self.boxes[:, [0, 3]]


def boxes_overlap(a: NDArray[np.float64], b: NDArray[np.float64], margin: float = 0.0) -> NDArray[np.bool_]:
    """Whether box ``a`` (4,) overlaps each of ``b`` (M, 4) when grown by ``margin``."""
    b = np.asarray(b, dtype=float).reshape(-1, 4)
    return ((a[0] - margin < b[:, 2]) & (b[:, 0] < a[2] + margin)
            & (a[1] - margin < b[:, 3]) & (b[:, 1] < a[3] + margin))


def segments_hit_box(box: ArrayLike, segments: ArrayLike) -> NDArray[np.bool_]:
    """Whether each segment of ``segments`` (K, 2, 2) crosses or lies in ``box`` (4,)
    (Liang–Barsky clipping, all segments at once): (K,); for boxes (C, 4), (C, K)."""
    boxes = np.asarray(box, dtype=float)
    single = boxes.ndim == 1
    boxes = boxes.reshape(-1, 1, 4)
    segments = np.asarray(segments, dtype=float).reshape(-1, 2, 2)
    p0, d = segments[:, 0], segments[:, 1] - segments[:, 0]
    shape = (len(boxes), len(segments))
    t0, t1 = np.zeros(shape), np.ones(shape)
    hit = np.broadcast_to(np.all(np.isfinite(segments.reshape(-1, 4)), axis=1), shape).copy()
    for axis, (lo, hi) in enumerate(((boxes[..., 0], boxes[..., 2]), (boxes[..., 1], boxes[..., 3]))):
        for p, q in ((-d[:, axis], p0[:, axis] - lo), (d[:, axis], hi - p0[:, axis])):
            parallel = p == 0.0
            hit &= ~(parallel & (q < 0.0))  # parallel to this edge and outside it
            with np.errstate(divide="ignore", invalid="ignore"):
                r = np.where(parallel, 0.0, q / np.where(parallel, 1.0, p))
            t0 = np.where(~parallel & (p < 0.0), np.maximum(t0, r), t0)
            t1 = np.where(~parallel & (p > 0.0), np.minimum(t1, r), t1)
    hit &= t0 <= t1
    return hit[0] if single else hit


def _overlap_areas(boxes: NDArray[np.float64], others: NDArray[np.float64]) -> NDArray[np.float64]:
    """Total area (C,) by which each of ``boxes`` (C, 4) overlaps ``others`` (M, 4)."""
    b, o = boxes[:, None, :], others[None, :, :]
    w = np.clip(np.minimum(b[..., 2], o[..., 2]) - np.maximum(b[..., 0], o[..., 0]), 0.0, None)
    h = np.clip(np.minimum(b[..., 3], o[..., 3]) - np.maximum(b[..., 1], o[..., 1]), 0.0, None)
    return np.sum(w * h, axis=1)


def candidate_boxes(anchor: NDArray[np.float64], size: tuple[float, float],
                    offset: tuple[float, float] = gd.LABEL_OFFSET_PX) -> NDArray[np.float64]:
    """Candidate boxes (C, 4) of a label ``size`` (w, h) at ``anchor`` (2,), nearest first:
    the usual place (``offset`` right of and above the anchor), then the rings."""
    w, h = float(size[0]), float(size[1])
    dx, dy = float(offset[0]), float(offset[1])
    usual = np.array([[anchor[0] + dx, anchor[1] - dy - h, anchor[0] + dx + w, anchor[1] - dy]])
    r = RING_STEP_LINES * h * np.repeat(np.arange(1, RINGS + 1), len(_DIRECTIONS))
    ux, uy = np.tile(_DIRECTIONS, (RINGS, 1)).T
    # the box's corner (or edge middle) nearest the anchor sits r away along the direction
    left = anchor[0] + ux * (r + dx) - np.where(ux < 0, w, np.where(ux == 0, 0.5 * w, 0.0))
    top = anchor[1] + uy * (r + dy) - np.where(uy < 0, h, np.where(uy == 0, 0.5 * h, 0.0))
    return np.vstack([usual, np.stack([left, top, left + w, top + h], axis=1)])


def _leader(anchor: NDArray[np.float64], box: NDArray[np.float64]) -> NDArray[np.float64]:
    nearest = np.clip(anchor, box[:2], box[2:])
    return np.array([anchor, nearest])


def place_labels(anchors: ArrayLike, sizes: Sequence[tuple[float, float]], viewport: tuple[int, int],
                 obstacles: ArrayLike | None = None, taken: ArrayLike | None = None,
                 offset: tuple[float, float] = gd.LABEL_OFFSET_PX) -> LabelPlacement:
    """Place labels of ``sizes`` (w, h) pixels at ``anchors`` (N, 2) in a ``viewport``
    (width, height) so that no two boxes overlap, none meets an ``obstacles`` segment
    (K, 2, 2) and none covers a ``taken`` box (M, 4) (something else written in the
    picture) where a free place exists (see the module docstring)."""
    anchors = np.asarray(anchors, dtype=float).reshape(-1, 2)
    segments = np.zeros((0, 2, 2)) if obstacles is None else np.asarray(obstacles, dtype=float).reshape(-1, 2, 2)
    n = len(anchors)
    boxes = np.full((n, 4), np.nan)
    moved = np.zeros(n, dtype=bool)
    leaders = np.full((n, 2, 2), np.nan)
    fixed = np.zeros((0, 4)) if taken is None else np.asarray(taken, dtype=float).reshape(-1, 4)
    width, height = float(viewport[0]), float(viewport[1])
    margin = gd.LABEL_GAP_PX
    for k in range(n):
        anchor = anchors[k]
        if not np.all(np.isfinite(anchor)):
            continue
        placed = np.vstack([fixed, boxes[:k][np.all(np.isfinite(boxes[:k]), axis=1)]])
        candidates = candidate_boxes(anchor, sizes[k], offset)
        inside = ((candidates[:, 0] >= 0.0) & (candidates[:, 1] >= 0.0)
                  & (candidates[:, 2] <= width) & (candidates[:, 3] <= height))
        grown = candidates + np.array([-margin, -margin, margin, margin])
        crossings = np.count_nonzero(segments_hit_box(grown, segments), axis=1)
        overlap = _overlap_areas(grown, placed)
        free = np.flatnonzero(inside & (crossings == 0) & (overlap == 0.0))
        # the nearest free candidate, else the least bad (nearest among equals)
        cost = overlap + 50.0 * crossings + np.where(inside, 0.0, 1e6) + np.arange(len(candidates))
        best = int(free[0]) if len(free) else int(np.argmin(cost))
        boxes[k] = candidates[best]
        if best != 0:
            moved[k] = True
            leaders[k] = _leader(anchor, candidates[best])
    return LabelPlacement(boxes, moved, leaders)


def polyline_segments(polylines: Sequence[NDArray[np.float64]]) -> NDArray[np.float64]:
    """Consecutive point pairs (K, 2, 2) of pixel polylines (each (m, 2))."""
    parts = [np.stack([p[:-1], p[1:]], axis=1) for p in (np.asarray(q, dtype=float).reshape(-1, 2) for q in polylines)
             if len(p) >= 2]
    return np.concatenate(parts) if parts else np.zeros((0, 2, 2))
