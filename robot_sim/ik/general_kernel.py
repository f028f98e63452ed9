"""Every real solution of a general 6R arm's pose (compiled): Raghavan and Roth's
elimination, the determinant's real roots, back-substitution and Newton's polish.

Method (Raghavan & Roth, "Inverse kinematics of the general 6R manipulator and related
linkages", ASME J. Mech. Design 115(3), 1993; the matrix form of Manocha & Canny,
"Efficient inverse kinematics for general 6R manipulators", IEEE T-RA 10(5), 1994),
written here on the joint screws of :mod:`robot_sim.ik.geometry` (lengths divided by the
robot's size):

1. Axis 6 is reached two ways: ``E3 E4 E5 · axis6 = E2⁻¹ E1⁻¹ · (T M⁻¹ · axis6)``, with
   p a point on it (measured from a point O on axis 3) and l its direction.  The six
   components of p and l and the eight of p·p, p·l, p×l and (p·p)l − 2(p·l)p are, on the
   left, linear in sᵢ, cᵢ, 1 of each of q3, q4, q5 (14 × 27 coefficients ``C``, fixed
   per robot), and on the right in those of q1, q2 (14 × 9, found per pose from nine
   samples on a 3 × 3 grid of angles: the fit is exact).
2. The 14 equations ``C·x345 = Q·x12`` lose the eight products of q1, q2 by the six rows
   of Householder's Qᵀ orthogonal to Q's columns: six equations in q3, q4, q5.
3. Half-angle tangents of q4 and q5, and the six equations again times x4, give a 12 × 12
   matrix ``Σ(q3)`` whose determinant vanishes at every solution's q3.  The determinant
   is a trigonometric polynomial of degree 8 in q3 (degree 24 in tan(q3/2), of which
   (1 + x²)⁴ is a spurious factor): its 17 coefficients come from 18 samples, and its real
   roots (at most 16) are found by :func:`robot_sim.ik.realroots.real_roots` in the
   tangent of (q3 − φ)/2, φ chosen so that the largest sample sits at infinity.
4. For each root: q4, q5 from the null vector of Σ(q3) (LU with complete pivoting), q1,
   q2 from the least-squares solution of the 14 equations, q6 from the rotation left;
   then Newton (Levenberg–Marquardt) steps on the whole chain's pose error, to 1e-14.

A pose out of reach has no real root: the critical points of the determinant take the
roots' place, and the steps end at local minima of |Δp|²/size² + |log(R_T Rᵀ)|².
"""
from __future__ import annotations

import math

import numba
import numpy as np

from robot_sim.ik.dense import apply_qt, determinant, householder, null_vector
from robot_sim.ik.finish import LANES, RADIX, expand, fk_lanes, nearest_turn, screen, to_lane
from robot_sim.ik.polish import polish
from robot_sim.ik.realroots import real_roots
from robot_sim.kernels.jit import INLINE, JIT

#: Samples of the determinant (17 coefficients of a degree-8 trigonometric polynomial; an
#: even count so that rolling the samples by half a turn keeps the grid).
SAMPLES = 18
#: Critical points of the determinant within this (relative) of zero are candidates.
NEAR = 1e-9
#: Candidates per pose: 16 roots and up to 15 near-tangent critical points.
MAX_CANDIDATES = 32


@numba.njit(**INLINE)
def _quantities(px: float, py: float, pz: float, lx: float, ly: float, lz: float, out: np.ndarray) -> None:
    """The 14 quantities of Raghavan and Roth: p, l, p·p, p·l, p×l, (p·p)l − 2(p·l)p."""
    pp = px * px + py * py + pz * pz
    pl = px * lx + py * ly + pz * lz
    out[0], out[1], out[2], out[3], out[4], out[5] = px, py, pz, lx, ly, lz
    out[6], out[7] = pp, pl
    out[8], out[9], out[10] = py * lz - pz * ly, pz * lx - px * lz, px * ly - py * lx
    out[11], out[12], out[13] = pp * lx - 2.0 * pl * px, pp * ly - 2.0 * pl * py, pp * lz - 2.0 * pl * pz


@numba.njit(**INLINE)
def _change_basis(M: np.ndarray, src: np.ndarray, out: np.ndarray) -> None:
    """out[3i + j] = Σ M[i, a] M[j, b] src[3a + b]: the 3 × 3 change of basis M applied to
    both factors of a product basis."""
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for a in range(3):
                for b in range(3):
                    acc += M[i, a] * M[j, b] * src[3 * a + b]
            out[3 * i + j] = acc


@numba.njit(**JIT)
def _apply(E: np.ndarray, x: np.ndarray, point: bool, out: np.ndarray) -> None:
    """out = E (3, 4) applied to x: a point (with the offset) or a direction."""
    for a in range(3):
        out[a] = E[a, 0] * x[0] + E[a, 1] * x[1] + E[a, 2] * x[2] + (E[a, 3] if point else 0.0)


@numba.njit(**JIT)
def rhs_coefficients(T: np.ndarray, inv_size: float, tool: np.ndarray, E1: np.ndarray, E2: np.ndarray,
                     O: np.ndarray, Vi: np.ndarray, Q: np.ndarray) -> None:
    """Q (14, 9): the right side's quantities as coefficients of (s1, c1, 1) ⊗ (s2, c2, 1),
    for the pose T.  ``tool`` (2, 3): the point and direction of axis 6 in the tool frame
    (scaled); E1, E2 (3, 3, 4): the inverse motions of joints 1 and 2 at the grid angles."""
    pt = np.empty(3)
    ln = np.empty(3)
    for a in range(3):
        pt[a] = (T[a, 0] * tool[0, 0] + T[a, 1] * tool[0, 1] + T[a, 2] * tool[0, 2]) + T[a, 3] * inv_size
        ln[a] = T[a, 0] * tool[1, 0] + T[a, 1] * tool[1, 1] + T[a, 2] * tool[1, 2]
    F = np.empty((3, 3, 14))
    y, z, ly, lz = np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    for a in range(3):
        _apply(E1[a], pt, True, y)
        _apply(E1[a], ln, False, ly)
        for b in range(3):
            _apply(E2[b], y, True, z)
            _apply(E2[b], ly, False, lz)
            _quantities(z[0] - O[0], z[1] - O[1], z[2] - O[2], lz[0], lz[1], lz[2], F[a, b])
    for r in range(14):
        _change_basis(Vi, F[:, :, r].copy().reshape(9), Q[r])


@numba.njit(**JIT)
def sigma(G: np.ndarray, theta: float, S: np.ndarray) -> None:
    """The 12 × 12 matrix Σ(q3) into S: rows 0-5 the six equations on the monomials
    x4^i x5^j (column 3i + j), rows 6-11 the same times x4."""
    s, c = math.sin(theta), math.cos(theta)
    S[:, :] = 0.0
    for e in range(6):
        for k in range(9):
            v = G[e, 0, k] * s + G[e, 1, k] * c + G[e, 2, k]
            S[e, k] = v
            S[e + 6, k + 3] = v


@numba.njit(**INLINE)
def _half_angle(z0: float, z1: float, z2: float) -> float:
    """The angle whose half-angle monomials are proportional to (1, x, x²) = (z0, z1, z2)."""
    sign = 1.0 if z0 + z2 >= 0.0 else -1.0
    return math.atan2(2.0 * z1 * sign, (z0 - z2) * sign)


@numba.njit(**JIT)
def wrist_angles(z: np.ndarray) -> tuple[float, float]:
    """(q4, q5) from the null vector z (z[3i + j] ∝ x4^i x5^j, i < 4, j < 3), read where
    the monomials are largest (so an angle near π, x = ∞, is read well)."""
    best, bi, bj = -1.0, 0, 0
    for i in range(2):
        for j in range(3):
            w = abs(z[3 * i + j] + z[3 * (i + 2) + j])
            if w > best:
                best, bi, bj = w, i, j
    q4 = _half_angle(z[3 * bi + bj], z[3 * (bi + 1) + bj], z[3 * (bi + 2) + bj])
    best, bi = -1.0, 0
    for i in range(4):
        w = abs(z[3 * i] + z[3 * i + 2])
        if w > best:
            best, bi = w, i
    q5 = _half_angle(z[3 * bi], z[3 * bi + 1], z[3 * bi + 2])
    return q4, q5


@numba.njit(**JIT)
def rotation_about(h: np.ndarray, q: float, R: np.ndarray) -> None:
    """R (3, 3): the turn by q about the unit axis h (Rodrigues)."""
    c, s = math.cos(q), math.sin(q)
    v = 1.0 - c
    R[0, 0], R[0, 1], R[0, 2] = c + v * h[0] * h[0], v * h[0] * h[1] - s * h[2], v * h[0] * h[2] + s * h[1]
    R[1, 0], R[1, 1], R[1, 2] = v * h[0] * h[1] + s * h[2], c + v * h[1] * h[1], v * h[1] * h[2] - s * h[0]
    R[2, 0], R[2, 1], R[2, 2] = v * h[0] * h[2] - s * h[1], v * h[1] * h[2] + s * h[0], c + v * h[2] * h[2]


@numba.njit(**JIT)
def last_angle(H: np.ndarray, q: np.ndarray, RT: np.ndarray, u: np.ndarray) -> float:
    """q6 from q1..q5: the turn about axis 6 left in (R1⋯R5)ᵀ RT (RT: the target's
    rotation times M's transposed), measured on ``u`` ⊥ axis 6."""
    A = np.eye(3)
    B = np.empty((3, 3))
    R = np.empty((3, 3))
    for j in range(5):
        rotation_about(H[j], q[j], R)
        for a in range(3):
            for b in range(3):
                B[a, b] = A[a, 0] * R[0, b] + A[a, 1] * R[1, b] + A[a, 2] * R[2, b]
        A[:, :] = B
    v = np.zeros(3)  # (A^T RT) u
    for a in range(3):
        ru = RT[a, 0] * u[0] + RT[a, 1] * u[1] + RT[a, 2] * u[2]
        for b in range(3):
            v[b] += A[a, b] * ru
    h = H[5]
    cx = u[1] * v[2] - u[2] * v[1]
    cy = u[2] * v[0] - u[0] * v[2]
    cz = u[0] * v[1] - u[1] * v[0]
    return math.atan2(h[0] * cx + h[1] * cy + h[2] * cz, u[0] * v[0] + u[1] * v[1] + u[2] * v[2])


@numba.njit(**JIT)
def eliminate(Te: np.ndarray, inv_size: float, C: np.ndarray, axis6: np.ndarray, E1: np.ndarray, E2: np.ndarray,
              O: np.ndarray, Vi: np.ndarray, Q: np.ndarray, A: np.ndarray, V: np.ndarray, beta: np.ndarray,
              G: np.ndarray) -> None:
    """Steps 1-3 of the module docstring for the pose Te: Q (14, 9) the right side's
    coefficients, A (14, 8) and V, beta the Householder QR of its eight product columns,
    G (6, 3, 9) the six equations as (equation, s3 | c3 | 1, x4^i x5^j) coefficients."""
    rhs_coefficients(Te, inv_size, axis6, E1, E2, O, Vi, Q)
    A[:, :] = Q[:, :8]
    householder(A, V, beta)
    B = C.copy()  # C x345 − q_const = Q8 x12
    for r in range(14):
        B[r, 26] -= Q[r, 8]
    apply_qt(V, beta, B)
    half = np.array([[0.0, 1.0, 1.0], [2.0, 0.0, 0.0], [0.0, -1.0, 1.0]])  # (s, c, 1) → (1, x, x²)·(1 + x²)
    for e in range(6):  # rows 8-13 of Qᵀ B
        for a in range(3):
            _change_basis(half, B[8 + e, 9 * a:9 * a + 9], G[e, a])


@numba.njit(**JIT)
def candidates(T: np.ndarray, Te: np.ndarray, inv_size: float, C: np.ndarray, axis6: np.ndarray,
               E1: np.ndarray, E2: np.ndarray, O: np.ndarray, Vi: np.ndarray, W: np.ndarray, H: np.ndarray,
               RM: np.ndarray, u6: np.ndarray, reverse: bool, table: np.ndarray, modified: bool, base: np.ndarray,
               tool: np.ndarray, out: np.ndarray) -> int:
    """The polished candidates of one pose T (world, 4 × 4) into out (MAX_CANDIDATES, 6);
    returns their number.  The elimination solves the pose Te of the chain it was
    prepared for: T itself, or T⁻¹ for the chain read from the tool back (``reverse``,
    whose joint values come in the reverse order).  The arguments are those
    :mod:`robot_sim.ik.general` prepares per robot (module docstring)."""
    Q = np.empty((14, 9))
    A = np.empty((14, 8))
    V = np.empty((14, 8))
    beta = np.empty(8)
    G = np.empty((6, 3, 9))
    eliminate(Te, inv_size, C, axis6, E1, E2, O, Vi, Q, A, V, beta, G)
    S = np.empty((12, 12))
    f = np.empty(SAMPLES)
    m = 0
    for k in range(SAMPLES):
        sigma(G, 2.0 * math.pi * k / SAMPLES, S)
        f[k] = determinant(S)
        if abs(f[k]) > abs(f[m]):
            m = k
    rolled = np.empty(SAMPLES)
    for k in range(SAMPLES):
        rolled[k] = f[(k + m + SAMPLES // 2) % SAMPLES]
    poly = np.zeros(W.shape[0])
    for r in range(W.shape[0]):
        for k in range(SAMPLES):
            poly[r] += W[r, k] * rolled[k]
    phi = 2.0 * math.pi * m / SAMPLES - math.pi
    roots = np.empty(2 * (poly.shape[0] - 1))
    crit = np.empty(poly.shape[0] - 1)
    nr, nc = real_roots(poly, NEAR, roots, crit)
    starts = roots[:nr] if nr > 0 else crit[:nc]
    z = np.empty(12)
    x = np.empty(27)
    w3, w4, w5 = np.empty(3), np.empty(3), np.empty(3)
    rhs = np.empty((14, 1))
    RT = np.empty((3, 3))
    for a in range(3):
        for b in range(3):
            RT[a, b] = Te[a, 0] * RM[0, b] + Te[a, 1] * RM[1, b] + Te[a, 2] * RM[2, b]
    count = 0
    for k in range(starts.shape[0]):
        q = out[count]
        q[2] = 2.0 * math.atan(starts[k]) + phi
        sigma(G, q[2], S)
        null_vector(S, z)
        q[3], q[4] = wrist_angles(z)
        w3[0], w3[1], w3[2] = math.sin(q[2]), math.cos(q[2]), 1.0
        w4[0], w4[1], w4[2] = math.sin(q[3]), math.cos(q[3]), 1.0
        w5[0], w5[1], w5[2] = math.sin(q[4]), math.cos(q[4]), 1.0
        for a in range(3):
            for b in range(3):
                for c in range(3):
                    x[9 * a + 3 * b + c] = w3[a] * w4[b] * w5[c]
        for r in range(14):
            acc = -Q[r, 8]
            for i in range(27):
                acc += C[r, i] * x[i]
            rhs[r, 0] = acc
        apply_qt(V, beta, rhs)
        x12 = np.empty(8)
        for i in range(7, -1, -1):  # R x12 = (Qᵀ rhs)[:8]
            acc = rhs[i, 0]
            for c in range(i + 1, 8):
                acc -= A[i, c] * x12[c]
            x12[i] = acc / A[i, i]
        q[0] = math.atan2(x12[2], x12[5])
        q[1] = math.atan2(x12[6], x12[7])
        q[5] = last_angle(H, q, RT, u6)
        if not np.isfinite(q).all():
            continue
        if reverse:
            q[:] = q[::-1].copy()
        polish(table, modified, base, tool, T, inv_size, q)
        count += 1
    return count


@numba.njit(**JIT)
def solve_general(Ts: np.ndarray, Te: np.ndarray, inv_size: float, C: np.ndarray, axis6: np.ndarray,
                  E1: np.ndarray, E2: np.ndarray, O: np.ndarray, Vi: np.ndarray, W: np.ndarray, H: np.ndarray,
                  RM: np.ndarray, u6: np.ndarray, reverse: bool, table: np.ndarray, modified: bool, base: np.ndarray,
                  tool: np.ndarray, Hs: np.ndarray, Ps: np.ndarray, rev: np.ndarray, Ms: np.ndarray, q0: np.ndarray,
                  lo: np.ndarray, hi: np.ndarray, mode: int, tol: float, max_values: int) -> tuple:
    """Every solution of each pose Ts[i] (N, 4, 4) (Te: the poses the elimination solves,
    see :func:`candidates`), with the turns ``mode`` asks (RAW or EVERY_TURN of
    :mod:`robot_sim.ik.finish`), as :func:`robot_sim.ik.pipeline.run` returns them: (q
    (N, K, 6) NaN-padded nearest q0 first, code, exact, count, needed), checked and
    expanded by :func:`robot_sim.ik.finish.screen` and :func:`robot_sim.ik.finish.expand`
    on the chain's screws (Hs, Ps, rev, Ms).  A branch's code is its number in the order
    of its q3 in (−π, π]."""
    N = Ts.shape[0]
    raw = np.full((N, MAX_CANDIDATES, 6), np.nan)
    code = np.zeros((N, MAX_CANDIDATES), dtype=np.int64)
    count = np.zeros(N, dtype=np.int64)
    exact = np.zeros((N, MAX_CANDIDATES), dtype=np.bool_)
    total = np.zeros(N, dtype=np.int64)
    lq, lcs = np.empty((6, MAX_CANDIDATES)), np.empty((12, MAX_CANDIDATES))
    pose, pos, rot = np.empty(MAX_CANDIDATES, dtype=np.int64), np.empty(MAX_CANDIDATES), np.empty(MAX_CANDIDATES)
    S = np.empty(12 * LANES)
    for i in range(N):
        got = candidates(Ts[i], Te[i], inv_size, C, axis6, E1, E2, O, Vi, W, H, RM, u6, reverse, table, modified,
                         base, tool, raw[i])
        for k in range(got):  # wrapped to (−π, π], ordered by q3
            for j in range(6):
                raw[i, k, j] = nearest_turn(raw[i, k, j], 0.0)
        order = np.argsort(raw[i, :got, 2])
        raw[i, :got] = raw[i, order]
        lcs[:, :] = np.nan  # no cosines known: to_lane computes them
        for k in range(got):
            to_lane(raw, i, k, rev, q0, lq, lcs, k)
            pose[k] = i
        fk_lanes(Hs, Ps, rev, Ms, Ts, pose, lq, lcs, got, True, S, pos, rot)
        count[i], total[i] = screen(raw, code, exact, i, got, pos, rot, 0, rev, lo, hi, mode, tol, False)
        for k in range(count[i]):
            code[i, k] = k
    width = 0
    for i in range(N):
        width = max(width, total[i])
    needed = N * width * 6
    if needed > max_values:
        return (np.empty((0, 0, 6)), np.empty((0, 0), dtype=np.int64), np.empty((0, 0), dtype=np.bool_),
                total, needed)
    out = np.full((N, width, 6), np.nan)
    out_code = np.full((N, width), -1, dtype=np.int64)
    out_exact = np.zeros((N, width), dtype=np.bool_)
    out_count = np.zeros(N, dtype=np.int64)
    work, dist = np.empty((width, 6)), np.empty(width)
    source, order = np.empty(width, dtype=np.int64), np.empty(width, dtype=np.int64)
    spare = np.empty(width + RADIX, dtype=np.int64)
    digit, ways, first = np.empty(6, dtype=np.int64), np.empty(6, dtype=np.int64), np.empty(6)
    for i in range(N):
        out_count[i] = expand(raw, code, exact, i, count[i], q0, lo, hi, rev, mode, out, out_code, out_exact,
                              work, dist, source, order, spare, digit, ways, first)
    return out, out_code, out_exact, out_count, needed
