"""Signed distance of one pair of packed shapes (compiled): the narrow phase.

:func:`pair_distance` dispatches on the two kinds (:mod:`.layout`) to the exact closed
forms where there is one and to GJK/EPA otherwise:

* sphere/capsule with sphere/capsule: closest points of the core segments, exact;
* sphere/capsule with box: exact distance and exact penetration (:func:`.closest.segment_box`);
* sphere with cylinder: exact (:func:`.closest.point_cylinder`);
* anything with a half-space: exact, from the shape's support point;
* box with box: GJK (exact for polytopes) apart, separating axes (exact) in overlap;
* the rest (capsule, box, cylinder or convex with cylinder or convex): GJK apart, EPA
  in overlap (exact for polytopes, to ``gjk.EPA_TOL`` for curved ones); a capsule farther
  than the cutoff from the capsule around a cylinder is answered by that lower bound.

Returns ``(d, a, b, n)`` as :mod:`.closest` does: signed distance in metres (negative:
penetration depth), world witness points on each shape and the unit normal from the
first shape to the second, with ``b = a + d n``.
"""
from __future__ import annotations

import math

import numpy as np

from robot_sim.collision import layout as L
from robot_sim.kernels.jit import JIT, njit
from robot_sim.collision.closest import inflate, point_cylinder, segment_box, segment_segment
from robot_sim.kernels.algebra import dot, madd, scale, sub
from robot_sim.collision.gjk import epa, gjk, support


@njit(**JIT)
def to_local(rec, p):
    """World point p in the shape's frame."""
    x, y, z = p[0] - rec[L.POS], p[1] - rec[L.POS + 1], p[2] - rec[L.POS + 2]
    return (rec[0] * x + rec[3] * y + rec[6] * z,
            rec[1] * x + rec[4] * y + rec[7] * z,
            rec[2] * x + rec[5] * y + rec[8] * z)


@njit(**JIT)
def rotate(rec, v):
    """Direction v of the shape's frame in the world."""
    return (rec[0] * v[0] + rec[1] * v[1] + rec[2] * v[2],
            rec[3] * v[0] + rec[4] * v[1] + rec[5] * v[2],
            rec[6] * v[0] + rec[7] * v[1] + rec[8] * v[2])


@njit(**JIT)
def to_world(rec, p):
    """Point p of the shape's frame in the world."""
    r = rotate(rec, p)
    return (r[0] + rec[L.POS], r[1] + rec[L.POS + 1], r[2] + rec[L.POS + 2])


@njit(**JIT)
def axis_z(rec):
    return (rec[2], rec[5], rec[8])


@njit(**JIT)
def core_ends(kind, rec):
    """The core segment's two ends in the world (equal for a sphere)."""
    c = (rec[L.POS], rec[L.POS + 1], rec[L.POS + 2])
    if kind == L.CAPSULE:
        z = axis_z(rec)
        h = rec[L.HALF_LENGTH]
        return madd(c, z, -h), madd(c, z, h)
    return c, c


@njit(**JIT)
def _with_half_space(ka, ra, rb, verts):
    normal = axis_z(rb)
    offset = dot(normal, (rb[L.POS], rb[L.POS + 1], rb[L.POS + 2]))
    s = support(ka, ra, verts, scale(normal, -1.0))
    radius = ra[L.RADIUS]
    d = dot(normal, s) - offset - radius
    a = madd(s, normal, -radius)
    return d, a, madd(a, normal, -d), scale(normal, -1.0)


@njit(**JIT)
def _core_box(ka, ra, rb):
    p0, p1 = core_ends(ka, ra)
    h = (rb[L.HALF_X], rb[L.HALF_Y], rb[L.HALF_Z])
    d, a, b, n = segment_box(to_local(rb, p0), to_local(rb, p1), h)
    return inflate(d, to_world(rb, a), to_world(rb, b), rotate(rb, n), ra[L.RADIUS], 0.0)


@njit(**JIT)
def _sphere_cylinder(ra, rb):
    p = to_local(rb, (ra[L.POS], ra[L.POS + 1], ra[L.POS + 2]))
    d, a, b, n = point_cylinder(p, rb[L.CYL_RADIUS], rb[L.HALF_LENGTH])
    return inflate(d, to_world(rb, a), to_world(rb, b), rotate(rb, n), ra[L.RADIUS], 0.0)


@njit(**JIT)
def _box_axis(rec, i):
    return (rec[i], rec[3 + i], rec[6 + i])


@njit(**JIT)
def _box_radius(rec, axis):
    return (rec[L.HALF_X] * abs(dot(_box_axis(rec, 0), axis))
            + rec[L.HALF_Y] * abs(dot(_box_axis(rec, 1), axis))
            + rec[L.HALF_Z] * abs(dot(_box_axis(rec, 2), axis)))


@njit(**JIT)
def _support_edge(rec, axis, n):
    """The edge of the box along its axis ``axis`` that lies farthest along n."""
    c = (rec[L.POS], rec[L.POS + 1], rec[L.POS + 2])
    for j in range(3):
        if j != axis:
            e = _box_axis(rec, j)
            c = madd(c, e, rec[L.HALF_X + j] if dot(e, n) >= 0.0 else -rec[L.HALF_X + j])
    e = _box_axis(rec, axis)
    return madd(c, e, -rec[L.HALF_X + axis]), madd(c, e, rec[L.HALF_X + axis])


@njit(**JIT)
def _box_box_overlap(ra, rb):
    """Two overlapping boxes: the separating axis of least overlap (15 candidates)."""
    centre = sub((rb[L.POS], rb[L.POS + 1], rb[L.POS + 2]), (ra[L.POS], ra[L.POS + 1], ra[L.POS + 2]))
    best, n_best, kind, ia, ib = math.inf, (1.0, 0.0, 0.0), 0, 0, 0
    for k in range(15):
        if k < 3:
            axis = _box_axis(ra, k)
        elif k < 6:
            axis = _box_axis(rb, k - 3)
        else:
            i, j = (k - 6) // 3, (k - 6) % 3
            ea, eb = _box_axis(ra, i), _box_axis(rb, j)
            c = (ea[1] * eb[2] - ea[2] * eb[1], ea[2] * eb[0] - ea[0] * eb[2], ea[0] * eb[1] - ea[1] * eb[0])
            m = math.sqrt(dot(c, c))
            if m < 1e-9:
                continue
            axis = scale(c, 1.0 / m)
        s = dot(axis, centre)
        overlap = _box_radius(ra, axis) + _box_radius(rb, axis) - abs(s)
        if overlap < best:
            best = overlap
            n_best = axis if s >= 0.0 else scale(axis, -1.0)
            kind = 0 if k < 3 else (1 if k < 6 else 2)
            if kind == 2:
                ia, ib = (k - 6) // 3, (k - 6) % 3
    depth = max(best, 0.0)
    n = n_best
    empty = np.zeros((0, 3))
    if kind == 0:  # a face of A: B's deepest vertex, projected onto that face
        b = support(L.BOX, rb, empty, scale(n, -1.0))
        return -depth, madd(b, n, depth), b, n
    if kind == 1:  # a face of B: A's deepest vertex
        a = support(L.BOX, ra, empty, n)
        return -depth, a, madd(a, n, -depth), n
    p0, p1 = _support_edge(ra, ia, n)
    q0, q1 = _support_edge(rb, ib, scale(n, -1.0))
    _, a, b, _ = segment_segment(p0, p1, q0, q1)
    mid = scale((a[0] + b[0], a[1] + b[1], a[2] + b[2]), 0.5)
    a = madd(mid, n, 0.5 * depth)
    return -depth, a, madd(a, n, -depth), n


@njit(**JIT)
def _ordered(ka, ra, kb, rb, verts, cutoff):
    """pair_distance for kinds ka <= kb."""
    if kb == L.HALFSPACE:
        if ka == L.HALFSPACE:
            return math.inf, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)
        return _with_half_space(ka, ra, rb, verts)
    if kb <= L.CAPSULE:
        p0, p1 = core_ends(ka, ra)
        q0, q1 = core_ends(kb, rb)
        d, a, b, n = segment_segment(p0, p1, q0, q1)
        return inflate(d, a, b, n, ra[L.RADIUS], rb[L.RADIUS])
    if ka <= L.CAPSULE and kb == L.BOX:
        return _core_box(ka, ra, rb)
    if ka == L.SPHERE and kb == L.CYLINDER:
        return _sphere_cylinder(ra, rb)
    if ka == L.CAPSULE and kb == L.CYLINDER:  # the capsule around the cylinder holds it: a lower bound
        p0, p1 = core_ends(ka, ra)
        z, h = axis_z(rb), rb[L.HALF_LENGTH]
        c = (rb[L.POS], rb[L.POS + 1], rb[L.POS + 2])
        d, a, b, n = segment_segment(p0, p1, madd(c, z, -h), madd(c, z, h))
        if d - ra[L.RADIUS] - rb[L.CYL_RADIUS] >= cutoff:
            return inflate(d, a, b, n, ra[L.RADIUS], rb[L.CYL_RADIUS])
    W = np.empty((4, 3))
    A = np.empty((4, 3))
    B = np.empty((4, 3))
    d, a, b, n, size = gjk(ka, ra, kb, rb, verts, W, A, B, cutoff + ra[L.RADIUS] + rb[L.RADIUS])
    if size < 0:
        return inflate(d, a, b, n, ra[L.RADIUS], rb[L.RADIUS])
    if ka == L.BOX and kb == L.BOX:
        return _box_box_overlap(ra, rb)
    d, a, b, n = epa(ka, ra, kb, rb, verts, W, A, B, size)
    return inflate(d, a, b, n, ra[L.RADIUS], rb[L.RADIUS])


@njit(**JIT)
def pair_distance(ka, ra, kb, rb, verts, cutoff):
    """Signed distance (d, a, b, n) between packed shapes a and b (any order of kinds).
    Exact when d < ``cutoff`` (m); otherwise possibly only a lower bound >= cutoff, with
    witness points not final (pass inf for the exact distance everywhere)."""
    if ka <= kb:
        return _ordered(ka, ra, kb, rb, verts, cutoff)
    d, b, a, n = _ordered(kb, rb, ka, ra, verts, cutoff)
    return d, a, b, scale(n, -1.0)
