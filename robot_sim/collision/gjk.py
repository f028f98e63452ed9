"""GJK distance and EPA penetration between convex cores given by support functions.

Shapes are packed records (:mod:`.layout`); a sphere or capsule enters as its core (a
point or a segment), the caller sweeps the radius (:func:`.closest.inflate`).  GJK
(Gilbert-Johnson-Keerthi, with Ericson's closest-point sub-algorithm on the simplex)
iterates on the Minkowski difference A - B until the lower bound v·w/|v| and the upper
bound |v| of the distance agree to ``GJK_TOL`` metres.  For polytopes it ends exactly;
for curved shapes (cylinders) it converges to that tolerance.  When the origin is
inside the difference, EPA (expanding polytope) grows GJK's simplex toward the
difference's boundary until the nearest face's support gap is below ``EPA_TOL``: exact
for polytopes, to tolerance for curved shapes.  Witness points and the normal follow
:mod:`.closest`: ``b = a + d n``, n from the first shape to the second.
"""
from __future__ import annotations

import math

import numpy as np

from robot_sim.collision import layout as L
from robot_sim.kernels.jit import JIT, njit
from robot_sim.collision.closest import any_perpendicular
from robot_sim.kernels.algebra import add, cross, dot, madd, norm, scale, sub

GJK_TOL = 1e-11  # m: distance bounds' gap at convergence
GJK_MAX_ITER = 200
TOUCH_SQ = 1e-24  # m²: |v|² below this is contact (the origin is in A - B)
EPA_TOL = 1e-10  # m: support gap of the nearest face at convergence
EPA_MAX_VERTS = 160
EPA_MAX_FACES = 4 * EPA_MAX_VERTS  # live faces <= 2 V - 4; the rest leaves room for a horizon


@njit(**JIT)
def support(kind, rec, verts, u):
    """The point of the core of shape ``rec`` farthest along world direction u."""
    r00, r01, r02 = rec[L.ROT + 0], rec[L.ROT + 1], rec[L.ROT + 2]
    r10, r11, r12 = rec[L.ROT + 3], rec[L.ROT + 4], rec[L.ROT + 5]
    r20, r21, r22 = rec[L.ROT + 6], rec[L.ROT + 7], rec[L.ROT + 8]
    ux = r00 * u[0] + r10 * u[1] + r20 * u[2]
    uy = r01 * u[0] + r11 * u[1] + r21 * u[2]
    uz = r02 * u[0] + r12 * u[1] + r22 * u[2]
    x, y, z = 0.0, 0.0, 0.0
    if kind == L.CAPSULE:
        z = rec[L.HALF_LENGTH] if uz >= 0.0 else -rec[L.HALF_LENGTH]
    elif kind == L.BOX:
        x = rec[L.HALF_X] if ux >= 0.0 else -rec[L.HALF_X]
        y = rec[L.HALF_Y] if uy >= 0.0 else -rec[L.HALF_Y]
        z = rec[L.HALF_Z] if uz >= 0.0 else -rec[L.HALF_Z]
    elif kind == L.CYLINDER:
        z = rec[L.HALF_LENGTH] if uz >= 0.0 else -rec[L.HALF_LENGTH]
        rho = math.hypot(ux, uy)
        if rho > 1e-300:
            x, y = ux / rho * rec[L.CYL_RADIUS], uy / rho * rec[L.CYL_RADIUS]
    elif kind == L.CONVEX:
        start, count = int(rec[L.VSTART]), int(rec[L.VCOUNT])
        best = -math.inf
        for i in range(start, start + count):
            s = verts[i, 0] * ux + verts[i, 1] * uy + verts[i, 2] * uz
            if s > best:
                best, x, y, z = s, verts[i, 0], verts[i, 1], verts[i, 2]
    return (r00 * x + r01 * y + r02 * z + rec[L.POS],
            r10 * x + r11 * y + r12 * z + rec[L.POS + 1],
            r20 * x + r21 * y + r22 * z + rec[L.POS + 2])


@njit(**JIT)
def _row(arr, i):
    return (arr[i, 0], arr[i, 1], arr[i, 2])


@njit(**JIT)
def _put(arr, i, p):
    arr[i, 0], arr[i, 1], arr[i, 2] = p[0], p[1], p[2]


@njit(**JIT)
def _keep(W, A, B, lam, idx, weights, k):
    """Reduce the simplex to its vertices ``idx[:k]`` with barycentric ``weights``."""
    i0, i1, i2 = idx[0], idx[1] if k > 1 else idx[0], idx[2] if k > 2 else idx[0]
    w0, w1, w2 = _row(W, i0), _row(W, i1), _row(W, i2)
    a0, a1, a2 = _row(A, i0), _row(A, i1), _row(A, i2)
    b0, b1, b2 = _row(B, i0), _row(B, i1), _row(B, i2)
    _put(W, 0, w0)
    _put(A, 0, a0)
    _put(B, 0, b0)
    _put(W, 1, w1)
    _put(A, 1, a1)
    _put(B, 1, b1)
    _put(W, 2, w2)
    _put(A, 2, a2)
    _put(B, 2, b2)
    lam[0], lam[1], lam[2] = weights[0], weights[1], weights[2]
    return k


@njit(**JIT)
def _closest_triangle(a, b, c):
    """Ericson's closest point of triangle abc to the origin: (vertex indices, weights)."""
    ab, ac, ap = sub(b, a), sub(c, a), scale(a, -1.0)
    d1, d2 = dot(ab, ap), dot(ac, ap)
    if d1 <= 0.0 and d2 <= 0.0:
        return (0, 0, 0), (1.0, 0.0, 0.0), 1
    bp = scale(b, -1.0)
    d3, d4 = dot(ab, bp), dot(ac, bp)
    if d3 >= 0.0 and d4 <= d3:
        return (1, 0, 0), (1.0, 0.0, 0.0), 1
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        t = d1 / (d1 - d3)
        return (0, 1, 0), (1.0 - t, t, 0.0), 2
    cp = scale(c, -1.0)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    if d6 >= 0.0 and d5 <= d6:
        return (2, 0, 0), (1.0, 0.0, 0.0), 1
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        t = d2 / (d2 - d6)
        return (0, 2, 0), (1.0 - t, t, 0.0), 2
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return (1, 2, 0), (1.0 - t, t, 0.0), 2
    den = va + vb + vc
    if den == 0.0:  # degenerate triangle: its longest edge
        return (0, 1, 0), (0.5, 0.5, 0.0), 2
    v, w = vb / den, vc / den
    return (0, 1, 2), (1.0 - v - w, v, w), 3


@njit(**JIT)
def _solve(W, A, B, lam, size):
    """Closest point of the simplex W[:size] to the origin; reduces the simplex to the
    smallest face holding it and returns the new size (4 when the origin is inside)."""
    if size == 1:
        lam[0] = 1.0
        return 1
    if size == 2:
        a, b = _row(W, 0), _row(W, 1)
        ab = sub(b, a)
        den = dot(ab, ab)
        t = 0.0 if den <= 0.0 else -dot(a, ab) / den
        if t <= 0.0:
            return _keep(W, A, B, lam, (0, 0, 0), (1.0, 0.0, 0.0), 1)
        if t >= 1.0:
            return _keep(W, A, B, lam, (1, 0, 0), (1.0, 0.0, 0.0), 1)
        lam[0], lam[1] = 1.0 - t, t
        return 2
    if size == 3:
        idx, wts, k = _closest_triangle(_row(W, 0), _row(W, 1), _row(W, 2))
        return _keep(W, A, B, lam, idx, wts, k)
    # tetrahedron: the faces whose plane has the origin on the far side from the 4th vertex
    faces = ((0, 1, 2, 3), (0, 2, 3, 1), (0, 3, 1, 2), (1, 3, 2, 0))
    best, inside = math.inf, True
    bi, bw, bk = (0, 0, 0), (1.0, 0.0, 0.0), 1
    for f in faces:
        a, b, c, d = _row(W, f[0]), _row(W, f[1]), _row(W, f[2]), _row(W, f[3])
        n = cross(sub(b, a), sub(c, a))
        side_o, side_d = -dot(n, a), dot(n, sub(d, a))
        flat = abs(side_d) <= 1e-14 * (norm(n) * norm(sub(d, a)) + 1e-300)
        if side_o * side_d < 0.0 or flat:
            inside = False
            idx, wts, k = _closest_triangle(a, b, c)
            p = (0.0, 0.0, 0.0)
            tri = (a, b, c)
            for j in range(k):
                p = madd(p, tri[idx[j]], wts[j])
            dd = dot(p, p)
            if dd < best:
                best, bk, bw = dd, k, wts
                bi = (f[idx[0]], f[idx[1]], f[idx[2]])
    if inside:
        return 4
    return _keep(W, A, B, lam, bi, bw, bk)


@njit(**JIT)
def _combine(P, lam, size):
    p = (0.0, 0.0, 0.0)
    for j in range(size):
        p = madd(p, _row(P, j), lam[j])
    return p


@njit(**JIT)
def gjk(ka, ra, kb, rb, verts, W, A, B, cutoff):
    """Distance between the cores of shapes a and b.  Returns (d, a, b, n, size): d > 0
    with witness points and normal when apart (size -1); d = 0 and the final simplex in
    W, A, B (its first ``size`` rows, support points of A - B, A and B) when they meet.
    Once the distance is known to be at least ``cutoff`` (m) it stops early and returns
    that lower bound (size -2, witness points not final)."""
    lam = np.zeros(4)
    v = (ra[L.POS] - rb[L.POS], ra[L.POS + 1] - rb[L.POS + 1], ra[L.POS + 2] - rb[L.POS + 2])
    if dot(v, v) == 0.0:
        v = (1.0, 0.0, 0.0)
    size = 0
    for _ in range(GJK_MAX_ITER):
        pa = support(ka, ra, verts, scale(v, -1.0))
        pb = support(kb, rb, verts, v)
        w = sub(pa, pb)
        vv, vw = dot(v, v), dot(v, w)
        if vw > 0.0 and vw >= cutoff * math.sqrt(vv):
            lower = vw / math.sqrt(vv)
            return lower, _combine(A, lam, size), _combine(B, lam, size), scale(v, -1.0 / math.sqrt(vv)), -2
        if size > 0 and vv - vw <= max(GJK_TOL * math.sqrt(vv), 1e-14 * vv):
            break
        _put(W, size, w)
        _put(A, size, pa)
        _put(B, size, pb)
        size = _solve(W, A, B, lam, size + 1)
        if size == 4:
            return 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), 4
        v = _combine(W, lam, size)
        if dot(v, v) <= TOUCH_SQ:
            return 0.0, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), size
    a, b = _combine(A, lam, size), _combine(B, lam, size)
    gap = sub(b, a)
    d = norm(gap)
    if d * d <= TOUCH_SQ:
        return 0.0, a, b, (1.0, 0.0, 0.0), size
    return d, a, b, scale(gap, 1.0 / d), -1


@njit(**JIT)
def _face(V, F, fn, fd, i, centroid):
    a, b, cc = _row(V, F[i, 0]), _row(V, F[i, 1]), _row(V, F[i, 2])
    n = cross(sub(b, a), sub(cc, a))
    m = norm(n)
    if m <= 1e-300:
        fd[i] = math.inf
        _put(fn, i, (0.0, 0.0, 0.0))
        return
    n = scale(n, 1.0 / m)
    if dot(n, sub(a, centroid)) < 0.0:  # outward: away from an interior point
        n = scale(n, -1.0)
        F[i, 1], F[i, 2] = F[i, 2], F[i, 1]
    _put(fn, i, n)
    fd[i] = max(dot(n, a), 0.0)


@njit(**JIT)
def _add_vertex(ka, ra, kb, rb, verts, V, VA, VB, nv, u):
    pa = support(ka, ra, verts, u)
    pb = support(kb, rb, verts, scale(u, -1.0))
    _put(VA, nv, pa)
    _put(VB, nv, pb)
    _put(V, nv, sub(pa, pb))
    return nv + 1


@njit(**JIT)
def epa(ka, ra, kb, rb, verts, W, A, B, size):
    """Penetration of the cores of a and b from GJK's final simplex (size 1..4 rows of
    W, A, B holding the origin): (d <= 0, a, b, n) with n the direction of least
    penetration, from a to b."""
    V = np.empty((EPA_MAX_VERTS, 3))
    VA = np.empty((EPA_MAX_VERTS, 3))
    VB = np.empty((EPA_MAX_VERTS, 3))
    for i in range(size):
        for c in range(3):
            V[i, c], VA[i, c], VB[i, c] = W[i, c], A[i, c], B[i, c]
    nv = size
    if nv == 1:  # touching at a point: grow a segment through it
        nv = _add_vertex(ka, ra, kb, rb, verts, V, VA, VB, nv, (1.0, 0.0, 0.0))
        if norm(sub(_row(V, 1), _row(V, 0))) <= 1e-300:
            return 0.0, _row(VA, 0), _row(VB, 0), (1.0, 0.0, 0.0)
    if nv == 2:  # grow a triangle holding the segment
        seg = sub(_row(V, 1), _row(V, 0))
        p = any_perpendicular(seg)
        for attempt in range(2):
            nv = _add_vertex(ka, ra, kb, rb, verts, V, VA, VB, 2, p)
            n = cross(seg, sub(_row(V, 2), _row(V, 0)))
            if norm(n) > 1e-12 * dot(seg, seg):
                break
            p = cross(seg, p)
            p = scale(p, 1.0 / norm(p))
    if nv == 3:  # a double pyramid on the triangle
        n = cross(sub(_row(V, 1), _row(V, 0)), sub(_row(V, 2), _row(V, 0)))
        m = norm(n)
        if m <= 1e-300:
            return 0.0, _row(VA, 0), _row(VB, 0), (1.0, 0.0, 0.0)
        n = scale(n, 1.0 / m)
        nv = _add_vertex(ka, ra, kb, rb, verts, V, VA, VB, 3, n)
        nv = _add_vertex(ka, ra, kb, rb, verts, V, VA, VB, 4, scale(n, -1.0))
        faces = ((0, 1, 3), (1, 2, 3), (2, 0, 3), (0, 1, 4), (1, 2, 4), (2, 0, 4))
    else:
        faces = ((0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2), (0, 0, 0), (0, 0, 0))
    nf = 6 if nv == 5 else 4
    F = np.zeros((EPA_MAX_FACES, 3), dtype=np.int64)
    fn = np.zeros((EPA_MAX_FACES, 3))
    fd = np.full(EPA_MAX_FACES, math.inf)
    alive = np.zeros(EPA_MAX_FACES, dtype=np.bool_)
    centroid = (0.0, 0.0, 0.0)
    for i in range(nv):
        centroid = madd(centroid, _row(V, i), 1.0 / nv)
    for i in range(nf):
        F[i, 0], F[i, 1], F[i, 2] = faces[i]
        alive[i] = True
        _face(V, F, fn, fd, i, centroid)
    edges = np.empty((3 * EPA_MAX_FACES, 2), dtype=np.int64)
    best, full = 0, False
    while True:
        best, dmin = -1, math.inf
        for i in range(nf):
            if alive[i] and fd[i] < dmin:
                best, dmin = i, fd[i]
        if best < 0:
            return 0.0, _row(VA, 0), _row(VB, 0), (1.0, 0.0, 0.0)
        n = _row(fn, best)
        if full or nv >= EPA_MAX_VERTS or nf + nv >= EPA_MAX_FACES:
            break
        pa = support(ka, ra, verts, n)
        pb = support(kb, rb, verts, scale(n, -1.0))
        w = sub(pa, pb)
        if dot(n, w) - dmin <= EPA_TOL:
            break
        _put(V, nv, w)
        _put(VA, nv, pa)
        _put(VB, nv, pb)
        # remove the faces that see w; their unshared edges are the horizon
        ne = 0
        for i in range(nf):
            if alive[i] and dot(_row(fn, i), sub(w, _row(V, F[i, 0]))) > 0.0:
                alive[i] = False
                for k in range(3):
                    e0, e1 = F[i, k], F[i, (k + 1) % 3]
                    found = -1
                    for j in range(ne):
                        if edges[j, 0] == e1 and edges[j, 1] == e0:
                            found = j
                            break
                    if found >= 0:
                        ne -= 1
                        edges[found, 0], edges[found, 1] = edges[ne, 0], edges[ne, 1]
                    else:
                        edges[ne, 0], edges[ne, 1] = e0, e1
                        ne += 1
        slot = 0
        for j in range(ne):  # new faces fill the removed faces' slots first
            while slot < nf and alive[slot]:
                slot += 1
            if slot == nf:
                if nf == EPA_MAX_FACES:  # a broken horizon: stop at the nearest live face
                    full = True
                    break
                nf += 1
            F[slot, 0], F[slot, 1], F[slot, 2] = edges[j, 0], edges[j, 1], nv
            alive[slot] = True
            _face(V, F, fn, fd, slot, centroid)
        nv += 1
    # witness: the origin's projection onto the nearest face, in barycentric coordinates
    i0, i1, i2 = F[best, 0], F[best, 1], F[best, 2]
    p = scale(n, dmin)
    a, b, c = _row(V, i0), _row(V, i1), _row(V, i2)
    v0, v1, v2 = sub(b, a), sub(c, a), sub(p, a)
    d00, d01, d11 = dot(v0, v0), dot(v0, v1), dot(v1, v1)
    d20, d21 = dot(v2, v0), dot(v2, v1)
    den = d00 * d11 - d01 * d01
    if den > 0.0:
        lv = (d11 * d20 - d01 * d21) / den
        lw = (d00 * d21 - d01 * d20) / den
    else:
        lv, lw = 0.0, 0.0
    lu = 1.0 - lv - lw
    pa = add(add(scale(_row(VA, i0), lu), scale(_row(VA, i1), lv)), scale(_row(VA, i2), lw))
    pb = madd(pa, n, -dmin)
    return -dmin, pa, pb, n
