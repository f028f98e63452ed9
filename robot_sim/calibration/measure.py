"""Residuals between measured and modelled tool poses, and the stacked, weighted Jacobian
of the calibration's least-squares problem.

Each pose contributes 3 rows (position [m]) or 6 (position, then the rotation vector of
R_measured R_modelᵀ [rad] times :data:`ROTATION_LENGTH`, so 1 mrad counts as 1 mm),
multiplied by the square root of the pose's weight.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.calibration.chain import Chain, parameter_jacobian, walk
from robot_sim.model.calibration_data import CalibrationData

FloatArray = NDArray[np.float64]

#: Length [m] a rotation residual [rad] is multiplied by to weigh against positions.
ROTATION_LENGTH = 1.0


def rotation_vectors(R: FloatArray) -> FloatArray:
    """Rotation vectors (N, 3) [rad] of rotation matrices (N, 3, 3) (angles below π)."""
    v = 0.5 * np.stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]], axis=1)
    sin = np.linalg.norm(v, axis=1)
    cos = 0.5 * (np.trace(R, axis1=1, axis2=2) - 1.0)
    angle = np.arctan2(sin, cos)
    factor = np.where(sin > 1e-300, angle / np.where(sin > 1e-300, sin, 1.0), 1.0)
    return v * factor[:, None]


def pose_errors(chain: Chain, data: CalibrationData) -> tuple[FloatArray, FloatArray | None]:
    """Measured minus modelled: positions (N, 3) [m] and, with poses, rotation vectors of
    R_measured R_modelᵀ (N, 3) [rad] (None for position data)."""
    R, p, _, _ = walk(chain, data.q, np.zeros(chain.size, dtype=bool))
    if data.poses is None:
        return data.positions - p, None
    return data.positions - p, rotation_vectors(data.poses[:, :3, :3] @ R.transpose(0, 2, 1))


def stacked(chain: Chain, data: CalibrationData, columns: NDArray[np.int64]) -> tuple[FloatArray, FloatArray]:
    """Weighted residual vector r (m,) and Jacobian J (m, P) of the model's values with
    respect to the motions ``columns`` (so r(x + δ) ≈ r − J δ)."""
    R, p, J = parameter_jacobian(chain, data.q, columns, data.has_rotation)
    position = data.positions - p
    if data.poses is None:
        r = position
    else:
        turn = rotation_vectors(data.poses[:, :3, :3] @ R.transpose(0, 2, 1))
        r = np.concatenate([position, ROTATION_LENGTH * turn], axis=1)
        J[:, 3:] *= ROTATION_LENGTH
    root = np.sqrt(data.weights)
    return (r * root[:, None]).ravel(), (J * root[:, None, None]).reshape(r.size, len(columns))


def jacobian_rows(chain: Chain, q: FloatArray, columns: NDArray[np.int64], poses: bool) -> FloatArray:
    """Unweighted Jacobian rows (N, k, P) of the poses q for ``columns`` (k = 3 or 6)."""
    J = parameter_jacobian(chain, q, columns, poses)[2]
    if poses:
        J[:, 3:] *= ROTATION_LENGTH
    return J
