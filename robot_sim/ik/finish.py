"""From raw branches to the answer (compiled): which branches reach the pose, their
turns inside the joint limits, duplicates dropped, nearest to q0 first.

Two passes so that the output is sized by the largest count of the batch, not by the
worst case (a UR arm's ±2π joints give up to 2⁶ turns per branch):

1. :func:`screen` checks each raw branch by forward kinematics on the whole chain: it is
   exact when it puts the tool within ``tol`` of T (metres, and radians as the Frobenius
   distance of the rotations over √2); if none is, every branch is kept as the
   least-squares answer.  Duplicates (equal modulo 2π) go, and each branch counts its
   turns inside the limits.
2. :func:`expand` writes every turn of every kept branch and sorts them by the distance
   to q0 (Euclidean, rad and m).

Which turns: :data:`RAW` takes each revolute angle's turn nearest q0 and ignores the
limits (``within_limits=False``); :data:`EVERY_TURN` every turn inside the limits;
:data:`NEAREST_TURN` only the turn of each branch nearest q0 inside the limits (the first
rows :data:`EVERY_TURN` would give each branch: what ``solve_ik`` asks).  Revolute joints
without limits take the turn nearest q0.
"""
from __future__ import annotations

import math

import numba
import numpy as np

from robot_sim.kernels.jit import JIT

TWO_PI = 2.0 * math.pi
#: Turns per radian: angles are divided by 2π as a product (a division takes several times as long).
PER_TURN = 1.0 / TWO_PI
#: Two branches closer than this in every joint (modulo 2π for revolute ones) are one.
SAME = 1e-9
#: A joint value this far outside a limit still counts as on it (and is clipped to it).
EDGE = 1e-10
#: Which turns of the revolute angles are solutions (module docstring).
RAW, EVERY_TURN, NEAREST_TURN = 0, 1, 2


@numba.njit(**JIT)
def fk_error(H: np.ndarray, P: np.ndarray, rev: np.ndarray, M: np.ndarray, q: np.ndarray, cs: np.ndarray,
             T: np.ndarray, check_rot: bool) -> tuple[float, float]:
    """Position error [m] and (with ``check_rot``, else 0) rotation chord of the tool at q
    against T, by the product of exponentials.  The chord ‖R_q − R_T‖_F / √2 is
    2 sin(θ/2) for the angle θ [rad] between the rotations (:func:`chord_angle`), θ to
    within θ³/24.  cs (2n,) holds cos q_j, sin q_j at 2j, 2j + 1 where the caller has
    them (NaN where not).  (Scalars only: the chain's rotation and offset stay in
    registers.)"""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0
    t0 = t1 = t2 = 0.0
    for j in range(H.shape[0]):
        h0, h1, h2 = H[j, 0], H[j, 1], H[j, 2]
        if rev[j]:
            c, s = cs[2 * j], cs[2 * j + 1]
            if not c == c:
                c, s = math.cos(q[j]), math.sin(q[j])
            v = 1.0 - c
            a00, a01, a02 = c + v * h0 * h0, v * h0 * h1 - s * h2, v * h0 * h2 + s * h1
            a10, a11, a12 = v * h0 * h1 + s * h2, c + v * h1 * h1, v * h1 * h2 - s * h0
            a20, a21, a22 = v * h0 * h2 - s * h1, v * h1 * h2 + s * h0, c + v * h2 * h2
            x, y, z = P[j, 0], P[j, 1], P[j, 2]  # offset of the turn: p - Rj p
            o0 = x - (a00 * x + a01 * y + a02 * z)
            o1 = y - (a10 * x + a11 * y + a12 * z)
            o2 = z - (a20 * x + a21 * y + a22 * z)
        else:
            a00, a01, a02, a10, a11, a12, a20, a21, a22 = 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0
            o0, o1, o2 = q[j] * h0, q[j] * h1, q[j] * h2
        t0 += r00 * o0 + r01 * o1 + r02 * o2  # moved by the chain so far
        t1 += r10 * o0 + r11 * o1 + r12 * o2
        t2 += r20 * o0 + r21 * o1 + r22 * o2
        r00, r01, r02 = r00 * a00 + r01 * a10 + r02 * a20, r00 * a01 + r01 * a11 + r02 * a21, \
            r00 * a02 + r01 * a12 + r02 * a22
        r10, r11, r12 = r10 * a00 + r11 * a10 + r12 * a20, r10 * a01 + r11 * a11 + r12 * a21, \
            r10 * a02 + r11 * a12 + r12 * a22
        r20, r21, r22 = r20 * a00 + r21 * a10 + r22 * a20, r20 * a01 + r21 * a11 + r22 * a21, \
            r20 * a02 + r21 * a12 + r22 * a22
    e0 = t0 + r00 * M[0, 3] + r01 * M[1, 3] + r02 * M[2, 3] - T[0, 3]
    e1 = t1 + r10 * M[0, 3] + r11 * M[1, 3] + r12 * M[2, 3] - T[1, 3]
    e2 = t2 + r20 * M[0, 3] + r21 * M[1, 3] + r22 * M[2, 3] - T[2, 3]
    pos = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
    if not check_rot:
        return pos, 0.0
    rot = 0.0
    for b in range(3):
        m0, m1, m2 = M[0, b], M[1, b], M[2, b]
        e0 = r00 * m0 + r01 * m1 + r02 * m2 - T[0, b]
        e1 = r10 * m0 + r11 * m1 + r12 * m2 - T[1, b]
        e2 = r20 * m0 + r21 * m1 + r22 * m2 - T[2, b]
        rot += e0 * e0 + e1 * e1 + e2 * e2
    return pos, math.sqrt(0.5 * rot)


@numba.njit(inline="always", **JIT)
def chord_angle(chord: float) -> float:
    """The angle θ [rad] of a rotation chord 2 sin(θ/2) (:func:`fk_error`)."""
    return 2.0 * math.asin(min(1.0, 0.5 * chord))


@numba.njit(inline="always", **JIT)
def nearest_turn(x: float, target: float) -> float:
    return x + TWO_PI * round((target - x) * PER_TURN)


@numba.njit(**JIT)
def turns(x: float, lo: float, hi: float) -> tuple[float, int]:
    """(first turn of angle x at or above lo, how many turns lie in [lo, hi])."""
    first = x + TWO_PI * math.ceil((lo - EDGE - x) * PER_TURN)
    if first > hi + EDGE:
        return first, 0
    return first, int(math.floor((hi + EDGE - first) * PER_TURN)) + 1


@numba.njit(**JIT)
def screen(raw: np.ndarray, code: np.ndarray, cs: np.ndarray, m: int, exact: np.ndarray, err: np.ndarray,
           H: np.ndarray,
           P: np.ndarray, rev: np.ndarray, M: np.ndarray, T: np.ndarray, q0: np.ndarray, lo: np.ndarray,
           hi: np.ndarray, mode: int, check_rot: bool, tol: float) -> tuple[int, int]:
    """Pass 1 of one pose, in place: of its m raw branches raw[:m] (K, n) and code[:m]
    (with the cosines and sines of their angles cs[:m] (K, 2n), NaN where not known),
    the distinct ones kept (exact ones if any) move to the front, with exact[k].
    Returns (how many are kept, how many solutions they expand to).  ``err`` (K,) is
    scratch."""
    n = raw.shape[1]
    any_exact = False
    for k in range(m):
        q = raw[k]
        ok = True
        for j in range(n):
            if not math.isfinite(q[j]):
                ok = False
            elif rev[j]:
                q[j] = nearest_turn(q[j], q0[j])
        err[k] = math.inf
        if ok:
            pos, chord = fk_error(H, P, rev, M, q, cs[k], T, check_rot)
            err[k] = max(pos, chord)
        any_exact = any_exact or err[k] <= tol
    kept = 0
    for k in range(m):
        if (any_exact and err[k] > tol) or not math.isfinite(err[k]):
            continue
        duplicate = False
        for k2 in range(kept):
            same = True
            for j in range(n):
                d = raw[k, j] - raw[k2, j]
                if rev[j]:
                    d = nearest_turn(d, 0.0)
                if abs(d) > SAME:
                    same = False
                    break
            if same:
                duplicate = True
                break
        if duplicate:
            continue
        for j in range(n):
            raw[kept, j] = raw[k, j]
        code[kept] = code[k]
        exact[kept] = err[k] <= tol
        kept += 1
    total = 0
    for k in range(kept):
        ways = 1
        for j in range(n):
            x = raw[k, j]
            if mode == RAW:
                continue
            if rev[j] and math.isfinite(lo[j]) and math.isfinite(hi[j]):
                ways *= turns(x, lo[j], hi[j])[1]
            elif not rev[j] or math.isfinite(lo[j]) or math.isfinite(hi[j]):
                if not (lo[j] - EDGE <= x <= hi[j] + EDGE):
                    ways = 0
        total += ways if mode == EVERY_TURN else min(ways, 1)
    return kept, total


#: Up to this many solutions are sorted by insertion, more by merging.
SHORT = 16


@numba.njit(**JIT)
def stable_order(key: np.ndarray, m: int, order: np.ndarray, spare: np.ndarray) -> None:
    """order[:m] = the indices of key[:m] ascending, equal keys in index order (the
    permutation of a stable argsort), without allocating; ``spare`` (m,) is scratch."""
    for a in range(m):
        order[a] = a
    if m <= SHORT:
        for a in range(1, m):
            x = order[a]
            b = a - 1
            while b >= 0 and key[order[b]] > key[x]:
                order[b + 1] = order[b]
                b -= 1
            order[b + 1] = x
        return
    src, dst = order, spare
    in_order = True  # whether src is ``order``
    width = 1
    while width < m:
        for start in range(0, m, 2 * width):
            mid, stop = min(start + width, m), min(start + 2 * width, m)
            a, b = start, mid
            for k in range(start, stop):
                if b < stop and (a >= mid or key[src[b]] < key[src[a]]):
                    dst[k] = src[b]
                    b += 1
                else:
                    dst[k] = src[a]
                    a += 1
        src, dst = dst, src
        in_order = not in_order
        width *= 2
    if not in_order:
        for a in range(m):
            order[a] = src[a]


@numba.njit(**JIT)
def expand(raw: np.ndarray, code: np.ndarray, kept: int, exact: np.ndarray, q0: np.ndarray, lo: np.ndarray,
           hi: np.ndarray, rev: np.ndarray, mode: int, out: np.ndarray, out_code: np.ndarray,
           out_exact: np.ndarray, work: np.ndarray, dist: np.ndarray, source: np.ndarray, order: np.ndarray,
           spare: np.ndarray, digit: np.ndarray, ways: np.ndarray, first: np.ndarray) -> int:
    """Pass 2 of one pose: every turn of each of its ``kept`` branches into out (W, n),
    nearest q0 first, with out_code and out_exact; returns how many.  The rest is scratch:
    work (W, n), dist, source, order, spare (W,); digit, ways, first (n,)."""
    n = raw.shape[1]
    within = mode != RAW
    m = 0
    for k in range(kept):
        q = raw[k]
        usable = True
        for j in range(n):
            first[j], ways[j] = q[j], 1
            if within and rev[j] and math.isfinite(lo[j]) and math.isfinite(hi[j]):
                first[j], ways[j] = turns(q[j], lo[j], hi[j])
            elif within and not (lo[j] - EDGE <= q[j] <= hi[j] + EDGE):
                usable = False
            digit[j] = 0
            if ways[j] == 0:
                usable = False
            elif mode == NEAREST_TURN and ways[j] > 1:  # one turn: the nearest q0 (the lowest on a tie)
                best = math.inf
                for d in range(0, ways[j]):
                    x = min(max(first[j] + TWO_PI * d, lo[j]), hi[j])
                    if (x - q0[j]) ** 2 < best:
                        best, digit[j] = (x - q0[j]) ** 2, d
                ways[j] = digit[j] + 1  # the enumeration below stops after it
        while usable:
            d2 = 0.0
            for j in range(n):
                x = first[j] + TWO_PI * digit[j]
                if within:
                    x = min(max(x, lo[j]), hi[j])
                work[m, j] = x
                d2 += (x - q0[j]) ** 2
            dist[m] = d2
            source[m] = k
            m += 1
            j = 0  # next combination of turns, joint 0 fastest
            while j < n:
                digit[j] += 1
                if digit[j] < ways[j]:
                    break
                digit[j] = 0
                j += 1
            if j == n:
                break
    stable_order(dist, m, order, spare)  # equal distances keep branch order
    for a in range(m):
        b = order[a]
        for j in range(n):
            out[a, j] = work[b, j]
        out_code[a] = code[source[b]]
        out_exact[a] = exact[source[b]]
    return m
