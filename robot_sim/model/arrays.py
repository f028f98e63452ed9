"""Read-only arrays: the immutable values of the model (and of trajectories and tasks)."""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import DTypeLike, NDArray


def frozen(values: Any, shape: tuple[int, ...] | None = None, dtype: DTypeLike = float) -> NDArray[Any]:
    """A new array of ``values`` (as ``dtype``, reshaped to ``shape`` when given) that cannot
    be written to, so immutable dataclasses can hold it without copying on every read."""
    arr = np.array(values, dtype=dtype)
    if shape is not None:
        arr = arr.reshape(shape)
    arr.setflags(write=False)
    return arr
