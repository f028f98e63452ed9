"""From raw branches to the answer (compiled): which branches reach the pose, their
turns inside the joint limits, duplicates dropped, nearest to q0 first.

Two passes so that the output is sized by the largest count of the batch, not by the
worst case (a UR arm's ±2π joints give up to 2⁶ turns per branch):

1. :func:`fk_lanes` checks the raw branches by forward kinematics on the whole chain
   (many at once: :func:`to_lane` puts each in a lane), and :func:`screen` keeps, per
   pose, the exact ones: those putting the tool within ``tol`` of T (metres, and radians
   as the Frobenius distance of the rotations over √2); if none is, every branch is kept
   as the least-squares answer.  Duplicates (equal modulo 2π) go, and each branch counts
   its turns inside the limits; in the pipeline's pass 1 the branches with none go too,
   and (:func:`check_within`) only the branches that may have one are checked, the
   others only for a pose that none of those reaches.
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

from robot_sim.kernels.jit import JIT, UNCOUNTED

TWO_PI = 2.0 * math.pi
#: Turns per radian: angles are divided by 2π as a product (a division takes several times as long).
PER_TURN = 1.0 / TWO_PI
#: Two branches closer than this in every joint (modulo 2π for revolute ones) are one.
SAME = 1e-9
#: A joint value this far outside a limit still counts as on it (and is clipped to it).
EDGE = 1e-10
#: Which turns of the revolute angles are solutions (module docstring).
RAW, EVERY_TURN, NEAREST_TURN = 0, 1, 2


#: Branches checked at once by :func:`fk_lanes`: its loops over them run on the vector
#: registers (AVX-512: 8 lanes, twice) when this many are checked together.
LANES = 16


@numba.njit(**UNCOUNTED)
def fk_lanes(H: np.ndarray, P: np.ndarray, rev: np.ndarray, M: np.ndarray, Ts: np.ndarray, pose: np.ndarray,
             q: np.ndarray, cs: np.ndarray, m: int, check_rot: bool, S: np.ndarray, pos: np.ndarray,
             rot: np.ndarray) -> None:
    """Position error pos[k] [m] and (with ``check_rot``, else 0) rotation chord rot[k] of
    the tool at the joint values q[:, k] (n, L) against the pose Ts[pose[k]] (world), for
    the lanes k < m, by the product of exponentials.  cs (2n, L) holds cos q_j, sin q_j at
    rows 2j, 2j + 1 for every revolute joint.  The chord ‖R_q − R_T‖_F / √2 is 2 sin(θ/2)
    for the angle θ [rad] between the rotations (:func:`chord_angle`), θ to within θ³/24.

    The lanes go :data:`LANES` at a time, joint by joint, each loop over them one
    compiled vector loop (the chain's rotation and offset of lane k live in
    S[a·LANES + k], a = 0..11: rows of R, then t); every lane gets the same arithmetic,
    so a lane's answer does not depend on its neighbours."""
    n = H.shape[0]
    for b in range(0, m, LANES):
        w = min(LANES, m - b)
        for k in range(w):
            S[k], S[LANES + k], S[2 * LANES + k] = 1.0, 0.0, 0.0
            S[3 * LANES + k], S[4 * LANES + k], S[5 * LANES + k] = 0.0, 1.0, 0.0
            S[6 * LANES + k], S[7 * LANES + k], S[8 * LANES + k] = 0.0, 0.0, 1.0
            S[9 * LANES + k], S[10 * LANES + k], S[11 * LANES + k] = 0.0, 0.0, 0.0
        for j in range(n):
            h0, h1, h2 = H[j, 0], H[j, 1], H[j, 2]
            if not rev[j]:
                for k in range(w):
                    o0, o1, o2 = q[j, b + k] * h0, q[j, b + k] * h1, q[j, b + k] * h2
                    S[9 * LANES + k] += S[k] * o0 + S[LANES + k] * o1 + S[2 * LANES + k] * o2
                    S[10 * LANES + k] += S[3 * LANES + k] * o0 + S[4 * LANES + k] * o1 + S[5 * LANES + k] * o2
                    S[11 * LANES + k] += S[6 * LANES + k] * o0 + S[7 * LANES + k] * o1 + S[8 * LANES + k] * o2
                continue
            # R_j = c I + s [h]× + (1 − c) h hᵀ; its offset p − R_j p = (1 − c) (p − h hᵀp) − s h × p
            x, y, z = P[j, 0], P[j, 1], P[j, 2]
            hp = h0 * x + h1 * y + h2 * z
            u0, u1, u2 = x - hp * h0, y - hp * h1, z - hp * h2
            w0, w1, w2 = h1 * z - h2 * y, h2 * x - h0 * z, h0 * y - h1 * x
            g00, g01, g02, g11, g12, g22 = h0 * h0, h0 * h1, h0 * h2, h1 * h1, h1 * h2, h2 * h2
            for k in range(w):
                c, s = cs[2 * j, b + k], cs[2 * j + 1, b + k]
                v = 1.0 - c
                a00, a01, a02 = c + v * g00, v * g01 - s * h2, v * g02 + s * h1
                a10, a11, a12 = v * g01 + s * h2, c + v * g11, v * g12 - s * h0
                a20, a21, a22 = v * g02 - s * h1, v * g12 + s * h0, c + v * g22
                o0, o1, o2 = v * u0 - s * w0, v * u1 - s * w1, v * u2 - s * w2
                r00, r01, r02 = S[k], S[LANES + k], S[2 * LANES + k]
                r10, r11, r12 = S[3 * LANES + k], S[4 * LANES + k], S[5 * LANES + k]
                r20, r21, r22 = S[6 * LANES + k], S[7 * LANES + k], S[8 * LANES + k]
                S[9 * LANES + k] += r00 * o0 + r01 * o1 + r02 * o2  # moved by the chain so far
                S[10 * LANES + k] += r10 * o0 + r11 * o1 + r12 * o2
                S[11 * LANES + k] += r20 * o0 + r21 * o1 + r22 * o2
                S[k] = r00 * a00 + r01 * a10 + r02 * a20
                S[LANES + k] = r00 * a01 + r01 * a11 + r02 * a21
                S[2 * LANES + k] = r00 * a02 + r01 * a12 + r02 * a22
                S[3 * LANES + k] = r10 * a00 + r11 * a10 + r12 * a20
                S[4 * LANES + k] = r10 * a01 + r11 * a11 + r12 * a21
                S[5 * LANES + k] = r10 * a02 + r11 * a12 + r12 * a22
                S[6 * LANES + k] = r20 * a00 + r21 * a10 + r22 * a20
                S[7 * LANES + k] = r20 * a01 + r21 * a11 + r22 * a21
                S[8 * LANES + k] = r20 * a02 + r21 * a12 + r22 * a22
        for k in range(w):
            r00, r01, r02 = S[k], S[LANES + k], S[2 * LANES + k]
            r10, r11, r12 = S[3 * LANES + k], S[4 * LANES + k], S[5 * LANES + k]
            r20, r21, r22 = S[6 * LANES + k], S[7 * LANES + k], S[8 * LANES + k]
            i = pose[b + k]
            e0 = S[9 * LANES + k] + r00 * M[0, 3] + r01 * M[1, 3] + r02 * M[2, 3] - Ts[i, 0, 3]
            e1 = S[10 * LANES + k] + r10 * M[0, 3] + r11 * M[1, 3] + r12 * M[2, 3] - Ts[i, 1, 3]
            e2 = S[11 * LANES + k] + r20 * M[0, 3] + r21 * M[1, 3] + r22 * M[2, 3] - Ts[i, 2, 3]
            pos[b + k] = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            chord = 0.0
            if check_rot:
                for a in range(3):
                    m0, m1, m2 = M[0, a], M[1, a], M[2, a]
                    e0 = r00 * m0 + r01 * m1 + r02 * m2 - Ts[i, 0, a]
                    e1 = r10 * m0 + r11 * m1 + r12 * m2 - Ts[i, 1, a]
                    e2 = r20 * m0 + r21 * m1 + r22 * m2 - Ts[i, 2, a]
                    chord += e0 * e0 + e1 * e1 + e2 * e2
            rot[b + k] = math.sqrt(0.5 * chord)


@numba.njit(inline="always", **JIT)
def chord_angle(chord: float) -> float:
    """The angle θ [rad] of a rotation chord 2 sin(θ/2) (:func:`fk_lanes`)."""
    return 2.0 * math.asin(min(1.0, 0.5 * chord))


# Whole numbers of turns are rounded in floating point (np.rint, np.ceil, np.floor), not by
# Python's round and math's ceil and floor, which give integers: the trip to an integer and
# back is two conversions on the critical path of every joint of every branch.  The same
# numbers result; ``+ 0.0`` makes a rounded −0 the +0 an integer would give.


@numba.njit(inline="always", **JIT)
def nearest_turn(x: float, target: float) -> float:
    return x + TWO_PI * (np.rint((target - x) * PER_TURN) + 0.0)


@numba.njit(**JIT)
def turns(x: float, lo: float, hi: float) -> tuple[float, int]:
    """(first turn of angle x at or above lo, how many turns lie in [lo, hi])."""
    first = x + TWO_PI * (np.ceil((lo - EDGE - x) * PER_TURN) + 0.0)
    return first, int(max(0.0, np.floor((hi + EDGE - first) * PER_TURN) + 1.0))  # (no branch to mispredict)


@numba.njit(inline="always", **JIT)
def turns_inside(x: float, revolute: bool, lo: float, hi: float, slack: float) -> tuple[float, int]:
    """The one rule for a joint value x inside its limits [lo, hi] widened by ``slack``
    (and :data:`EDGE`): (first turn, how many turns) of :func:`turns` for a revolute joint
    with both limits finite, else (x, whether x lies inside: 0 or 1)."""
    if revolute and math.isfinite(lo) and math.isfinite(hi):
        return turns(x, lo - slack, hi + slack)
    return x, int((lo - EDGE - slack <= x) & (x <= hi + EDGE + slack))  # (no branch on the value to mispredict)


#: Slack [rad, m] on the limits when pass 1 picks the branches worth checking
#: (:func:`check_within`): more than :data:`SAME` + :data:`EDGE`, so that a branch left
#: unchecked is never the duplicate of one with a turn inside the limits.
SLACK = 1e-8


@numba.njit(inline="always", **JIT)
def live_lanes(q: np.ndarray, rev: np.ndarray, lo: np.ndarray, hi: np.ndarray, m: int, alive: np.ndarray,
               lanes: np.ndarray) -> int:
    """The lanes k < m whose joint values q[:, k] (n, L) have a turn inside the limits
    widened by :data:`SLACK` (finite values only), listed in lanes[:count], with alive[k]
    (m,) telling each; returns count.  Joint by joint over all lanes, as the lanes lie."""
    n = q.shape[0]
    for k in range(m):
        alive[k] = True
    for j in range(n):
        for k in range(m):
            alive[k] &= turns_inside(q[j, k], rev[j], lo[j], hi[j], SLACK)[1] > 0
    count = 0
    for k in range(m):  # (without a branch: lanes[count] is overwritten until a live lane keeps it)
        lanes[count] = k
        count += alive[k]
    return count


@numba.njit(**UNCOUNTED)
def fk_some(H: np.ndarray, P: np.ndarray, rev: np.ndarray, M: np.ndarray, Ts: np.ndarray, pose: np.ndarray,
            q: np.ndarray, cs: np.ndarray, lanes: np.ndarray, m: int, check_rot: bool, S: np.ndarray,
            pos: np.ndarray, rot: np.ndarray, gq: np.ndarray, gcs: np.ndarray, gpose: np.ndarray,
            gpos: np.ndarray, grot: np.ndarray) -> None:
    """:func:`fk_lanes` of the lanes lanes[:m] only, their errors into pos and rot at their
    lanes: gathered side by side into gq, gcs, gpose (checked there into gpos, grot), so
    that the vector loops run full.  A lane's errors do not depend on its neighbours, so
    they are those :func:`fk_lanes` of every lane would give."""
    for a in range(m):
        k = lanes[a]
        for j in range(q.shape[0]):
            gq[j, a] = q[j, k]
        for j in range(cs.shape[0]):
            gcs[j, a] = cs[j, k]
        gpose[a] = pose[k]
    fk_lanes(H, P, rev, M, Ts, gpose, gq, gcs, m, check_rot, S, gpos, grot)
    for a in range(m):
        pos[lanes[a]], rot[lanes[a]] = gpos[a], grot[a]


@numba.njit(inline="always", **JIT)
def lane_exact(q: np.ndarray, pos: np.ndarray, rot: np.ndarray, k: int, tol: float) -> bool:
    """Whether lane k reaches its pose, as :func:`screen` judges it: finite joint values
    and both errors within ``tol``."""
    finite = True
    for j in range(q.shape[0]):
        finite = finite and math.isfinite(q[j, k])
    return finite and max(pos[k], rot[k]) <= tol


@numba.njit(**UNCOUNTED)
def check_within(H: np.ndarray, P: np.ndarray, rev: np.ndarray, M: np.ndarray, Ts: np.ndarray, pose: np.ndarray,
                 q: np.ndarray, cs: np.ndarray, poses: int, L: int, lo: np.ndarray,
                 hi: np.ndarray, tol: float, check_rot: bool, S: np.ndarray, pos: np.ndarray, rot: np.ndarray,
                 alive: np.ndarray, lanes: np.ndarray, gq: np.ndarray, gcs: np.ndarray, gpose: np.ndarray,
                 gpos: np.ndarray, grot: np.ndarray) -> None:
    """The errors pos, rot of the lanes :func:`screen` needs when only turns inside the
    limits are asked, for ``poses`` poses of L branches each (pose p's from lane p·L): by :func:`fk_some`, first of the lanes with a turn inside the limits
    (:func:`live_lanes`); the others get infinite errors, unless no checked lane of their
    pose reaches it.  Only then does :func:`screen` need them: whether any branch is exact
    decides which are kept, and a branch out of the limits writes no solution, nor (by
    :data:`SLACK`) is it the duplicate of one that does.  So :func:`screen` keeps the same
    branches as with every lane checked, for about half the checks (PUMA 560)."""
    m = poses * L
    for k in range(m):
        pos[k], rot[k] = math.inf, math.inf
    live = live_lanes(q, rev, lo, hi, m, alive, lanes)
    fk_some(H, P, rev, M, Ts, pose, q, cs, lanes, live, check_rot, S, pos, rot, gq, gcs, gpose, gpos, grot)
    rest = 0
    for p in range(poses):
        reached = False
        for k in range(p * L, (p + 1) * L):
            reached = reached or (alive[k] and lane_exact(q, pos, rot, k, tol))
        if not reached:
            for k in range(p * L, (p + 1) * L):
                if not alive[k]:
                    lanes[rest] = k
                    rest += 1
    fk_some(H, P, rev, M, Ts, pose, q, cs, lanes, rest, check_rot, S, pos, rot, gq, gcs, gpose, gpos, grot)


@numba.njit(inline="always", **JIT)
def to_lane(raw: np.ndarray, i: int, k: int, rev: np.ndarray, q0: np.ndarray, q: np.ndarray, cs: np.ndarray,
            lane: int) -> None:
    """Branch k of pose i, raw[i, k] (n,), into lane ``lane`` of :func:`fk_lanes`' q
    (n, L) and cs (2n, L).  A revolute angle whose cosine and sine cs holds is the one q
    holds already (their atan2), any other value is raw's; finite revolute angles are
    turned nearest q0 (in raw too), and the cosines and sines that are NaN (not known)
    computed from the angles."""
    for j in range(raw.shape[2]):
        known = cs[2 * j, lane] == cs[2 * j, lane]
        x = q[j, lane] if rev[j] and known else raw[i, k, j]
        if rev[j] and math.isfinite(x):
            x = nearest_turn(x, q0[j])
        raw[i, k, j] = x
        if rev[j] and not known:
            cs[2 * j, lane], cs[2 * j + 1, lane] = math.cos(x), math.sin(x)
        q[j, lane] = x


@numba.njit(inline="always", **JIT)
def screen(raw: np.ndarray, code: np.ndarray, exact: np.ndarray, i: int, m: int, pos: np.ndarray, rot: np.ndarray,
           e0: int, rev: np.ndarray, lo: np.ndarray, hi: np.ndarray, mode: int, tol: float,
           live_only: bool) -> tuple[int, int]:
    """Pass 1 of pose i, in place: of its m raw branches raw[i, :m] (K, n) and
    code[i, :m], their errors against the pose in pos[e0 + k] and rot[e0 + k]
    (:func:`fk_lanes`; overwritten), the distinct ones kept (exact ones if any) move to
    the front, with exact[i, k].  A branch with a value that is not finite is never
    kept.  With ``live_only``, in the modes within the limits, only the kept branches
    with a turn inside them stay (:func:`expand` writes nothing for the others, and
    skips them then).  Returns (how many are kept, how many solutions they expand to)."""
    n = raw.shape[2]
    any_exact = False
    for k in range(m):
        err = max(pos[e0 + k], rot[e0 + k])
        for j in range(n):
            if not math.isfinite(raw[i, k, j]):
                err = math.inf
        pos[e0 + k] = err
        any_exact = any_exact or err <= tol
    kept = 0
    for k in range(m):
        err = pos[e0 + k]
        if (any_exact and err > tol) or not math.isfinite(err):
            continue
        duplicate = False
        for k2 in range(kept):
            same = True
            for j in range(n):
                d = abs(raw[i, k, j] - raw[i, k2, j])
                if rev[j] and d > math.pi:  # (a whole turn apart is the same angle)
                    d = abs(nearest_turn(d, 0.0))
                if d > SAME:
                    same = False
                    break
            if same:
                duplicate = True
                break
        if duplicate:
            continue
        for j in range(n):
            raw[i, kept, j] = raw[i, k, j]
        code[i, kept] = code[i, k]
        exact[i, kept] = err <= tol
        kept += 1
    if mode == RAW:  # one solution per branch
        return kept, kept
    total, live = 0, 0
    for k in range(kept):
        ways = 1
        for j in range(n):
            ways *= turns_inside(raw[i, k, j], rev[j], lo[j], hi[j], 0.0)[1]
        total += ways if mode == EVERY_TURN else min(ways, 1)
        if live_only:  # branch k to row ``live``, which only a live branch then keeps
            for j in range(n):
                raw[i, live, j] = raw[i, k, j]
            code[i, live], exact[i, live] = code[i, k], exact[i, k]
            live += ways > 0
    return (live if live_only else kept), total


#: Up to this many solutions are sorted by rank, more by their keys' bytes.
SHORT = 16
#: Counters of :func:`stable_order`'s radix sort, one per value of a byte; ``spare`` holds
#: them after its first m entries.
RADIX = 256


@numba.njit(inline="always", **JIT)
def _radix_pass(bits: np.ndarray, m: int, shift: int, src: np.ndarray, dst: np.ndarray, count: np.ndarray) -> bool:
    """One stable counting pass of src[:m] into dst by the byte of bits at ``shift``;
    False (and nothing moved) when every key has the same byte there."""
    count[:] = 0
    for a in range(m):
        count[(bits[a] >> shift) & 0xFF] += 1
    if count[(bits[0] >> shift) & 0xFF] == m:
        return False
    total = 0
    for d in range(RADIX):
        total, count[d] = total + count[d], total
    for a in range(m):
        s = src[a]
        d = (bits[s] >> shift) & 0xFF
        dst[count[d]] = s
        count[d] += 1
    return True


@numba.njit(inline="always", **JIT)
def _count_sort(bits: np.ndarray, m: int, lowest: int, order: np.ndarray, spare: np.ndarray) -> None:
    """order[:m] = the indices of bits[:m] sorted stably by their bits from ``lowest`` up,
    a byte per counting pass (:func:`_radix_pass`), least significant first; ``spare``
    (m + :data:`RADIX`) is scratch."""
    count = spare[m:m + RADIX]
    for a in range(m):
        order[a] = a
    src, dst = order, spare
    in_order = True  # whether src is ``order``
    for shift in range(lowest, 64, 8):
        if _radix_pass(bits, m, shift, src, dst, count):
            src, dst = dst, src
            in_order = not in_order
    if not in_order:
        for a in range(m):
            order[a] = src[a]


#: Bits of a key that :func:`stable_order` sorts by counting (sign, exponent and 12 bits of
#: the mantissa), and most pairs of neighbours alike in them that insertion then sorts.
TOP_SHIFT, TIES = 40, 32


@numba.njit(**UNCOUNTED)
def stable_order(key: np.ndarray, m: int, order: np.ndarray, spare: np.ndarray) -> None:
    """order[:m] = the indices of key[:m] ascending, equal keys in index order (the
    permutation of a stable argsort), without allocating; ``spare`` (m + :data:`RADIX`,
    int64) is scratch.  Keys are never NaN and never negative (distances of finite joint
    values; no -0.0: a sum of squares from 0.0).

    Up to :data:`SHORT` keys each goes straight to its rank, the count of keys before it
    (smaller, or equal at a lower index): m² comparisons without a branch, which cost
    less than the mispredicted branches of an insertion sort.  More keys are sorted by the
    bytes of their bit patterns, least significant first (for floats ≥ 0 the patterns
    read as unsigned integers order as the values do): each pass counts and scatters,
    stably, and compares no two keys (a merge sort's comparisons mispredict half the time:
    420 keys took 23 µs that way); a pass whose byte is alike in every key is skipped.
    Only the top three bytes are sorted so (:data:`TOP_SHIFT`): keys that differ there are
    then in order, and neighbours alike in them (rare: 12 bits of mantissa) are put in
    order by insertion, which moves nothing else.  When more than :data:`TIES` neighbours
    are alike there, the five lower bytes are sorted too, the whole key by counting."""
    if m <= SHORT:
        for a in range(m):
            x, rank = key[a], 0
            for b in range(m):
                rank += (key[b] < x) | ((key[b] == x) & (b < a))
            order[rank] = a
        return
    bits = key[:m].view(np.uint64)
    _count_sort(bits, m, TOP_SHIFT, order, spare)
    ties = 0
    for a in range(1, m):
        ties += (bits[order[a]] >> TOP_SHIFT) == (bits[order[a - 1]] >> TOP_SHIFT)
    if ties > TIES:  # too many: every byte
        _count_sort(bits, m, 0, order, spare)
        return
    if ties == 0:
        return
    for a in range(1, m):  # insertion, stable (only neighbours alike in the top bytes move)
        s, x = order[a], key[order[a]]
        b = a - 1
        while b >= 0 and key[order[b]] > x:
            order[b + 1] = order[b]
            b -= 1
        order[b + 1] = s


@numba.njit(inline="always", **JIT)
def sort_raw(raw: np.ndarray, code: np.ndarray, exact: np.ndarray, i: int, kept: int, q0: np.ndarray,
             key: np.ndarray, order: np.ndarray, spare: np.ndarray, rows: np.ndarray) -> None:
    """Pose i's ``kept`` branches in place nearest q0 first (Euclidean, rad and m; equal
    distances in branch order), the rows after them padded (NaN, code -1, not exact): what
    :func:`expand` would write for :data:`RAW`.  key, order (K,), spare (K + RADIX) and rows (K, n)
    are scratch."""
    K, n = raw.shape[1], raw.shape[2]
    for k in range(kept):
        d2 = 0.0
        for j in range(n):
            d2 += (raw[i, k, j] - q0[j]) ** 2
        key[k] = d2
    stable_order(key, kept, order, spare)
    for k in range(kept):  # the rows, codes and exactness as they were (key and spare are free now)
        for j in range(n):
            rows[k, j] = raw[i, k, j]
        spare[k] = code[i, k]
        key[k] = 1.0 if exact[i, k] else 0.0
    for k in range(kept):
        b = order[k]
        for j in range(n):
            raw[i, k, j] = rows[b, j]
        code[i, k] = spare[b]
        exact[i, k] = key[b] != 0.0
    for k in range(kept, K):
        for j in range(n):
            raw[i, k, j] = np.nan
        code[i, k] = -1
        exact[i, k] = False


@numba.njit(inline="always", **JIT)
def expand(raw: np.ndarray, code: np.ndarray, exact: np.ndarray, i: int, kept: int, q0: np.ndarray,
           lo: np.ndarray, hi: np.ndarray, rev: np.ndarray, mode: int, out: np.ndarray, out_code: np.ndarray,
           out_exact: np.ndarray, work: np.ndarray, dist: np.ndarray, source: np.ndarray, order: np.ndarray,
           spare: np.ndarray, digit: np.ndarray, ways: np.ndarray, first: np.ndarray) -> int:
    """Pass 2 of pose i: every turn of each of its ``kept`` branches raw[i, :kept] (with
    code[i], exact[i]) into out[i] (W, n), nearest q0 first, with out_code[i] and
    out_exact[i]; returns how many.  The rest is scratch: work (W, n), dist, source,
    order (W,), spare (W + RADIX); digit, ways, first (n,).  (Indexed, not sliced: a view of an array
    costs two atomic reference counts.)"""
    n = raw.shape[2]
    limited = mode != RAW
    m = 0
    for k in range(kept):
        combos = 1
        for j in range(n):
            x = raw[i, k, j]
            f, w = turns_inside(x, rev[j], lo[j], hi[j], 0.0) if limited else (x, 1)
            first[j], ways[j], digit[j] = f, w, 0
            if mode == NEAREST_TURN and w > 1:  # one turn: the nearest q0 (the lowest on a tie)
                best = math.inf
                for d in range(w):
                    x = min(max(f + TWO_PI * d, lo[j]), hi[j])
                    if (x - q0[j]) ** 2 < best:
                        best, digit[j] = (x - q0[j]) ** 2, d
                ways[j] = digit[j] + 1  # the enumeration below stops after it
            combos *= ways[j] - digit[j]
        for c in range(combos):  # every combination of turns, joint 0 fastest
            d2 = 0.0
            for j in range(n):
                x = first[j] + TWO_PI * digit[j]
                if limited:
                    x = min(max(x, lo[j]), hi[j])
                work[m, j] = x
                d2 += (x - q0[j]) ** 2
            dist[m] = d2
            source[m] = k
            m += 1
            j = 0
            while c + 1 < combos:  # the next combination (none after the last)
                digit[j] += 1
                if digit[j] < ways[j]:
                    break
                digit[j] = 0
                j += 1
    stable_order(dist, m, order, spare)  # equal distances keep branch order
    for a in range(m):
        b = order[a]
        for j in range(n):
            out[i, a, j] = work[b, j]
        out_code[i, a] = code[i, source[b]]
        out_exact[i, a] = exact[i, source[b]]
    return m
