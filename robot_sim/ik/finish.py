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

Revolute joints without limits, and every joint with ``within=False``, take the turn
nearest q0.
"""
from __future__ import annotations

import math

import numba
import numpy as np

from robot_sim.kernels.jit import JIT

TWO_PI = 2.0 * math.pi
#: Two branches closer than this in every joint (modulo 2π for revolute ones) are one.
SAME = 1e-9
#: A joint value this far outside a limit still counts as on it (and is clipped to it).
EDGE = 1e-10


@numba.njit(**JIT)
def fk_error(H: np.ndarray, P: np.ndarray, rev: np.ndarray, M: np.ndarray, q: np.ndarray, T: np.ndarray,
             R: np.ndarray, Rj: np.ndarray, t: np.ndarray, check_rot: bool) -> float:
    """Largest of the position error [m] and (with ``check_rot``) the rotation error [rad]
    of the tool at q against T, by the product of exponentials."""
    R[:, :] = 0.0
    R[0, 0] = R[1, 1] = R[2, 2] = 1.0
    t[:] = 0.0
    for j in range(H.shape[0]):
        h0, h1, h2 = H[j, 0], H[j, 1], H[j, 2]
        if rev[j]:
            c, s = math.cos(q[j]), math.sin(q[j])
            v = 1.0 - c
            Rj[0, 0], Rj[0, 1], Rj[0, 2] = c + v * h0 * h0, v * h0 * h1 - s * h2, v * h0 * h2 + s * h1
            Rj[1, 0], Rj[1, 1], Rj[1, 2] = v * h0 * h1 + s * h2, c + v * h1 * h1, v * h1 * h2 - s * h0
            Rj[2, 0], Rj[2, 1], Rj[2, 2] = v * h0 * h2 - s * h1, v * h1 * h2 + s * h0, c + v * h2 * h2
            for a in range(3):  # offset of the turn: p - Rj p, moved by the chain so far
                off = P[j, a] - (Rj[a, 0] * P[j, 0] + Rj[a, 1] * P[j, 1] + Rj[a, 2] * P[j, 2])
                Rj[a, 3] = off
        else:
            Rj[:, :3] = 0.0
            Rj[0, 0] = Rj[1, 1] = Rj[2, 2] = 1.0
            Rj[0, 3], Rj[1, 3], Rj[2, 3] = q[j] * h0, q[j] * h1, q[j] * h2
        for a in range(3):
            t[a] += R[a, 0] * Rj[0, 3] + R[a, 1] * Rj[1, 3] + R[a, 2] * Rj[2, 3]
        for a in range(3):
            r0, r1, r2 = R[a, 0], R[a, 1], R[a, 2]
            for b in range(3):
                R[a, b] = r0 * Rj[0, b] + r1 * Rj[1, b] + r2 * Rj[2, b]
    pos = 0.0
    for a in range(3):
        e = t[a] + R[a, 0] * M[0, 3] + R[a, 1] * M[1, 3] + R[a, 2] * M[2, 3] - T[a, 3]
        pos += e * e
    err = math.sqrt(pos)
    if check_rot:
        rot = 0.0
        for a in range(3):
            for b in range(3):
                e = R[a, 0] * M[0, b] + R[a, 1] * M[1, b] + R[a, 2] * M[2, b] - T[a, b]
                rot += e * e
        err = max(err, math.sqrt(0.5 * rot))
    return err


@numba.njit(inline="always", **JIT)
def nearest_turn(x: float, target: float) -> float:
    return x + TWO_PI * round((target - x) / TWO_PI)


@numba.njit(**JIT)
def turns(x: float, lo: float, hi: float) -> tuple[float, int]:
    """(first turn of angle x at or above lo, how many turns lie in [lo, hi])."""
    first = x + TWO_PI * math.ceil((lo - EDGE - x) / TWO_PI)
    if first > hi + EDGE:
        return first, 0
    return first, int(math.floor((hi + EDGE - first) / TWO_PI)) + 1


@numba.njit(**JIT)
def screen(raw: np.ndarray, code: np.ndarray, count: np.ndarray, exact: np.ndarray, total: np.ndarray,
           H: np.ndarray, P: np.ndarray, rev: np.ndarray, M: np.ndarray, Ts: np.ndarray,
           q0: np.ndarray, lo: np.ndarray, hi: np.ndarray, within: bool, check_rot: bool, tol: float) -> None:
    """Pass 1, in place: raw[i, :count[i]] become the distinct branches kept (exact ones
    if any), with exact[i, k]; total[i] the number of solutions they expand to."""
    n = raw.shape[2]
    R, Rj, t = np.empty((3, 3)), np.empty((3, 4)), np.empty(3)
    err = np.empty(raw.shape[1])
    for i in range(raw.shape[0]):
        m = count[i]
        any_exact = False
        for k in range(m):
            q = raw[i, k]
            ok = True
            for j in range(n):
                if not math.isfinite(q[j]):
                    ok = False
                elif rev[j]:
                    q[j] = nearest_turn(q[j], q0[j])
            err[k] = fk_error(H, P, rev, M, q, Ts[i], R, Rj, t, check_rot) if ok else math.inf
            any_exact = any_exact or err[k] <= tol
        kept = 0
        for k in range(m):
            if (any_exact and err[k] > tol) or not math.isfinite(err[k]):
                continue
            duplicate = False
            for k2 in range(kept):
                same = True
                for j in range(n):
                    d = raw[i, k, j] - raw[i, k2, j]
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
            raw[i, kept] = raw[i, k]
            code[i, kept] = code[i, k]
            exact[i, kept] = err[k] <= tol
            kept += 1
        count[i] = kept
        total[i] = 0
        for k in range(kept):
            ways = 1
            for j in range(n):
                x = raw[i, k, j]
                if not within:
                    continue
                if rev[j] and math.isfinite(lo[j]) and math.isfinite(hi[j]):
                    ways *= turns(x, lo[j], hi[j])[1]
                elif not rev[j] or math.isfinite(lo[j]) or math.isfinite(hi[j]):
                    if not (lo[j] - EDGE <= x <= hi[j] + EDGE):
                        ways = 0
            total[i] += ways


@numba.njit(**JIT)
def expand(raw: np.ndarray, code: np.ndarray, count: np.ndarray, exact: np.ndarray, q0: np.ndarray,
           lo: np.ndarray, hi: np.ndarray, rev: np.ndarray, within: bool,
           out: np.ndarray, out_code: np.ndarray, out_exact: np.ndarray, out_count: np.ndarray) -> None:
    """Pass 2: every turn of every kept branch into out[i] (NaN beyond), nearest q0 first."""
    n = raw.shape[2]
    first = np.empty(n)
    ways = np.empty(n, dtype=np.int64)
    digit = np.empty(n, dtype=np.int64)
    dist = np.empty(out.shape[1])
    scratch = np.empty((out.shape[1], n))
    for i in range(raw.shape[0]):
        m = 0
        for k in range(count[i]):
            q = raw[i, k]
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
            while usable:
                d2 = 0.0
                for j in range(n):
                    x = first[j] + TWO_PI * digit[j]
                    if within:
                        x = min(max(x, lo[j]), hi[j])
                    scratch[m, j] = x
                    d2 += (x - q0[j]) ** 2
                dist[m] = d2
                out_code[i, m] = code[i, k]
                out_exact[i, m] = exact[i, k]
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
        order = np.argsort(dist[:m], kind="mergesort")  # stable: equal distances keep branch order
        codes, exacts = out_code[i, :m].copy(), out_exact[i, :m].copy()
        for a in range(m):
            out[i, a] = scratch[order[a]]
            out_code[i, a] = codes[order[a]]
            out_exact[i, a] = exacts[order[a]]
        out_count[i] = m
