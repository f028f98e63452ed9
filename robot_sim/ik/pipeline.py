"""One compiled call from poses to sorted solutions: the family's kernel for each pose and
free value, the branches mapped onto the whole chain, then :func:`robot_sim.ik.finish.screen`
and :func:`robot_sim.ik.finish.expand`.  The robot's data travel packed in two arrays
(:func:`pack`), so one call from Python costs a handful of argument conversions.
"""
from __future__ import annotations

import numba
import numpy as np
from numpy.typing import NDArray

from robot_sim.ik.classify import Plan
from robot_sim.ik.families import PARALLEL_AXES, SPHERICAL_WRIST, THREE_PARALLEL
from robot_sim.ik.families import parallel_axes, position_only, spherical_wrist, three_parallel
from robot_sim.ik.family import BRANCHES
from robot_sim.ik.finish import expand, screen
from robot_sim.ik.geometry import Screws
from robot_sim.kernels.jit import JIT

FloatArray = NDArray[np.float64]
#: Raw branches per pose, by kernel number.
BRANCH_COUNTS = np.array([BRANCHES[kind] for kind in range(len(BRANCHES))])
_HEAD = 10


def pack(p: Plan, sub: Screws, A: FloatArray, keep: NDArray[np.int64], full: Screws,
         lo: FloatArray, hi: FloatArray) -> tuple[FloatArray, NDArray[np.int64]]:
    """The float row (chain solved, constant rows, whole chain, limits) and the integer
    header (plan, joint kinds and order) that :func:`run` unpacks."""
    floats = np.concatenate([sub.H.ravel(), sub.P.ravel(), sub.M.ravel(), A.ravel(), full.H.ravel(),
                             full.P.ravel(), full.M.ravel(), lo, hi])
    head = [p.kind, p.case, *p.idx, -1 if p.free is None else p.free, int(p.reversed), sub.n, full.n]
    ints = np.concatenate([head, sub.revolute.astype(np.int64), keep, full.revolute.astype(np.int64)])
    return floats, ints.astype(np.int64)


@numba.njit(**JIT)
def first_bad_pose(Ts: np.ndarray, tol: float) -> int:
    """Index of the first pose that is not a rigid transform (finite, RᵀR = I and det R = 1
    to ``tol``, bottom row [0 0 0 1]), -1 if all are."""
    for i in range(Ts.shape[0]):
        T = Ts[i]
        ok = True
        for a in range(4):
            for b in range(4):
                ok = ok and np.isfinite(T[a, b])
        for a in range(3):
            for b in range(3):
                dot = T[0, a] * T[0, b] + T[1, a] * T[1, b] + T[2, a] * T[2, b]
                ok = ok and abs(dot - (1.0 if a == b else 0.0)) <= tol
        det = (T[0, 0] * (T[1, 1] * T[2, 2] - T[1, 2] * T[2, 1]) - T[0, 1] * (T[1, 0] * T[2, 2] - T[1, 2] * T[2, 0])
               + T[0, 2] * (T[1, 0] * T[2, 1] - T[1, 1] * T[2, 0]))
        ok = ok and abs(det - 1.0) <= tol and abs(T[3, 0]) <= tol and abs(T[3, 1]) <= tol
        ok = ok and abs(T[3, 2]) <= tol and abs(T[3, 3] - 1.0) <= tol
        if not ok:
            return i
    return -1


@numba.njit(**JIT)
def _chain(g: np.ndarray, at: int, m: int) -> tuple:
    """Screws H (m, 3), P (m, 3) and M (4, 4) packed in g from ``at``."""
    H = g[at:at + 3 * m].copy().reshape((m, 3))
    P = g[at + 3 * m:at + 6 * m].copy().reshape((m, 3))
    return H, P, g[at + 6 * m:at + 6 * m + 16].copy().reshape((4, 4))


@numba.njit(**JIT)
def _inverse(T: np.ndarray, out: np.ndarray) -> None:
    out[:, :] = 0.0
    out[3, 3] = 1.0
    for a in range(3):
        for b in range(3):
            out[a, b] = T[b, a]
        out[a, 3] = -(T[0, a] * T[0, 3] + T[1, a] * T[1, 3] + T[2, a] * T[2, 3])


@numba.njit(**JIT)
def run(gf: np.ndarray, gi: np.ndarray, Ts: np.ndarray, q0: np.ndarray, values: np.ndarray, within: bool,
        check_rot: bool, tol: float, max_values: int) -> tuple:
    """Solutions of every pose Ts[i] for each free value (row v of gf is packed at
    values[v]).  Returns (q, code, exact, count, needed): q (N, K, n) NaN-padded, nearest
    q0 first; ``needed`` = N·K·n, and empty arrays when it exceeds ``max_values``."""
    kind, case, free, rev_chain, m, n = gi[0], gi[1], gi[6], gi[7] != 0, gi[8], gi[9]
    idx = gi[2:6].copy()
    revs = gi[_HEAD:_HEAD + m] != 0
    keep = gi[_HEAD + m:_HEAD + 2 * m]
    revf = gi[_HEAD + 2 * m:_HEAD + 2 * m + n] != 0
    K = BRANCH_COUNTS[kind]
    N, V = Ts.shape[0], values.shape[0]
    raw = np.full((N, K * V, n), np.nan)
    code = np.zeros((N, K * V), dtype=np.int64)
    count = np.zeros(N, dtype=np.int64)
    sub = np.empty((K, m))
    sub_code = np.zeros(K, dtype=np.int64)
    q0s = np.empty(m)
    for j in range(m):
        q0s[j] = q0[keep[j]]
    Tinv = np.empty((4, 4))
    for v in range(V):
        Hs, Ps, Ms = _chain(gf[v], 0, m)
        A = gf[v, 6 * m + 16:6 * m + 37].copy().reshape((7, 3))
        for i in range(N):
            T = Ts[i]
            if rev_chain:
                _inverse(Ts[i], Tinv)
                T = Tinv
            sub[:, :] = np.nan
            if kind == SPHERICAL_WRIST:
                got = spherical_wrist(case, Hs, Ps, revs, A, T, q0s, sub, sub_code)
            elif kind == THREE_PARALLEL:
                got = three_parallel(Hs, Ps, Ms, A, T, q0s, sub, sub_code)
            elif kind == PARALLEL_AXES:
                got = parallel_axes(idx, Hs, Ps, A, T, q0s, sub, sub_code)
            else:
                got = position_only(case, Hs, Ps, A, T, q0s, sub, sub_code)
            for k in range(got):
                row = count[i]
                for j in range(m):
                    raw[i, row, keep[j]] = sub[k, j]
                if free >= 0:
                    raw[i, row, free] = values[v]
                code[i, row] = sub_code[k]
                count[i] = row + 1
    at = 6 * m + 37
    Hf, Pf, Mf = _chain(gf[0], at, n)
    at += 6 * n + 16
    lo = gf[0, at:at + n].copy()
    hi = gf[0, at + n:at + 2 * n].copy()
    exact = np.zeros((N, K * V), dtype=np.bool_)
    total = np.zeros(N, dtype=np.int64)
    screen(raw, code, count, exact, total, Hf, Pf, revf, Mf, Ts, q0, lo, hi, within, check_rot, tol)
    width = 0
    for i in range(N):
        width = max(width, total[i])
    needed = N * width * n
    if needed > max_values:
        return (np.empty((0, 0, n)), np.empty((0, 0), dtype=np.int64), np.empty((0, 0), dtype=np.bool_),
                total, needed)
    out = np.full((N, width, n), np.nan)
    out_code = np.full((N, width), -1, dtype=np.int64)
    out_exact = np.zeros((N, width), dtype=np.bool_)
    out_count = np.zeros(N, dtype=np.int64)
    expand(raw, code, count, exact, q0, lo, hi, revf, within, out, out_code, out_exact, out_count)
    return out, out_code, out_exact, out_count, needed
