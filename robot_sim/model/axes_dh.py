"""The DH table of a serial chain given by its joint axes: the common-normal construction
of modified (Craig) DH frames from points on the axes and their directions, and the
(a, α, θ, d) row between two such frames.  What a URDF (or any axes-and-points
description) becomes as a :class:`~robot_sim.model.params.RobotParams`; the URDF reader
(robot_sim/io/urdf_in.py) calls it.  Metres and radians, the chain's root frame.
"""
from __future__ import annotations

import math

import numpy as np

#: Below this distance (m) two axes meet, below this sine of their angle they are parallel.
GEOMETRY_TOL = 1e-9
#: Lengths within this of 0 (m) and angles within this of a multiple of 90° (rad) are
#: rounded onto them (far below the construction's check in io/urdf_in.py).
SNAP_TOL = 1e-12


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _perpendicular(z: np.ndarray, preferred: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to z: the first of ``preferred`` (k, 3) that is not
    parallel to z, with z's part removed."""
    for helper in preferred:
        x = helper - (helper @ z) * z
        if np.linalg.norm(x) > 1e-6:
            return _unit(x)
    raise ValueError("every preferred direction is parallel to z")


def _frame(origin: np.ndarray, x: np.ndarray, z: np.ndarray) -> np.ndarray:
    mat = np.eye(4)
    mat[:3, 0], mat[:3, 2], mat[:3, 1] = x, z, np.cross(z, x)
    mat[:3, 3] = origin
    return mat


def dh_frames_from_axes(points: np.ndarray, axes: np.ndarray, joint_x: np.ndarray) -> np.ndarray:
    """Modified DH frames (n, 4, 4) in the root frame at q = 0 for joint axes through
    ``points`` (n, 3) along unit ``axes`` (n, 3) (the common-normal construction).

    Where the construction leaves x free (coincident axes, the last joint) or leaves its
    sign free (intersecting axes), x follows the URDF joint frame's x axis ``joint_x``
    (n, 3) as closely as it can, so a URDF written from a DH table gives that table back.
    """
    n = len(axes)
    frames = np.empty((n, 4, 4))
    start = points[0] - (points[0] @ axes[0]) * axes[0]  # axis 1's point nearest the root origin
    x_prev = None
    for i in range(n):
        z = axes[i]
        free = [joint_x[i], *([] if x_prev is None else [x_prev]), *np.eye(3)]
        if i == n - 1:
            frames[i] = _frame(start, _perpendicular(z, free), z)
            break
        p, u, q, v = start, z, points[i + 1], axes[i + 1]
        c = np.cross(u, v)
        skew = float(np.linalg.norm(c)) > GEOMETRY_TOL
        if skew:  # feet of the common normal: p + s u and q + t v
            w = q - p
            s = float(np.cross(w, v) @ c) / float(c @ c)
            t = float(np.cross(w, u) @ c) / float(c @ c)
            origin, other = p + s * u, q + t * v
        else:  # parallel: the normal from where the previous one arrived
            origin = p
            other = q + ((p - q) @ v) * v
        normal = other - origin
        length = float(np.linalg.norm(normal))
        if length > GEOMETRY_TOL:
            x = normal / length
        elif skew:
            x = _unit(c)
            x = -x if x @ joint_x[i] < 0.0 else x
        else:
            x = _perpendicular(z, free)
        frames[i] = _frame(origin, x, z)
        start, x_prev = origin + length * x if length > GEOMETRY_TOL else origin, x
    return frames


def _snap(value: float, step: float | None = None) -> float:
    """``value`` moved onto the nearest multiple of ``step`` (0 when None) when within
    SNAP_TOL of it (rounding noise: 1e-16 m becomes 0, 89.99999999999999° 90°)."""
    nearest = 0.0 if step is None else round(value / step) * step
    return nearest + 0.0 if abs(value - nearest) < SNAP_TOL else value


def modified_row(rel: np.ndarray) -> tuple[float, float, float, float]:
    """(a, α, θ, d) of rel = Rx(α) Tx(a) Rz(θ) Tz(d), rounding noise snapped away."""
    alpha = _snap(math.atan2(-rel[1, 2], rel[2, 2]), math.pi / 2)
    theta = _snap(math.atan2(-rel[0, 1], rel[0, 0]), math.pi / 2)
    d = -math.sin(alpha) * rel[1, 3] + math.cos(alpha) * rel[2, 3]
    return _snap(float(rel[0, 3])), alpha, theta, _snap(d)
