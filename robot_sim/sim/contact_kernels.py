"""Compiled penalty-contact terms (:mod:`.contact`): point Jacobians of link points, the
contact frames fixed at a step's start and the joint torque of its contacts at any
state of the step, the check that the pairs near
contact are still the active ones, and the bound on how close a pair must be to become
active.  The step of an arm in contact is the one stepping kernel's
(:func:`robot_sim.sim.step_kernels.step_one` with a contact tuple).

Arrays as in :mod:`robot_sim.collision.batch`.  A *contact tuple* ``C`` holds a checker's
scene and the active pairs of the current step, in this order:

* ``world0`` (4, 4), ``link`` (S,), ``local`` (S, REC), ``recs0`` (S + O, REC), ``kinds``
  (S + O,), ``bc`` (S + O, 3), ``br`` (S + O,), ``verts`` (V, 3): the scene;
* ``body`` (S + O,): the link (0 base .. n) a scene row is fixed to, -1 for obstacles
  (fixed in the world); ``axis_frame`` (n,): the frame whose z axis and origin carry
  joint j (j for standard DH, j + 1 for modified); ``revolute`` (n,) bool;
* ``pairs`` (P, 2): every checked pair (scene rows); ``arms`` (n,): each joint's lever
  arm [m/rad, or 1 for a prismatic joint] (``collision.path.lever_arms``);
* ``rows`` (A, 2): the active pairs (in the order of ``pairs``), ``gains`` (A, 4),
  ``mu`` the Coulomb coefficient, ``anchors`` (A, POINTS, 2, 3), ``anchored`` (A, POINTS),
  ``fixed`` (n + 2,) (where the contact frames were fixed, :func:`contact_begin`),
  ``out`` (A, POINTS, OUT) (:func:`contact_begin`, :func:`contact_stage`).

Its work arrays come from :func:`contact_work`.  World frame, metres, newtons; joint
torques in N·m (revolute) or N (prismatic).
"""
from __future__ import annotations

import math

import numpy as np

from robot_sim.collision import layout as L
from robot_sim.collision.batch import _gap, _pose, place_shape
from robot_sim.collision.closest import any_perpendicular, point_box
from robot_sim.collision.narrow import axis_z, core_ends, pair_distance, to_local
from robot_sim.kernels.algebra import cholesky, cross, dot, perp, solve_factored, sub
from robot_sim.kernels.chain import frames
from robot_sim.kernels.jit import INLINE, JIT, UNCOUNTED, njit

# Columns of ``gains`` (A, 4) per active pair.
K_N, C_N, K_T, C_T = range(4)
# Columns of ``out`` (A, POINTS, OUT) per contact point: signed distance, the first
# shape's witness point, the normal (first toward second), the force on the first shape,
# the tangential offset u between its friction anchors; for a capsule's end spheres
# (slots 1, 2) also the last distance computed of that end to an obstacle and where the
# end's centre was then (:func:`contact_begin`: a bound that spares the call); whether
# the point takes part in the step (1.0), n·b at the step's start, the two shapes' core
# points under their witness points, each in its body's frame (the contact frame held
# over the step), and what :func:`contact_stage` reads besides: the two bodies, the two
# radii, the pair's gains, the two anchors and whether they are set (1.0).
(O_D, O_POINT, O_NORMAL, O_FORCE, O_SLIP, O_GAP, O_CENTRE, O_ON, O_FIXED, O_HELD_A, O_HELD_B, O_BODY_A, O_BODY_B,
 O_RADIUS_A, O_RADIUS_B, O_GAINS, O_ANCHOR_A, O_ANCHOR_B, O_ANCHORED) = (
    0, 1, 4, 7, 10, 13, 14, 17, 18, 19, 22, 25, 26, 27, 28, 29, 33, 36, 39)
OUT = 40
#: Contact slots per pair: the closest points, then a capsule's two end spheres.
POINTS = 3
#: How far [m] (:func:`moved`) the arm may move from where the contact frames were last
#: fixed from the exact narrow phase and a step's start still hold them
#: (:func:`contact_begin`); the held distances then differ from the exact ones by
#: second-order terms of this.
HOLD = 1e-6
#: Round-off guard [m] of the held distances against the margin.
HOLD_TOL = 1e-12
#: Pairs closer than this [m] (or than twice the step's motion bound, if larger) at the
#: start of a step are the active ones: only they can touch during the step.
MIN_MARGIN = 2e-3


@njit(**INLINE)
def point_velocity(F, k, p, qd, axis_frame, revolute):
    """Velocity (3-tuple) of the point p (world) fixed to link k (-1 or 0: fixed) at joint
    rates qd."""
    o0 = o1 = o2 = 0.0
    for j in range(max(k, 0)):
        f = axis_frame[j]
        z0, z1, z2 = F[f, 0, 2], F[f, 1, 2], F[f, 2, 2]
        if revolute[j]:
            r0, r1, r2 = p[0] - F[f, 0, 3], p[1] - F[f, 1, 3], p[2] - F[f, 2, 3]
            o0 += (z1 * r2 - z2 * r1) * qd[j]
            o1 += (z2 * r0 - z0 * r2) * qd[j]
            o2 += (z0 * r1 - z1 * r0) * qd[j]
        else:
            o0 += z0 * qd[j]
            o1 += z1 * qd[j]
            o2 += z2 * qd[j]
    return o0, o1, o2


@njit(**INLINE)
def add_point_torque(F, k, p, force, sign, axis_frame, revolute, tau):
    """tau += sign · J_k(p)ᵀ force: the joint torque of a force (3-tuple) at the point p
    (world) of link k (nothing for -1 or 0)."""
    for j in range(max(k, 0)):
        f = axis_frame[j]
        z0, z1, z2 = F[f, 0, 2], F[f, 1, 2], F[f, 2, 2]
        if revolute[j]:
            r0, r1, r2 = p[0] - F[f, 0, 3], p[1] - F[f, 1, 3], p[2] - F[f, 2, 3]
            m0 = r1 * force[2] - r2 * force[1]
            m1 = r2 * force[0] - r0 * force[2]
            m2 = r0 * force[1] - r1 * force[0]
            tau[j] += sign * (z0 * m0 + z1 * m1 + z2 * m2)
        else:
            tau[j] += sign * (z0 * force[0] + z1 * force[1] + z2 * force[2])


@njit(**INLINE)
def relative_jacobian(F, ka, pa, kb, pb, axis_frame, revolute, J):
    """J (3, n) = J_kb(pb) − J_ka(pa): the velocity of point pb of body kb relative to
    point pa of body ka per unit joint rate."""
    n = J.shape[1]
    e = np.zeros(n)
    for j in range(n):
        e[j] = 1.0
        vb = point_velocity(F, kb, pb, e, axis_frame, revolute)
        va = point_velocity(F, ka, pa, e, axis_frame, revolute)
        J[0, j], J[1, j], J[2, j] = vb[0], vb[1], vb[2]
        J[0, j] -= va[0]
        J[1, j] -= va[1]
        J[2, j] -= va[2]
        e[j] = 0.0


@njit(**JIT)
def pair_gains(F, M, ka, pa, kb, pb, normals, axis_frame, revolute, omega, zeta, immobile, gains):
    """The gains [k_n, c_n, k_t, c_t] (B, 4) of B pairs at the link frames F and the mass
    matrix M (n, n) (overwritten by its Cholesky factor): pair b's bodies ka[b], kb[b],
    witness points pa[b], pb[b] (3,) and normal normals[b] (3,).  With Λ = J M⁻¹ Jᵀ
    (3, 3), J the :func:`relative_jacobian` of the witness points, the effective mass
    along the normal is m_n = 1 / nᵀ Λ n and across it m_t = 1 / λ_max (the largest
    eigenvalue of Λ in the tangent plane, never below nᵀ Λ n: the lightest direction):
    k = m ω², c = 2 ζ m ω.  Zero for a pair with nᵀ Λ n <= ``immobile`` [1/kg] (shapes
    that cannot move each other)."""
    n = M.shape[0]
    positive = cholesky(M)
    J, X, lam = np.empty((3, n)), np.empty((3, n)), np.empty((3, 3))
    for b in range(ka.shape[0]):
        relative_jacobian(F, ka[b], pa[b], kb[b], pb[b], axis_frame, revolute, J)
        for r in range(3):
            if positive:
                solve_factored(M, J[r], X[r])
            else:
                X[r, :] = math.nan
        for r in range(3):  # Λ = J M⁻¹ Jᵀ
            for c in range(3):
                s = 0.0
                for k in range(n):
                    s += J[r, k] * X[c, k]
                lam[r, c] = s
        nrm = (normals[b, 0], normals[b, 1], normals[b, 2])
        t1 = any_perpendicular(nrm)
        t2 = cross(nrm, t1)
        n_inv = _quadratic(lam, nrm, nrm)
        if not n_inv > immobile:
            gains[b, :] = 0.0
            continue
        a, off, c = _quadratic(lam, t1, t1), _quadratic(lam, t1, t2), _quadratic(lam, t2, t2)
        t_inv = max(0.5 * (a + c) + math.sqrt(0.25 * (a - c) ** 2 + off * off), n_inv)
        m_n, m_t = 1.0 / n_inv, 1.0 / t_inv
        gains[b, K_N], gains[b, C_N] = m_n * omega * omega, 2.0 * zeta * m_n * omega
        gains[b, K_T], gains[b, C_T] = m_t * omega * omega, 2.0 * zeta * m_t * omega


@njit(**INLINE)
def _quadratic(lam, x, y):
    """xᵀ Λ y for the (3, 3) Λ and 3-tuples x, y."""
    s = 0.0
    for r in range(3):
        s += x[r] * (lam[r, 0] * y[0] + lam[r, 1] * y[1] + lam[r, 2] * y[2])
    return s


@njit(**INLINE)
def to_world(F, k, x):
    """Point x of body k's frame in the world (3-tuple)."""
    if k < 0:
        return x[0], x[1], x[2]
    return (F[k, 0, 0] * x[0] + F[k, 0, 1] * x[1] + F[k, 0, 2] * x[2] + F[k, 0, 3],
            F[k, 1, 0] * x[0] + F[k, 1, 1] * x[1] + F[k, 1, 2] * x[2] + F[k, 1, 3],
            F[k, 2, 0] * x[0] + F[k, 2, 1] * x[1] + F[k, 2, 2] * x[2] + F[k, 2, 3])


@njit(**INLINE)
def to_body(F, k, x, out):
    """World point x in body k's frame (obstacles, k = -1: the world itself) into out."""
    if k < 0:
        out[0], out[1], out[2] = x[0], x[1], x[2]
        return
    r0, r1, r2 = x[0] - F[k, 0, 3], x[1] - F[k, 1, 3], x[2] - F[k, 2, 3]
    for c in range(3):
        out[c] = F[k, 0, c] * r0 + F[k, 1, c] * r1 + F[k, 2, c] * r2


@njit(**UNCOUNTED)
def _move_anchors(F, ka, kb, d, a, b, nrm, qd, axis_frame, revolute, gains, mu, anchors, anchored, p, slot):
    """At a step's start (friction on), the anchors of contact point ``slot`` of active
    pair p, of depth −d > 0 (exact witness points a, b and normal nrm; 3-tuples): a point
    touching for the first time is anchored at its witness points, and a slipping one's
    second anchor is slid back onto the friction cap μ f_n / k_T."""
    g = gains[p]
    anchor = anchors[p, slot]
    if not anchored[p, slot]:
        to_body(F, ka, a, anchor[0])
        to_body(F, kb, b, anchor[1])
        anchored[p, slot] = True
        return
    va = point_velocity(F, ka, a, qd, axis_frame, revolute)
    vb = point_velocity(F, kb, b, qd, axis_frame, revolute)
    rate = (vb[0] - va[0]) * nrm[0] + (vb[1] - va[1]) * nrm[1] + (vb[2] - va[2]) * nrm[2]
    fn = max(g[K_N] * (-d) - g[C_N] * rate, 0.0)
    xa = to_world(F, ka, anchor[0])
    xb = to_world(F, kb, anchor[1])
    u0, u1, u2 = perp(nrm, sub(xb, xa))  # the anchors' offset across the normal
    size = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    cap = mu * fn / g[K_T]
    if size > cap:
        keep = 1.0 - cap / size
        to_body(F, kb, (xb[0] - keep * u0, xb[1] - keep * u1, xb[2] - keep * u2), anchor[1])


@njit(**INLINE)
def _contact_force(F, ka, kb, d, a, b, nrm, qd, axis_frame, revolute, mu, out, p, slot, tau):
    """Contact point ``slot`` of active pair p at depth −d > 0 along its normal nrm (from
    the first shape to the second; witness points a, b; 3-tuples) on bodies ka, kb: its
    force into tau (joint torque) and out[p, slot] (force on the first shape, anchor
    offset), with the gains and anchors ``out`` holds (:func:`_stage_record`)."""
    k_n, c_n = out[p, slot, O_GAINS + K_N], out[p, slot, O_GAINS + C_N]
    k_t, c_t = out[p, slot, O_GAINS + K_T], out[p, slot, O_GAINS + C_T]
    va = point_velocity(F, ka, a, qd, axis_frame, revolute)
    vb = point_velocity(F, kb, b, qd, axis_frame, revolute)
    v0, v1, v2 = vb[0] - va[0], vb[1] - va[1], vb[2] - va[2]
    rate = v0 * nrm[0] + v1 * nrm[1] + v2 * nrm[2]
    fn = max(k_n * (-d) - c_n * rate, 0.0)
    u0 = u1 = u2 = 0.0
    if mu > 0.0 and out[p, slot, O_ANCHORED] == 1.0:
        xa = to_world(F, ka, (out[p, slot, O_ANCHOR_A], out[p, slot, O_ANCHOR_A + 1], out[p, slot, O_ANCHOR_A + 2]))
        xb = to_world(F, kb, (out[p, slot, O_ANCHOR_B], out[p, slot, O_ANCHOR_B + 1], out[p, slot, O_ANCHOR_B + 2]))
        u0, u1, u2 = perp(nrm, sub(xb, xa))
    f0, f1, f2 = fn * nrm[0], fn * nrm[1], fn * nrm[2]
    if mu > 0.0 and fn > 0.0:
        t0, t1, t2 = v0 - rate * nrm[0], v1 - rate * nrm[1], v2 - rate * nrm[2]
        g0 = -k_t * u0 - c_t * t0
        g1 = -k_t * u1 - c_t * t1
        g2 = -k_t * u2 - c_t * t2
        size = math.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
        s = mu * fn / size if size > mu * fn else 1.0
        f0 += s * g0
        f1 += s * g1
        f2 += s * g2
    add_point_torque(F, kb, b, (f0, f1, f2), 1.0, axis_frame, revolute, tau)
    add_point_torque(F, ka, a, (f0, f1, f2), -1.0, axis_frame, revolute, tau)
    out[p, slot, O_FORCE], out[p, slot, O_FORCE + 1], out[p, slot, O_FORCE + 2] = -f0, -f1, -f2
    out[p, slot, O_SLIP], out[p, slot, O_SLIP + 1], out[p, slot, O_SLIP + 2] = u0, u1, u2


@njit(**JIT)
def contact_work(dh, C):
    """The work arrays of :func:`contact_begin`, :func:`contact_stage` and
    :func:`near_slack` for the model table ``dh`` and the contact tuple ``C``: link frames,
    world records (obstacle rows filled), world bounding centres (obstacle rows filled),
    a record, room for ``out`` and ``fixed`` as they were before the last refix, and the
    contact torque at the step's start (n,)."""
    recs0, bc = C[3], C[5]
    return (np.empty((dh.shape[0] + 1, 3, 4)), recs0.copy(), bc.copy(), np.empty(recs0.shape[1]), np.empty_like(C[19]),
            np.empty_like(C[18]), np.empty(dh.shape[0]))


@njit(**INLINE)
def _pose_active(q, dh, modified, C, work):
    """Frames at q and the world records of the active pairs' robot shapes into ``work``."""
    world0, link, local, bc, rows = C[0], C[1], C[2], C[5], C[13]
    F, recs, wc = work[0], work[1], work[2]
    frames(dh, modified, world0, q, F)
    for p in range(rows.shape[0]):
        for s in range(2):
            if rows[p, s] < link.shape[0]:
                place_shape(F, link, local, recs, bc, wc, rows[p, s])


@njit(**INLINE)
def _held_point(F, out, p, s):
    """Contact point s of active pair p in its held frame at the frames F: (d, a, b, n),
    the distance along the held normal n and the witness points (3-tuples), and its
    bodies (:func:`contact_stage`); d and a also into ``out``."""
    ka, kb = int(out[p, s, O_BODY_A]), int(out[p, s, O_BODY_B])
    n = (out[p, s, O_NORMAL], out[p, s, O_NORMAL + 1], out[p, s, O_NORMAL + 2])
    ra = out[p, s, O_RADIUS_A]
    x = to_world(F, ka, (out[p, s, O_HELD_A], out[p, s, O_HELD_A + 1], out[p, s, O_HELD_A + 2]))
    a = (x[0] + ra * n[0], x[1] + ra * n[1], x[2] + ra * n[2])
    if kb > 0:  # both shapes move
        rb = out[p, s, O_RADIUS_B]
        y = to_world(F, kb, (out[p, s, O_HELD_B], out[p, s, O_HELD_B + 1], out[p, s, O_HELD_B + 2]))
        b = (y[0] - rb * n[0], y[1] - rb * n[1], y[2] - rb * n[2])
        d = dot(n, b) - dot(n, a)
    else:
        d = out[p, s, O_FIXED] - dot(n, a)
        b = (a[0] + d * n[0], a[1] + d * n[1], a[2] + d * n[2])
    out[p, s, O_D] = d
    for c in range(3):
        out[p, s, O_POINT + c] = a[c]
    return d, a, b, n, ka, kb


@njit(**INLINE)
def _held_begin(F, qd, axis_frame, revolute, gains, mu, anchors, anchored, out, update, threshold, since, tau):
    """:func:`contact_begin` keeping the frames it fixed last (the arm has moved at most
    ``since`` <= HOLD [m] since, and no capsule end left out then can come within
    ``threshold``): with ``update`` the anchors moved and released as from exact ones,
    then each point's distance, witness points and force in its held frame into ``out``
    and the contact torque at the start into tau (:func:`contact_stage`).  False
    (nothing written but slot 0's held distances) when a pair's distance is within 2
    ``since`` (+ round-off) of ``threshold``: its held and exact distances, each within
    ``since`` of their common value at the fix, could fall on either side, and the
    pair's staying active must be decided on the exact one."""
    for p in range(out.shape[0]):
        d = _held_point(F, out, p, 0)[0]
        if abs(d - threshold) <= 2.0 * since + HOLD_TOL:
            return False
    for p in range(out.shape[0] if update else 0):
        touches = gains[p, K_N] > 0.0
        for s in range(POINTS):
            if out[p, s, O_ON] == 0.0:
                continue
            d, a, b, n, ka, kb = _held_point(F, out, p, s)
            if mu > 0.0 and touches and d < 0.0:
                _move_anchors(F, ka, kb, d, a, b, n, qd, axis_frame, revolute, gains, mu, anchors, anchored, p, s)
            if not (d < 0.0 and touches):
                anchored[p, s] = False
            _stage_record(out[p, s], ka, kb, out[p, s, O_RADIUS_A], out[p, s, O_RADIUS_B], gains[p], anchors[p, s],
                          anchored[p, s])
    contact_stage(F, qd, axis_frame, revolute, mu, out, tau)
    return True


@njit(**UNCOUNTED)
def contact_hold(q, qd, dh, modified, C, update, posed, threshold, F, tau):
    """:func:`contact_begin`'s held case: True (and its work done, through
    :func:`_held_begin`, the start's contact torque into tau) when the contact tuple
    ``C``'s frames fixed last may be held at (q, qd) (the frames F (n + 1, 3, 4) then at
    q; already when ``posed``), else False (the anchors and the frames held untouched)."""
    axis_frame, revolute, arms = C[9], C[10], C[12]
    gains, mu, anchors, anchored, fixed, out = C[14:]
    n = q.shape[0]
    if fixed[n + 1] != 1.0 or fixed[n] == -math.inf:
        return False
    since = moved(arms, q, fixed[:n])
    if since > HOLD or fixed[n] - since < threshold:
        return False
    if not posed:
        frames(dh, modified, C[0], q, F)
    return _held_begin(F, qd, axis_frame, revolute, gains, mu, anchors, anchored, out, update, threshold, since, tau)


@njit(**UNCOUNTED)
def contact_begin(q, qd, dh, modified, C, update, posed, threshold, work):
    """Fix the contact frames of a step's start at (q, qd) for the active pairs ``rows`` of
    the contact tuple ``C``: per pair and contact point, into its ``out`` (A, POINTS, OUT),
    the exact signed distance, first witness point and normal (from the first shape to
    the second), O_ON 1.0 for the points that take part in the step, and the contact
    frame held over the step (O_FIXED, O_HELD_A, O_HELD_B: :func:`_fix`); distance inf
    and O_ON 0.0 elsewhere.  ``dh``, ``modified``: the model table and its convention;
    ``threshold`` [m]: the step's margin (:func:`margin`); ``work``: :func:`contact_work`,
    already posed at q when ``posed`` (by :func:`near_slack`).  :func:`contact_stage` then
    gives the force of every point at any state of the step; the contact torque at the
    start (q, qd), :func:`contact_stage`'s there, goes into ``work[6]``.  True when the
    frames were fixed anew (``out`` and ``fixed`` as they were before are then in
    ``work[4]``, ``work[5]``).

    The frames fixed last are held instead (:func:`contact_hold`, no narrow phase) while
    the arm has moved at most :data:`HOLD` since (``fixed`` (n + 2,): q then, the least
    distance bound of the capsule ends left out then, and 1.0 where the lever arms
    ``arms`` hold at every q; -inf: fix anew) and no end left out can come within
    ``threshold``: an arm at rest takes the narrow phase once.

    Contact points of a pair (first shape a, second b): their closest points (slot 0,
    always) and, when a is a capsule, the sphere of one of its ends (slot 1 or 2 for its
    end): the shallower end if both overlap (a capsule lying flat rests on both ends
    instead of rocking between them, and the springs' energy ½ k (δ² + δ_end²) stays a
    smooth function of q: the two ends trade places where their depths are equal), else
    the end farther from the closest point if it is within ``threshold`` (it may come to
    touch during the step).  The end farther from the closest point is computed first:
    when it does not touch, the shallower end does not either, and the other need not be
    computed.

    ``update`` (at a step's start) also moves the friction anchors (``anchors`` (A,
    POINTS, 2, 3), a point on each shape in its body's frame, and ``anchored`` (A,
    POINTS); :func:`_move_anchors`) of the touching points and releases those of points
    that do not touch.  An end sphere of a capsule against a shape fixed in the world
    whose last computed distance (``out``'s O_GAP, the end's centre then at O_CENTRE) less
    how far its centre has moved since is still >= ``threshold`` cannot touch during the
    step: its distance is not computed (the result is the same)."""
    link, local, kinds, verts, body, axis_frame, revolute = C[1], C[2], C[4], C[7], C[8], C[9], C[10]
    rows, gains, mu, anchors, anchored, fixed, out = C[13:]
    F, recs, end = work[0], work[1], work[3]
    n = q.shape[0]
    moving = update and mu > 0.0
    if contact_hold(q, qd, dh, modified, C, update, posed, threshold, F, work[6]):
        return False
    saved = work[4]  # what a caller that takes the step back restores
    for p in range(out.shape[0]):
        for e in range(POINTS):
            for c in range(OUT):
                saved[p, e, c] = out[p, e, c]
    _copy(fixed, work[5])
    if not posed:
        _pose_active(q, dh, modified, C, work)
    reach = math.inf
    for p in range(rows.shape[0]):
        i, j = rows[p, 0], rows[p, 1]
        ka, kb = body[i], body[j]
        ra, rb = local[i, L.RADIUS], local[j, L.RADIUS] if j < link.shape[0] else 0.0
        for e in range(POINTS):
            out[p, e, O_D] = math.inf
            out[p, e, O_ON] = 0.0
        d, a, b, nrm = pair_distance(kinds[i], recs[i], kinds[j], recs[j], verts, math.inf)
        _fix(F, ka, kb, ra, rb, out[p, 0], d, a, b, nrm)
        touches = gains[p, K_N] > 0.0
        if moving and touches and d < 0.0:
            _move_anchors(F, ka, kb, d, a, b, nrm, qd, axis_frame, revolute, gains, mu, anchors, anchored, p, 0)
        if kinds[i] == L.CAPSULE:
            ends = core_ends(kinds[i], recs[i])
            far = 0 if _distance2(ends[0], a) >= _distance2(ends[1], a) else 1
            # against a shape fixed in the world, the end's own motion bounds its change of distance
            bound = out[p, 1 + far, O_GAP] - _moved(out[p, 1 + far], ends[far])
            apart = kb <= 0 and bound >= threshold
            if apart:
                reach = min(reach, bound)
            else:
                _copy(recs[i], end)
                for c in range(3):
                    end[L.POS + c] = ends[far][c]
                result = pair_distance(L.SPHERE, end, kinds[j], recs[j], verts, math.inf)
                _remember(out[p, 1 + far], result[0], ends[far])
                de, ae, be, ne, e = result[0], result[1], result[2], result[3], far
                if de < 0.0:
                    for c in range(3):
                        end[L.POS + c] = ends[1 - far][c]
                    other = pair_distance(L.SPHERE, end, kinds[j], recs[j], verts, math.inf)
                    _remember(out[p, 2 - far], other[0], ends[1 - far])
                    first, second = (result, other) if far == 0 else (other, result)
                    e = 0 if first[0] >= second[0] else 1  # the shallower end
                    de, ae, be, ne = first if e == 0 else second
                if de >= threshold:
                    reach = min(reach, de)
                else:
                    _fix(F, ka, kb, ra, rb, out[p, 1 + e], de, ae, be, ne)
                    if moving and touches and de < 0.0:
                        _move_anchors(F, ka, kb, de, ae, be, ne, qd, axis_frame, revolute, gains, mu, anchors,
                                      anchored, p, 1 + e)
        for e in range(POINTS):
            if update and (not out[p, e, O_D] < 0.0 or not touches):
                anchored[p, e] = False
            if out[p, e, O_ON] == 1.0:
                _stage_record(out[p, e], ka, kb, ra, rb, gains[p], anchors[p, e], anchored[p, e])
    _copy(q, fixed[:n])
    fixed[n] = reach
    contact_stage(F, qd, axis_frame, revolute, mu, out, work[6])
    return True


@njit(**UNCOUNTED)
def contact_stage(F, qd, axis_frame, revolute, mu, out, tau):
    """The joint torque tau (n,) at (q, qd) of the contact points that take part in the
    step (O_ON, fixed by :func:`contact_begin` at its start, which also wrote what is
    read here into ``out``), and per point into ``out`` its distance, first witness
    point, force and anchor offset.  ``F`` (n + 1, 3, 4): the link frames at q;
    ``axis_frame``, ``revolute``, ``mu`` as in the contact tuple.  Compiled once and
    called by every kernel that needs the contact torque (a call costs less than
    compiling it into each).

    The contact frame is held over the step: each point keeps the normal n of the step's
    start, and the core points under its witness points move with their bodies (a
    shape's core: a sphere's centre, a point of a capsule's segment, a box's surface
    point).  Its distance is d = n·(b − a), with a = x_a + r_a n and b = x_b − r_b n
    (x the held core points, r the radii; for a second shape fixed in the world, n·b
    as at the start: its tangent plane).  At the start d is the exact signed distance
    and its gradient the exact one; over the step it differs from the exact distance by
    the second-order terms of that tangent-plane picture (the curvature of the shapes
    times the square of the witness points' slide, and the turn of the exact normal times
    the lever of the point): none for a sphere, or a capsule's end or side, on a face of
    a fixed shape.

    A point of depth δ = −d > 0 pushes the shapes apart with f_n = max(0, k_n δ − c_n ḋ)
    along n (ḋ the separation rate).  With friction (mu > 0) the tangential force is
    −k_T u − c_T v_t, capped at mu · f_n, where u is the part across n of the offset
    between the point's two anchors (zero where not set) and v_t the slip velocity.  The
    force on b acts at b, its opposite at a."""
    for j in range(tau.shape[0]):
        tau[j] = 0.0
    for p in range(out.shape[0]):
        for s in range(POINTS):
            if out[p, s, O_ON] == 0.0:
                continue
            d, a, b, n, ka, kb = _held_point(F, out, p, s)
            for c in range(3):
                out[p, s, O_FORCE + c] = 0.0
                out[p, s, O_SLIP + c] = 0.0
            if out[p, s, O_GAINS + K_N] > 0.0 and d < 0.0:
                _contact_force(F, ka, kb, d, a, b, n, qd, axis_frame, revolute, mu, out, p, s, tau)


@njit(**JIT)
def contact_torque(q, qd, dh, modified, C, tau, work):
    """:func:`contact_stage` at (q, qd) for the contact tuple ``C`` and its
    :func:`contact_work` (``dh``, ``modified``: the model table and its convention): the
    joint torque of the step's contact points into tau."""
    frames(dh, modified, C[0], q, work[0])
    contact_stage(work[0], qd, C[9], C[10], C[15], C[19], tau)


@njit(**INLINE)
def margin(arms, qd, dt):
    """How close [m] a pair must be at joint rates qd to be active in a step of dt [s]:
    twice the lever-arm bound Σ_j arms_j |q̇_j| dt of any shape point's motion in the
    step, at least :data:`MIN_MARGIN`."""
    speed = 0.0
    for j in range(qd.shape[0]):
        speed += arms[j] * abs(qd[j])
    return max(MIN_MARGIN, 2.0 * dt * speed)


@njit(**INLINE)
def _lower_bound(kinds, recs, wc, br, i, j):
    """A lower bound [m] of the distance of scene rows i and j: from the bounding sphere of
    i to the box or half-space j itself (exact for the sphere), else from bounding sphere
    to bounding sphere."""
    kind = kinds[j]
    if kind == L.HALFSPACE:
        rec = recs[j]
        normal = axis_z(rec)
        return dot(normal, (wc[i, 0], wc[i, 1], wc[i, 2])) - dot(normal, (rec[L.POS], rec[L.POS + 1], rec[L.POS + 2])) - br[i]
    if kind == L.BOX:
        rec = recs[j]
        centre = to_local(rec, (wc[i, 0], wc[i, 1], wc[i, 2]))
        return point_box(centre, (rec[L.HALF_X], rec[L.HALF_Y], rec[L.HALF_Z]))[0] - br[i]
    return _gap(wc, br, i, j)


@njit(**JIT)
def near_slack(q, dh, modified, C, threshold, work):
    """Whether the checked pairs of the contact tuple ``C`` closer than ``threshold`` [m]
    at q (the broad phase first: a pair whose :func:`_lower_bound` is that far is not;
    then the narrow-phase distance) are exactly its active ``rows``: if so, a lower bound
    [m] of the distance of every other pair (inf without one), else -inf (found at the
    first pair that differs).  Leaves ``work`` posed at q."""
    world0, link, local, _, kinds, bc, br, verts = C[:8]
    pairs, rows = C[11], C[13]
    F, recs, wc = work[0], work[1], work[2]
    _pose(q, dh, modified, world0, link, local, bc, F, recs, wc)
    k = 0
    slack = math.inf
    for p in range(pairs.shape[0]):
        i, j = pairs[p, 0], pairs[p, 1]
        bound = _lower_bound(kinds, recs, wc, br, i, j)
        if bound < threshold:
            bound = pair_distance(kinds[i], recs[i], kinds[j], recs[j], verts, threshold)[0]
            if bound < threshold:
                if k == rows.shape[0] or rows[k, 0] != i or rows[k, 1] != j:
                    return -math.inf
                k += 1
                continue
        slack = min(slack, bound)
    return slack if k == rows.shape[0] else -math.inf


@njit(**INLINE)
def moved(arms, q, q0):
    """A bound [m] on how far any point of two shapes moves relative to each other from
    q0 to q: twice Σ_j arms_j |q_j − q0_j| (each shape's points move at most the lever-arm
    bound along the straight joint path, ``collision.path.lever_arms``)."""
    bound = 0.0
    for j in range(q.shape[0]):
        bound += arms[j] * abs(q[j] - q0[j])
    return 2.0 * bound


@njit(**INLINE)
def _copy(x, y):
    """The vector x into y (no temporary: for :data:`UNCOUNTED` kernels)."""
    for c in range(x.shape[0]):
        y[c] = x[c]


@njit(**INLINE)
def _distance2(x, y):
    """Squared distance of two 3-vectors."""
    return (x[0] - y[0]) ** 2 + (x[1] - y[1]) ** 2 + (x[2] - y[2]) ** 2


@njit(**INLINE)
def _moved(out, centre):
    """How far [m] an end sphere's centre is from where ``out`` last saw it."""
    return math.sqrt(_distance2(centre, out[O_CENTRE:O_CENTRE + 3]))


@njit(**INLINE)
def _remember(out, d, centre):
    """An end sphere's distance d [m] at its centre (3-tuple) into ``out``."""
    out[O_GAP] = d
    for c in range(3):
        out[O_CENTRE + c] = centre[c]


@njit(**INLINE)
def _stage_record(out, ka, kb, ra, rb, gains, anchor, anchored):
    """What :func:`contact_stage` reads of a contact point besides its frame, into ``out``:
    its bodies and radii, the pair's gains (4,), its anchors (2, 3) and whether they are set."""
    out[O_BODY_A], out[O_BODY_B], out[O_RADIUS_A], out[O_RADIUS_B] = ka, kb, ra, rb
    for c in range(4):
        out[O_GAINS + c] = gains[c]
    for c in range(3):
        out[O_ANCHOR_A + c] = anchor[0, c]
        out[O_ANCHOR_B + c] = anchor[1, c]
    out[O_ANCHORED] = 1.0 if anchored else 0.0


@njit(**INLINE)
def _fix(F, ka, kb, ra, rb, out, d, a, b, nrm):
    """A contact point of the step into ``out``: its exact distance d [m], witness points
    a, b and normal nrm (3-tuples) at the step's start, O_ON set, O_FIXED = n·b and the
    core points under a and b (radii ra, rb) in the frames of their bodies ka, kb."""
    out[O_D] = d
    out[O_ON] = 1.0
    out[O_FIXED] = dot(nrm, a) + d
    for c in range(3):
        out[O_POINT + c] = a[c]
        out[O_NORMAL + c] = nrm[c]
    to_body(F, ka, (a[0] - ra * nrm[0], a[1] - ra * nrm[1], a[2] - ra * nrm[2]), out[O_HELD_A:O_HELD_A + 3])
    to_body(F, kb, (b[0] + rb * nrm[0], b[1] + rb * nrm[1], b[2] + rb * nrm[2]), out[O_HELD_B:O_HELD_B + 3])
