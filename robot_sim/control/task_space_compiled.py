"""Compiled (numba) operational-space law for one configuration.

The same algorithm as :meth:`robot_sim.control.task_space.OperationalSpace._law` (the
NumPy code, which stays the reference the tests compare against): the chain walk to the
joint axes and the tool, J and J̇q̇ (the shared chain kernels of ``robot_sim.kernels.chain``), the task error and the log-map rotation command, and
the solve for q̈.  The solve uses the Schur complement of the same KKT system,
``X = M⁻¹ Jᵀ``, ``F = (J X + λ² W⁻²)⁻¹ (a − J̇q̇ − J q̈₀)``, ``q̈ = q̈₀ + X F``, by Cholesky
factorisations.  M and the bias torque come from the compiled dynamics kernels
(``dynamics.compiled``), called from here.

Imported on first use only (numba takes about half a second to import), compiled once per
machine (``cache=True``, the settings of ``robot_sim.kernels.jit``).  ``P`` is the robot's
compiled model table (``robot_sim.kernels.model``).  This module imports numpy, numba, the
compiled dynamics kernels and the kernels layer only.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from robot_sim.dynamics.compiled import crba_batch, rnea_batch
from robot_sim.kernels.algebra import cholesky, cross, euler_combine, rk4_combine, rk4_stage, solve_factored
from robot_sim.kernels.chain import frames, jacobian_and_bias, tool_pose
from robot_sim.kernels.jit import JIT

#: Angle [rad] below which the SO(3) coefficients use their series (as task_error).
SERIES_ANGLE = 0.1
_NEAR_PI_SIN = 1e-3
#: Jacobi eigenvalues: at most this many sweeps (a 6x6 converges in 5-6), stopping once the
#: off-diagonal square sum is below (1e-16)^2 of the matrix's.
JACOBI_SWEEPS = 30
JACOBI_TOL2 = 1e-32


@njit(**JIT)
def _log(R, phi):
    """Rotation vector of R (3, 3) into phi (as transforms.rotation_log)."""
    wx, wy, wz = R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]
    two_sin = math.sqrt(wx * wx + wy * wy + wz * wz)
    cos = 0.5 * (R[0, 0] + R[1, 1] + R[2, 2] - 1.0)
    angle = math.atan2(0.5 * two_sin, cos)
    if two_sin < 1e-12 and cos > 0.0:
        phi[0], phi[1], phi[2] = 0.5 * wx, 0.5 * wy, 0.5 * wz
        return
    if two_sin > _NEAR_PI_SIN or cos > 0.0:
        f = angle / two_sin
        phi[0], phi[1], phi[2] = f * wx, f * wy, f * wz
        return
    best, i = -1.0, 0
    for k in range(3):
        kk = (R[k, k] - cos) / (1.0 - cos)
        if kk > best:
            best, i = kk, k
    axis = np.empty(3)
    for k in range(3):
        axis[k] = (0.5 * (R[k, i] + R[i, k]) - (cos if k == i else 0.0)) / (1.0 - cos)
    norm = math.sqrt(axis[0] ** 2 + axis[1] ** 2 + axis[2] ** 2)
    sign = -1.0 if axis[0] * wx + axis[1] * wy + axis[2] * wz < 0.0 else 1.0
    for k in range(3):
        phi[k] = sign * angle * axis[k] / norm


@njit(**JIT)
def _coefficients(t):
    if t < SERIES_ANGLE:
        t2 = t * t
        t4 = t2 * t2
        return (0.5 - t2 / 24.0 + t4 / 720.0, 1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0,
                1.0 / 12.0 + t2 / 720.0 + t4 / 30240.0, -1.0 / 12.0 + t2 / 180.0 - t4 / 6720.0,
                -1.0 / 60.0 + t2 / 1260.0 - t4 / 60480.0)
    s, c = math.sin(t), math.cos(t)
    t2 = t * t
    return ((1.0 - c) / t2, (t - s) / (t2 * t), 1.0 / t2 - (1.0 + c) / (2.0 * t * s),
            (t * s - 2.0 * (1.0 - c)) / (t2 * t2), ((1.0 - c) * t - 3.0 * (t - s)) / (t2 * t2 * t))


@njit(**JIT)
def _mv(A, x, out):
    """out = A x by loops (BLAS costs more than the product at these sizes)."""
    for i in range(A.shape[0]):
        acc = 0.0
        for k in range(A.shape[1]):
            acc += A[i, k] * x[k]
        out[i] = acc


@njit(**JIT)
def _cr(a, b):
    """a × b of two (3,) arrays as an array."""
    return np.array(cross(a, b))


@njit(**JIT)
def _rotation_command(Re, phi, omega, omega_d, alpha_d, kp, kd, out):
    """ω̇ into out (as task_error._rotation_command)."""
    a, b, c, da, db = _coefficients(math.sqrt(phi[0] ** 2 + phi[1] ** 2 + phi[2] ** 2))
    rw = np.empty(3)
    _mv(Re, omega, rw)
    we = omega_d - rw
    p_w = _cr(phi, we)
    phi_dot = we - 0.5 * p_w + c * _cr(phi, p_w)
    f = -kd * phi_dot - kp * phi
    p_f = _cr(phi, f)
    p_d = _cr(phi, phi_dot)
    rate = phi[0] * phi_dot[0] + phi[1] * phi_dot[1] + phi[2] * phi_dot[2]
    rhs = alpha_d - _cr(we, rw) - (f + a * p_f + b * _cr(phi, p_f)) \
        - (rate * da * p_d + rate * db * _cr(phi, p_d) + b * _cr(phi_dot, p_d))
    for k in range(3):
        out[k] = Re[0, k] * rhs[0] + Re[1, k] * rhs[1] + Re[2, k] * rhs[2]


@njit(**JIT)
def _smallest_eigenvalue(W):
    """The smallest eigenvalue of the symmetric matrix W (overwritten), by cyclic Jacobi
    rotations (Golub & Van Loan, Matrix Computations, §8.5) until the off-diagonal part is
    below round-off: the task matrix has at most six rows, and numba's ``np.linalg`` needs
    SciPy's LAPACK, which is not a dependency."""
    m = W.shape[0]
    for _ in range(JACOBI_SWEEPS):
        off = 0.0
        diag = 0.0
        for p in range(m):
            diag += W[p, p] * W[p, p]
            for r in range(p + 1, m):
                off += W[p, r] * W[p, r]
        if not off > JACOBI_TOL2 * (diag + off):
            break
        for p in range(m - 1):
            for r in range(p + 1, m):
                if W[p, r] == 0.0:
                    continue
                theta = (W[r, r] - W[p, p]) / (2.0 * W[p, r])
                t = (1.0 if theta >= 0.0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(m):  # W J: columns p and r
                    wp, wr = W[k, p], W[k, r]
                    W[k, p], W[k, r] = c * wp - s * wr, s * wp + c * wr
                for k in range(m):  # Jᵀ (W J): rows p and r
                    wp, wr = W[p, k], W[r, k]
                    W[p, k], W[r, k] = c * wp - s * wr, s * wp + c * wr
    low = W[0, 0]
    for p in range(1, m):
        low = min(low, W[p, p])
    return low


@njit(**JIT)
def osc_one(P, modified, base, tool, rows, weights, q, qd, Td, Vd, Ad, M, qdd0, kp, kd, lam2, eps, qdd, task, e):
    """The OSC law at (q, q̇): q̈ into ``qdd``, τ − b = M q̈ into ``task``, the task error
    into ``e`` (m,); returns λ² (computed from W J M⁻¹ Jᵀ W when ``lam2`` < 0, else
    ``lam2``), or NaN when an input is not finite or the system cannot be solved."""
    for v in (q, qd, Vd, Ad, qdd0):
        for x in v:
            if not math.isfinite(x):
                return math.nan
    for r in range(4):
        for k in range(4):
            if not math.isfinite(Td[r, k]):
                return math.nan
    return _law(P, modified, base, tool, rows, weights, q, qd, Td, Vd, Ad, M, qdd0, kp, kd, lam2, eps, qdd, task, e)


@njit(**JIT)
def _law(P, modified, base, tool, rows, weights, q, qd, Td, Vd, Ad, M, qdd0, kp, kd, lam2, eps, qdd, task, e):
    """:func:`osc_one` without the input checks."""
    n, m = P.shape[0], rows.shape[0]
    chain, T = np.empty((n + 1, 3, 4)), np.empty((4, 4))
    frames(P, modified, base, q, chain)
    tool_pose(chain, tool, T)
    J, jd = np.empty((6, n)), np.empty(6)
    jacobian_and_bias(P, modified, chain, T[:3, 3], qd, J, jd)
    twist = np.empty(6)
    _mv(J, qd, twist)
    accel = np.empty(6)
    err = np.empty(6)
    for k in range(3):
        err[k] = Td[k, 3] - T[k, 3]
        accel[k] = Ad[k] + kd * (Vd[k] - twist[k]) + kp * err[k]
    if m == 6:
        Re = np.empty((3, 3))
        for r in range(3):
            for k in range(3):
                Re[r, k] = Td[r, 0] * T[k, 0] + Td[r, 1] * T[k, 1] + Td[r, 2] * T[k, 2]  # R_d Rᵀ
        phi = np.empty(3)
        _log(Re, phi)
        err[3:] = phi
        out = np.empty(3)
        _rotation_command(Re, phi, twist[3:].copy(), Vd[3:].copy(), Ad[3:].copy(), kp, kd, out)
        accel[3:] = out
    Jr = np.empty((m, n))
    goal = np.empty(m)
    for i in range(m):
        Jr[i, :] = J[rows[i], :]
        e[i] = err[rows[i]]
        acc = 0.0
        for j in range(n):
            acc += J[rows[i], j] * qdd0[j]
        goal[i] = accel[rows[i]] - jd[rows[i]] - acc
    L = M.copy()
    if not cholesky(L):
        return math.nan
    X = np.empty((n, m))
    col = np.empty(n)
    for i in range(m):
        solve_factored(L, Jr[i], col)
        X[:, i] = col
    S = np.empty((m, m))
    for i in range(m):
        for k in range(m):
            acc = 0.0
            for j in range(n):
                acc += Jr[i, j] * X[j, k]
            S[i, k] = acc
    if lam2 < 0.0:
        W = np.empty((m, m))
        for i in range(m):
            for k in range(m):
                W[i, k] = S[i, k] * weights[i] * weights[k]
            W[i, i] -= eps
        if cholesky(W):  # s_min > ε: no damping, without the eigenvalues (the usual case)
            lam2 = 0.0
        else:
            for i in range(m):
                for k in range(m):
                    W[i, k] = S[i, k] * weights[i] * weights[k]
            lam2 = max(eps - _smallest_eigenvalue(W), 0.0)
    for i in range(m):
        S[i, i] += lam2 / (weights[i] * weights[i])
    if not cholesky(S):
        return math.nan
    F = np.empty(m)
    solve_factored(S, goal, F)
    for j in range(n):
        acc = qdd0[j]
        for i in range(m):
            acc += X[j, i] * F[i]
        qdd[j] = acc
    _mv(M, qdd, task)
    return lam2


@njit(**JIT)
def osc_step(P, g0, limit, check, modified, base, tool, rows, weights, rk4, h, q, qd, TD, VD, AD, POST,
             use_posture, kp, kd, eps, lo, hi, q1, qd1, a1, tau, e):
    """One integration step of the OSC closed loop from (q, q̇), the law evaluated at every
    stage on the desired values at the stage's time: TD (3, 4, 4), VD, AD (3, 6) at the
    step's start, middle and end, and the posture's (q_d, q̇_d, q̈_d) there, POST (3, 3, n)
    (used when ``use_posture``).  Semi-implicit Euler (``rk4`` False) or classical RK4 as
    ``Simulation`` does them.  Writes (q, q̇) after
    the step into q1, qd1, the start's acceleration into a1, its effort (τ = M q̈ + b) into
    tau and its task error into e.  ``P``, ``g0``: the dynamics kernels' table and frame-0
    gravity (``dynamics.compiled_kernels``).  Returns 0, 1 when an input or a stage is not finite or
    cannot be solved, 2 when a stage's effort exceeds ``limit`` (n,) (the caller then
    saturates it step by step; checked only when ``check``), 3 when the step ends beyond
    the joint limits ``lo``, ``hi`` (n,) (the caller resolves the stops)."""
    n = P.shape[0]
    for v in (q, qd):
        for x in v:
            if not math.isfinite(x):
                return 1
    for x in TD.ravel():
        if not math.isfinite(x):
            return 1
    for x in VD.ravel():
        if not math.isfinite(x):
            return 1
    for x in AD.ravel():
        if not math.isfinite(x):
            return 1
    for x in POST.ravel():
        if not math.isfinite(x):
            return 1
    Q, QDs = np.empty((1, n)), np.empty((1, n))
    MM, TAU, ZERO = np.empty((1, n, n)), np.empty((1, n)), np.zeros((1, n))
    FEXT = np.zeros((1, 6))
    qdd0, task, err = np.empty(n), np.empty(n), np.empty(rows.shape[0])
    stages = 4 if rk4 else 1
    times = (0, 1, 1, 2)
    qs, vs = q.copy(), qd.copy()
    acc = np.empty((4, n))
    lam2 = -1.0
    for k in range(stages):
        if k > 0:  # stage state: v_k = v + step·a_{k−1}, q_k = q + step·v_{k−1}
            rk4_stage(h if k == 3 else 0.5 * h, q, qd, acc[k - 1], qd if k == 1 else vs, qs, vs)
        i = times[k]
        for j in range(n):
            qdd0[j] = (POST[i, 2, j] + kp * (POST[i, 0, j] - qs[j]) + kd * (POST[i, 1, j] - vs[j])) if use_posture else 0.0
        Q[0, :], QDs[0, :] = qs, vs
        crba_batch(P, Q, MM)
        lam2 = _law(P, modified, base, tool, rows, weights, qs, vs, TD[i], VD[i], AD[i], MM[0], qdd0, kp, kd,
                    lam2, eps, acc[k], task, err)
        if math.isnan(lam2):
            return 1
        if k == 0 or check:
            rnea_batch(P, Q, QDs, ZERO, g0, FEXT, False, TAU)
        for j in range(n):
            effort = task[j] + TAU[0, j]
            if not math.isfinite(effort) or not math.isfinite(acc[k, j]):
                return 1
            if check and abs(effort) > limit[j]:
                return 2
            if k == 0:
                tau[j] = effort
        if k == 0:
            e[:] = err
    a1[:] = acc[0]
    if rk4:
        rk4_combine(h, q, qd, acc[0], acc[1], acc[2], acc[3], q1, qd1)
    else:
        euler_combine(h, q, qd, acc[0], q1, qd1)
    for j in range(n):
        if q1[j] < lo[j] or q1[j] > hi[j]:
            return 3
    return 0
