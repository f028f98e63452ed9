"""SE(3) and SO(3) maths for the simulator: homogeneous transforms, rotations,
the Denavit–Hartenberg transform (standard and modified) and angle-axis helpers.

Conventions
-----------
* Units are SI: metres and radians.
* A homogeneous transform ``T_a_b`` maps coordinates in frame *b* to frame *a*:
  ``p_a = T_a_b @ p_b``.  Composition reads left to right along the chain:
  ``T_w_c = T_w_b @ T_b_c``.
* Roll-pitch-yaw follows URDF: ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)``.
* Standard DH: ``A = Rz(theta) @ Tz(d) @ Tx(a) @ Rx(alpha)``; modified (Craig) DH:
  ``A = Rx(alpha) @ Tx(a) @ Rz(theta) @ Tz(d)`` with the row's a_{i-1}, alpha_{i-1}.

This module knows nothing about robots or OpenGL.
"""
from __future__ import annotations

import math
from typing import Union, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]

#: Below this norm a direction vector is treated as zero (metres or unitless).
EPS_NORM = 1e-12


def rot_x(angle: float) -> FloatArray:
    """Rotation matrix (3, 3) about x by ``angle`` radians."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(angle: float) -> FloatArray:
    """Rotation matrix (3, 3) about y by ``angle`` radians."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(angle: float) -> FloatArray:
    """Rotation matrix (3, 3) about z by ``angle`` radians."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_from_rpy(rpy: ArrayLike) -> FloatArray:
    """Rotation (3, 3) from roll, pitch, yaw in radians: ``Rz(yaw) Ry(pitch) Rx(roll)``."""
    roll, pitch, yaw = np.asarray(rpy, dtype=float).reshape(3)
    return rot_z(yaw) @ rot_y(pitch) @ rot_x(roll)


def rpy_from_rot(R: ArrayLike) -> tuple[float, float, float]:
    """Roll, pitch, yaw in radians of a rotation matrix (inverse of :func:`rot_from_rpy`).

    At the gimbal lock (pitch = ±90°, where only yaw ∓ roll is defined) roll is set to 0
    and yaw carries the rotation.
    """
    R = np.asarray(R, dtype=float)
    cos_pitch = math.hypot(R[0, 0], R[1, 0])
    pitch = math.atan2(-R[2, 0], cos_pitch)
    if cos_pitch > 1e-12:
        return math.atan2(R[2, 1], R[2, 2]), pitch, math.atan2(R[1, 0], R[0, 0])
    return 0.0, pitch, math.atan2(-R[0, 1], R[1, 1])


def quaternion_from_rot(R: ArrayLike) -> FloatArray:
    """Unit quaternion (w, x, y, z) of a rotation matrix, with w >= 0.

    ``(cos(θ/2), sin(θ/2)·axis)`` for a rotation of θ about ``axis``; computed from the
    largest of the four squared components (Shepperd), so it is accurate at every angle.
    """
    R = np.asarray(R, dtype=float)
    trace = R[0, 0] + R[1, 1] + R[2, 2]
    squares = np.array([1.0 + trace, 1.0 + 2.0 * R[0, 0] - trace,
                        1.0 + 2.0 * R[1, 1] - trace, 1.0 + 2.0 * R[2, 2] - trace])
    k = int(np.argmax(squares))
    big = 0.5 * math.sqrt(squares[k])
    quarter = 0.25 / big
    w_x_y_z = {
        0: (big, (R[2, 1] - R[1, 2]) * quarter, (R[0, 2] - R[2, 0]) * quarter, (R[1, 0] - R[0, 1]) * quarter),
        1: ((R[2, 1] - R[1, 2]) * quarter, big, (R[0, 1] + R[1, 0]) * quarter, (R[0, 2] + R[2, 0]) * quarter),
        2: ((R[0, 2] - R[2, 0]) * quarter, (R[0, 1] + R[1, 0]) * quarter, big, (R[1, 2] + R[2, 1]) * quarter),
        3: ((R[1, 0] - R[0, 1]) * quarter, (R[0, 2] + R[2, 0]) * quarter, (R[1, 2] + R[2, 1]) * quarter, big),
    }[k]
    quat = np.array(w_x_y_z)
    return quat if quat[0] >= 0.0 else -quat


def rot_from_quaternion(wxyz: ArrayLike) -> FloatArray:
    """Rotation matrix (3, 3) of the quaternion (w, x, y, z), normalised first (the inverse
    of :func:`quaternion_from_rot`).  ValueError for a zero or non-finite quaternion."""
    q = np.asarray(wxyz, dtype=float).reshape(4)
    norm = float(np.linalg.norm(q))
    if not math.isfinite(norm) or norm == 0.0:
        raise ValueError(f"quaternion: expected four finite numbers, not all zero, got {q.tolist()}")
    w, x, y, z = q / norm
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def rot_from_angle_axis(angle: float, axis: ArrayLike) -> FloatArray:
    """Rotation (3, 3) of ``angle`` radians about ``axis`` (normalised here; Rodrigues)."""
    k = np.asarray(axis, dtype=float).reshape(3)
    norm = np.linalg.norm(k)
    if norm < EPS_NORM:
        return np.eye(3)
    k = k / norm
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * (K @ K)


def rotation_log(R: ArrayLike) -> FloatArray:
    """Rotation vector ``angle * axis`` (3,) of a rotation matrix, accurate at every angle.

    The angle comes from ``atan2(sin, cos)`` (well conditioned near 0 and π, unlike
    ``acos`` of the trace); near π, where the skew part vanishes, the axis comes from the
    symmetric part ``(R + Rᵀ)/2 = cos θ I + (1 − cos θ) k kᵀ``.  The result has norm in
    [0, π]; it is the orientation error used by inverse kinematics (scalar maths on the
    nine entries: this runs once per IK iteration).
    """
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = np.asarray(R, dtype=float).tolist()
    w = np.array([r21 - r12, r02 - r20, r10 - r01])  # 2 sin θ k
    two_sin = math.sqrt(float(w @ w))
    cos_angle = (r00 + r11 + r22 - 1.0) * 0.5
    angle = math.atan2(0.5 * two_sin, cos_angle)
    if two_sin < 1e-12 and cos_angle > 0.0:
        return 0.5 * w  # identity up to rounding: θ k ≈ w / 2
    if two_sin > 1e-3 or cos_angle > 0.0:
        return (angle / two_sin) * w
    sym = np.array([[r00, r01 + r10, r02 + r20], [r01 + r10, r11, r12 + r21], [r02 + r20, r12 + r21, r22]])
    sym[~np.eye(3, dtype=bool)] *= 0.5
    kk = (sym - cos_angle * np.eye(3)) / (1.0 - cos_angle)  # k kᵀ
    i = int(np.argmax(np.diag(kk)))
    k = kk[:, i] / math.sqrt(kk[i, i])
    if k @ w < 0.0:
        k = -k
    return (angle / math.sqrt(float(k @ k))) * k


def angle_axis_from_vec_dir(vec: ArrayLike, dir: ArrayLike) -> tuple[float, FloatArray]:
    """Angle (radians) and unit axis (3,) of the rotation that turns ``vec`` onto ``dir``.

    Used to orient a drawable modelled along ``vec`` (e.g. a cylinder along z) so that it
    points along ``dir``.  Every input gives a valid rotation, never NaN:

    * ``dir`` parallel to ``vec``: angle 0 about z (identity);
    * antiparallel: angle π about an axis perpendicular to ``vec``;
    * ``dir`` (or ``vec``) of zero length: identity (angle 0 about z).
    """
    v = np.asarray(vec, dtype=float).reshape(3)
    d = np.asarray(dir, dtype=float).reshape(3)
    nv, nd = np.linalg.norm(v), np.linalg.norm(d)
    z_axis = np.array([0.0, 0.0, 1.0])
    if nv < EPS_NORM or nd < EPS_NORM or not (np.isfinite(nv) and np.isfinite(nd)):
        return 0.0, z_axis
    v, d = v / nv, d / nd
    axis = np.cross(v, d)
    s = np.linalg.norm(axis)
    c = float(np.clip(np.dot(v, d), -1.0, 1.0))
    if s < 1e-9:
        if c > 0.0:
            return 0.0, z_axis
        # Antiparallel: any axis perpendicular to v; pick the one least aligned with v.
        helper = np.eye(3)[int(np.argmin(np.abs(v)))]
        perp = np.cross(v, helper)
        return float(np.pi), perp / np.linalg.norm(perp)
    return float(np.arctan2(s, c)), axis / s


def rotations_z_onto(dirs: ArrayLike) -> FloatArray:
    """Rotations (N, 3, 3) whose z column is each direction ``dirs[i]`` (N, 3) normalised.

    The batched counterpart of :func:`angle_axis_from_vec_dir` for drawables modelled
    along z and symmetric about it (cylinders, cones): x and y complete a right-handed
    orthonormal basis, with no preference about z.  Zero-length or non-finite directions
    give the identity; every input gives a valid rotation, never NaN.
    """
    d = np.asarray(dirs, dtype=float).reshape(-1, 3)
    norm = np.sqrt(np.einsum("ij,ij->i", d, d))
    valid = np.isfinite(norm) & (norm > EPS_NORM)
    z = np.where(valid[:, None], d / np.where(valid, norm, 1.0)[:, None], (0.0, 0.0, 1.0))
    # the world axis least aligned with z (x unless z is close to it) gives a stable x
    helper = np.where((np.abs(z[:, 0]) < 0.9)[:, None], (1.0, 0.0, 0.0), (0.0, 1.0, 0.0))
    x = np.cross(helper, z)
    x /= np.linalg.norm(x, axis=1)[:, None]
    out = np.stack([x, np.cross(z, x), z], axis=-1)
    out[~valid] = np.eye(3)
    return out


def dh_transform(
    theta: ArrayLike, d: ArrayLike, a: ArrayLike, alpha: ArrayLike, convention: str = "standard"
) -> FloatArray:
    """DH link transform from frame i-1 to frame i (radians and metres).

    ``convention="standard"``: ``A = Rz(theta) Tz(d) Tx(a) Rx(alpha)`` (a, alpha of row i).
    ``convention="modified"`` (Craig): ``A = Rx(alpha) Tx(a) Rz(theta) Tz(d)``, where a and
    alpha are the row's a_{i-1}, α_{i-1}.
    Arguments are scalars or arrays that broadcast together; the result has shape
    ``broadcast_shape + (4, 4)``: (4, 4) for scalars, (N, 4, 4) for arrays of length N.
    """
    if convention not in ("standard", "modified"):
        raise ValueError(f"convention must be 'standard' or 'modified', got {convention!r}")
    theta, d, a, alpha = np.broadcast_arrays(
        *(np.asarray(x, dtype=float) for x in (theta, d, a, alpha))
    )
    ct, st = np.cos(theta), np.sin(theta)
    ca, sa = np.cos(alpha), np.sin(alpha)
    out = np.zeros(theta.shape + (4, 4))
    out[..., 3, 3] = 1.0
    if convention == "standard":
        out[..., 0, :] = np.stack([ct, -st * ca, st * sa, a * ct], axis=-1)
        out[..., 1, :] = np.stack([st, ct * ca, -ct * sa, a * st], axis=-1)
        out[..., 2, 1] = sa
        out[..., 2, 2] = ca
        out[..., 2, 3] = d
    else:
        out[..., 0, 0] = ct
        out[..., 0, 1] = -st
        out[..., 0, 3] = a
        out[..., 1, :] = np.stack([st * ca, ct * ca, -sa, -sa * d], axis=-1)
        out[..., 2, :] = np.stack([st * sa, ct * sa, ca, ca * d], axis=-1)
    return out


def is_rigid_transform(mat: ArrayLike, tol: float = 1e-6) -> bool:
    """True if ``mat`` is a finite (4, 4) matrix with an orthonormal, det +1 rotation
    block (to ``tol``) and bottom row [0, 0, 0, 1]."""
    # Plain float arithmetic on 16 numbers: a few µs, against about 100 µs for the same
    # tests through NumPy calls (it runs on every IK target and every world_tf given to
    # forward kinematics, e.g. per sample of a Cartesian path).  The tolerances
    # are np.allclose's: |x - expected| <= tol + 1e-5 |expected|.
    m = np.asarray(mat, dtype=float)
    if m.shape != (4, 4):
        return False
    rows = m.tolist()
    if not all(math.isfinite(v) for row in rows for v in row):
        return False
    (r00, r01, r02, _), (r10, r11, r12, _), (r20, r21, r22, _), bottom = rows
    cols = ((r00, r10, r20), (r01, r11, r21), (r02, r12, r22))
    for i in range(3):
        for j in range(i, 3):
            expected = 1.0 if i == j else 0.0
            dot = cols[i][0] * cols[j][0] + cols[i][1] * cols[j][1] + cols[i][2] * cols[j][2]
            if not abs(dot - expected) <= tol + 1e-5 * expected:
                return False
    det = r00 * (r11 * r22 - r12 * r21) - r01 * (r10 * r22 - r12 * r20) + r02 * (r10 * r21 - r11 * r20)
    return (
        abs(det - 1.0) < tol
        and abs(bottom[0]) <= tol
        and abs(bottom[1]) <= tol
        and abs(bottom[2]) <= tol
        and abs(bottom[3] - 1.0) <= tol + 1e-5
    )


class HomogeneousTransform:
    """A rigid transform as a 4×4 matrix ``mat`` (rotation ``R``, translation ``t`` in metres).

    ``T @ T2`` composes, ``T @ p`` maps a point (3,) and ``T @ P`` an (N, 3) array of points.
    """

    __slots__ = ("mat",)

    def __init__(self, mat: ArrayLike | None = None) -> None:
        if mat is None:
            self.mat = np.eye(4)
        else:
            m = np.array(mat, dtype=float)
            if m.shape != (4, 4):
                raise ValueError(f"HomogeneousTransform needs a 4x4 matrix, got shape {m.shape}")
            self.mat = m

    @classmethod
    def wrap(cls, mat: FloatArray) -> "HomogeneousTransform":
        """Transform sharing ``mat`` (a float64 (4, 4) array, not copied or checked).

        For hot paths that have just computed ``mat`` and hand it over.
        """
        obj = cls.__new__(cls)
        obj.mat = mat
        return obj

    @classmethod
    def from_rt(cls, R: ArrayLike | None = None, t: ArrayLike | None = None) -> "HomogeneousTransform":
        """Transform from a rotation (3, 3) and a translation (3,) in metres."""
        m = np.eye(4)
        if R is not None:
            m[:3, :3] = np.asarray(R, dtype=float)
        if t is not None:
            m[:3, 3] = np.asarray(t, dtype=float).reshape(3)
        return cls(m)

    @classmethod
    def from_xyz_rpy(cls, xyz: ArrayLike, rpy: ArrayLike) -> "HomogeneousTransform":
        """Transform from a translation (metres) and URDF roll-pitch-yaw (radians)."""
        return cls.from_rt(rot_from_rpy(rpy), xyz)

    def R(self) -> FloatArray:
        """Rotation block (3, 3) (a view)."""
        return self.mat[:3, :3]

    def t(self) -> FloatArray:
        """Translation (3,) in metres (a view)."""
        return self.mat[:3, 3]

    def Rx(self) -> FloatArray:
        """x axis of the frame expressed in the parent frame (3,)."""
        return self.mat[:3, 0]

    def Ry(self) -> FloatArray:
        """y axis of the frame expressed in the parent frame (3,)."""
        return self.mat[:3, 1]

    def Rz(self) -> FloatArray:
        """z axis of the frame expressed in the parent frame (3,)."""
        return self.mat[:3, 2]

    def rpy(self) -> tuple[float, float, float]:
        """URDF roll, pitch, yaw (radians) of the rotation."""
        return rpy_from_rot(self.R())

    def inv(self) -> "HomogeneousTransform":
        """Inverse transform, computed as ``[Rᵀ, −Rᵀ t]`` (exact for rigid transforms)."""
        Rt = self.R().T
        m = np.eye(4)
        m[:3, :3] = Rt
        m[:3, 3] = -Rt @ self.t()
        return HomogeneousTransform(m)

    @overload
    def __matmul__(self, other: "HomogeneousTransform") -> "HomogeneousTransform": ...
    @overload
    def __matmul__(self, other: ArrayLike) -> FloatArray: ...

    def __matmul__(
        self, other: Union["HomogeneousTransform", ArrayLike]
    ) -> Union["HomogeneousTransform", FloatArray]:
        if isinstance(other, HomogeneousTransform):
            return HomogeneousTransform(self.mat @ other.mat)
        pts = np.asarray(other, dtype=float)
        if pts.shape == (4, 4):
            return HomogeneousTransform(self.mat @ pts)
        if pts.shape == (3,):
            return self.R() @ pts + self.t()
        if pts.ndim == 2 and pts.shape[1] == 3:
            return pts @ self.R().T + self.t()
        raise ValueError(
            f"HomogeneousTransform applies to a transform, a point (3,) or points (N, 3); got shape {pts.shape}"
        )

    def __repr__(self) -> str:
        return f"HomogeneousTransform(\n{np.array2string(self.mat, precision=4, suppress_small=True)})"
