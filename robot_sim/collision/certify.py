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
  then the middle knot, then the quarters, ... (a colliding path usually shows it early);
* then each stretch between two asked rows a < b is proven free when, for every group,
  clearance(a) + clearance(b) exceeds C(b) - C(a) (no pair can close the gap from both
  ends), or a row inside it is asked (the middle of what neither end's clearance
  covers), depth first from the left.

Nothing proven free would be found colliding by asking every row.  Clearances are asked
exactly only up to the largest closing bound between two knots (beyond, a lower bound
that large is as good).  World frame, metres; no Qt, no OpenGL.
"""
from __future__ import annotations

import math

import numpy as np

from robot_sim.collision._jit import JIT, njit
from robot_sim.collision.batch import _gap, _pose, _workspace
from robot_sim.collision.narrow import pair_distance


@njit(**JIT)
def clearance_at(q, dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, group, padding, limit,
                 F, recs, wc, out):
    """out[g] = signed distance minus ``padding`` of group g's closest pair at q (n,):
    exact below ``limit[g]``, else a lower bound of at least it (inf when the bounding
    spheres tell).  When a pair is closer than the padding, every column gets that
    (negative) value and True is returned."""
    _pose(q, dh, modified, world0, link, local, bc, F, recs, wc)
    for g in range(out.shape[0]):
        out[g] = math.inf
    for p in range(pairs.shape[0]):
        g = group[p]
        cutoff = min(out[g], limit[g]) + padding
        i, j = pairs[p, 0], pairs[p, 1]
        if _gap(wc, br, i, j) >= cutoff:
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
        if not (da[g] + db[g] > cb[g] - ca[g]):
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
        if rate > 0.0:
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
    kq, kc = np.empty((nk, n)), np.empty((nk, G))
    for i in range(nk):
        _row(P, Mc, H, C, rs, krow[i], kq[i], kc[i])
    limit = np.full(G, math.inf)  # exact clearances are needed up to the largest knot-to-knot bound
    if nk > 1:
        for g in range(G):
            widest = 0.0
            for i in range(nk - 1):
                widest = max(widest, kc[i + 1, g] - kc[i, g])
            limit[g] = widest
    kd = np.empty((nk, G))
    first, count = R + 1, 0  # rows from `first` on are not asked
    # the knots, coarse to fine: both ends, then every span-th knot for span = 2^p, ..., 1
    span = 1
    while span < nk - 1:
        span *= 2
    order = np.empty(nk, dtype=np.int64)
    order[0], size = 0, 1
    if nk > 1:
        order[1], size = nk - 1, 2
    while span > 1:
        span //= 2
        for i in range(span, nk - 1, 2 * span):
            order[size] = i
            size += 1
    for idx in order:
        if krow[idx] >= first:
            continue
        count += 1
        if clearance_at(kq[idx], dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, group,
                        padding, limit, F, recs, wc, kd[idx]):
            if not first_only:
                return krow[idx], count
            first = min(first, krow[idx])
    # the stretches between knots, depth first from the left
    buf_d, buf_c = np.empty((stride + 2, G)), np.empty((stride + 2, G))
    stack = np.empty((stride + 2, 4), dtype=np.int64)  # rows a, b and their slots in buf
    q = np.empty(n)
    for i in range(nk - 1):
        if krow[i] >= first:
            break
        buf_d[0], buf_c[0], buf_d[1], buf_c[1] = kd[i], kc[i], kd[i + 1], kc[i + 1]
        slots, top = 2, 0
        stack[0, 0], stack[0, 1], stack[0, 2], stack[0, 3] = krow[i], krow[i + 1], 0, 1
        top = 1
        while top > 0:
            top -= 1
            a, b, sa, sb = stack[top, 0], stack[top, 1], stack[top, 2], stack[top, 3]
            if b - a <= 1 or a >= first or _proven(buf_d[sa], buf_d[sb], buf_c[sa], buf_c[sb]):
                continue
            m, sm = _split(a, b, buf_d[sa], buf_d[sb], buf_c[sa], buf_c[sb]), slots
            slots += 1
            _row(P, Mc, H, C, rs, m, q, buf_c[sm])
            count += 1
            if clearance_at(q, dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, group,
                            padding, limit, F, recs, wc, buf_d[sm]):
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
    for k in range(Q.shape[0]):
        clearance_at(Q[k], dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, group, padding,
                     limit, F, recs, wc, out[k])
