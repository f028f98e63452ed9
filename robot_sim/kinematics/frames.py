"""Forward and differential kinematics of one configuration or a batch: the frames, the
tool pose, the geometric Jacobian and J̇q̇, the rows a task can command, manipulability,
and the robot's characteristic length (frames and units: :mod:`robot_sim.kinematics.chain`).
Imports neither OpenGL nor Qt.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.kernels.model import per_robot
from robot_sim.kinematics.chain import CHUNK, _ChainModel, _model, _world0
from robot_sim.model.params import RobotParams, require_robot
from robot_sim.model.state import check_joint_vector
from robot_sim.transforms import HomogeneousTransform

FloatArray = NDArray[np.float64]


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

    Raises ValueError if q does not have n values per configuration or holds NaN/inf,
    TypeError if ``robot`` is not a RobotParams (a robot's name included).
    """
    Q = check_joint_vector(q, require_robot(robot).n_dofs)
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
    return per_robot(robot, "moving_position_rows", _moving_position_rows)


def _moving_position_rows(robot: RobotParams) -> FloatArray:
    """Indices of the position rows of ``robot``'s Jacobian that are not structurally
    zero, found from a few random in-range configurations."""
    # Which rows move is a property of the structure, not of the joint ranges, so
    # unlimited joints are probed over a unit range about home.
    lo, hi = np.array(robot.q_min), np.array(robot.q_max)
    unlimited = ~np.isfinite(lo) | ~np.isfinite(hi)
    lo[unlimited] = robot.q_home[unlimited] - 1.0
    hi[unlimited] = robot.q_home[unlimited] + 1.0
    probe = lo + (hi - lo) * np.random.default_rng(0).random((8, robot.n_dofs))
    jac = jacobian(robot, probe)
    return np.flatnonzero(np.abs(jac[:, :3, :]).max(axis=(0, 2)) > 1e-9)


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



def characteristic_length(robot: RobotParams) -> float:
    """A length [m] that scales with the robot: :attr:`RobotParams.size` (1 m if it is zero).
    Inverse kinematics divides position errors by it, so its iterations are the same for
    a robot and any scaled copy of it."""
    length = robot.size
    return length if 0.0 < length < math.inf else 1.0
