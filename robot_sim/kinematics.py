"""Kinematics of DH manipulators: forward (single and batched), differential and inverse.

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
import os
import weakref
from dataclasses import dataclass
from typing import Any, Callable, Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.model.messages import clip, clip_repr
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.model.state import JointState, check_joint_vector
from robot_sim.transforms import HomogeneousTransform, is_rigid_transform, rotation_log

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
        self._moving_rows: FloatArray | None = None

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

    def moving_position_rows(self, robot: RobotParams) -> FloatArray:
        """Indices of the position rows of ``robot``'s Jacobian (the robot of this model)
        that are not structurally zero, found once from a few random in-range configurations."""
        if self._moving_rows is None:
            # Which rows move is a property of the structure, not of the joint ranges, so
            # unlimited joints are probed over a unit range about home.
            lo, hi = np.array(robot.q_min), np.array(robot.q_max)
            unlimited = ~np.isfinite(lo) | ~np.isfinite(hi)
            lo[unlimited] = robot.q_home[unlimited] - 1.0
            hi[unlimited] = robot.q_home[unlimited] + 1.0
            probe = lo + (hi - lo) * np.random.default_rng(0).random((8, robot.n_dofs))
            jac = jacobian(robot, probe)
            self._moving_rows = np.flatnonzero(np.abs(jac[:, :3, :]).max(axis=(0, 2)) > 1e-9)
        return self._moving_rows

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


_MODELS: "weakref.WeakKeyDictionary[RobotParams, _ChainModel]" = weakref.WeakKeyDictionary()


def _model(robot: RobotParams) -> _ChainModel:
    model = _MODELS.get(robot)
    if model is None:
        model = _MODELS[robot] = _ChainModel(robot)
    return model


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


def _store_columns(out: FloatArray, X: FloatArray, Y: FloatArray, Z: FloatArray, P: FloatArray) -> None:
    """Write (3, M) column arrays into ``out`` (M, 4, 4) (bottom row written by the caller)."""
    for col, arr in enumerate((X, Y, Z, P)):
        out[:, :3, col] = arr.T


def forward_kinematics(
    robot: RobotParams,
    q: ArrayLike,
    all_frames: bool = False,
    world_tf: HomogeneousTransform | ArrayLike | None = None,
) -> FloatArray:
    """World pose of the endeffector for joint vector(s) q.

    q of shape (n,) gives a (4, 4) pose; q of shape (N, n) gives (N, 4, 4), computed
    chunk by chunk without a per-configuration Python loop.  With ``all_frames=True`` the
    result holds frames 0..n followed by the endeffector: (n+2, 4, 4) or (N, n+2, 4, 4).
    ``world_tf`` places the robot's base in the world (identity by default).

    Raises ValueError if q does not have n values per configuration or holds NaN/inf.
    """
    Q = check_joint_vector(q, robot.n_dofs)
    single = Q.ndim == 1
    Q = np.ascontiguousarray(Q.reshape(-1, robot.n_dofs))
    N, n = Q.shape[0], robot.n_dofs
    model = _model(robot)
    world0 = _world0(robot, world_tf)
    if all_frames:
        out = np.empty((N, n + 2, 4, 4))
        out[:, :, 3, :] = (0.0, 0.0, 0.0, 1.0)
        for s in range(0, N, CHUNK):
            block = out[s : s + CHUNK]
            ee = model.walk(Q[s : s + CHUNK], world0, lambda i, *cols: _store_columns(block[:, i], *cols))
            _store_columns(block[:, n + 1], *ee)
    else:
        out = np.empty((N, 4, 4))
        out[:, 3, :] = (0.0, 0.0, 0.0, 1.0)
        for s in range(0, N, CHUNK):
            _store_columns(out[s : s + CHUNK], *model.walk(Q[s : s + CHUNK], world0))
    return out[0] if single else out


def jacobian(
    robot: RobotParams, q: ArrayLike, world_tf: HomogeneousTransform | ArrayLike | None = None
) -> FloatArray:
    """Geometric Jacobian of the endeffector (tool point included) in the world frame.

    q of shape (n,) gives (6, n); (N, n) gives (N, 6, n), batched like
    :func:`forward_kinematics`.  Rows are [linear velocity; angular velocity]: a revolute
    column is [z × (p_e − p); z], a prismatic column [z; 0], with z and p the axis and
    origin of the joint's frame: frame i-1 for joint i in standard DH, frame i in modified.
    """
    Q = check_joint_vector(q, robot.n_dofs)
    single = Q.ndim == 1
    Q = np.ascontiguousarray(Q.reshape(-1, robot.n_dofs))
    N, n = Q.shape[0], robot.n_dofs
    model = _model(robot)
    world0 = _world0(robot, world_tf)
    out = np.empty((N, 6, n))
    prismatic = np.flatnonzero(~model.revolute)
    for s in range(0, N, CHUNK):
        Qc = Q[s : s + CHUNK]
        M = Qc.shape[0]
        jac = np.empty((6, n, M))  # [v; ω] rows × joints × configurations
        lever = np.empty((n, 3, M))

        def keep(i: int, X: FloatArray, Y: FloatArray, Z: FloatArray, P: FloatArray) -> None:
            j = i - model.axis_frame  # frame i carries the axis and origin of column j
            if 0 <= j < n:
                jac[3:, j] = Z
                lever[j] = P

        p_e = model.walk(Qc, world0, keep)[3]
        np.subtract(p_e, lever, out=lever)  # p_e − p_i
        z, r = jac[3:], lever.transpose(1, 0, 2)  # (3, n, M) views
        tmp = np.empty((n, M))
        for row, (a, b) in enumerate(((1, 2), (2, 0), (0, 1))):
            np.multiply(z[a], r[b], out=jac[row])
            np.multiply(z[b], r[a], out=tmp)
            jac[row] -= tmp
        jac[:3, prismatic] = z[:, prismatic]
        jac[3:, prismatic] = 0.0
        out[s : s + M] = jac.transpose(2, 0, 1)
    return out[0] if single else out


def tool_kinematics(
    robot: RobotParams,
    q: ArrayLike,
    qd: ArrayLike,
    world_tf: HomogeneousTransform | ArrayLike | None = None,
    *,
    check: bool = True,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Tool pose, geometric Jacobian and J̇(q, q̇) q̇ from one walk of the chain.

    q, qd (n,) give the world pose (4, 4), the Jacobian (6, n) of :func:`jacobian` and the
    bias acceleration (6,) of :func:`jacobian_dot_qd`; (N, n) give (N, 4, 4), (N, 6, n) and
    (N, 6).  ValueError if q or qd lacks n finite values per configuration or their shapes
    differ; ``check=False`` skips these checks for callers that made them (float arrays
    of matching shapes).
    """
    n = robot.n_dofs
    if check:
        Q = check_joint_vector(q, n)
        QD = check_joint_vector(qd, n, "qd")
        if QD.shape != Q.shape:
            raise ValueError(f"qd must have the shape of q, {Q.shape}, got {QD.shape}")
    else:
        Q, QD = q, qd
    model = _model(robot)
    if Q.ndim == 1:  # Python floats throughout
        q_list = Q.tolist()
        th = [t + v if r else t for t, v, r in zip(model._dh_th, q_list, model._revolute)]
        d = [t if r else t + v for t, v, r in zip(model._dh_d, q_list, model._revolute)]
        frames = model.walk_floats(th, d, model._base_rows if world_tf is None else _world0(robot, world_tf))
        rows = model.tool_floats(frames[n])
        axes = frames[model.axis_frame : model.axis_frame + n]
        z, p = [f[2] for f in axes], [f[3] for f in axes]
        jac, bias = _jacobian_and_bias(model, z, p, (rows[0][3], rows[1][3], rows[2][3]), QD.tolist(), 0.0)
        return np.array(rows + [[0.0, 0.0, 0.0, 1.0]]), jac, bias
    every = forward_kinematics(robot, Q, all_frames=True, world_tf=world_tf)
    axes = every[:, model.axis_frame : model.axis_frame + n, :3]
    tool = every[:, n + 1]
    jac, bias = _jacobian_and_bias(model, axes[..., 2].transpose(1, 2, 0), axes[..., 3].transpose(1, 2, 0),
                                   tool[:, :3, 3].T, QD.T, np.zeros(Q.shape[0]))
    return tool, jac.transpose(2, 0, 1), bias.T


def jacobian_dot_qd(
    robot: RobotParams, q: ArrayLike, qd: ArrayLike, world_tf: HomogeneousTransform | ArrayLike | None = None
) -> FloatArray:
    """J̇(q, q̇) q̇: the endeffector's acceleration [linear (m/s²) at the tool origin; angular
    (rad/s²)] in the world frame when q̈ = 0, so that the tool's acceleration is
    ``J q̈ + J̇ q̇``.  q, qd (n,) give (6,); (N, n) give (N, 6), batched over configurations
    (the loops run over joints).  Errors as :func:`tool_kinematics`.
    """
    return tool_kinematics(robot, q, qd, world_tf)[2]


def _jacobian_and_bias(model: _ChainModel, z: Any, p: Any, pe: Any, rates: Any, zero: Any) -> tuple[FloatArray, FloatArray]:
    """J (6, n[, N]) and J̇q̇ (6[, N]) from joint axes ``z[j]`` and axis points ``p[j]`` (world
    triples), the tool point ``pe`` and the rates ``rates[j]``, each component a Python
    float (one configuration; ``zero`` = 0.0) or an (N,) array (a batch; ``zero`` zeros).

    With u_j = z_j q̇_j and Ω_j the angular velocity of the link carrying axis j (the sum
    of the revolute u_k, k < j): ż_j q̇_j = Ω_j × u_j.  A point x of that link moves at
    Ω_j × x + c_j with c_j = Σ_{k<j} (slide_k − ω_k × p_k).  Differentiating the columns
    [z_j × (p_e − p_j); z_j] (revolute) and [z_j; 0] (prismatic) along the motion and summing
    them weighted by q̇_j gives J̇q̇ = Σ [ż_j q̇_j × (p_e − p_j) + u_j × (ṗ_e − ṗ_j); ż_j q̇_j]
    (prismatic: [ż_j q̇_j; 0]).  The loops run over joints only.
    """
    n, revolute = model.n, model._revolute
    wx = wy = wz = cx = cy = cz = zero  # Ω and c of the link carrying the next axis
    moves = []  # per joint: u, ż q̇, ṗ of its axis point
    for j in range(n):
        (zx, zy, zz), (px, py, pz), r = z[j], p[j], rates[j]
        ux, uy, uz = zx * r, zy * r, zz * r
        moves.append((
            (ux, uy, uz),
            (wy * uz - wz * uy, wz * ux - wx * uz, wx * uy - wy * ux),
            (wy * pz - wz * py + cx, wz * px - wx * pz + cy, wx * py - wy * px + cz),
        ))
        if revolute[j]:
            wx, wy, wz = wx + ux, wy + uy, wz + uz
            cx, cy, cz = cx - (uy * pz - uz * py), cy - (uz * px - ux * pz), cz - (ux * py - uy * px)
        else:
            cx, cy, cz = cx + ux, cy + uy, cz + uz
    ex, ey, ez = pe
    vx, vy, vz = wy * ez - wz * ey + cx, wz * ex - wx * ez + cy, wx * ey - wy * ex + cz  # ṗ_e
    rows: list[list] = [[] for _ in range(6)]
    ax = ay = az = bx = by = bz = zero  # J̇q̇: linear, angular
    for j in range(n):
        (zx, zy, zz), ((ux, uy, uz), (dx, dy, dz), (qx, qy, qz)) = z[j], moves[j]
        if revolute[j]:
            lx, ly, lz = ex - p[j][0], ey - p[j][1], ez - p[j][2]
            col = (zy * lz - zz * ly, zz * lx - zx * lz, zx * ly - zy * lx, zx, zy, zz)
            rx, ry, rz = vx - qx, vy - qy, vz - qz
            ax = ax + dy * lz - dz * ly + uy * rz - uz * ry  # not +=: the zeros are one shared array
            ay = ay + dz * lx - dx * lz + uz * rx - ux * rz
            az = az + dx * ly - dy * lx + ux * ry - uy * rx
            bx, by, bz = bx + dx, by + dy, bz + dz
        else:
            col = (zx, zy, zz, zero, zero, zero)
            ax, ay, az = ax + dx, ay + dy, az + dz
        for k in range(6):
            rows[k].append(col[k])
    return np.array(rows), np.array([ax, ay, az, bx, by, bz])


def task_rows(robot: RobotParams) -> FloatArray:
    """Rows of the Jacobian a task-space controller can command: all six for arms with six
    or more joints; otherwise the position rows the arm's structure moves (x and y of a
    planar arm), found once per robot."""
    if robot.n_dofs >= 6:
        return np.arange(6)
    return _model(robot).moving_position_rows(robot)


def manipulability(robot: RobotParams, q: ArrayLike, jac: ArrayLike | None = None) -> FloatArray | float:
    """Yoshikawa's manipulability √det(J Jᵀ) at q (n,) or for each row of q (N, n).

    Arms with six or more joints use the full 6×n Jacobian.  Arms with fewer use the
    position rows only (√det(J_v J_vᵀ), or √det(J_vᵀ J_v) when there are more rows than
    joints), leaving out any position row the arm's structure keeps at zero (the z row of
    a planar arm), which would otherwise make the measure vanish everywhere.  A
    precomputed Jacobian of matching shape may be passed as ``jac``.
    """
    J = jacobian(robot, q) if jac is None else np.asarray(jac, dtype=float)
    n = robot.n_dofs
    if n < 6:
        J = J[..., task_rows(robot), :]
    JJt = J @ np.swapaxes(J, -1, -2) if J.shape[-2] <= n else np.swapaxes(J, -1, -2) @ J
    m = np.sqrt(np.clip(np.linalg.det(JJt), 0.0, None))
    return float(m) if m.ndim == 0 else m


class Kinematics:
    """Forward and differential kinematics of one robot at one joint state.

    After :meth:`update` the attributes hold, all in the world frame (metres, radians):

    * ``frames``: (n+1, 4, 4) array of frames 0..n;
    * ``h_tf``: the same frames as a list of n+1 :class:`HomogeneousTransform`;
    * ``endeff_tf``: endeffector (tool) frame = frame n · tool;
    * ``link_com``: (n_links+1, 3) centres of mass, ``link_com[0]`` at the base (frame 0
      origin), ``link_com[i]`` at ``inertials.com[i-1]`` in frame i when the robot has
      inertial data, otherwise at fraction ``link_com_frac[i-1]`` from frame i-1 to frame i;
    * ``jacobian``: (6, n) geometric Jacobian of the endeffector;
    * ``link_vel``: (n+1, 6) twist [v; ω] of each frame's origin (frame 0 is fixed);
    * ``link_com_vel``: (n_links+1, 3) linear velocity of each COM;
    * ``endeff_twist``: (6,) twist [v; ω] of the endeffector = ``jacobian @ qd``.

    ``h_tf`` and the three velocity attributes are derived on first access after each
    update (from the joint rates captured by that update), so a caller that needs only
    poses does not pay for them.
    """

    def __init__(self, robot_params: RobotParams) -> None:
        self.robot = robot_params
        self._model = _model(robot_params)
        home = JointState(robot_params.jtype)
        home.th[:], home.d[:] = self._model.th_d(np.asarray(robot_params.q_home))
        self.update(home)

    def update(self, joint_state: JointState, base_tf: HomogeneousTransform | None = None) -> None:
        """Recompute the frames, COMs and Jacobian from scratch (velocities on demand).

        ``joint_state`` supplies full DH θ and d and their rates; ``base_tf`` places the
        robot's base in the world (identity when None).
        """
        model = self._model
        frames = model.frames(joint_state.th, joint_state.d, _world0(self.robot, base_tf))
        endeff = frames[-1] @ model.tool
        self.frames = frames
        self.endeff_tf = HomogeneousTransform.wrap(endeff)
        self.link_com = model.link_com(frames)
        self.jacobian = model.jacobian(frames, endeff[:3, 3])
        self._qd = np.where(model.revolute, joint_state.thd, joint_state.dd)
        self._h_tf: list[HomogeneousTransform] | None = None
        self._velocities: tuple[FloatArray, FloatArray, FloatArray] | None = None

    @property
    def h_tf(self) -> list[HomogeneousTransform]:
        """World frames 0..n as transforms (views of ``frames``)."""
        if self._h_tf is None:
            self._h_tf = [HomogeneousTransform.wrap(f) for f in self.frames]
        return self._h_tf

    @property
    def link_vel(self) -> FloatArray:
        """(n+1, 6) twist [v (m/s); ω (rad/s)] of each frame's origin, world frame."""
        return self._derive_velocities()[0]

    @property
    def link_com_vel(self) -> FloatArray:
        """(n_links+1, 3) linear velocity (m/s) of each link COM, world frame."""
        return self._derive_velocities()[1]

    @property
    def endeff_twist(self) -> FloatArray:
        """(6,) endeffector twist [v (m/s); ω (rad/s)] in the world frame (= J q̇)."""
        return self._derive_velocities()[2]

    def _derive_velocities(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        # Accumulate joint contributions along the chain: ω_i = Σ_{j≤i} ω_j and, for any
        # point x moving with link i, v(x) = Σ_{j≤i} (ω_j × (x − p_j) + v_j^prismatic)
        # = ω_i × x + c_i with c_i = Σ_{j≤i} (v_j^prismatic − ω_j × p_j), p_j a point of
        # joint j's axis (origin of frame j-1 in standard DH, of frame j in modified).  A COM sits
        # at a fixed fraction between two frame origins, so its velocity is the same
        # blend of theirs (exact also while a prismatic joint stretches its link).
        if self._velocities is None:
            n, qd, revolute = self.robot.n_dofs, self._qd, self._model.revolute
            axes = self._model.axis_frames(self.frames)
            origins, z = self.frames[:, :3, 3], axes[:, :3, 2]
            qd_revolute = np.where(revolute, qd, 0.0)
            w_joint = z * qd_revolute[:, None]
            omega = np.cumsum(w_joint, axis=0)
            crosses = _cross(np.concatenate([w_joint, omega]), np.concatenate([axes[:, :3, 3], origins[1:]]))
            link_vel = np.zeros((n + 1, 6))
            link_vel[1:, :3] = crosses[n:] + np.cumsum(z * (qd - qd_revolute)[:, None] - crosses[:n], axis=0)
            link_vel[1:, 3:] = omega
            if self._model.com_local is None:
                com_vel = self._model.com_weights @ link_vel[:, :3]
            else:  # v_com = v_i + ω_i × (R_i c_i)
                com_vel = link_vel[:, :3].copy()
                com_vel[1:] += _cross(omega, self.link_com[1:] - origins[1:])
            self._velocities = (link_vel, com_vel, self.jacobian @ qd)
        return self._velocities


# ------------------------------------------------------------------ workspace


def sampling_bounds(robot: RobotParams) -> tuple[FloatArray, FloatArray]:
    """Finite per-joint sampling ranges: the joint limits, with unlimited revolute joints
    sampled over [−π, π].  ValueError naming the joint if a prismatic joint has no limits."""
    lo, hi = np.array(robot.q_min), np.array(robot.q_max)
    for i in np.flatnonzero(~np.isfinite(lo) | ~np.isfinite(hi)):
        if robot.jtype[i] != JTYPE_REVOLUTE:
            raise ValueError(f"{robot.name}: prismatic joint {i + 1} has no limits; cannot sample its range")
        lo[i], hi[i] = max(lo[i], -np.pi), min(hi[i], np.pi)
    return lo, hi


def random_configurations(robot: RobotParams, n_samples: int, rng: np.random.Generator) -> FloatArray:
    """(n_samples, n) joint vectors drawn uniformly inside :func:`sampling_bounds`."""
    lo, hi = sampling_bounds(robot)
    return lo + (hi - lo) * rng.random((n_samples, robot.n_dofs))


class WorkspaceCancelled(Exception):
    """Raised by :func:`workspace_points` when its ``cancelled`` callback returns True."""


def workspace_points(
    robot: RobotParams,
    n_samples: int,
    seed: int | None = None,
    cancelled: Callable[[], bool] | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Endeffector positions (n_samples, 3) [m, world] of uniformly sampled in-limit
    configurations, and the manipulability (n_samples,) of each (see :func:`manipulability`).

    ValueError for an ``n_samples`` that is not a positive integer or needs more memory
    than :func:`max_workspace_samples` allows, a bad ``seed``, or a prismatic joint
    without limits (its range cannot be sampled).  ``cancelled()`` is called between
    chunks of samples (from a worker thread, say); when it returns True the computation
    stops with :class:`WorkspaceCancelled`."""
    n_samples = _check_int("n_samples", n_samples, 1)
    seed = _check_seed(seed)
    limit = max_workspace_samples(robot)
    if n_samples > limit:
        raise ValueError(
            f"n_samples = {clip_repr(n_samples)} needs {_size_text(n_samples * _workspace_bytes(robot))} "
            f"of memory; at most {limit} samples fit in the {_size_text(available_memory())} available"
        )
    Q = random_configurations(robot, n_samples, np.random.default_rng(seed))
    points = np.empty((Q.shape[0], 3))
    manip = np.empty(Q.shape[0])
    for s in range(0, Q.shape[0], CHUNK * 8):
        if cancelled is not None and cancelled():
            raise WorkspaceCancelled(f"workspace of {robot.name} cancelled after {s} of {n_samples} samples")
        chunk = Q[s : s + CHUNK * 8]
        jac = jacobian(robot, chunk)
        points[s : s + len(chunk)] = forward_kinematics(robot, chunk)[:, :3, 3]
        manip[s : s + len(chunk)] = manipulability(robot, chunk, jac)
    return points, manip


def available_memory() -> int:
    """Bytes of memory the system can give this process without swapping (Linux
    ``MemAvailable``; elsewhere the free physical pages)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def _workspace_bytes(robot: RobotParams) -> int:
    """Bytes :func:`workspace_points` holds per sample: its configuration, point and
    manipulability (float64)."""
    return 8 * (robot.n_dofs + 4)


def max_workspace_samples(robot: RobotParams) -> int:
    """Most samples :func:`workspace_points` accepts: what fits in half the available
    memory (the other half is left for drawing them and for everything else)."""
    return max(1, available_memory() // 2 // _workspace_bytes(robot))


def _size_text(n_bytes: int) -> str:
    return f"about {n_bytes / 2**30:.3g} GiB" if n_bytes < 2**80 else "more than 2**80 bytes"


# ------------------------------------------------------------------ inverse kinematics


class CollisionQuery(Protocol):
    """What :func:`solve_ik` asks of a collision checker (``robot_sim.collision``)."""

    def in_collision(self, q: FloatArray) -> bool: ...


@dataclass(frozen=True)
class IKResult:
    """Outcome of :func:`solve_ik`.

    ``q`` is the best joint vector found (never NaN), ``success`` whether it meets the
    tolerances, ``iterations`` the total damped-least-squares steps over all restarts,
    ``restarts`` how many random restarts were used, ``pos_err`` [m] and ``rot_err`` [rad]
    the remaining errors, ``position_only`` whether orientation was ignored, and
    ``message`` a one-line explanation.
    """

    q: FloatArray
    success: bool
    iterations: int
    restarts: int
    pos_err: float
    rot_err: float
    position_only: bool
    message: str


def ik_position_only_required(robot: RobotParams) -> bool:
    """True for arms with fewer than six joints, which cannot reach an arbitrary pose."""
    return robot.n_dofs < 6


def _is_real(value: object) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def _check_tolerance(name: str, value: float) -> float:
    if not (_is_real(value) and math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be a positive finite number, got {clip_repr(value)}")
    return float(value)


def _check_int(name: str, value: int, minimum: int) -> int:
    """``value`` as an int >= ``minimum`` (Python or NumPy integer, not bool); ValueError otherwise."""
    if not (isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)) and value >= minimum):
        wanted = "a positive integer" if minimum == 1 else f"an integer >= {minimum}"
        raise ValueError(f"{name} must be {wanted}, got {clip_repr(value)}")
    return int(value)


def _check_seed(seed: int | None) -> int | None:
    if seed is not None and not (isinstance(seed, (int, np.integer)) and not isinstance(seed, bool) and seed >= 0):
        raise ValueError(f"seed must be None or a non-negative integer, got {clip_repr(seed)}")
    return seed


def _target_matrix(target: HomogeneousTransform | ArrayLike) -> FloatArray:
    try:
        mat = target.mat if isinstance(target, HomogeneousTransform) else np.asarray(target, dtype=float)
    except (ValueError, TypeError):
        raise ValueError(f"IK target must be a 4x4 transform, got {clip_repr(target)}") from None
    if mat.shape != (4, 4):
        raise ValueError(f"IK target must be a 4x4 transform, got shape {mat.shape}")
    if not is_rigid_transform(mat):
        raise ValueError(
            "IK target is not a rigid transform (needs finite values, an orthonormal rotation "
            f"with det +1 and bottom row [0 0 0 1]), got {clip_repr(mat.tolist(), 200)}"
        )
    return mat


def characteristic_length(robot: RobotParams) -> float:
    """A length [m] that scales with the robot: :attr:`RobotParams.size` (1 m if it is zero).
    Inverse kinematics divides position errors by it, so its iterations are the same for
    a robot and any scaled copy of it."""
    length = robot.size
    return length if 0.0 < length < math.inf else 1.0


@dataclass(frozen=True)
class _Pose:
    """One evaluated IK iterate: joint vector, error, Jacobian and error norms."""

    q: FloatArray
    err: FloatArray
    jac: FloatArray
    pos_err: float
    rot_err: float

    @property
    def cost(self) -> float:
        return float(self.err @ self.err)


class _IKProblem:
    """Pose error, Jacobian, limits and the damped least-squares descent of one IK query."""

    # Levenberg–Marquardt damping schedule
    LAMBDA_INIT = 1e-3
    LAMBDA_MIN = 1e-9
    LAMBDA_MAX = 1e6
    LAMBDA_DOWN = 0.2
    LAMBDA_UP = 10.0
    MAX_STEP = 0.6  # largest joint step per iteration [rad, or characteristic lengths], keeps far starts stable
    STALL_RATIO = 0.999  # an iteration that keeps more of the cost than this makes no progress
    STALL_ITERS = 6  # this many in a row: the descent has stalled
    ITERS_PER_START = 40  # a start that has not converged by then is abandoned
    NULLSPACE_GAIN = 0.05  # pull of redundant joints toward home per iteration
    NULLSPACE_MIN_COST = 1e-6  # below this squared error the pull stops, so the last steps are pure Gauss-Newton
    PRISMATIC_RESTART_SPAN = 1.0  # characteristic lengths either side of the current value for an unlimited prismatic joint

    def __init__(
        self,
        robot: RobotParams,
        target: FloatArray,
        position_only: bool,
        lo: FloatArray,
        hi: FloatArray,
        tol_pos: float,
        tol_rot: float,
    ) -> None:
        self.robot = robot
        self.model = _model(robot)
        self.target = target
        self.position_only = position_only
        self.lo, self.hi = lo, hi
        self.tol_pos, self.tol_rot = tol_pos, tol_rot
        self.rows = slice(0, 3) if position_only else slice(0, 6)
        self.redundant = robot.n_dofs > (3 if position_only else 6)
        self.world0 = robot.base_tf.mat
        # The descent runs in scale-free units: positions in characteristic lengths L,
        # prismatic joint values too; angles stay radians.  ``var_scale`` turns a step in
        # those units back into joint units.
        self.length = characteristic_length(robot)
        self.var_scale = np.where(self.model.revolute, 1.0, self.length)

    def evaluate(self, q: FloatArray) -> _Pose:
        """Pose at q: error and Jacobian in scale-free units, error norms in m and rad."""
        frames = self.model.frames(*self.model.th_d(q), self.world0)
        ee = frames[-1] @ self.model.tool
        dp = self.target[:3, 3] - ee[:3, 3]
        dr = rotation_log(self.target[:3, :3] @ ee[:3, :3].T)
        jac = self.model.jacobian(frames, ee[:3, 3])[self.rows] * self.var_scale
        jac[:3] /= self.length
        err = dp / self.length if self.position_only else np.concatenate([dp / self.length, dr])
        return _Pose(q, err, jac, math.sqrt(dp @ dp), math.sqrt(dr @ dr))

    def converged(self, pose: _Pose) -> bool:
        return pose.pos_err <= self.tol_pos and (self.position_only or pose.rot_err <= self.tol_rot)

    def into_limits(self, q: FloatArray) -> FloatArray:
        """q inside the limits: a revolute joint outside its range first turns by whole
        turns when that lands inside it (the same pose), otherwise it is clipped."""
        with np.errstate(invalid="ignore"):
            turns = np.where(q < self.lo, np.ceil((self.lo - q) / (2 * np.pi)), 0.0)
            turns = np.where(q > self.hi, np.floor((self.hi - q) / (2 * np.pi)), turns)
        wrapped = q + 2 * np.pi * turns
        inside = self.model.revolute & (wrapped >= self.lo) & (wrapped <= self.hi)
        return np.clip(np.where(inside, wrapped, q), self.lo, self.hi)

    def restart_sample(self, rng: np.random.Generator, q: FloatArray) -> FloatArray:
        """A random configuration inside the limits (unlimited revolute joints over ±π,
        unlimited prismatic ones around their current value)."""
        span = self.PRISMATIC_RESTART_SPAN * self.length
        lo = np.where(np.isfinite(self.lo), self.lo, np.where(self.model.revolute, -np.pi, q - span))
        hi = np.where(np.isfinite(self.hi), self.hi, np.where(self.model.revolute, np.pi, q + span))
        return lo + (hi - lo) * rng.random(q.shape[0])

    def descend(self, q: FloatArray, bounded: bool, budget: int) -> tuple[_Pose, int]:
        """Levenberg–Marquardt from q for at most ``budget`` iterations, until converged or
        stalled; ``bounded`` keeps every iterate inside the limits.  Returns the best pose
        and the iterations used."""
        pose = self.evaluate(self.into_limits(q) if bounded else q)
        lam, stalled, used = self.LAMBDA_INIT, 0, 0
        while used < budget and stalled < self.STALL_ITERS and not self.converged(pose):
            used += 1
            try:
                q_new = pose.q + self.step(pose, lam, bounded)
            except np.linalg.LinAlgError:  # damping lost in rounding: damp more
                lam, stalled = min(lam * self.LAMBDA_UP, self.LAMBDA_MAX), stalled + 1
                continue
            new = self.evaluate(self.into_limits(q_new) if bounded else q_new)
            stalled = 0 if new.cost < pose.cost * self.STALL_RATIO else stalled + 1
            if new.cost < pose.cost:
                pose, lam = new, max(lam * self.LAMBDA_DOWN, self.LAMBDA_MIN)
            else:
                lam = min(lam * self.LAMBDA_UP, self.LAMBDA_MAX)
        return pose, used

    def step(self, pose: _Pose, lam: float, bounded: bool) -> FloatArray:
        """Damped least-squares step Jᵀ(JJᵀ + λI)⁻¹e, plus, for redundant arms still far
        from the target, a null-space pull toward home.

        When ``bounded``, joints resting on a limit that the step would push further out
        are frozen (their Jacobian column removed) and the step recomputed, so the other
        joints make up for them instead of the clipped step losing its direction.
        """
        dq = self._damped_step(pose, pose.jac, lam)
        if bounded:
            blocked = ((pose.q <= self.lo) & (dq < 0.0)) | ((pose.q >= self.hi) & (dq > 0.0))
            if blocked.any():
                dq = self._damped_step(pose, pose.jac * ~blocked, lam)
                dq[blocked] = 0.0
        largest = np.max(np.abs(dq))
        if largest > self.MAX_STEP:
            dq *= self.MAX_STEP / largest
        return dq * self.var_scale

    def _damped_step(self, pose: _Pose, jac: FloatArray, lam: float) -> FloatArray:
        gram = jac @ jac.T
        gram[np.diag_indices_from(gram)] += lam
        if self.redundant and pose.cost > self.NULLSPACE_MIN_COST:
            sol = np.linalg.solve(gram, np.column_stack([pose.err, jac]))
            null = np.eye(self.robot.n_dofs) - jac.T @ sol[:, 1:]
            pull = (self.robot.q_home - pose.q) / self.var_scale
            return jac.T @ sol[:, 0] + null @ (self.NULLSPACE_GAIN * pull)
        return jac.T @ np.linalg.solve(gram, pose.err)


def solve_ik(
    robot_params: RobotParams,
    target: HomogeneousTransform | ArrayLike,
    q0: ArrayLike | None = None,
    *,
    position_only: bool = False,
    tol_pos: float = 1e-6,
    tol_rot: float = 1e-6,
    max_iter: int = 1000,
    max_restarts: int = 50,
    respect_limits: bool = True,
    seed: int | None = 0,
    checker: CollisionQuery | None = None,
) -> IKResult:
    """Joint vector that puts the endeffector at ``target`` (world frame, 4×4 or
    :class:`HomogeneousTransform`), by damped least squares (Levenberg–Marquardt).

    Each iteration solves ``(JJᵀ + λI) y = e`` for the pose error
    e = [p* − p; log(R* Rᵀ)] and steps ``Δq = Jᵀy``, adapting λ (smaller after a step that
    lowers the error, larger after one that does not).  The first descent starts at ``q0``
    (home when None) and, with ``respect_limits``, keeps every iterate inside the joint
    limits, freezing joints that push against a limit.  A descent that stalls or has not
    converged in 40 iterations is followed by one from a random configuration, up to
    ``max_restarts`` times within ``max_iter`` iterations in total.  Restarts descend
    without bounds (far more of them converge) and then bring the solution into the
    limits by whole turns of revolute joints, or polish it with a bounded descent.
    Redundant arms add a null-space pull toward home.  Arms with fewer than six joints
    always solve position only (``position_only`` in the result says so, with a message).

    With a ``checker`` (a ``robot_sim.collision.CollisionChecker`` of this robot, or any
    object whose ``in_collision(q)`` answers for one configuration) a converged
    configuration in collision is not a solution: the search restarts past it, and the
    message of a failure says how many such minima it met.

    Success means ``pos_err <= tol_pos`` and, unless position only, ``rot_err <= tol_rot``
    (and, with a checker, no collision).  A target farther from the base than
    :attr:`RobotParams.reach` is answered by the first descent alone, with the message
    saying so (restarts cannot reach it).  A failure is a result with ``success=False``
    holding the best in-limit configuration found.  Raises ValueError for a target that is not a rigid transform, a wrong-length
    or non-finite ``q0``, or non-positive tolerances.
    """
    robot = robot_params
    tmat = _target_matrix(target)
    tol_pos = _check_tolerance("tol_pos", tol_pos)
    tol_rot = _check_tolerance("tol_rot", tol_rot)
    max_iter = _check_int("max_iter", max_iter, 1)
    max_restarts = _check_int("max_restarts", max_restarts, 0)
    seed = _check_seed(seed)
    if checker is not None and not callable(getattr(checker, "in_collision", None)):
        raise ValueError(f"checker must have an in_collision(q) method (a CollisionChecker), got {clip_repr(checker)}")
    q = check_joint_vector(robot.q_home if q0 is None else q0, robot.n_dofs, "q0")
    if q.ndim != 1:
        raise ValueError(f"q0 must be one configuration of shape ({robot.n_dofs},), got {q.shape}")

    message = ""
    if not position_only and ik_position_only_required(robot):
        position_only = True
        message = f"{robot.name} has {robot.n_dofs} joints (< 6): solved for position only. "
    if respect_limits:
        lo, hi = np.array(robot.q_min), np.array(robot.q_max)
    else:
        lo, hi = np.full(robot.n_dofs, -np.inf), np.full(robot.n_dofs, np.inf)
    from robot_sim.ik.nearest import answers, nearest_exact  # closed form first, where the arm has one

    if answers(robot, position_only):
        q_exact = nearest_exact(robot, tmat, q, respect_limits, None if checker is None else checker.in_collision)
        model = _model(robot)  # its single-configuration chain: the batched walk costs more for one
        ee = model.frames(*model.th_d(q_exact), robot.base_tf.mat)[-1] @ model.tool if q_exact is not None else tmat
        pos_err = float(np.linalg.norm(tmat[:3, 3] - ee[:3, 3]))
        rot_err = 0.0 if position_only else float(np.linalg.norm(rotation_log(tmat[:3, :3] @ ee[:3, :3].T)))
        if q_exact is not None and pos_err <= tol_pos and rot_err <= tol_rot:
            return IKResult(q_exact, True, 0, 0, pos_err, rot_err, position_only,
                            message + "analytic: the exact solution nearest to q0")
    problem = _IKProblem(robot, tmat, position_only, lo, hi, tol_pos, tol_rot)
    rng = np.random.default_rng(seed)
    distance = float(np.linalg.norm(tmat[:3, 3] - robot.base_tf.mat[:3, 3]))
    if respect_limits and distance > robot.reach + tol_pos:  # no configuration gets there: one descent toward it
        message += f"target is {distance:.3g} m from the base, beyond the arm's reach of {robot.reach:.3g} m; "
        max_restarts = 0

    # From here on nothing raises: overflow on absurd robots gives inf/NaN errors that no
    # step accepts, and any arithmetic failure ends the search with the best pose so far.
    best, iterations, restarts, bounded, failure, colliding = None, 0, 0, True, "", 0

    def accepted(pose: _Pose) -> bool:
        """False for a converged pose that the checker finds in collision."""
        nonlocal colliding
        if checker is None or not problem.converged(pose) or not checker.in_collision(pose.q):
            return True
        colliding += 1
        return False

    with np.errstate(all="ignore"):
        try:
            while True:
                pose, used = problem.descend(q, bounded, min(problem.ITERS_PER_START, max_iter - iterations))
                iterations += used
                if not bounded:
                    pose = problem.evaluate(problem.into_limits(pose.q))
                    if not problem.converged(pose) and iterations < max_iter:
                        pose, used = problem.descend(pose.q, True, min(problem.ITERS_PER_START, max_iter - iterations))
                        iterations += used
                if accepted(pose) and (best is None or pose.cost < best.cost):
                    best = pose
                done = best is not None and problem.converged(best)
                if done or restarts >= max_restarts or iterations >= max_iter:
                    break
                restarts += 1
                q, bounded = problem.restart_sample(rng, pose.q if best is None else best.q), False
        except (np.linalg.LinAlgError, ArithmeticError) as exc:
            failure = f"numerical failure ({clip(str(exc))}) after {iterations} iterations: "
        if best is None:  # failed in the first descent, or every minimum collided: report where it started
            q_start = problem.into_limits(q) if np.isfinite(q).all() else np.array(robot.q_home)
            try:
                best = problem.evaluate(q_start)
            except (np.linalg.LinAlgError, ArithmeticError):
                best = _Pose(q_start, np.full(1, np.inf), np.zeros((1, robot.n_dofs)), math.inf, math.inf)

    success = problem.converged(best) and not failure and (checker is None or not checker.in_collision(best.q))
    if success:
        message += f"converged in {iterations} iterations ({restarts} restarts)"
    else:
        message += failure or f"did not converge in {iterations} iterations ({restarts} restarts): "
        message += f"position error {best.pos_err:.3g} m"
        message += "" if position_only else f", rotation error {best.rot_err:.3g} rad"
        if colliding:
            message += f"; {colliding} converged configuration{'s were' if colliding > 1 else ' was'} in collision"
    return IKResult(
        q=best.q.copy(),
        success=success,
        iterations=iterations,
        restarts=restarts,
        pos_err=best.pos_err,
        rot_err=best.rot_err,
        position_only=position_only,
        message=message,
    )


def diff_ik_velocity(
    robot_params: RobotParams, q: ArrayLike, twist_des: ArrayLike, damping: float = 1e-2
) -> FloatArray:
    """Joint velocities (n,) that best produce the endeffector twist ``twist_des``.

    ``twist_des`` is (6,) [v (m/s); ω (rad/s)] or (3,) linear velocity only, in the world
    frame.  Uses the damped pseudo-inverse ``Jᵀ(JJᵀ + damping² I)⁻¹``, which stays bounded
    near singularities at the cost of a small tracking error there.
    """
    v = np.asarray(twist_des, dtype=float)
    if v.shape not in ((6,), (3,)) or not np.isfinite(v).all():
        raise ValueError(f"twist_des must be a finite (6,) or (3,) vector, got {v!r}")
    jac = jacobian(robot_params, q)[: v.shape[0]]
    gram = jac @ jac.T
    gram[np.diag_indices_from(gram)] += damping**2
    return jac.T @ np.linalg.solve(gram, v)
