"""Newton's polish of a joint vector toward a pose (compiled): Levenberg–Marquardt steps
on the pose error, with the package's one chain kernel for forward kinematics and the
Jacobian (:mod:`robot_sim.kernels.chain`).  World frame, poses 4×4, joint values in rad
or m; the position error is divided by the robot's size so that it weighs as radians."""
from __future__ import annotations

import math

import numba
import numpy as np

from robot_sim.kernels.algebra import cholesky_solve
from robot_sim.kernels.chain import frames, jacobian_and_bias, tool_pose
from robot_sim.kernels.jit import JIT

#: Most Levenberg–Marquardt steps (a least-squares descent toward a pose out of reach may
#: take many), and the pose error at which they stop: |Δp|/size and |log(R_T Rᵀ)|
#: combined [m / m, rad].
STEPS = 200
STOP = 1e-14
#: An error below this that a full step does not lower is final (the limit of rounding).
CONVERGED = 1e-12


@numba.njit(**JIT)
def pose_error(X: np.ndarray, T: np.ndarray, inv_size: float, e: np.ndarray) -> float:
    """e = [(t_T − t_X)/size; log(R_T R_Xᵀ)] and its norm."""
    for a in range(3):
        e[a] = (T[a, 3] - X[a, 3]) * inv_size
    E = np.empty((3, 3))
    for a in range(3):
        for b in range(3):
            E[a, b] = T[a, 0] * X[b, 0] + T[a, 1] * X[b, 1] + T[a, 2] * X[b, 2]
    wx, wy, wz = 0.5 * (E[2, 1] - E[1, 2]), 0.5 * (E[0, 2] - E[2, 0]), 0.5 * (E[1, 0] - E[0, 1])
    sn = math.sqrt(wx * wx + wy * wy + wz * wz)
    cs = 0.5 * (E[0, 0] + E[1, 1] + E[2, 2] - 1.0)
    angle = math.atan2(sn, cs)
    f = angle / sn if sn > 1e-12 else 1.0
    if cs < 0.0 and sn <= 1e-12:  # a half turn, E = 2hhᵀ − I: h along E's column k plus e_k
        k = 0
        for a in range(3):
            if E[a, a] > E[k, k]:
                k = a
        wx, wy, wz = E[0, k], E[1, k], E[2, k]
        if k == 0:
            wx += 1.0
        elif k == 1:
            wy += 1.0
        else:
            wz += 1.0
        norm = math.sqrt(wx * wx + wy * wy + wz * wz)
        f = math.pi / norm
    e[3], e[4], e[5] = f * wx, f * wy, f * wz
    total = 0.0
    for a in range(6):
        total += e[a] * e[a]
    return math.sqrt(total)


@numba.njit(**JIT)
def polish(table: np.ndarray, modified: bool, base: np.ndarray, tool: np.ndarray, T: np.ndarray,
           inv_size: float, q: np.ndarray) -> float:
    """Levenberg–Marquardt steps on q (in place) toward the pose T; returns the last pose
    error (see :func:`pose_error`).  Forward kinematics and the Jacobian are the package's
    one chain kernel (:mod:`robot_sim.kernels.chain`)."""
    n = q.shape[0]
    F = np.empty((n + 1, 3, 4))
    X = np.empty((4, 4))
    J = np.empty((6, n))
    jd = np.empty(6)
    zero = np.zeros(n)
    e = np.empty(6)
    trial = np.empty(n)
    dq = np.empty(n)
    A = np.empty((n, n))
    M = np.empty((n, n))
    g = np.empty(n)
    e_new = np.empty(6)
    frames(table, modified, base, q, F)
    tool_pose(F, tool, X)
    err = pose_error(X, T, inv_size, e)
    lam = 0.0
    for _ in range(STEPS):
        if err <= STOP:
            break
        jacobian_and_bias(table, modified, F, X[:3, 3], zero, J, jd)
        for r in range(3):
            for c in range(n):
                J[r, c] *= inv_size
        for a in range(n):
            g[a] = 0.0
            for r in range(6):
                g[a] += J[r, a] * e[r]
            for b in range(n):
                acc = 0.0
                for r in range(6):
                    acc += J[r, a] * J[r, b]
                A[a, b] = acc
        improved = False
        for _ in range(8):
            M[:, :] = A
            for a in range(n):
                M[a, a] += lam * (1.0 + A[a, a])
            cholesky_solve(M, g, dq)
            for a in range(n):
                trial[a] = q[a] + dq[a]
            frames(table, modified, base, trial, F)
            tool_pose(F, tool, X)
            err_new = pose_error(X, T, inv_size, e_new)
            if err_new < err:
                q[:] = trial
                e[:] = e_new
                err = err_new
                lam = lam * 0.1 if lam > 1e-12 else 0.0
                improved = True
                break
            if err <= CONVERGED:  # rounding, not the model, stops it: no damping will help
                break
            lam = max(lam * 10.0, 1e-9)
        if not improved:
            frames(table, modified, base, q, F)
            tool_pose(F, tool, X)
            break
    return err
