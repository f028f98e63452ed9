"""trail: the endeffector path ring buffer."""
from __future__ import annotations

import numpy as np
import pytest

from robot_sim.viewer.trail import Trail


def test_points_closer_than_min_step_are_skipped():
    trail = Trail(capacity=10, min_step=0.01)
    assert trail.add([0, 0, 0]) and not trail.add([0.005, 0, 0]) and trail.add([0.01, 0, 0])
    np.testing.assert_array_equal(trail.points(), [[0, 0, 0], [0.01, 0, 0]])


def test_the_oldest_points_are_dropped_in_order():
    trail = Trail(capacity=3, min_step=0.0)
    for x in range(5):
        trail.add([x, 0, 0])
    assert len(trail) == 3
    np.testing.assert_array_equal(trail.points()[:, 0], [2, 3, 4])
    trail.clear()
    assert len(trail) == 0 and trail.points().shape == (0, 3)


def test_capacity_below_two_is_refused():
    with pytest.raises(ValueError, match="^capacity must be at least 2 points, got 1$"):
        Trail(capacity=1)
