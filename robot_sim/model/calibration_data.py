"""Measurements for calibration: joint values with the measured tool positions or poses."""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.model.messages import clip_repr
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.transforms import is_rigid_transform

FloatArray = NDArray[np.float64]

#: Most poses one data set may hold (every array is sized by this count).
MAX_POSES = 100_000
#: Most joints a data set may describe.
MAX_JOINTS = 64


class CalibrationDataError(ValueError):
    """Measurements that cannot be used; the message says which value and why."""


class CalibrationData:
    """Joint values and what an instrument measured at each: tool positions or full poses.

    ``q`` (N, n): joint values [rad for revolute, m for prismatic joints].  Exactly one of
    ``positions`` (N, 3) [m], the tool frame's origin, or ``poses`` (N, 4, 4), the tool
    frame, both in the measuring instrument's frame (the frame the calibrated base is given
    in).  ``weights`` (N,): positive weights of the poses' squared residuals (1 when None;
    pass 1/σ² for poses measured with different precision).  ``source`` (a file name) and
    ``lines`` (the line of each pose in it) are set by
    :func:`robot_sim.io.calibration_csv.load_calibration_data` so errors can name them;
    ``joint_units`` says per column whether the file gave an angle (``"angle"``) or a
    length (``"length"``), None for data built in code.  Raises CalibrationDataError
    naming the argument and pose for wrong shapes, NaN or infinite values, poses that are
    not rigid transforms, or weights that are not positive.
    """

    def __init__(self, q: ArrayLike, positions: ArrayLike | None = None, poses: ArrayLike | None = None,
                 weights: ArrayLike | None = None, *, source: str = "", lines: ArrayLike | None = None,
                 joint_units: tuple[str, ...] | None = None) -> None:
        self.source = source
        Q = _array("q", q, 2)
        N = Q.shape[0]
        if N > MAX_POSES or Q.shape[1] > MAX_JOINTS or Q.shape[1] == 0:
            raise CalibrationDataError(
                f"q: expected (N, n) joint values with N <= {MAX_POSES} and 1 <= n <= {MAX_JOINTS}, got shape {Q.shape}")
        self.lines = np.arange(2, N + 2) if lines is None else np.asarray(lines, dtype=np.int64)
        if (positions is None) == (poses is None):
            raise CalibrationDataError("give exactly one of positions (N, 3) [m] or poses (N, 4, 4)")
        if positions is not None:
            measured = _array("positions", positions, 2)
            expected = (N, 3)
        else:
            measured = _array("poses", poses, 3)
            expected = (N, 4, 4)
        if measured.shape != expected:
            raise CalibrationDataError(f"{'positions' if poses is None else 'poses'}: expected shape {expected} "
                                       f"(one per row of q), got {measured.shape}")
        for name, values in (("q", Q), ("positions" if poses is None else "poses", measured)):
            bad = ~np.isfinite(values.reshape(N, -1)).all(axis=1)
            if bad.any():
                raise CalibrationDataError(f"{self.where(int(np.argmax(bad)))}: {name} holds NaN or infinite values")
        if poses is not None:
            for i in range(N):
                if not is_rigid_transform(measured[i]):
                    raise CalibrationDataError(f"{self.where(i)}: poses[{i}] is not a rigid transform "
                                               "(orthonormal rotation, det +1, bottom row 0 0 0 1)")
        w = np.ones(N) if weights is None else _array("weights", weights, 1)
        if w.shape != (N,):
            raise CalibrationDataError(f"weights: expected shape ({N},), got {w.shape}")
        if not (np.isfinite(w) & (w > 0)).all():
            i = int(np.argmax(~(np.isfinite(w) & (w > 0))))
            raise CalibrationDataError(f"{self.where(i)}: weights[{i}] must be positive and finite, got {float(w[i])!r}")
        self.q: FloatArray = Q
        self.positions: FloatArray = measured[:, :3, 3].copy() if poses is not None else measured
        self.poses: FloatArray | None = measured if poses is not None else None
        self.weights: FloatArray = w
        self.joint_units = joint_units

    def __len__(self) -> int:
        return self.q.shape[0]

    def __repr__(self) -> str:
        kind = "poses" if self.has_rotation else "positions"
        return f"<CalibrationData: {len(self)} {kind} of {self.q.shape[1]} joints>"

    @property
    def has_rotation(self) -> bool:
        """True when full poses were measured (positions and orientations)."""
        return self.poses is not None

    def where(self, i: int) -> str:
        """Where pose i (0-based) is: ``file line L (pose k)`` or ``pose k``."""
        return f"{self.source} line {int(self.lines[i])} (pose {i + 1})" if self.source else f"pose {i + 1}"

    def subset(self, rows: NDArray[np.int64]) -> "CalibrationData":
        """The poses ``rows`` (indices) as a new data set."""
        return CalibrationData(self.q[rows], None if self.has_rotation else self.positions[rows],
                               None if self.poses is None else self.poses[rows], self.weights[rows],
                               source=self.source, lines=self.lines[rows], joint_units=self.joint_units)

    def check_robot(self, robot: RobotParams) -> None:
        """CalibrationDataError unless the data suit ``robot``: n joint columns, angles for
        revolute and lengths for prismatic joints (when the file said), values within the
        joint limits (naming the first pose and joint outside)."""
        n = robot.n_dofs
        if self.q.shape[1] != n:
            raise CalibrationDataError(f"{self.source or 'q'}: {self.q.shape[1]} joint columns, "
                                       f"{robot.name} has {n} joints")
        if self.joint_units is not None:
            for j, unit in enumerate(self.joint_units):
                wanted = "angle" if robot.jtype[j] == JTYPE_REVOLUTE else "length"
                if unit != wanted:
                    kind = "revolute" if wanted == "angle" else "prismatic"
                    units = "deg or rad" if wanted == "angle" else "m or mm"
                    raise CalibrationDataError(f"{self.source}: column q{j + 1}: joint {j + 1} of {robot.name} is "
                                               f"{kind}; its unit must be {units}")
        outside = (self.q < robot.q_min) | (self.q > robot.q_max)
        if outside.any():
            i, j = (int(k) for k in np.argwhere(outside)[0])
            revolute = robot.jtype[j] == JTYPE_REVOLUTE
            scale, unit = (180.0 / np.pi, "deg") if revolute else (1.0, "m")
            raise CalibrationDataError(
                f"{self.where(i)}: q{j + 1} = {self.q[i, j] * scale:.6g} {unit} is outside joint {j + 1}'s limits "
                f"[{robot.q_min[j] * scale:.6g}, {robot.q_max[j] * scale:.6g}] {unit}")


def _array(name: str, values: Any, ndim: int) -> FloatArray:
    """``values`` as a float array of ``ndim`` dimensions; CalibrationDataError otherwise."""
    try:
        arr = np.asarray(values, dtype=float)
    except (ValueError, TypeError):
        raise CalibrationDataError(f"{name}: expected an array of numbers, got {clip_repr(values)}") from None
    if arr.ndim != ndim:
        raise CalibrationDataError(f"{name}: expected {ndim} dimensions, got shape {arr.shape}")
    return arr
