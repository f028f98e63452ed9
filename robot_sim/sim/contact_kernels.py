"""Compiled penalty-contact terms (:mod:`.contact`): point Jacobians of link points, the
joint torque of the contacts of one configuration, and the step of an arm in contact
(:func:`contact_step`: the contact torque at every integration stage, in one call).

Arrays as in :mod:`.batch`, plus ``body`` (S + O,): the link (0 base .. n) a scene row is
fixed to, -1 for obstacles (fixed in the world); ``axis_frame`` (n,): the frame whose z
axis and origin carry joint j (j for standard DH, j + 1 for modified); ``revolute`` (n,).
World frame, metres, newtons; joint torques in N·m (revolute) or N (prismatic).
"""
from __future__ import annotations

import math

import numpy as np

from robot_sim.collision import layout as L
from robot_sim.collision.batch import _pose, _workspace
from robot_sim.collision.narrow import core_ends, pair_distance
from robot_sim.dynamics.compiled import all_finite, fd_one, step_work
from robot_sim.kernels.status import BAD_ACCEL, BAD_STATE, OK
from robot_sim.kernels.algebra import euler_combine, rk4_combine, rk4_stage
from robot_sim.kernels.jit import JIT, njit
from robot_sim.kernels.model import MOD

# Columns of ``gains`` (A, 4) per active pair.
K_N, C_N, K_T, C_T = range(4)
# Columns of ``out`` (A, POINTS, OUT) per contact point: signed distance, the first
# shape's witness point, the normal (first toward second), the force on the first shape,
# the tangential offset u between its friction anchors.
O_D, O_POINT, O_NORMAL, O_FORCE, O_SLIP = 0, 1, 4, 7, 10
OUT = 13
#: Contact slots per pair: the closest points, then a capsule's two end spheres.
POINTS = 3


@njit(**JIT)
def point_velocity(F, k, p, qd, axis_frame, revolute, out):
    """Velocity (3,) of the point p (world) fixed to link k (-1 or 0: fixed) at joint rates qd."""
    out[0] = out[1] = out[2] = 0.0
    for j in range(max(k, 0)):
        f = axis_frame[j]
        z0, z1, z2 = F[f, 0, 2], F[f, 1, 2], F[f, 2, 2]
        if revolute[j]:
            r0, r1, r2 = p[0] - F[f, 0, 3], p[1] - F[f, 1, 3], p[2] - F[f, 2, 3]
            out[0] += (z1 * r2 - z2 * r1) * qd[j]
            out[1] += (z2 * r0 - z0 * r2) * qd[j]
            out[2] += (z0 * r1 - z1 * r0) * qd[j]
        else:
            out[0] += z0 * qd[j]
            out[1] += z1 * qd[j]
            out[2] += z2 * qd[j]


@njit(**JIT)
def add_point_torque(F, k, p, force, sign, axis_frame, revolute, tau):
    """tau += sign · J_k(p)ᵀ force: the joint torque of a force (3,) at the point p (world)
    of link k (nothing for -1 or 0)."""
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


@njit(**JIT)
def relative_jacobian(F, ka, pa, kb, pb, axis_frame, revolute, J):
    """J (3, n) = J_kb(pb) − J_ka(pa): the velocity of point pb of body kb relative to
    point pa of body ka per unit joint rate."""
    n = J.shape[1]
    e = np.zeros(n)
    v = np.empty(3)
    for j in range(n):
        e[j] = 1.0
        point_velocity(F, kb, pb, e, axis_frame, revolute, v)
        J[0, j], J[1, j], J[2, j] = v[0], v[1], v[2]
        point_velocity(F, ka, pa, e, axis_frame, revolute, v)
        J[0, j] -= v[0]
        J[1, j] -= v[1]
        J[2, j] -= v[2]
        e[j] = 0.0


@njit(**JIT)
def to_world(F, k, x, out):
    """Point x of body k's frame in the world."""
    if k < 0:
        out[0], out[1], out[2] = x[0], x[1], x[2]
        return
    for r in range(3):
        out[r] = F[k, r, 0] * x[0] + F[k, r, 1] * x[1] + F[k, r, 2] * x[2] + F[k, r, 3]


@njit(**JIT)
def to_body(F, k, x, out):
    """World point x in body k's frame (obstacles, k = -1: the world itself)."""
    if k < 0:
        out[0], out[1], out[2] = x[0], x[1], x[2]
        return
    r0, r1, r2 = x[0] - F[k, 0, 3], x[1] - F[k, 1, 3], x[2] - F[k, 2, 3]
    for c in range(3):
        out[c] = F[k, 0, c] * r0 + F[k, 1, c] * r1 + F[k, 2, c] * r2


@njit(**JIT)
def _contact_force(F, ka, kb, d, a, b, nrm, qd, axis_frame, revolute, gains, mu, anchor, anchored, slot, update,
                   tau, out):
    """One contact point of depth −d > 0 (witness points a, b, normal nrm from the first
    shape to the second): its force into tau (joint torque) and out (distance, point,
    normal, force on the first, anchor offset).  With ``update`` (a step's start) a point
    touching for the first time is anchored at its witness points, and a slipping one's
    second anchor is slid back onto the friction cap."""
    va, vb, xa, xb, fb = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(3)
    pa, pb = np.empty(3), np.empty(3)
    for c in range(3):
        pa[c], pb[c] = a[c], b[c]
    point_velocity(F, ka, pa, qd, axis_frame, revolute, va)
    point_velocity(F, kb, pb, qd, axis_frame, revolute, vb)
    v0, v1, v2 = vb[0] - va[0], vb[1] - va[1], vb[2] - va[2]
    rate = v0 * nrm[0] + v1 * nrm[1] + v2 * nrm[2]
    fn = max(gains[K_N] * (-d) - gains[C_N] * rate, 0.0)
    for c in range(3):
        fb[c] = fn * nrm[c]
    u0 = u1 = u2 = 0.0
    if mu > 0.0 and anchored[slot]:
        to_world(F, ka, anchor[0], xa)
        to_world(F, kb, anchor[1], xb)
        w0, w1, w2 = xb[0] - xa[0], xb[1] - xa[1], xb[2] - xa[2]
        wn = w0 * nrm[0] + w1 * nrm[1] + w2 * nrm[2]
        u0, u1, u2 = w0 - wn * nrm[0], w1 - wn * nrm[1], w2 - wn * nrm[2]
    if mu > 0.0 and fn > 0.0:
        t0, t1, t2 = v0 - rate * nrm[0], v1 - rate * nrm[1], v2 - rate * nrm[2]
        g0 = -gains[K_T] * u0 - gains[C_T] * t0
        g1 = -gains[K_T] * u1 - gains[C_T] * t1
        g2 = -gains[K_T] * u2 - gains[C_T] * t2
        size = math.sqrt(g0 * g0 + g1 * g1 + g2 * g2)
        s = mu * fn / size if size > mu * fn else 1.0
        fb[0] += s * g0
        fb[1] += s * g1
        fb[2] += s * g2
    add_point_torque(F, kb, pb, fb, 1.0, axis_frame, revolute, tau)
    add_point_torque(F, ka, pa, fb, -1.0, axis_frame, revolute, tau)
    for c in range(3):
        out[O_FORCE + c] = -fb[c]
    out[O_SLIP], out[O_SLIP + 1], out[O_SLIP + 2] = u0, u1, u2
    if not (update and mu > 0.0):
        return
    if not anchored[slot]:
        to_body(F, ka, pa, anchor[0])
        to_body(F, kb, pb, anchor[1])
        anchored[slot] = True
        return
    size = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    cap = mu * fn / gains[K_T]
    if size > cap:
        keep = 1.0 - cap / size
        xb[0] -= keep * u0
        xb[1] -= keep * u1
        xb[2] -= keep * u2
        to_body(F, kb, xb, anchor[1])


@njit(**JIT)
def contact_torque(q, qd, dh, modified, world0, link, local, recs0, kinds, bc, br, verts, body, axis_frame,
                   revolute, rows, gains, mu, anchors, anchored, update, tau, out):
    """The joint torque tau (n,) of the active pairs ``rows`` (A, 2) at (q, qd), and per
    pair and contact point into ``out`` (A, POINTS, OUT) its distance, witness point,
    normal, force and anchor offset (distance inf: no such point).

    Contact points of a pair (first shape a, second b): their closest points and, when a
    is a capsule, the sphere of its shallower end (slot 1 or 2 for its end) if that
    overlaps too: a capsule lying flat rests on both ends instead of rocking between them,
    and the springs' energy ½ k (δ² + δ_end²) stays a smooth function of q (the two ends
    trade places where their depths are equal).  A point of depth δ > 0 pushes the
    shapes apart with f_n = max(0, k_n δ − c_n ḋ) along its normal (ḋ the separation
    rate).  With friction (mu > 0) the tangential force is −k_T u − c_T v_t, capped at
    mu · f_n, where u is the tangential offset between the point's two anchors
    (``anchors`` (A, POINTS, 2, 3): a point on each shape, in its body's frame; zero
    where not ``anchored`` (A, POINTS)) and v_t the slip velocity.  The force on b acts
    at b's witness point, its opposite at a's.  ``update`` (at a step's start) also
    moves the anchors (:func:`_contact_force`) and releases those of points that do not
    touch."""
    F, recs, wc = _workspace(dh, link, recs0, bc)
    _pose(q, dh, modified, world0, link, local, bc, F, recs, wc)
    for j in range(tau.shape[0]):
        tau[j] = 0.0
    end = np.empty(recs.shape[1])
    for p in range(rows.shape[0]):
        i, j = rows[p, 0], rows[p, 1]
        for e in range(POINTS):
            out[p, e, O_D] = math.inf
        d, a, b, nrm = pair_distance(kinds[i], recs[i], kinds[j], recs[j], verts, math.inf)
        _record(out[p, 0], d, a, nrm)
        if gains[p, K_N] > 0.0 and d < 0.0:
            _contact_force(F, body[i], body[j], d, a, b, nrm, qd, axis_frame, revolute, gains[p], mu, anchors[p, 0],
                           anchored[p], 0, update, tau, out[p, 0])
            if kinds[i] == L.CAPSULE:
                ends = core_ends(kinds[i], recs[i])
                d_end = np.empty(2)
                for e in range(2):
                    end[:] = recs[i]
                    for c in range(3):
                        end[L.POS + c] = ends[e][c]
                    d_end[e] = pair_distance(L.SPHERE, end, kinds[j], recs[j], verts, math.inf)[0]
                e = 0 if d_end[0] >= d_end[1] else 1  # the shallower end
                if d_end[e] < 0.0:
                    for c in range(3):
                        end[L.POS + c] = ends[e][c]
                    de, ae, be, ne = pair_distance(L.SPHERE, end, kinds[j], recs[j], verts, math.inf)
                    _record(out[p, 1 + e], de, ae, ne)
                    _contact_force(F, body[i], body[j], de, ae, be, ne, qd, axis_frame, revolute, gains[p], mu,
                                   anchors[p, 1 + e], anchored[p], 1 + e, update, tau, out[p, 1 + e])
        if update:
            for e in range(POINTS):
                if not out[p, e, O_D] < 0.0 or gains[p, K_N] <= 0.0:
                    anchored[p, e] = False


@njit(**JIT)
def _record(out, d, a, nrm):
    out[O_D] = d
    for c in range(3):
        out[O_POINT + c] = a[c]
        out[O_NORMAL + c] = nrm[c]
        out[O_FORCE + c] = 0.0
        out[O_SLIP + c] = 0.0


@njit(**JIT)
def _contact_accel(P, modified, q, qd, tau, g0, world0, link, local, recs0, kinds, bc, br, verts, body, axis_frame,
                   revolute, rows, gains, mu, anchors, anchored, out, total, contact, acc, held, work):
    """q̈ at (q, q̇) under the effort tau plus the contact torque of the active pairs
    (:func:`contact_torque` with the step's gains and anchors) into ``acc`` (``held``: the
    placeholder of ``fd_one``'s held joints, none here)."""
    O, CS, F, NM, zero, bias, M, fext, _, _, _, _, _, _, react = work
    contact_torque(q, qd, P, modified, world0, link, local, recs0, kinds, bc, br, verts, body, axis_frame, revolute,
                   rows, gains, mu, anchors, anchored, False, contact, out)
    for j in range(tau.shape[0]):
        total[j] = tau[j] + contact[j]
    fd_one(P, modified, q, qd, total, g0, fext, False, held, False, acc, react, zero, bias, M, O, CS, F, NM)


@njit(**JIT)
def contact_step(P, rk4, h, q, qd, tau, a_start, use_start, g0, world0, link, local, recs0, kinds, bc, br, verts, body,
                 axis_frame, revolute, rows, gains, mu, anchors, anchored, out, q1, qd1, qdd1):
    """One step of length h [s] of an arm in contact from (q, q̇) (n,) with the effort tau
    held: classical RK4 (``rk4``) or semi-implicit Euler, the acceleration of every stage
    that of tau plus the contact torque at the stage's state (forward dynamics of the
    model table P, gravity g0 in frame 0; the scene arrays and the active pairs, gains and
    anchors of :func:`contact_torque`, P being the scene's table too).  ``a_start`` is the
    start's acceleration when ``use_start`` and finite.  (q, q̇) after the step into q1,
    qd1, the start's acceleration into qdd1; returns the status of
    ``dynamics.compiled.step_batch`` (OK, BAD_STATE, BAD_ACCEL).  The operations of
    ``Simulation``'s stage-by-stage step, so the same bits."""
    n = P.shape[0]
    modified = P[0, MOD] != 0.0
    work = step_work(n)
    held = np.zeros(1, dtype=np.bool_)
    a1, a2, a3, a4, qs, vs = work[8], work[9], work[10], work[11], work[12], work[13]
    total, contact = np.empty(n), np.empty(n)
    if use_start and all_finite(a_start):
        a1[:] = a_start
    else:
        _contact_accel(P, modified, q, qd, tau, g0, world0, link, local, recs0, kinds, bc, br, verts, body, axis_frame,
                       revolute, rows, gains, mu, anchors, anchored, out, total, contact, a1, held, work)
        if not all_finite(a1):
            return BAD_ACCEL
    qdd1[:] = a1
    if not rk4:
        euler_combine(h, q, qd, a1, q1, qd1)
        return OK
    for stage in range(3):  # stages 2, 3, 4 of RK4
        prev = a1 if stage == 0 else (a2 if stage == 1 else a3)
        acc = a2 if stage == 0 else (a3 if stage == 1 else a4)
        rk4_stage(h if stage == 2 else 0.5 * h, q, qd, prev, qd if stage == 0 else vs, qs, vs)
        if not (all_finite(qs) and all_finite(vs)):
            return BAD_STATE
        _contact_accel(P, modified, qs, vs, tau, g0, world0, link, local, recs0, kinds, bc, br, verts, body,
                       axis_frame, revolute, rows, gains, mu, anchors, anchored, out, total, contact, acc, held, work)
        if not all_finite(acc):
            return BAD_ACCEL
    rk4_combine(h, q, qd, a1, a2, a3, a4, q1, qd1)
    return OK
