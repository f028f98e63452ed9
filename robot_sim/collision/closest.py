"""Closed-form closest points between cores and primitives (compiled scalar kernels).

Points and directions are 3-tuples of floats in metres.  Every pair function returns
``(d, a, b, n)``: the signed distance d (negative: penetration depth), a witness point
on each shape (a on the first, b on the second) and the unit normal n from the first
shape to the second, with ``b = a + d n`` always (so ``b - a`` points from the first
shape into the second when they are apart, and back out of it when they overlap).

Cores: a sphere is a point and a capsule a segment, each swept by its radius, so
:func:`inflate` turns a core result into the swept shapes' result exactly.
"""
from __future__ import annotations

import math

from robot_sim.kernels.algebra import cross, dot, madd, norm, scale, sub
from robot_sim.kernels.jit import JIT, njit

#: Squared length below which a segment is a point (m²).
DEGENERATE_SQ = 1e-30


@njit(**JIT)
def clamp01(x):
    return 0.0 if x < 0.0 else (1.0 if x > 1.0 else x)


@njit(**JIT)
def any_perpendicular(u):
    """A unit vector perpendicular to u (u need not be unit; (0, 0, 1) for u = 0)."""
    if abs(u[0]) < 0.6:
        p = cross(u, (1.0, 0.0, 0.0))
    else:
        p = cross(u, (0.0, 1.0, 0.0))
    m = norm(p)
    if m == 0.0:
        return (0.0, 0.0, 1.0)
    return scale(p, 1.0 / m)


@njit(**JIT)
def inflate(d, a, b, n, ra, rb):
    """The result for cores (d, a, b, n) swept by radii ``ra`` and ``rb``."""
    return d - ra - rb, madd(a, n, ra), madd(b, n, -rb), n


@njit(**JIT)
def segment_params(p1, q1, p2, q2):
    """Parameters (s, t) in [0, 1] of the closest points p1 + s (q1 - p1) and
    p2 + t (q2 - p2) of two segments (either may be a point)."""
    d1, d2, r = sub(q1, p1), sub(q2, p2), sub(p1, p2)
    a, e, f = dot(d1, d1), dot(d2, d2), dot(d2, r)
    if a <= DEGENERATE_SQ and e <= DEGENERATE_SQ:
        return 0.0, 0.0
    if a <= DEGENERATE_SQ:
        return 0.0, clamp01(f / e)
    c = dot(d1, r)
    if e <= DEGENERATE_SQ:
        return clamp01(-c / a), 0.0
    b = dot(d1, d2)
    denom = a * e - b * b
    s = clamp01((b * f - c * e) / denom) if denom > 1e-14 * a * e else 0.0
    t = (b * s + f) / e
    if t < 0.0:
        return clamp01(-c / a), 0.0
    if t > 1.0:
        return clamp01((b - c) / a), 1.0
    return s, t


@njit(**JIT)
def segment_segment(p1, q1, p2, q2):
    """Closest points of two segments (points allowed); d >= 0.  When they touch or
    cross, n is the direction that separates them fastest: perpendicular to both."""
    s, t = segment_params(p1, q1, p2, q2)
    d1, d2 = sub(q1, p1), sub(q2, p2)
    a, b = madd(p1, d1, s), madd(p2, d2, t)
    gap = sub(b, a)
    d = norm(gap)
    if d > 1e-15:
        return d, a, b, scale(gap, 1.0 / d)
    c = cross(d1, d2)
    m = norm(c)
    if m > 1e-12 * (norm(d1) * norm(d2)) and m > 0.0:
        return 0.0, a, b, scale(c, 1.0 / m)
    return 0.0, a, b, any_perpendicular(d1 if dot(d1, d1) > 0.0 else d2)


@njit(**JIT)
def unit_axis(k, sign):
    """``sign`` times the k-th unit vector."""
    return (sign if k == 0 else 0.0, sign if k == 1 else 0.0, sign if k == 2 else 0.0)


@njit(**JIT)
def point_box(p, h):
    """Signed distance from point p to the box of half extents h (both in the box frame),
    the point itself, its closest point on the box surface and the normal from p toward
    the box (the box's outward face normal, negated, when p is inside)."""
    cx = min(max(p[0], -h[0]), h[0])
    cy = min(max(p[1], -h[1]), h[1])
    cz = min(max(p[2], -h[2]), h[2])
    gap = (cx - p[0], cy - p[1], cz - p[2])
    d = norm(gap)
    if d > 0.0:
        return d, p, (cx, cy, cz), scale(gap, 1.0 / d)
    # inside: leave through the nearest face
    best, axis = h[0] - abs(p[0]), 0
    for k in range(1, 3):
        g = h[k] - abs(p[k])
        if g < best:
            best, axis = g, k
    side = 1.0 if p[axis] >= 0.0 else -1.0
    out = unit_axis(axis, side)
    face = madd(p, out, best)
    return -best, p, face, scale(out, -1.0)


@njit(**JIT)
def _slope(p0, u, h, t):
    """Half the derivative in t of the squared distance from p0 + t u to the box."""
    g = 0.0
    for k in range(3):
        x = p0[k] + t * u[k]
        if x > h[k]:
            g += u[k] * (x - h[k])
        elif x < -h[k]:
            g += u[k] * (x + h[k])
    return g


@njit(**JIT)
def segment_meets_box(p0, u, h):
    """Whether the segment p0 + t u, t in [0, 1], meets the closed box (slab clipping)."""
    lo, hi = 0.0, 1.0
    for k in range(3):
        if u[k] == 0.0:
            if abs(p0[k]) > h[k]:
                return False
        else:
            ta, tb = (-h[k] - p0[k]) / u[k], (h[k] - p0[k]) / u[k]
            lo, hi = max(lo, min(ta, tb)), min(hi, max(ta, tb))
            if lo > hi:
                return False
    return True


@njit(**JIT)
def segment_box(p0, p1, h):
    """Signed distance from the segment p0-p1 to the box of half extents h (all in the box
    frame), exact.  The squared distance f(t) from p0 + t (p1 - p0) to the box is convex
    and piecewise quadratic, with pieces ending where the segment crosses a face plane;
    its slope, evaluated at those crossings, brackets the minimiser in one piece, where
    it is solved for.  When the segment enters the box the penetration depth comes from
    the separating axes of a box and a segment (the three face normals and the three edge
    directions crossed with the segment), which is exact for this pair."""
    u = sub(p1, p0)
    if segment_meets_box(p0, u, h):
        return _segment_box_depth(p0, p1, u, h)
    if _slope(p0, u, h, 0.0) >= 0.0:
        t = 0.0
    elif _slope(p0, u, h, 1.0) <= 0.0:
        t = 1.0
    else:
        lo, hi = 0.0, 1.0
        for k in range(3):
            if u[k] != 0.0:
                for side in (-1.0, 1.0):
                    tb = (side * h[k] - p0[k]) / u[k]
                    if lo < tb < hi:
                        if _slope(p0, u, h, tb) <= 0.0:
                            lo = tb
                        else:
                            hi = tb
        tm = 0.5 * (lo + hi)
        qa, qb = 0.0, 0.0  # f'(t)/2 = qa t + qb on [lo, hi]
        for k in range(3):
            x = p0[k] + tm * u[k]
            if x > h[k]:
                qa += u[k] * u[k]
                qb += u[k] * (p0[k] - h[k])
            elif x < -h[k]:
                qa += u[k] * u[k]
                qb += u[k] * (p0[k] + h[k])
        t = lo if qa <= 0.0 else min(max(-qb / qa, lo), hi)
    d, a, b, n = point_box(madd(p0, u, t), h)
    if d > 0.0:
        return d, a, b, n
    return _segment_box_depth(p0, p1, u, h)


@njit(**JIT)
def _segment_box_depth(p0, p1, u, h):
    """Penetration of a segment that meets the box: the separating axis needing the
    shortest push of the segment out of the box."""
    best, m_best = math.inf, (1.0, 0.0, 0.0)
    for k in range(6):
        if k < 3:
            a = unit_axis(k, 1.0)
        else:
            c = cross(unit_axis(k - 3, 1.0), u)
            m = norm(c)
            if m <= 1e-9 * norm(u) or m == 0.0:
                continue
            a = scale(c, 1.0 / m)
        hb = abs(a[0]) * h[0] + abs(a[1]) * h[1] + abs(a[2]) * h[2]
        s0, s1 = dot(a, p0), dot(a, p1)
        smin, smax = min(s0, s1), max(s0, s1)
        if hb - smin < best:  # push the segment along +a
            best, m_best = hb - smin, a
        if smax + hb < best:  # push it along -a
            best, m_best = smax + hb, scale(a, -1.0)
    s0, s1 = dot(m_best, p0), dot(m_best, p1)
    if abs(s0 - s1) <= 1e-12 * (abs(s0) + abs(s1) + 1e-300):
        # parallel to the face: the witness is the middle of the part inside the box
        lo, hi = 0.0, 1.0
        for k in range(3):
            if u[k] != 0.0:
                ta, tb = (-h[k] - p0[k]) / u[k], (h[k] - p0[k]) / u[k]
                lo, hi = max(lo, min(ta, tb)), min(hi, max(ta, tb))
        a = madd(p0, u, 0.5 * (lo + hi) if hi >= lo else 0.0)
    else:
        a = p0 if s0 < s1 else p1
    n = scale(m_best, -1.0)  # from the segment toward the box
    return -best, a, madd(a, m_best, best), n


@njit(**JIT)
def point_cylinder(p, radius, half):
    """Signed distance from point p to the cylinder of ``radius`` and half height
    ``half`` along z (both in the cylinder frame); (d, p, closest surface point, normal
    from p toward the cylinder)."""
    rho = math.hypot(p[0], p[1])
    if rho > 1e-300:
        ex, ey = p[0] / rho, p[1] / rho
    else:
        ex, ey = 1.0, 0.0
    dr, dz = rho - radius, abs(p[2]) - half
    zs = 1.0 if p[2] >= 0.0 else -1.0
    if dr <= 0.0 and dz <= 0.0:  # inside: the nearer of the side and the caps
        if -dr < -dz:
            c = (ex * radius, ey * radius, p[2])
            return dr, p, c, (-ex, -ey, 0.0)
        c = (p[0], p[1], zs * half)
        return dz, p, c, (0.0, 0.0, -zs)
    cr = min(rho, radius)
    cz = min(max(p[2], -half), half)
    c = (ex * cr, ey * cr, cz)
    gap = sub(c, p)
    d = norm(gap)
    return d, p, c, scale(gap, 1.0 / d)
