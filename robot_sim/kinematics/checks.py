"""Checks of the numbers the kinematics' public functions take (tolerances, counts,
seeds), raising ValueError that names the argument."""
from __future__ import annotations

import math

import numpy as np

from robot_sim.model.messages import clip_repr


def _is_real(value: object) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def _check_tolerance(name: str, value: float) -> float:
    if type(value) is float and 0.0 < value < math.inf:  # the common case, answered first
        return value
    if not (_is_real(value) and math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be a positive finite number, got {clip_repr(value)}")
    return float(value)


def _check_int(name: str, value: int, minimum: int) -> int:
    """``value`` as an int >= ``minimum`` (Python or NumPy integer, not bool); ValueError otherwise."""
    if type(value) is int and value >= minimum:  # the common case, answered first
        return value
    if not (isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)) and value >= minimum):
        wanted = "a positive integer" if minimum == 1 else f"an integer >= {minimum}"
        raise ValueError(f"{name} must be {wanted}, got {clip_repr(value)}")
    return int(value)


def _check_seed(seed: int | None) -> int | None:
    if seed is not None and not (isinstance(seed, (int, np.integer)) and not isinstance(seed, bool) and seed >= 0):
        raise ValueError(f"seed must be None or a non-negative integer, got {clip_repr(seed)}")
    return seed
