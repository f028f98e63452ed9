"""Compiled (numba) kernels of the rigid-body dynamics: RNEA, CRBA, forward dynamics by a
Cholesky solve (with joints locked on request), computed torque.  The physics loop's
step over these is :mod:`robot_sim.sim.step_kernels`.

The same algorithms as the readable recursion in ``dynamics`` (which stays the reference
the tests compare against), written as scalar code over one configuration and compiled
once per machine (``cache=True``: later processes load the machine code from
``__pycache__``).  A batch of N configurations is N calls of the same one-configuration
code, so a batched result equals the one-configuration result bit for bit: a
``BatchSimulation`` of n arms is n ``Simulation``\\ s, exactly.

Inputs are plain arrays: the robot is its compiled model's table ``P`` (n, NCOL) of
:mod:`robot_sim.kernels.model` (named columns; link quantities in each link's own DH
frame, inertia about the frame origin; column ``MOD`` says the DH convention).
Gravity ``g0`` (3,) [m/s²] is given in frame 0; an external wrench ``fext`` (6,) [N; N·m]
on the last link acts about its frame origin, in its frame.  Units are SI throughout.

This module imports nothing of the project but the kernels layer (:mod:`robot_sim.kernels`:
the model's columns, numba's settings, sin/cos, the cross product and the Cholesky solve).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from robot_sim.kernels.algebra import cholesky_solve, cos_sin, cross
from robot_sim.kernels.jit import INLINE, JIT
from robot_sim.kernels.model import (
    CA, CNEG, CPOS, HX, HY, HZ, IXX, IXY, IXZ, IYY, IYZ, IZZ, MASS, MOD, REFL, REV, SA, SVX, SVY, SVZ,
    SWX, SWY, SWZ, TH, VISC, A, D,
)




# ------------------------------------------------------------------ 3-vector algebra


@njit(**INLINE)
def _rz(x, y, z, c, s):
    return c * x - s * y, s * x + c * y, z


@njit(**INLINE)
def _rz_t(x, y, z, c, s):
    return c * x + s * y, c * y - s * x, z


@njit(**INLINE)
def _rx(x, y, z, c, s):
    return x, c * y - s * z, s * y + c * z


@njit(**INLINE)
def _rx_t(x, y, z, c, s):
    return x, c * y + s * z, c * z - s * y


@njit(**INLINE)
def _to_child(modified, x, y, z, c, s, ca, sa):
    """Vector in frame j−1 expressed in frame j (Rᵀ v)."""
    if modified:
        x, y, z = _rx_t(x, y, z, ca, sa)
        return _rz_t(x, y, z, c, s)
    x, y, z = _rz_t(x, y, z, c, s)
    return _rx_t(x, y, z, ca, sa)


@njit(**INLINE)
def _to_parent(modified, x, y, z, c, s, ca, sa):
    """Vector in frame j expressed in frame j−1 (R v)."""
    if modified:
        x, y, z = _rz(x, y, z, c, s)
        return _rx(x, y, z, ca, sa)
    x, y, z = _rx(x, y, z, ca, sa)
    return _rz(x, y, z, c, s)


@njit(**INLINE)
def _sym_mv(xx, yy, zz, xy, yz, xz, x, y, z):
    """Symmetric matrix (xx, yy, zz, xy, yz, xz) times (x, y, z)."""
    return xx * x + xy * y + xz * z, xy * x + yy * y + yz * z, xz * x + yz * y + zz * z


@njit(**INLINE)
def _rot_sym_z(xx, yy, zz, xy, yz, xz, c, s):
    """Rz(θ) S Rz(θ)ᵀ."""
    c2, s2 = c * c - s * s, 2.0 * c * s
    mean, half = 0.5 * (xx + yy), 0.5 * (xx - yy)
    t = half * c2 - xy * s2
    return mean + t, mean - t, zz, half * s2 + xy * c2, s * xz + c * yz, c * xz - s * yz


@njit(**INLINE)
def _rot_sym_x(xx, yy, zz, xy, yz, xz, c, s):
    """Rx(α) S Rx(α)ᵀ."""
    c2, s2 = c * c - s * s, 2.0 * c * s
    mean, half = 0.5 * (yy + zz), 0.5 * (yy - zz)
    t = half * c2 - yz * s2
    return xx, mean + t, mean - t, c * xy - s * xz, half * s2 + yz * c2, s * xy + c * xz


# ------------------------------------------------------------------ chain geometry


@njit(**JIT)
def geometry(P, modified, q, O, CS):
    """Offsets O[j] (origin j from origin j−1: in frame j for standard DH, in frame j−1
    for modified) and cos/sin of θ_j into CS[j]."""
    for j in range(P.shape[0]):
        rev = P[j, REV] != 0.0
        th = P[j, TH] + q[j] if rev else P[j, TH]
        d = P[j, D] if rev else P[j, D] + q[j]
        CS[j, 0], CS[j, 1] = cos_sin(th)
        O[j, 0] = P[j, A]
        O[j, 1] = (-P[j, SA] if modified else P[j, SA]) * d
        O[j, 2] = P[j, CA] * d


@njit(**INLINE)
def _wrench_to_parent(modified, fx, fy, fz, nx, ny, nz, c, s, ca, sa, px, py, pz):
    """Force f and moment n about origin j (frame j) → about origin j−1, in frame j−1."""
    if modified:
        fx, fy, fz = _to_parent(True, fx, fy, fz, c, s, ca, sa)
        nx, ny, nz = _to_parent(True, nx, ny, nz, c, s, ca, sa)
        mx, my, mz = cross((px, py, pz), (fx, fy, fz))
        return fx, fy, fz, nx + mx, ny + my, nz + mz
    mx, my, mz = cross((px, py, pz), (fx, fy, fz))
    nx, ny, nz = _to_parent(False, nx + mx, ny + my, nz + mz, c, s, ca, sa)
    fx, fy, fz = _to_parent(False, fx, fy, fz, c, s, ca, sa)
    return fx, fy, fz, nx, ny, nz


# ------------------------------------------------------------------ one configuration


@njit(**JIT)
def rnea_one(P, modified, qd, qdd, g0, fext, use_ext, tau, O, CS, F, NM):
    """τ (n,) into ``tau``: rigid bodies by Newton–Euler plus the drive terms
    G²Jm q̈ + G²B q̇ + |G|Tc±.  O, CS: :func:`geometry` of q; work arrays F, NM (n, 3)."""
    n = P.shape[0]
    wx = wy = wz = 0.0
    dx = dy = dz = 0.0
    ax, ay, az = -g0[0], -g0[1], -g0[2]
    W00 = W01 = W02 = W10 = W11 = W12 = W20 = W21 = W22 = 0.0
    for j in range(n):
        rev = P[j, REV] != 0.0
        c, s, ca, sa = CS[j, 0], CS[j, 1], P[j, CA], P[j, SA]
        px, py, pz = O[j, 0], O[j, 1], O[j, 2]
        v, acc = qd[j], qdd[j]
        if modified:
            ax, ay, az = ax + W00 * px + W01 * py + W02 * pz, ay + W10 * px + W11 * py + W12 * pz, az + W20 * px + W21 * py + W22 * pz
            wx, wy, wz = _to_child(True, wx, wy, wz, c, s, ca, sa)
            dx, dy, dz = _to_child(True, dx, dy, dz, c, s, ca, sa)
            ax, ay, az = _to_child(True, ax, ay, az, c, s, ca, sa)
            if rev:
                dx, dy, dz = dx + wy * v, dy - wx * v, dz + acc
                wz = wz + v
            else:
                ax, ay, az = ax + 2.0 * wy * v, ay - 2.0 * wx * v, az + acc
        else:
            if rev:
                dx, dy, dz = dx + wy * v, dy - wx * v, dz + acc
                wz = wz + v
            else:
                ax, ay, az = ax + 2.0 * wy * v, ay - 2.0 * wx * v, az + acc
            wx, wy, wz = _to_child(False, wx, wy, wz, c, s, ca, sa)
            dx, dy, dz = _to_child(False, dx, dy, dz, c, s, ca, sa)
            ax, ay, az = _to_child(False, ax, ay, az, c, s, ca, sa)
        xx, yy, zz, xy, yz, xz = wx * wx, wy * wy, wz * wz, wx * wy, wy * wz, wx * wz
        W00, W01, W02 = -(yy + zz), xy - dz, xz + dy
        W10, W11, W12 = xy + dz, -(xx + zz), yz - dx
        W20, W21, W22 = xz - dy, yz + dx, -(xx + yy)
        if not modified:
            ax, ay, az = ax + W00 * px + W01 * py + W02 * pz, ay + W10 * px + W11 * py + W12 * pz, az + W20 * px + W21 * py + W22 * pz
        m, hx, hy, hz = P[j, MASS], P[j, HX], P[j, HY], P[j, HZ]
        F[j, 0] = m * ax + W00 * hx + W01 * hy + W02 * hz
        F[j, 1] = m * ay + W10 * hx + W11 * hy + W12 * hz
        F[j, 2] = m * az + W20 * hx + W21 * hy + W22 * hz
        ixx, iyy, izz, ixy, iyz, ixz = P[j, IXX], P[j, IYY], P[j, IZZ], P[j, IXY], P[j, IYZ], P[j, IXZ]
        lx, ly, lz = _sym_mv(ixx, iyy, izz, ixy, iyz, ixz, wx, wy, wz)
        gx, gy, gz = _sym_mv(ixx, iyy, izz, ixy, iyz, ixz, dx, dy, dz)
        cx, cy, cz = cross((wx, wy, wz), (lx, ly, lz))
        ex, ey, ez = cross((hx, hy, hz), (ax, ay, az))
        NM[j, 0], NM[j, 1], NM[j, 2] = gx + cx + ex, gy + cy + ey, gz + cz + ez
    if use_ext:
        for k in range(3):
            F[n - 1, k] -= fext[k]
            NM[n - 1, k] -= fext[3 + k]
    for j in range(n - 1, -1, -1):
        fx, fy, fz, nx, ny, nz = F[j, 0], F[j, 1], F[j, 2], NM[j, 0], NM[j, 1], NM[j, 2]
        px, py, pz = O[j, 0], O[j, 1], O[j, 2]
        ca, sa = P[j, CA], P[j, SA]
        rev = P[j, REV] != 0.0
        if modified:
            t = nz if rev else fz
        elif rev:
            mx, my, mz = cross((px, py, pz), (fx, fy, fz))
            t = sa * (ny + my) + ca * (nz + mz)
        else:
            t = sa * fy + ca * fz
        v = qd[j]
        friction = P[j, CPOS] if v > 0.0 else (P[j, CNEG] if v < 0.0 else 0.0)
        tau[j] = t + (P[j, REFL] * qdd[j] + (P[j, VISC] * v + friction))
        if j > 0:
            fx, fy, fz, nx, ny, nz = _wrench_to_parent(modified, fx, fy, fz, nx, ny, nz, CS[j, 0], CS[j, 1], ca, sa, px, py, pz)
            F[j - 1, 0] += fx
            F[j - 1, 1] += fy
            F[j - 1, 2] += fz
            NM[j - 1, 0] += nx
            NM[j - 1, 1] += ny
            NM[j - 1, 2] += nz


@njit(**JIT)
def crba_one(P, modified, M, O, CS):
    """M(q) (n, n) into ``M``: composite rigid bodies plus G²Jm on the diagonal (O, CS:
    :func:`geometry` of q)."""
    n = P.shape[0]
    cm = 0.0
    chx = chy = chz = 0.0
    cxx = cyy = czz = cxy = cyz = cxz = 0.0
    for j in range(n - 1, -1, -1):
        cm += P[j, MASS]
        chx, chy, chz = chx + P[j, HX], chy + P[j, HY], chz + P[j, HZ]
        cxx, cyy, czz = cxx + P[j, IXX], cyy + P[j, IYY], czz + P[j, IZZ]
        cxy, cyz, cxz = cxy + P[j, IXY], cyz + P[j, IYZ], cxz + P[j, IXZ]
        vx, vy, vz, ux, uy, uz = P[j, SVX], P[j, SVY], P[j, SVZ], P[j, SWX], P[j, SWY], P[j, SWZ]
        kx, ky, kz = cross((chx, chy, chz), (ux, uy, uz))
        fx, fy, fz = cm * vx - kx, cm * vy - ky, cm * vz - kz
        ix, iy, iz = _sym_mv(cxx, cyy, czz, cxy, cyz, cxz, ux, uy, uz)
        kx, ky, kz = cross((chx, chy, chz), (vx, vy, vz))
        nx, ny, nz = ix + kx, iy + ky, iz + kz
        M[j, j] = (vx * fx + vy * fy + vz * fz) + (ux * nx + uy * ny + uz * nz) + P[j, REFL]
        for k in range(j, 0, -1):
            fx, fy, fz, nx, ny, nz = _wrench_to_parent(
                modified, fx, fy, fz, nx, ny, nz, CS[k, 0], CS[k, 1], P[k, CA], P[k, SA], O[k, 0], O[k, 1], O[k, 2]
            )
            i = k - 1
            bx, by, bz, ex, ey, ez = P[i, SVX], P[i, SVY], P[i, SVZ], P[i, SWX], P[i, SWY], P[i, SWZ]
            value = (bx * fx + by * fy + bz * fz) + (ex * nx + ey * ny + ez * nz)
            M[k - 1, j] = value
            M[j, k - 1] = value
        if j > 0:
            c, s, ca, sa = CS[j, 0], CS[j, 1], P[j, CA], P[j, SA]
            px, py, pz = O[j, 0], O[j, 1], O[j, 2]
            if modified:
                chx, chy, chz = _to_parent(True, chx, chy, chz, c, s, ca, sa)
                cxx, cyy, czz, cxy, cyz, cxz = _rot_sym_z(cxx, cyy, czz, cxy, cyz, cxz, c, s)
                cxx, cyy, czz, cxy, cyz, cxz = _rot_sym_x(cxx, cyy, czz, cxy, cyz, cxz, ca, sa)
            # shift about origin j−1: I + 2(h·r)1 − (r hᵀ + h rᵀ) + m(|r|² 1 − r rᵀ), r = p
            hr = chx * px + chy * py + chz * pz
            diag = 2.0 * hr + cm * (px * px + py * py + pz * pz)
            cxx = cxx - (2.0 * px * chx + cm * px * px) + diag
            cyy = cyy - (2.0 * py * chy + cm * py * py) + diag
            czz = czz - (2.0 * pz * chz + cm * pz * pz) + diag
            cxy = cxy - (px * chy + chx * py + cm * px * py)
            cyz = cyz - (py * chz + chy * pz + cm * py * pz)
            cxz = cxz - (px * chz + chx * pz + cm * px * pz)
            chx, chy, chz = chx + cm * px, chy + cm * py, chz + cm * pz
            if not modified:
                chx, chy, chz = _to_parent(False, chx, chy, chz, c, s, ca, sa)
                cxx, cyy, czz, cxy, cyz, cxz = _rot_sym_x(cxx, cyy, czz, cxy, cyz, cxz, ca, sa)
                cxx, cyy, czz, cxy, cyz, cxz = _rot_sym_z(cxx, cyy, czz, cxy, cyz, cxz, c, s)


@njit(**JIT)
def fd_one(P, modified, q, qd, tau, g0, fext, use_ext, held, use_held, out, react, zero, bias, M, O, CS, F, NM, posed):
    """q̈ = M⁻¹ (τ − C q̇ − g − τ_f + ext) into ``out`` (O, CS: :func:`geometry` of q,
    computed here unless ``posed``, when the caller did).  With ``use_held``, the joints j with
    ``held[j]`` are locked: their rows and columns of M are replaced by the identity's and
    their right-hand side by 0, so q̈_j = 0 exactly, and their reaction
    λ_j = (M q̈ − (τ − C q̇ − g − τ_f + ext))_j goes into ``react`` (0.0 elsewhere; ``react``
    is not touched without ``use_held``)."""
    if not posed:
        geometry(P, modified, q, O, CS)
    rnea_one(P, modified, qd, zero, g0, fext, use_ext, bias, O, CS, F, NM)
    n = P.shape[0]
    for j in range(n):
        bias[j] = tau[j] - bias[j]
    crba_one(P, modified, M, O, CS)
    if not use_held:
        cholesky_solve(M, bias, out)
        return
    for j in range(n):  # lock in the lower triangle only: the solve reads nothing else
        react[j] = 0.0
        if held[j]:
            react[j] = -bias[j]
            bias[j] = 0.0
            for k in range(j):
                M[j, k] = 0.0
            for k in range(j + 1, n):
                M[k, j] = 0.0
            M[j, j] = 1.0
    cholesky_solve(M, bias, out)
    for j in range(n):  # the strict upper triangle still holds M
        if held[j]:
            out[j] = 0.0
            acc = react[j]
            for k in range(j):
                acc += M[k, j] * out[k]
            for k in range(j + 1, n):
                acc += M[j, k] * out[k]
            react[j] = acc


@njit(**INLINE)
def all_finite(x):
    """True if every entry of the vector x is finite."""
    for v in x:
        if not math.isfinite(v):
            return False
    return True


@njit(**INLINE)
def ct_one(P, modified, q, qd, q_des, qd_des, qdd_des, kp, kd, g0, tau, qdd_ref, O, CS, F, NM):
    """Computed torque: q̈_ref = q̈_des + kp (q_des − q) + kd (q̇_des − q̇) into ``qdd_ref``
    (the operations and their order of NumPy's ``qdd_des + kp * (q_des - q) + kd * (qd_des - qd)``)
    and τ = ID(q, q̇, q̈_ref) into ``tau``."""
    for j in range(P.shape[0]):
        qdd_ref[j] = (qdd_des[j] + kp * (q_des[j] - q[j])) + kd * (qd_des[j] - qd[j])
    geometry(P, modified, q, O, CS)
    rnea_one(P, modified, qd, qdd_ref, g0, O[0], False, tau, O, CS, F, NM)


@njit("b1(f8[:, ::1], f8[::1], f8[::1], f8[::1], f8[::1], f8[::1], f8, f8, f8[::1], f8[::1], f8[::1])", **JIT)
def ct_vec(P, q, qd, q_des, qd_des, qdd_des, kp, kd, g0, tau, qdd_ref):
    """:func:`ct_one` for one configuration; False (nothing computed) unless every vector
    has n entries (g0 3) and the state and reference are finite."""
    modified = P[0, MOD] != 0.0
    n = P.shape[0]
    for x in (q, qd, q_des, qd_des, qdd_des, tau, qdd_ref):
        if x.shape[0] != n:
            return False
    if g0.shape[0] != 3 or not (all_finite(q) and all_finite(qd) and all_finite(q_des) and all_finite(qd_des) and all_finite(qdd_des)):
        return False
    O, CS, F, NM = np.empty((n, 3)), np.empty((n, 2)), np.empty((n, 3)), np.empty((n, 3))
    ct_one(P, modified, q, qd, q_des, qd_des, qdd_des, kp, kd, g0, tau, qdd_ref, O, CS, F, NM)
    return True


# ------------------------------------------------------------------ batches


# Each returns whether every input was finite (the caller names the culprit).


# The one-configuration entry points have explicit signatures: a call with anything but
# C-contiguous float64 vectors raises TypeError in the dispatcher (the caller then takes
# the checked path), and the machine code is loaded from the cache at import.
_VEC_SIGNATURE = "b1(f8[:, ::1], f8[::1], f8[::1], f8[::1], f8[::1], f8[::1])"


@njit(_VEC_SIGNATURE, **JIT)
def rnea_vec(P, q, qd, qdd, g0, tau):
    """τ (n,) into ``tau`` for one configuration q, qd, qdd (n,), no external wrench; False
    (and nothing computed) unless all have n entries, g0 has 3 and every input is finite."""
    modified = P[0, MOD] != 0.0
    n = P.shape[0]
    if not (q.shape[0] == n and qd.shape[0] == n and qdd.shape[0] == n and tau.shape[0] == n and g0.shape[0] == 3):
        return False
    if not (all_finite(q) and all_finite(qd) and all_finite(qdd)):
        return False
    O, CS, F, NM = np.empty((n, 3)), np.empty((n, 2)), np.empty((n, 3)), np.empty((n, 3))
    geometry(P, modified, q, O, CS)
    rnea_one(P, modified, qd, qdd, g0, O[0], False, tau, O, CS, F, NM)
    return True


@njit(_VEC_SIGNATURE, **JIT)
def fd_vec(P, q, qd, tau, g0, qdd):
    """q̈ (n,) into ``qdd`` for one configuration q, qd, τ (n,), no external wrench; False
    as :func:`rnea_vec`."""
    modified = P[0, MOD] != 0.0
    n = P.shape[0]
    if not (q.shape[0] == n and qd.shape[0] == n and tau.shape[0] == n and qdd.shape[0] == n and g0.shape[0] == 3):
        return False
    if not (all_finite(q) and all_finite(qd) and all_finite(tau)):
        return False
    O, CS, F, NM = np.empty((n, 3)), np.empty((n, 2)), np.empty((n, 3)), np.empty((n, 3))
    zero, bias, M = np.zeros(n), np.empty(n), np.empty((n, n))
    no_held = np.zeros(1, dtype=np.bool_)  # not a global: numba would freeze it read-only, another signature of fd_one
    fd_one(P, modified, q, qd, tau, g0, O[0], False, no_held, False, qdd, zero, zero, bias, M, O, CS, F, NM, False)
    return True


@njit(**JIT)
def rnea_batch(P, Q, QD, QDD, g0, FEXT, use_ext, TAU):
    """τ (N, n) into TAU for Q, QD, QDD (N, n); FEXT (N, 6) when ``use_ext``."""
    modified = P[0, MOD] != 0.0
    n = P.shape[0]
    O, CS, F, NM = np.empty((n, 3)), np.empty((n, 2)), np.empty((n, 3)), np.empty((n, 3))
    finite = True
    for i in range(Q.shape[0]):
        geometry(P, modified, Q[i], O, CS)
        rnea_one(P, modified, QD[i], QDD[i], g0, FEXT[i if use_ext else 0], use_ext, TAU[i], O, CS, F, NM)
        finite = finite and all_finite(Q[i]) and all_finite(QD[i]) and all_finite(QDD[i])
    return finite


@njit(**JIT)
def ct_batch(P, Q, QD, QDES, QDDES, QDDDES, KP, KD, g0, TAU, QDDREF):
    """:func:`ct_one` per configuration (gains KP, KD (N,)); finite inputs?"""
    modified = P[0, MOD] != 0.0
    n = P.shape[0]
    O, CS, F, NM = np.empty((n, 3)), np.empty((n, 2)), np.empty((n, 3)), np.empty((n, 3))
    finite = True
    for i in range(Q.shape[0]):
        ct_one(P, modified, Q[i], QD[i], QDES[i], QDDES[i], QDDDES[i], KP[i], KD[i], g0, TAU[i], QDDREF[i], O, CS, F, NM)
        finite = finite and all_finite(Q[i]) and all_finite(QD[i]) and all_finite(QDES[i]) and all_finite(QDDES[i]) and all_finite(QDDDES[i])
    return finite


@njit(**JIT)
def crba_batch(P, Q, MM):
    """M (N, n, n) into MM for Q (N, n)."""
    modified = P[0, MOD] != 0.0
    n = P.shape[0]
    O, CS = np.empty((n, 3)), np.empty((n, 2))
    finite = True
    for i in range(Q.shape[0]):
        geometry(P, modified, Q[i], O, CS)
        crba_one(P, modified, MM[i], O, CS)
        finite = finite and all_finite(Q[i])
    return finite


@njit(**JIT)
def fd_batch(P, Q, QD, TAU, g0, FEXT, use_ext, QDD):
    """q̈ (N, n) into QDD; NaN where M is not positive definite."""
    modified = P[0, MOD] != 0.0
    n = P.shape[0]
    O, CS, F, NM = np.empty((n, 3)), np.empty((n, 2)), np.empty((n, 3)), np.empty((n, 3))
    zero, bias, M = np.zeros(n), np.empty(n), np.empty((n, n))
    no_held = np.zeros(1, dtype=np.bool_)
    finite = True
    for i in range(Q.shape[0]):
        fd_one(P, modified, Q[i], QD[i], TAU[i], g0, FEXT[i if use_ext else 0], use_ext, no_held, False, QDD[i], zero, zero,
                bias, M, O, CS, F, NM, False)
        finite = finite and all_finite(Q[i]) and all_finite(QD[i]) and all_finite(TAU[i])
    return finite
