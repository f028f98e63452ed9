"""The endeffector trail: the last positions the endeffector passed through, for drawing
its path as a line (no GL, no Qt).  World frame, metres."""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.viewer import settings as vs


class Trail:
    """Ring buffer of up to ``capacity`` world points (m), oldest dropped first.

    A point closer than ``min_step`` metres to the last one kept is not stored, so a
    resting arm adds nothing and the line's vertices are evenly spread along the path.
    """

    def __init__(self, capacity: int = vs.TRAIL_MAX_POINTS, min_step: float = vs.TRAIL_MIN_STEP_M) -> None:
        if capacity < 2:
            raise ValueError(f"capacity must be at least 2 points, got {capacity}")
        self.min_step = float(min_step)
        self._buffer = np.zeros((capacity, 3))
        self._start = 0
        self._count = 0

    def __len__(self) -> int:
        return self._count

    def clear(self) -> None:
        """Forget every point."""
        self._start = self._count = 0

    def add(self, point: ArrayLike) -> bool:
        """Append ``point`` (3,) unless it is within ``min_step`` of the last one; returns
        whether it was stored."""
        p = np.asarray(point, dtype=float).reshape(3)
        capacity = len(self._buffer)
        if self._count and np.linalg.norm(p - self._buffer[(self._start + self._count - 1) % capacity]) < self.min_step:
            return False
        if self._count < capacity:
            self._buffer[(self._start + self._count) % capacity] = p
            self._count += 1
        else:
            self._buffer[self._start] = p
            self._start = (self._start + 1) % capacity
        return True

    def points(self) -> NDArray[np.float64]:
        """The stored points (k, 3), oldest first (a copy)."""
        index = (self._start + np.arange(self._count)) % len(self._buffer)
        return self._buffer[index]
