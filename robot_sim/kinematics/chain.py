"""The chain of a DH manipulator for the NumPy kinematics: the per-robot chain model
(kept with the robot's compiled model, :mod:`robot_sim.kernels.model`), one configuration
walked on Python floats, and the batched walk column by column on (3, M) arrays.

Frames and units
----------------
* Standard DH: ``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)`` maps frame i to frame i-1, and
  joint i turns (or slides) about z of frame i-1.  Modified (Craig) DH, for robots whose
  ``convention`` is ``"modified"``: ``A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)`` (row i
  holds a_{i-1}, α_{i-1}), and joint i turns (or slides) about z of frame i.
* Frame 0 in the world is ``world_tf @ robot.base_tf`` (``world_tf`` is where the robot
  stands, identity by default); frame i = frame 0 · A_1 ⋯ A_i.  The endeffector (tool)
  frame is frame n · ``robot.tool_tf``.
* Joint vector q: radians for revolute joints, metres for prismatic ones.
* Twists and Jacobians are stacked ``[linear velocity (m/s); angular velocity (rad/s)]``
  and expressed in the world frame, the linear part at the endeffector origin.

Hot paths
---------
Batched functions walk the chain *column by column* on (3, M) arrays for chunks of M
configurations that fit in cache: per joint a handful of vector operations update the
x, y, z and origin columns of the running transform, specialised for the twist angles
that DH tables nearly always use (0, ±90°, 180°).  No (N, n, 4, 4) stack of link matrices
is ever built; extra memory is a few chunk-sized buffers.  cos θ and sin θ come from one
SIMD ``tan`` of the half angle (``c = (1 - t²)/(1 + t²)``, ``s = 2t/(1 + t²)``), several
times faster than NumPy's scalar float64 ``cos`` and ``sin``.

This module imports neither OpenGL nor Qt.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.kernels.model import per_robot
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.transforms import HomogeneousTransform, is_rigid_transform

FloatArray = NDArray[np.float64]


#: Configurations processed per chunk by the batched kernels: small enough that the
#: dozen (3, CHUNK) work arrays stay in the L2 cache, large enough to hide NumPy's
#: per-call overhead.
CHUNK = 8192

# Twist angle classes: each gets its own cheap update of the (y, z) columns.
_ALPHA_ZERO, _ALPHA_PLUS90, _ALPHA_MINUS90, _ALPHA_PI, _ALPHA_GENERAL = range(5)
_ANGLE_TOL = 1e-12


_NEXT, _PREV = np.array([1, 2, 0]), np.array([2, 0, 1])


def _cross(a: FloatArray, b: FloatArray) -> FloatArray:
    """Cross product over the last axis of (..., 3) arrays (np.cross costs 3x more at these sizes)."""
    return a[..., _NEXT] * b[..., _PREV] - a[..., _PREV] * b[..., _NEXT]


def cos_sin_half(q: FloatArray, half_offset: FloatArray) -> tuple[FloatArray, FloatArray]:
    """cos and sin of θ = q + 2·half_offset (arrays of one shape) from one SIMD ``tan`` of
    the half angle: with t = tan(θ/2), cos θ = 2/(1 + t²) − 1 and sin θ = 2t/(1 + t²).
    NumPy's float64 ``cos`` and ``sin`` are scalar loops, several times slower."""
    t = np.multiply(q, 0.5)
    t += half_offset
    np.tan(t, out=t)
    w = t * t
    w += 1.0
    np.divide(2.0, w, out=w)
    cos = w - 1.0
    return cos, np.multiply(t, w, out=t)


def _alpha_kind(alpha: float) -> int:
    ca, sa = np.cos(alpha), np.sin(alpha)
    if abs(sa) < _ANGLE_TOL:
        return _ALPHA_ZERO if ca > 0 else _ALPHA_PI
    if abs(ca) < _ANGLE_TOL:
        return _ALPHA_PLUS90 if sa > 0 else _ALPHA_MINUS90
    return _ALPHA_GENERAL


class _ChainModel:
    """Precomputed, robot-specific data for the kinematic kernels (built once per robot).

    It keeps copies of the robot's arrays, never the robot itself: the cache that holds it
    is keyed weakly by the robot, so the entry goes when the robot's last user does."""

    def __init__(self, robot: RobotParams) -> None:
        self.n = robot.n_dofs
        self.dh_a, self.dh_d, self.dh_th = robot.dh_a, robot.dh_d, robot.dh_th
        self.modified = robot.is_modified
        # joint i+1 (0-based column i) turns about z of frame i (standard) or i+1 (modified)
        self.axis_frame = 1 if self.modified else 0
        self.revolute = robot.jtype == JTYPE_REVOLUTE
        self._revolute = self.revolute.tolist()
        self.rev_index = np.flatnonzero(self.revolute)
        self.alpha_kind = [_alpha_kind(al) for al in robot.dh_alpha]
        self.ca = np.cos(robot.dh_alpha)
        self.sa = np.sin(robot.dh_alpha)
        self.ct_const = np.cos(robot.dh_th)
        self.st_const = np.sin(robot.dh_th)
        self.half_th = 0.5 * robot.dh_th
        tool = robot.tool_tf.mat
        self.tool = tool
        self.tool_rotates = not np.allclose(tool[:3, :3], np.eye(3), atol=0.0, rtol=0.0)
        self.tool_translates = bool(np.any(tool[:3, 3] != 0.0))
        self._twists = list(zip(self.ca.tolist(), self.sa.tolist(), robot.dh_a.tolist()))
        self._dh_th, self._dh_d = robot.dh_th.tolist(), robot.dh_d.tolist()
        self._base_rows = robot.base_tf.mat.tolist()
        self._tool_rows = tool[:3].tolist()
        # link COMs = com_weights @ frame origins: link_com[0] at frame 0, link_com[i] at
        # fraction f_i from frame i-1 to frame i.
        weights = np.zeros((self.n + 1, self.n + 1))
        weights[0, 0] = 1.0
        rows = np.arange(1, self.n + 1)
        weights[rows, rows - 1] = 1.0 - robot.link_com_frac
        weights[rows, rows] = robot.link_com_frac
        self.com_weights = weights
        # With inertial data the COM of link i is fixed in frame i (``inertials.com``).
        self.com_local = None if robot.inertials is None else np.asarray(robot.inertials.com)

    # ---------------------------------------------------------------- single configuration
    def link_com(self, frames: FloatArray) -> FloatArray:
        """(n+1, 3) world COMs from world frames 0..n: the base at frame 0's origin, link i
        at ``inertials.com[i-1]`` in frame i when the robot has inertial data, otherwise at
        fraction ``link_com_frac[i-1]`` from frame i-1's origin to frame i's."""
        if self.com_local is None:
            return self.com_weights @ frames[:, :3, 3]
        com = frames[:, :3, 3].copy()
        com[1:] += np.einsum("nij,nj->ni", frames[1:, :3, :3], self.com_local)
        return com

    def frames(self, th: FloatArray, d: FloatArray, world0: FloatArray) -> FloatArray:
        """World frames 0..n (n+1, 4, 4) from full DH θ (rad) and d (m) of every joint."""
        flat: list[float] = []
        for X, Y, Z, P in self.walk_floats(th.tolist(), d.tolist(), world0):
            flat += (X[0], Y[0], Z[0], P[0], X[1], Y[1], Z[1], P[1], X[2], Y[2], Z[2], P[2], 0.0, 0.0, 0.0, 1.0)
        return np.array(flat).reshape(self.n + 1, 4, 4)

    def walk_floats(self, th: list[float], d: list[float], world0: FloatArray | list) -> list[tuple]:
        """World frames 0..n of one configuration as (x, y, z, origin) column triples of
        Python floats, from full DH θ [rad] and d [m] (floats cost far less than NumPy
        calls on 4×4 arrays): standard DH turns by θ, slides by d along z and a along the
        new x, then twists by α about it; modified DH twists, slides by a, turns, slides by d."""
        w = world0 if isinstance(world0, list) else world0.tolist()
        X, Y, Z, P = ((w[0][k], w[1][k], w[2][k]) for k in range(4))
        out = [(X, Y, Z, P)]
        modified = self.modified
        for (ca, sa, a), t, dj in zip(self._twists, th, d):
            c, s = math.cos(t), math.sin(t)
            if modified:
                Y, Z = (ca * Y[0] + sa * Z[0], ca * Y[1] + sa * Z[1], ca * Y[2] + sa * Z[2]), \
                    (ca * Z[0] - sa * Y[0], ca * Z[1] - sa * Y[1], ca * Z[2] - sa * Y[2])
                P = (P[0] + a * X[0], P[1] + a * X[1], P[2] + a * X[2])
                X, Y = (c * X[0] + s * Y[0], c * X[1] + s * Y[1], c * X[2] + s * Y[2]), \
                    (c * Y[0] - s * X[0], c * Y[1] - s * X[1], c * Y[2] - s * X[2])
                P = (P[0] + dj * Z[0], P[1] + dj * Z[1], P[2] + dj * Z[2])
            else:
                X, Y = (c * X[0] + s * Y[0], c * X[1] + s * Y[1], c * X[2] + s * Y[2]), \
                    (c * Y[0] - s * X[0], c * Y[1] - s * X[1], c * Y[2] - s * X[2])
                P = (P[0] + dj * Z[0] + a * X[0], P[1] + dj * Z[1] + a * X[1], P[2] + dj * Z[2] + a * X[2])
                Y, Z = (ca * Y[0] + sa * Z[0], ca * Y[1] + sa * Z[1], ca * Y[2] + sa * Z[2]), \
                    (ca * Z[0] - sa * Y[0], ca * Z[1] - sa * Y[1], ca * Z[2] - sa * Y[2])
            out.append((X, Y, Z, P))
        return out

    def tool_floats(self, frame: tuple) -> list[list[float]]:
        """The tool frame's rows (3 × 4 floats, world) from frame n as column triples."""
        X, Y, Z, P = frame
        cols = [[X[r] * t[0] + Y[r] * t[1] + Z[r] * t[2] for t in zip(*self._tool_rows)] for r in range(3)]
        for r in range(3):
            cols[r][3] += P[r]
        return cols

    def th_d(self, q: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Full DH θ and d of every joint for joint vector q (n,)."""
        return (
            np.where(self.revolute, self.dh_th + q, self.dh_th),
            np.where(self.revolute, self.dh_d, self.dh_d + q),
        )

    def axis_frames(self, frames: FloatArray) -> FloatArray:
        """The n frames (n, 4, 4) whose z axis and origin carry joints 1..n, from frames 0..n."""
        return frames[self.axis_frame : self.axis_frame + self.n]

    def jacobian(self, frames: FloatArray, p_e: FloatArray) -> FloatArray:
        """Geometric Jacobian (6, n) at world point ``p_e`` from world frames 0..n."""
        axes = self.axis_frames(frames)
        z = axes[:, :3, 2]
        lin = np.where(self.revolute[:, None], _cross(z, p_e - axes[:, :3, 3]), z)
        return np.concatenate([lin.T, (z * self.revolute[:, None]).T])

    # ---------------------------------------------------------------- batched kernel
    def walk(
        self,
        Q: FloatArray,
        world0: FloatArray,
        sink: Callable[[int, FloatArray, FloatArray, FloatArray, FloatArray], None] | None = None,
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Run the chain for a chunk Q (M, n); return the endeffector's x, y, z axes and
        origin as (3, M) world arrays.  ``sink(i, X, Y, Z, P)`` sees frame i = 0..n (the
        arrays are reused afterwards: copy what must be kept)."""
        M = Q.shape[0]
        X, Y, Z, P = (np.empty((3, M)) for _ in range(4))
        U, tmp = np.empty((3, M)), np.empty((3, M))
        for col, arr in zip(range(4), (X, Y, Z, P)):
            arr[:] = world0[:3, col : col + 1]
        if sink is not None:
            sink(0, X, Y, Z, P)
        rev = self.rev_index
        cos_all, sin_all = cos_sin_half(Q.T[rev], self.half_th[rev, None])
        k = 0
        for j in range(self.n):
            if self.revolute[j]:
                c, s = cos_all[k], sin_all[k]
                k += 1
            else:
                c, s = self.ct_const[j], self.st_const[j]
            d = Q[:, j] + self.dh_d[j] if not self.revolute[j] else self.dh_d[j]
            if self.modified:
                # Rx(α_{j-1}) Tx(a_{j-1}) Rz(θ_j) Tz(d_j)
                Y, Z, U = self._twist(j, Y, Z, U, tmp)
                self._slide(P, X, self.dh_a[j], tmp)
                X, Y, U = self._turn(j, c, s, X, Y, U, tmp)
                self._slide(P, Z, d, tmp)
            else:
                # Rz(θ_j) Tz(d_j) Tx(a_j) Rx(α_j)
                X, Y, U = self._turn(j, c, s, X, Y, U, tmp)
                self._slide(P, Z, d, tmp)
                self._slide(P, X, self.dh_a[j], tmp)
                Y, Z, U = self._twist(j, Y, Z, U, tmp)
            if sink is not None:
                sink(j + 1, X, Y, Z, P)
        return self._apply_tool(X, Y, Z, P)

    def _turn(
        self, j: int, c: FloatArray | float, s: FloatArray | float, X: FloatArray, Y: FloatArray, U: FloatArray, tmp: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Rotate the running frame about its z by θ_j (cos c, sin s): x' = c x + s y,
        y' = -s x + c y, in place; returns the new X, Y and the spare buffer."""
        if not self.revolute[j] and s == 0.0:
            return X, Y, U
        np.multiply(X, s, out=tmp)
        np.multiply(Y, c, out=U)
        U -= tmp
        X *= c
        np.multiply(Y, s, out=tmp)
        X += tmp
        return X, U, Y

    def _twist(
        self, j: int, Y: FloatArray, Z: FloatArray, U: FloatArray, tmp: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Rotate the running frame about its x by α_j: y' = cα y + sα z, z' = -sα y + cα z,
        specialised for α = 0, ±90°, 180°; returns the new Y, Z and the spare buffer."""
        kind = self.alpha_kind[j]
        if kind == _ALPHA_PLUS90:
            np.negative(Y, out=Y)
            return Z, Y, U
        if kind == _ALPHA_MINUS90:
            np.negative(Z, out=Z)
            return Z, Y, U
        if kind == _ALPHA_PI:
            np.negative(Y, out=Y)
            np.negative(Z, out=Z)
        elif kind == _ALPHA_GENERAL:
            ca, sa = self.ca[j], self.sa[j]
            np.multiply(Y, ca, out=U)
            np.multiply(Z, sa, out=tmp)
            U += tmp
            Z *= ca
            Y *= sa
            Z -= Y
            return U, Z, Y
        return Y, Z, U

    @staticmethod
    def _slide(P: FloatArray, axis: FloatArray, length: FloatArray | float, tmp: FloatArray) -> None:
        """Move the running origin P along ``axis`` by ``length`` (a constant or one per
        configuration), in place; a zero constant costs nothing."""
        if np.ndim(length) == 0 and length == 0.0:
            return
        np.multiply(axis, length, out=tmp)
        P += tmp

    def _apply_tool(
        self, X: FloatArray, Y: FloatArray, Z: FloatArray, P: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        tool = self.tool
        if self.tool_translates:
            P = P + X * tool[0, 3] + Y * tool[1, 3] + Z * tool[2, 3]
        if self.tool_rotates:
            X, Y, Z = (X * tool[0, c] + Y * tool[1, c] + Z * tool[2, c] for c in range(3))
        return X, Y, Z, P


def _model(robot: RobotParams) -> _ChainModel:
    return per_robot(robot, "kinematics", _ChainModel)


def _world0(robot: RobotParams, world_tf: HomogeneousTransform | ArrayLike | None) -> FloatArray:
    """Frame 0 in the world: ``world_tf @ base_tf``; ValueError unless ``world_tf`` is None
    or a rigid 4×4 transform."""
    if world_tf is None:
        return robot.base_tf.mat
    try:
        mat = world_tf.mat if isinstance(world_tf, HomogeneousTransform) else np.asarray(world_tf, dtype=float)
    except (ValueError, TypeError):
        mat = None
    if mat is None or mat.shape != (4, 4) or not is_rigid_transform(mat):
        raise ValueError(
            "world_tf must be a rigid 4x4 transform (finite, orthonormal rotation with det +1, "
            f"bottom row [0 0 0 1]), got {clip_repr(world_tf)}"
        )
    return mat @ robot.base_tf.mat
