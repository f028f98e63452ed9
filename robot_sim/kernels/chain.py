"""The compiled chain: world frames of one configuration, the tool pose, and the geometric
Jacobian with J̇q̇ — the one forward-kinematics kernel of the compiled code (collision,
task-space control and the physics loop's pull call it).

Inputs: the compiled model's table ``T`` (n, NCOL) and convention ``modified``
(:mod:`robot_sim.kernels.model`), frame 0 in the world ``base`` (4, 4), the joint vector
q (n,) [rad or m].  Frames are written as (n + 1, 3, 4) [rotation | origin] rows, frame 0
first.  Standard DH: A = Rz(θ) Tz(d) Tx(a) Rx(α), joint j about z of frame j − 1;
modified DH: A = Rx(α) Tx(a) Rz(θ) Tz(d), joint j about z of frame j.  Jacobians are
[linear; angular] in the world frame, the linear part at the point ``pe``.
"""
from __future__ import annotations

import numpy as np

from robot_sim.kernels.algebra import cos_sin
from robot_sim.kernels.jit import INLINE, JIT, njit
from robot_sim.kernels.model import A, CA, D, REV, SA, TH


@njit(**JIT)
def frames(T, modified, base, q, F):
    """World frames 0..n of q into F (n + 1, 3, 4)."""
    _base(base, F)
    for j in range(T.shape[0]):
        rev = T[j, REV] != 0.0
        th = T[j, TH] + q[j] if rev else T[j, TH]
        c, s = cos_sin(th)
        _next_frame(T, modified, q, j, c, s, F)


@njit(**INLINE)
def frames_cs(T, modified, base, q, CS, F):
    """:func:`frames` with cos θ_j, sin θ_j at q given in CS (n, 2) (as
    ``dynamics.compiled.geometry`` leaves them): the same frames, without computing them
    again."""
    _base(base, F)
    for j in range(T.shape[0]):
        _next_frame(T, modified, q, j, CS[j, 0], CS[j, 1], F)


@njit(**INLINE)
def _base(base, F):
    """Frame 0: ``base``'s top three rows."""
    for r in range(3):
        for c in range(4):
            F[0, r, c] = base[r, c]


@njit(**INLINE)
def _next_frame(T, modified, q, j, c, s, F):
    """Frame j + 1 from frame j into F, with c, s the cosine and sine of θ_j at q."""
    rev = T[j, REV] != 0.0
    d = T[j, D] if rev else T[j, D] + q[j]
    ca, sa, a = T[j, CA], T[j, SA], T[j, A]
    for k in range(3):
        X, Y, Z, P = F[j, k, 0], F[j, k, 1], F[j, k, 2], F[j, k, 3]
        if modified:  # twist about x, slide a along x, turn about the new z, slide d along it
            y, z = ca * Y + sa * Z, ca * Z - sa * Y
            P += a * X
            x, y = c * X + s * y, c * y - s * X
            P += d * z
        else:  # turn about z, slide d along z and a along the new x, twist about it
            x, y = c * X + s * Y, c * Y - s * X
            P += d * Z + a * x
            y, z = ca * y + sa * Z, ca * Z - sa * y
        F[j + 1, k, 0], F[j + 1, k, 1], F[j + 1, k, 2], F[j + 1, k, 3] = x, y, z, P


@njit(**JIT)
def tool_pose(F, tool, out):
    """The tool frame (4, 4) into ``out``: frame n of F times ``tool`` (4, 4)."""
    n = F.shape[0] - 1
    for r in range(3):
        X, Y, Z = F[n, r, 0], F[n, r, 1], F[n, r, 2]
        for k in range(3):
            out[r, k] = X * tool[0, k] + Y * tool[1, k] + Z * tool[2, k]
        out[r, 3] = F[n, r, 3] + X * tool[0, 3] + Y * tool[1, 3] + Z * tool[2, 3]
        out[3, r] = 0.0
    out[3, 3] = 1.0


@njit(**JIT)
def jacobian_and_bias(T, modified, F, pe, qd, J, jd):
    """The geometric Jacobian J (6, n) at the world point ``pe`` (3,) and J̇q̇ (6,) into
    ``jd`` at joint rates qd (n,), from the frames F of :func:`frames`.  Joint j's axis is
    z of frame j (standard DH) or j + 1 (modified), through that frame's origin."""
    n = T.shape[0]
    shift = 1 if modified else 0
    wx = wy = wz = cx = cy = cz = 0.0
    U = np.empty((n, 3))
    DU = np.empty((n, 3))
    PD = np.empty((n, 3))
    for j in range(n):
        f = j + shift
        ux, uy, uz = F[f, 0, 2] * qd[j], F[f, 1, 2] * qd[j], F[f, 2, 2] * qd[j]
        px, py, pz = F[f, 0, 3], F[f, 1, 3], F[f, 2, 3]
        U[j, 0], U[j, 1], U[j, 2] = ux, uy, uz
        DU[j, 0], DU[j, 1], DU[j, 2] = wy * uz - wz * uy, wz * ux - wx * uz, wx * uy - wy * ux
        PD[j, 0], PD[j, 1], PD[j, 2] = wy * pz - wz * py + cx, wz * px - wx * pz + cy, wx * py - wy * px + cz
        if T[j, REV] != 0.0:
            wx, wy, wz = wx + ux, wy + uy, wz + uz
            cx, cy, cz = cx - (uy * pz - uz * py), cy - (uz * px - ux * pz), cz - (ux * py - uy * px)
        else:
            cx, cy, cz = cx + ux, cy + uy, cz + uz
    ex, ey, ez = pe[0], pe[1], pe[2]
    vx, vy, vz = wy * ez - wz * ey + cx, wz * ex - wx * ez + cy, wx * ey - wy * ex + cz
    for k in range(6):
        jd[k] = 0.0
    for j in range(n):
        f = j + shift
        zx, zy, zz = F[f, 0, 2], F[f, 1, 2], F[f, 2, 2]
        dx, dy, dz = DU[j, 0], DU[j, 1], DU[j, 2]
        if T[j, REV] != 0.0:
            lx, ly, lz = ex - F[f, 0, 3], ey - F[f, 1, 3], ez - F[f, 2, 3]
            J[0, j], J[1, j], J[2, j] = zy * lz - zz * ly, zz * lx - zx * lz, zx * ly - zy * lx
            J[3, j], J[4, j], J[5, j] = zx, zy, zz
            rx, ry, rz = vx - PD[j, 0], vy - PD[j, 1], vz - PD[j, 2]
            ux, uy, uz = U[j, 0], U[j, 1], U[j, 2]
            jd[0] += dy * lz - dz * ly + uy * rz - uz * ry
            jd[1] += dz * lx - dx * lz + uz * rx - ux * rz
            jd[2] += dx * ly - dy * lx + ux * ry - uy * rx
            jd[3] += dx
            jd[4] += dy
            jd[5] += dz
        else:
            J[0, j], J[1, j], J[2, j] = zx, zy, zz
            J[3, j] = J[4, j] = J[5, j] = 0.0
            jd[0] += dx
            jd[1] += dy
            jd[2] += dz
