"""One compiled call from poses to sorted solutions: the family's kernel for each pose and
free value, the branches mapped onto the whole chain, then :func:`robot_sim.ik.finish.screen`
and :func:`robot_sim.ik.finish.expand`.  The robot's data travel packed in two arrays
(:func:`pack`), so one call from Python costs a handful of argument conversions.

Two passes (:mod:`robot_sim.ik.finish` says why): :func:`pass1` solves, checks and
screens each pose, and counts its solutions; :func:`pass2` writes them into an output as
wide as the batch's widest pose.  Raw branches need no pass 2 when some pose keeps all
of its branches (:func:`raw_is_answer`).  Pass 2 was not folded into pass 1 for the
arms whose width has a small bound (PUMA 560 within the limits: 8 branches × 2 turns of
joint 6): written 16 wide, the answer must be cut to its width afterwards (12 on 10⁵
random poses), by a copy or as a strided view; even with a view the fold measured
within 1 % of the two passes' CPU.
"""
from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from robot_sim.ik.classify import Plan
from robot_sim.ik.families import PARALLEL_AXES, SPHERICAL_WRIST, THREE_PARALLEL
from robot_sim.ik.families import parallel_axes, position_only, spherical_wrist, three_parallel
from robot_sim.ik.family import BRANCHES
from robot_sim.ik.block import CS_ROWS, MAX_JOINTS, OUT_ROWS, POSES, branch_lane, get, load_poses, scratch
from robot_sim.ik.block import LANES as BLOCK_LANES
from robot_sim.ik.finish import LANES, RADIX, RAW, check_within, chord_angle, expand, fk_lanes, screen, sort_raw, to_lane
from robot_sim.ik.geometry import Screws
from robot_sim.kernels.atan2 import atan2_row
from robot_sim.kernels.jit import JIT

FloatArray = NDArray[np.float64]
#: Raw branches per pose, by kernel number.
BRANCH_COUNTS = np.array([BRANCHES[kind] for kind in range(len(BRANCHES))])
#: A pose is rigid when RᵀR = I and det R = 1 to this, and its last row is [0 0 0 1].
RIGID_TOL = 1e-6
#: Most joint values a result may hold (about 400 MB).
MAX_VALUES = 50_000_000
#: :func:`run`'s answer for a q0 holding NaN or infinite values (in place of a pose index).
BAD_Q0 = -2
#: Branches (at least) that :func:`pass1` takes a block at a time through atan2 and the
#: check: eight times :data:`~robot_sim.ik.finish.LANES`, so that a block of
#: :data:`~robot_sim.ik.block.POSES` poses of 8 branches (the solvers' block) goes
#: through at once, and the branches kept for the check within the limits (about 60 % on
#: PUMA 560) still fill the vector loops.
BLOCK = 8 * LANES
_HEAD = 11  # integers before the joint kinds in the header
_FHEAD = 2  # floats before the chain in each row: the free value and the tolerance


def pack(p: Plan, sub: Screws, A: FloatArray, keep: NDArray[np.int64], full: Screws,
         lo: FloatArray, hi: FloatArray, value: float, tol: float,
         check_rot: bool) -> tuple[FloatArray, NDArray[np.int64]]:
    """The float row (free value, exactness tolerance, chain solved, constant rows, whole
    chain, limits) and the integer header (plan, joint kinds and order, whether the
    rotation is checked) that :func:`run` unpacks."""
    floats = np.concatenate([[value, tol], sub.H.ravel(), sub.P.ravel(), sub.M.ravel(), A.ravel(), full.H.ravel(),
                             full.P.ravel(), full.M.ravel(), lo, hi])
    head = [p.kind, p.case, *p.idx, -1 if p.free is None else p.free, int(p.reversed), sub.n, full.n, int(check_rot)]
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
    """Screws H (m, 3), P (m, 3) and M (4, 4) packed in g from ``at`` (views of g)."""
    H = g[at:at + 3 * m].reshape((m, 3))
    P = g[at + 3 * m:at + 6 * m].reshape((m, 3))
    return H, P, g[at + 6 * m:at + 6 * m + 16].reshape((4, 4))


@numba.njit(**JIT)
def _whole(gf: np.ndarray, gi: np.ndarray) -> tuple:
    """The whole chain packed after the solved one: H, P, M, limits lo, hi, joint kinds
    (nonzero: revolute); views of gf and gi."""
    m, n = gi[8], gi[9]
    at = _FHEAD + 6 * m + 37
    row = gf[0]
    H, P, M = _chain(row, at, n)
    at += 6 * n + 16
    return H, P, M, row[at:at + n], row[at + n:at + 2 * n], gi[_HEAD + 2 * m:_HEAD + 2 * m + n]


@numba.njit(**JIT)
def pass1(gf: np.ndarray, gi: np.ndarray, Ts: np.ndarray, q0: np.ndarray, mode: int, start: int, stop: int,
           raw: np.ndarray, code: np.ndarray, count: np.ndarray, exact: np.ndarray, total: np.ndarray) -> None:
    """Poses start..stop-1, a block of :data:`~robot_sim.ik.block.POSES` at a time: the
    family's kernel for each free value (row v of gf is packed at its value) on every pose
    of the block at once (:mod:`robot_sim.ik.block`), the branches mapped onto the whole
    chain into raw[i] (K·V, n)
    (the angles the kernels give by cosine and sine taken by
    :func:`robot_sim.kernels.atan2.atan2_row`, every lane of a block at once),
    checked by :func:`robot_sim.ik.finish.fk_lanes` a block of poses at a time (at least
    :data:`BLOCK` branches together; within the limits only those that may have a turn
    inside them, :func:`robot_sim.ik.finish.check_within`), then
    :func:`robot_sim.ik.finish.screen`: count[i] branches kept (within the limits, those
    with a turn inside them), total[i] solutions.  For
    :data:`~robot_sim.ik.finish.RAW` the kept branches are sorted and padded as pass 2
    would write them (:func:`robot_sim.ik.finish.sort_raw`), so that a batch as wide as
    K·V needs no pass 2 (:func:`raw_is_answer`)."""
    kind, case, free, rev_chain, m, n = gi[0], gi[1], gi[6], gi[7] != 0, gi[8], gi[9]
    check_rot = gi[10] != 0
    idx = gi[2:6]
    revs = gi[_HEAD:_HEAD + m]  # nonzero: revolute
    keep = gi[_HEAD + m:_HEAD + 2 * m]
    K, V = BRANCH_COUNTS[kind], gf.shape[0]
    L = K * V  # lanes per pose
    G = max(1, min(POSES, BLOCK // L, stop - start))  # poses per block (no more than asked: scratch costs)
    tol = gf[0, 1]
    Hf, Pf, Mf, lo, hi, revf = _whole(gf, gi)
    W, C = scratch()  # the solvers' block (robot_sim.ik.block)
    lq, lcs = np.zeros((n, G * L)), np.zeros((2 * n, G * L))  # lanes never written stay finite
    pose, pos, rot = np.full(G * L, start), np.empty(G * L), np.empty(G * L)
    S = np.empty(12 * LANES)
    alive, lanes, gpose = np.empty(G * L, dtype=np.bool_), np.empty(G * L, dtype=np.int64), np.empty_like(pose)
    gq, gcs, gpos, grot = np.empty_like(lq), np.empty_like(lcs), np.empty(G * L), np.empty(G * L)  # check_within's
    key, order, rows = np.empty(L), np.empty(L, dtype=np.int64), np.empty((L, n))
    spare = np.empty(L + RADIX, dtype=np.int64)
    q0s, D = np.empty(m), np.empty((m, 2))  # q0's values of the chain solved, their cosines and sines
    for j in range(m):
        q0s[j] = q0[keep[j]]
        D[j, 0], D[j, 1] = math.cos(q0s[j]), math.sin(q0s[j])
    row = gf[0]  # views made once: each view of an array costs two atomic reference counts
    Hs, Ps, Ms = _chain(row, _FHEAD, m)
    A = row[_FHEAD + 6 * m + 16:_FHEAD + 6 * m + 37].reshape((7, 3))
    for i0 in range(start, stop, G):
        i1 = min(i0 + G, stop)
        B = i1 - i0
        load_poses(Ts, i0, B, rev_chain, W)
        for v in range(V):
            if V > 1:
                row = gf[v]
                Hs, Ps, Ms = _chain(row, _FHEAD, m)
                A = row[_FHEAD + 6 * m + 16:_FHEAD + 6 * m + 37].reshape((7, 3))
            if kind == SPHERICAL_WRIST:
                spherical_wrist(case, Hs, Ps, revs, A, B, D, W, C)
            elif kind == THREE_PARALLEL:
                three_parallel(Hs, Ps, Ms, A, B, q0s, D, W, C)
            elif kind == PARALLEL_AXES:
                parallel_axes(idx, Hs, Ps, A, B, q0s, m, W, C)
            else:
                position_only(case, Hs, Ps, A, B, D, W, C)
            for i in range(i0, i1):  # the K branches of every pose, for this free value
                g = i - i0
                for k in range(K):
                    at = v * K + k
                    lane = g * L + at
                    plane, b = branch_lane(k, g)
                    values, c = OUT_ROWS + plane * MAX_JOINTS, CS_ROWS + 2 * plane * MAX_JOINTS
                    for j in range(m):
                        raw[i, at, keep[j]] = get(W, values + j, b)
                        lcs[2 * keep[j], lane] = get(W, c + 2 * j, b)
                        lcs[2 * keep[j] + 1, lane] = get(W, c + 2 * j + 1, b)
                    if free >= 0:
                        raw[i, at, free] = row[0]
                        lcs[2 * free, lane] = np.nan  # to_lane takes its cosine and sine from its value
                    code[i, at] = C[plane * BLOCK_LANES + b]
                    pose[lane] = i
        for j in range(n):  # the angles of the cosines and sines, all lanes at once
            if revf[j] and j != free and kind != PARALLEL_AXES:  # (these two give values, no cosines)
                atan2_row(lcs, 2 * j + 1, lcs, 2 * j, lq, j, (i1 - i0) * L)
        for i in range(i0, i1):
            for at in range(L):
                to_lane(raw, i, at, revf, q0, lq, lcs, (i - i0) * L + at)
        if mode == RAW:
            fk_lanes(Hf, Pf, revf, Mf, Ts, pose, lq, lcs, (i1 - i0) * L, check_rot, S, pos, rot)
        else:
            check_within(Hf, Pf, revf, Mf, Ts, pose, lq, lcs, i1 - i0, L, lo, hi, tol, check_rot, S, pos, rot,
                         alive, lanes, gq, gcs, gpose, gpos, grot)
        for i in range(i0, i1):
            count[i], total[i] = screen(raw, code, exact, i, L, pos, rot, (i - i0) * L, revf, lo, hi, mode, tol,
                                        True)
            if mode == RAW:
                sort_raw(raw, code, exact, i, count[i], q0, key, order, spare, rows)


@numba.njit(**JIT)
def pass2(gf: np.ndarray, gi: np.ndarray, q0: np.ndarray, mode: int, start: int, stop: int,
           raw: np.ndarray, code: np.ndarray, count: np.ndarray, exact: np.ndarray,
           out: np.ndarray, out_code: np.ndarray, out_exact: np.ndarray, out_count: np.ndarray) -> None:
    """Poses start..stop-1: :func:`robot_sim.ik.finish.expand` into out[i] (W, n), the rows
    after its solutions padded (NaN, code -1, not exact)."""
    _, _, _, lo, hi, revf = _whole(gf, gi)
    W, n = out.shape[1], out.shape[2]
    work, dist = np.empty((W, n)), np.empty(W)
    source, order = np.empty(W, dtype=np.int64), np.empty(W, dtype=np.int64)
    spare = np.empty(W + RADIX, dtype=np.int64)
    digit, ways, first = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64), np.empty(n)
    for i in range(start, stop):
        k = expand(raw, code, exact, i, count[i], q0, lo, hi, revf, mode, out, out_code, out_exact,
                   work, dist, source, order, spare, digit, ways, first)
        for a in range(k, W):  # the padding
            for j in range(n):
                out[i, a, j] = np.nan
            out_code[i, a] = -1
            out_exact[i, a] = False
        out_count[i] = k


@numba.njit(**JIT)
def _q0_finite(q0: np.ndarray) -> bool:
    for j in range(q0.shape[0]):
        if not math.isfinite(q0[j]):
            return False
    return True


@numba.njit(**JIT)
def begin(gf: np.ndarray, gi: np.ndarray, Ts: np.ndarray, q0: np.ndarray) -> tuple[int, int]:
    """The checks of :func:`run`: (bad, K), K the raw branches per pose (0 when ``bad`` is
    not -1)."""
    bad = first_bad_pose(Ts, RIGID_TOL)
    if bad < 0 and not _q0_finite(q0):
        bad = BAD_Q0
    return bad, BRANCH_COUNTS[gi[0]] * gf.shape[0] if bad == -1 else 0


def pass1_arrays(N: int, K: int, n: int) -> tuple:
    """Pass 1's arrays (raw, code, count, exact, total) for N poses of K raw branches of n
    joints; pass 1 writes every entry it reads, so none is filled.  Plain Python, so that
    a batch from Python gets NumPy's arrays (on huge pages: a tenth of the page faults),
    and compiled as :func:`_pass1_arrays` for :func:`run`."""
    return (np.empty((N, K, n)), np.empty((N, K), dtype=np.int64), np.zeros(N, dtype=np.int64),
            np.empty((N, K), dtype=np.bool_), np.zeros(N, dtype=np.int64))


def pass2_arrays(N: int, width: int, n: int) -> tuple:
    """Pass 2's arrays (out, out_code, out_exact, out_count); pass 2 writes every entry,
    padding included.  Plain Python as :func:`pass1_arrays`, compiled as :func:`_pass2_arrays`."""
    return (np.empty((N, width, n)), np.empty((N, width), dtype=np.int64), np.empty((N, width), dtype=np.bool_),
            np.zeros(N, dtype=np.int64))


_pass1_arrays = numba.njit(**JIT)(pass1_arrays)
_pass2_arrays = numba.njit(**JIT)(pass2_arrays)


@numba.njit(**JIT)
def width(total: np.ndarray, n: int) -> tuple[int, int]:
    """(W, needed): the most solutions of a pose in ``total`` and needed = N·W·n, W = 0
    when ``needed`` exceeds :data:`MAX_VALUES` (nothing is allocated then)."""
    W = 0
    for i in range(total.shape[0]):
        W = max(W, total[i])
    needed = total.shape[0] * W * n
    return (0 if needed > MAX_VALUES else W), needed


def raw_is_answer(mode: int, W: int, raw: np.ndarray) -> bool:
    """Whether pass 1's arrays are already the answer: :data:`~robot_sim.ik.finish.RAW`
    branches (sorted and padded by pass 1) as wide as the answer."""
    return mode == RAW and W == raw.shape[1]


_raw_is_answer = numba.njit(**JIT)(raw_is_answer)


@numba.njit(**JIT)
def run(gf: np.ndarray, gi: np.ndarray, Ts: np.ndarray, q0: np.ndarray, mode: int) -> tuple:
    """Solutions of every pose Ts[i] (N, 4, 4), for each free value gf holds, with the
    turns ``mode`` asks (RAW, EVERY_TURN or NEAREST_TURN of :mod:`robot_sim.ik.finish`).  Returns
    (q, code, exact, count, needed, bad): q (N, K, n) NaN-padded, nearest q0 first;
    ``needed`` = N·K·n, and empty arrays (K = 0) when it exceeds :data:`MAX_VALUES`; ``bad`` the
    index of the first pose that is not a rigid transform (:data:`RIGID_TOL`), or
    :data:`BAD_Q0` for a q0 with NaN or infinite values (then nothing is solved and
    count is 0), else -1.  In this thread; :func:`robot_sim.ik.threads.run_threads` runs
    the same passes on chunks of a large batch."""
    N, n = Ts.shape[0], gi[9]
    bad, K = begin(gf, gi, Ts, q0)
    raw, code, count, exact, total = _pass1_arrays(N, K, n)
    if bad != -1:
        return raw, code, exact, count, 0, bad
    pass1(gf, gi, Ts, q0, mode, 0, N, raw, code, count, exact, total)
    W, needed = width(total, n)
    if _raw_is_answer(mode, W, raw):
        return raw, code, exact, count, needed, -1
    out, out_code, out_exact, out_count = _pass2_arrays(N, W, n)
    if needed > MAX_VALUES:
        return out, out_code, out_exact, total, needed, -1
    pass2(gf, gi, q0, mode, 0, N, raw, code, count, exact, out, out_code, out_exact, out_count)
    return out, out_code, out_exact, out_count, needed, -1


@numba.njit(**JIT)
def run_one(gf: np.ndarray, gi: np.ndarray, T: np.ndarray, q0: np.ndarray, mode: int) -> tuple:
    """:func:`run` of the one pose T (4, 4): (q (k, n), code (k,), exact (k,), needed, bad)."""
    q, code, exact, count, needed, bad = run(gf, gi, T.reshape((1, 4, 4)), q0, mode)
    if q.shape[1] == 0:  # not solved, or no solution
        return np.empty((0, q.shape[2])), np.empty(0, dtype=np.int64), np.empty(0, dtype=np.bool_), needed, bad
    k = count[0]
    return q[0, :k], code[0, :k], exact[0, :k], needed, bad


@numba.njit(**JIT)
def reach_error(gf: np.ndarray, gi: np.ndarray, q: np.ndarray, T: np.ndarray) -> tuple[float, float]:
    """Position error [m] and rotation angle [rad] of the tool at q (n,) against T (4, 4),
    on the whole chain packed in gf, gi."""
    H, P, M, _, _, rev = _whole(gf, gi)
    n = q.shape[0]
    lq, lcs = np.empty((n, 1)), np.empty((2 * n, 1))
    for j in range(n):
        lq[j, 0], lcs[2 * j, 0], lcs[2 * j + 1, 0] = q[j], math.cos(q[j]), math.sin(q[j])
    pos, rot = np.empty(1), np.empty(1)
    fk_lanes(H, P, rev, M, T.reshape((1, 4, 4)), np.zeros(1, dtype=np.int64), lq, lcs, 1, True,
             np.empty(12 * LANES), pos, rot)
    return pos[0], chord_angle(rot[0])


@numba.njit(**JIT)
def nearest_solution(gf: np.ndarray, gi: np.ndarray, T: np.ndarray, q0: np.ndarray, mode: int) -> tuple:
    """The first exact solution :func:`run_one` lists for T (4, 4), with its position [m]
    and rotation [rad] errors (:func:`reach_error`): (q (n,), pos, rot, found, bad)."""
    q, _, exact, _, bad = run_one(gf, gi, T, q0, mode)
    for k in range(q.shape[0]):
        if exact[k]:
            pos, rot = reach_error(gf, gi, q[k], T)
            return q[k].copy(), pos, rot, True, bad
    return np.zeros(q.shape[1]), 0.0, 0.0, False, bad
