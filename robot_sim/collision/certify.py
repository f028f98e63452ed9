"""Compiled continuous checks of sampled joint paths: where is the first collision, asking
as few configurations as the clearances allow.

A path is a run of points P[0..K-1] (K, n) with ``steps[k]`` >= 1 equal steps from point k
to point k + 1 (its rows: the points and the configurations between them, numbered 0..R
along the path) and, per group of pairs, the cumulative bound ``C`` (K, G) on how much
the group's clearance can shrink from the path's start (linear between the points).
Between two points the path is a straight line, or the cubic of a spline span: second
derivatives ``Mc`` (K, n) at the points and the span's parameter length ``H`` (K,),
stepped evenly in its parameter.  Rows are consecutive at most the checker's resolution
apart, so asking every row is the continuous check; this asks fewer:

* the knots (every ``stride``-th row and the last) are asked coarse to fine: both ends,
  then the middle knot, then the quarters, ... (a colliding path usually shows it early),
  each only where the stretch between its two neighbours of the coarser level is not
  already proven free (below);
* then each stretch between two asked rows a < b is proven free when, for every group,
  clearance(a) + clearance(b) exceeds C(b) - C(a) (no pair can close the gap from both
  ends), or a row inside it is asked (the middle of what neither end's clearance
  covers), depth first from the left.

A row asked inside a stretch (or a knot between two coarser ones) computes only the
groups that the stretch's ends do not prove free; each of the others takes the lower
bound its ends give there (:func:`_inherit`), which keeps both halves proven for it.

Nothing proven free would be found colliding by asking every row.  Clearances are exact
only up to the bound of one knot interval (a stretch being split: its own bound), and
lower bounds beyond: any lower bound proves as soundly, a larger one only proves more.
World frame, metres; no Qt, no OpenGL.
"""
from __future__ import annotations

import math

import numpy as np

from robot_sim.collision import layout as L
from robot_sim.kernels.jit import JIT, njit
from robot_sim.collision.batch import _gap, _pose, _workspace
from robot_sim.collision.narrow import pair_distance, to_local

#: A knot's state in :func:`_first_hit`: asked, or inside a stretch already proven free.
ASKED, COVERED = 1, 2


@njit(**JIT)
def _lower_bound(kinds, recs, wc, br, i, j):
    """A lower bound of the distance of shape i (a robot shape: its bounding sphere) and
    shape j: the bounding spheres' gap, or i's bounding sphere against a half-space or a
    box j (tighter for a floor or a table than j's own bounding sphere)."""
    if kinds[j] == L.HALFSPACE:
        r = recs[j]
        return (r[2] * (wc[i, 0] - r[L.POS]) + r[5] * (wc[i, 1] - r[L.POS + 1]) + r[8] * (wc[i, 2] - r[L.POS + 2])
                - br[i])
    gap = _gap(wc, br, i, j)
    if kinds[j] == L.BOX:
        x, y, z = to_local(recs[j], (wc[i, 0], wc[i, 1], wc[i, 2]))
        dx = max(abs(x) - recs[j, L.HALF_X], 0.0)
        dy = max(abs(y) - recs[j, L.HALF_Y], 0.0)
        dz = max(abs(z) - recs[j, L.HALF_Z], 0.0)
        gap = max(gap, math.sqrt(dx * dx + dy * dy + dz * dz) - br[i])
    return gap


@njit(**JIT)
def clearance_at(q, dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, group, padding, limit,
                 known, F, recs, wc, out):
    """out[g] = signed distance minus ``padding`` of group g's closest pair at q (n,):
    exact below ``limit[g]``, else a lower bound of at least it (inf for a group without
    pairs); a group whose ``known[g]`` is not NaN takes that lower bound and its pairs are
    not looked at.  When a pair is closer than the padding, every column gets that
    (negative) value and True is returned."""
    _pose(q, dh, modified, world0, link, local, bc, F, recs, wc)
    for g in range(out.shape[0]):
        out[g] = math.inf if math.isnan(known[g]) else known[g]
    for p in range(pairs.shape[0]):
        g = group[p]
        if not math.isnan(known[g]):
            continue
        cutoff = min(out[g], limit[g]) + padding
        i, j = pairs[p, 0], pairs[p, 1]
        bound = _lower_bound(kinds, recs, wc, br, i, j)
        if bound >= cutoff:  # a lower bound is all that is needed of this pair
            out[g] = min(out[g], bound - padding)
            continue
        d = pair_distance(kinds[i], recs[i], kinds[j], recs[j], verts, cutoff)[0] - padding
        if d < out[g]:
            out[g] = d
        if d < 0.0:
            for h in range(out.shape[0]):
                out[h] = d
            return True
    return False


@njit(**JIT)
def _holds(da, db, ca, cb, g):
    """Whether group g's clearances da, db at two rows prove the stretch between them free
    (their sum exceeds the bound cb - ca on how much the group can close over it)."""
    return da[g] + db[g] > cb[g] - ca[g]


@njit(**JIT)
def _inherit(da, db, ca, cb, cm, known):
    """For a row between rows a and b with clearances da, db and closings ca, cm, cb: each
    group that the stretch's ends already prove free gets the lower bound its ends give at
    the row, max(da - (cm - ca), db - (cb - cm)) (positive, and it keeps both halves
    proven); the others NaN (to be computed).  Returns whether any is to be computed."""
    todo = False
    for g in range(da.shape[0]):
        if _holds(da, db, ca, cb, g):
            known[g] = max(da[g] - (cm[g] - ca[g]), db[g] - (cb[g] - cm[g]))
        else:
            known[g] = math.nan
            todo = True
    return todo


@njit(**JIT)
def _row(P, Mc, H, C, rs, r, q, c):
    """Configuration q (n,) and cumulative closing c (G,) of row r (rs: first row of each
    point): on the cubic from point k to k + 1 over a parameter length H[k] with second
    derivatives Mc[k], Mc[k + 1] at its ends (a straight line when they are 0), at the
    fraction of the segment's rows that r is; the closing grows linearly."""
    if rs.shape[0] == 1:  # a path of one point
        k, f = 0, 0.0
    else:
        k = min(np.searchsorted(rs, r, side="right") - 1, rs.shape[0] - 2)
        f = (r - rs[k]) / (rs[k + 1] - rs[k])
    if f == 0.0:
        q[:] = P[k]
    else:
        h = H[k]
        b = f * h
        a = h - b
        for j in range(q.shape[0]):
            m0, m1 = Mc[k, j], Mc[k + 1, j]
            q[j] = (m0 * a**3 + m1 * b**3) / (6.0 * h) + (P[k, j] / h - m0 * h / 6.0) * a \
                + (P[k + 1, j] / h - m1 * h / 6.0) * b
    for g in range(c.shape[0]):
        c[g] = C[k, g] + f * (C[k + 1, g] - C[k, g]) if f > 0.0 else C[k, g]


@njit(**JIT)
def _proven(da, db, ca, cb):
    """Whether the stretch between rows with clearances da, db and closings ca, cb is free."""
    for g in range(da.shape[0]):
        if not _holds(da, db, ca, cb, g):
            return False
    return True


@njit(**JIT)
def _split(a, b, da, db, ca, cb):
    """The row to ask between rows a < b - 1 whose clearances do not prove the stretch
    free: the middle of what neither end covers, taking each group's bound as growing
    evenly along the rows (rows a + 1 .. b - 1)."""
    reach_a, reach_b = b - a, b - a  # rows past a (before b) that each end keeps free
    for g in range(da.shape[0]):
        rate = (cb[g] - ca[g]) / (b - a)
        if rate > 0.0 and not _holds(da, db, ca, cb, g):  # a group proven on the stretch stays so
            reach_a = min(reach_a, max(da[g], 0.0) / rate)
            reach_b = min(reach_b, max(db[g], 0.0) / rate)
    m = int(0.5 * ((a + reach_a) + (b - reach_b)))
    return min(max(m, a + 1), b - 1)


@njit(**JIT)
def _first_hit(P, Mc, H, steps, C, stride, first_only, dh, modified, world0, link, local, recs0, kinds, bc, br, pairs,
               verts, group, padding, F, recs, wc):
    """(row, asked): the first colliding row of one path (``first_only``) or any colliding
    row (else), -1 when free; and the number of configurations asked."""
    K, n, G = P.shape[0], P.shape[1], C.shape[1]
    rs = np.zeros(K, dtype=np.int64)
    for k in range(K - 1):
        rs[k + 1] = rs[k] + steps[k]
    R = rs[K - 1]
    nk = (R + stride - 1) // stride + 1 if R > 0 else 1
    krow = np.empty(nk, dtype=np.int64)
    for i in range(nk):
        krow[i] = min(i * stride, R)
    kq, kc, kd = np.empty((nk, n)), np.empty((nk, G)), np.empty((nk, G))
    for i in range(nk):
        _row(P, Mc, H, C, rs, krow[i], kq[i], kc[i])
    state = np.zeros(nk, dtype=np.int64)  # ASKED, or COVERED: inside a stretch proven free
    first, count = R + 1, 0  # rows from `first` on are not asked
    cap, known = np.empty(G), np.empty(G)
    # the knots, coarse to fine: both ends, then every span-th knot for span = 2^p, ..., 1,
    # each only if the stretch between its two neighbours one span away is not proven free
    top_span = 1
    while top_span < nk - 1:
        top_span *= 2
    span = 2 * top_span
    while span > 1:
        span //= 2
        start, every = (0, max(nk - 1, 1)) if span == top_span else (span, 2 * span)
        for idx in range(start, nk, every):
            if state[idx] != 0 or krow[idx] >= first:
                continue
            lo, hi = max(idx - span, 0), min(idx + span, nk - 1)
            known[:] = math.nan
            if span < top_span:
                if state[lo] == COVERED or state[hi] == COVERED or (
                        state[lo] == ASKED and state[hi] == ASKED
                        and not _inherit(kd[lo], kd[hi], kc[lo], kc[hi], kc[idx], known)):
                    state[idx] = COVERED
                    continue
            else:
                lo, hi = 0, nk - 1
            for g in range(G):  # exact up to the bound of one knot interval (a lower bound beyond)
                cap[g] = (kc[hi, g] - kc[lo, g]) / max(hi - lo, 1)
            state[idx] = ASKED
            count += 1
            if clearance_at(kq[idx], dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, group,
                            padding, cap, known, F, recs, wc, kd[idx]):
                if not first_only:
                    return krow[idx], count
                first = min(first, krow[idx])
    # the stretches between consecutive asked knots, depth first from the left; a stretch
    # asks at most its rows inside, each taking one slot and adding at most one to the stack
    widest, prev = 1, 0
    for i in range(1, nk):
        if state[i] == ASKED:
            widest, prev = max(widest, krow[i] - krow[prev]), i
    buf_d, buf_c = np.empty((widest + 2, G)), np.empty((widest + 2, G))
    stack = np.empty((widest + 2, 4), dtype=np.int64)  # rows a, b and their slots in buf
    q = np.empty(n)
    prev = 0
    for i in range(1, nk):
        if krow[prev] >= first:
            break
        if state[i] != ASKED:
            continue
        buf_d[0], buf_c[0], buf_d[1], buf_c[1] = kd[prev], kc[prev], kd[i], kc[i]
        stack[0, 0], stack[0, 1], stack[0, 2], stack[0, 3] = krow[prev], krow[i], 0, 1
        slots, top, prev = 2, 1, i
        while top > 0:
            top -= 1
            a, b, sa, sb = stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3]
            if b - a <= 1 or a >= first or _proven(buf_d[sa], buf_d[sb], buf_c[sa], buf_c[sb]):
                continue
            m, sm = _split(a, b, buf_d[sa], buf_d[sb], buf_c[sa], buf_c[sb]), slots
            slots += 1
            _row(P, Mc, H, C, rs, m, q, buf_c[sm])
            _inherit(buf_d[sa], buf_d[sb], buf_c[sa], buf_c[sb], buf_c[sm], known)
            for g in range(G):
                cap[g] = buf_c[sb, g] - buf_c[sa, g]
            count += 1
            if clearance_at(q, dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, group,
                            padding, cap, known, F, recs, wc, buf_d[sm]):
                if not first_only:
                    return m, count
                first = min(first, m)
            stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3] = m, b, sm, sb
            stack[top + 1, 0], stack[top + 1, 1], stack[top + 1, 2], stack[top + 1, 3] = a, m, sa, sm
            top += 2
    return (first if first <= R else -1), count


@njit(**JIT)
def first_hits(P, Mc, H, steps, C, starts, stride, first_only, until_free, dh, modified, world0, link, local, recs0,
               kinds, bc, br, pairs, verts, group, padding, out):
    """For each path e in order (points ``starts[e]`` .. ``starts[e + 1] - 1`` of P, C and
    steps), out[e] = its first colliding row (``first_only``), or some colliding row, or
    -1 when free (module docstring); with ``until_free`` the paths after the first free one
    are not checked (-2).  Returns the number of configurations asked."""
    F, recs, wc = _workspace(dh, link, recs0, bc)
    total = 0
    out[:] = -2
    for e in range(starts.shape[0] - 1):
        s, t = starts[e], starts[e + 1]
        out[e], asked = _first_hit(P[s:t], Mc[s:t], H[s:t], steps[s:t], C[s:t], stride, first_only, dh, modified,
                                   world0, link, local, recs0, kinds, bc, br, pairs, verts, group, padding, F, recs, wc)
        total += asked
        if until_free and out[e] < 0:
            break
    return total


@njit(**JIT)
def clearance_batch(Q, dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, group, padding, limit,
                    out):
    """out[k] = :func:`clearance_at` of Q[k] for every row of Q (N, n)."""
    F, recs, wc = _workspace(dh, link, recs0, bc)
    known = np.full(out.shape[1], math.nan)
    for k in range(Q.shape[0]):
        clearance_at(Q[k], dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, group, padding,
                     limit, known, F, recs, wc, out[k])
