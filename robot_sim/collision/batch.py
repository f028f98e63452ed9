"""Compiled loops over configurations: forward kinematics of the link frames, shapes
moved to the world, broad phase and narrow phase for every checked pair.

Inputs are plain arrays built once per checker (:class:`.model.CheckModel`):

* ``dh`` (n, NCOL): the robot's compiled model table (:mod:`robot_sim.kernels.model`; row
  i of a modified table holds a_{i-1}, α_{i-1}), whose frames come from the one chain
  kernel :func:`robot_sim.kernels.chain.frames`; ``modified`` its convention; ``world0``
  (4, 4) frame 0 in the world;
* ``link`` (S,): the link (0 base .. n) each robot shape is fixed to; ``local`` (S, REC)
  the shapes in their link frames; ``recs`` (S + O, REC) a work array whose rows S.. hold
  the obstacles in the world; ``kinds`` (S + O,); ``bc`` (S + O, 3) bounding-sphere
  centres (robot rows in link frames, obstacles in the world) and ``br`` (S + O,) radii;
* ``pairs`` (P, 2): rows of ``recs`` checked against each other; ``verts`` (V, 3).

A pair is skipped (the broad phase) when its bounding spheres are farther apart than
the threshold at hand: the padding for ``in_collision``, the best distance so far for
``distance``.  Loops run over configurations inside compiled code, so a batch of N
configurations gives exactly the N single results.
"""
from __future__ import annotations

import math

import numpy as np

from robot_sim.collision import layout as L
from robot_sim.kernels.chain import frames
from robot_sim.kernels.jit import INLINE, JIT, njit
from robot_sim.collision.narrow import pair_distance

@njit(**INLINE)
def place_shape(F, link, local, recs, bc, wc, s):
    """Robot shape s at frames F: its world record into recs[s], its bounding centre into wc[s]."""
    k = link[s]
    for r in range(3):
        f0, f1, f2 = F[k, r, 0], F[k, r, 1], F[k, r, 2]
        for c in range(3):
            recs[s, 3 * r + c] = f0 * local[s, c] + f1 * local[s, 3 + c] + f2 * local[s, 6 + c]
        recs[s, L.POS + r] = f0 * local[s, L.POS] + f1 * local[s, L.POS + 1] + f2 * local[s, L.POS + 2] + F[k, r, 3]
        wc[s, r] = f0 * bc[s, 0] + f1 * bc[s, 1] + f2 * bc[s, 2] + F[k, r, 3]
    for c in range(L.RADIUS, L.REC):
        recs[s, c] = local[s, c]


@njit(**JIT)
def place(F, link, local, recs, bc, wc):
    """Robot shapes at frames F: world records into recs[:S], bounding centres into wc[:S]."""
    for s in range(link.shape[0]):
        place_shape(F, link, local, recs, bc, wc, s)


@njit(**JIT)
def _gap(wc, br, i, j):
    """Lower bound of the distance of shapes i and j from their bounding spheres."""
    dx, dy, dz = wc[i, 0] - wc[j, 0], wc[i, 1] - wc[j, 1], wc[i, 2] - wc[j, 2]
    return math.sqrt(dx * dx + dy * dy + dz * dz) - br[i] - br[j]


@njit(**JIT)
def _workspace(dh, link, recs0, bc):
    """Work arrays of one loop: link frames, world records (obstacle rows filled) and
    world bounding centres (obstacle rows filled)."""
    F = np.empty((dh.shape[0] + 1, 3, 4))
    recs = recs0.copy()
    wc = bc.copy()
    return F, recs, wc


@njit(**JIT)
def _pose(q, dh, modified, world0, link, local, bc, F, recs, wc):
    frames(dh, modified, world0, q, F)
    place(F, link, local, recs, bc, wc)


@njit(**JIT)
def in_collision_batch(Q, dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, padding, out,
                       stats):
    """out[k] = whether any pair is closer than ``padding`` at Q[k]; stats[0] += pairs
    looked at, stats[1] += pairs the broad phase skipped."""
    F, recs, wc = _workspace(dh, link, recs0, bc)
    looked, skipped = 0, 0
    for k in range(Q.shape[0]):
        _pose(Q[k], dh, modified, world0, link, local, bc, F, recs, wc)
        hit = False
        for p in range(pairs.shape[0]):
            i, j = pairs[p, 0], pairs[p, 1]
            looked += 1
            if _gap(wc, br, i, j) >= padding:
                skipped += 1
                continue
            d = pair_distance(kinds[i], recs[i], kinds[j], recs[j], verts, padding)[0]
            if d < padding:
                hit = True
                break
        out[k] = hit
    stats[0] += looked
    stats[1] += skipped


@njit(**JIT)
def distance_batch(Q, dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, out_d, out_pair,
                   out_pts):
    """Smallest signed distance over the pairs at each Q[k] (inf without pairs), the pair
    (row of ``pairs``, -1 if none) and its witness points (2, 3) in the world."""
    F, recs, wc = _workspace(dh, link, recs0, bc)
    for k in range(Q.shape[0]):
        _pose(Q[k], dh, modified, world0, link, local, bc, F, recs, wc)
        best, arg = math.inf, -1
        pa, pb = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
        for p in range(pairs.shape[0]):
            i, j = pairs[p, 0], pairs[p, 1]
            if _gap(wc, br, i, j) >= best:
                continue
            d, a, b, _ = pair_distance(kinds[i], recs[i], kinds[j], recs[j], verts, best)
            if d < best:
                best, arg, pa, pb = d, p, a, b
        out_d[k], out_pair[k] = best, arg
        for c in range(3):
            out_pts[k, 0, c], out_pts[k, 1, c] = pa[c], pb[c]


@njit(**JIT)
def pair_results(q, dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, threshold, out_d,
                 out_pts, out_n, out_recs):
    """Every pair at one configuration: signed distance (inf where the bounding spheres are
    ``threshold`` or more apart), witness points (P, 2, 3) and normals (P, 3), and the
    world records of all shapes (S + O, REC)."""
    F, recs, wc = _workspace(dh, link, recs0, bc)
    _pose(q, dh, modified, world0, link, local, bc, F, recs, wc)
    out_recs[:, :] = recs
    for p in range(pairs.shape[0]):
        i, j = pairs[p, 0], pairs[p, 1]
        out_d[p] = math.inf
        if _gap(wc, br, i, j) >= threshold:
            continue
        d, a, b, nrm = pair_distance(kinds[i], recs[i], kinds[j], recs[j], verts, threshold)
        out_d[p] = d
        for c in range(3):
            out_pts[p, 0, c], out_pts[p, 1, c], out_n[p, c] = a[c], b[c], nrm[c]


@njit(**JIT)
def touching_batch(Q, dh, modified, world0, link, local, recs0, kinds, bc, br, pairs, verts, threshold, out):
    """out[k, p] = whether pair p is closer than ``threshold`` at Q[k] (all pairs)."""
    F, recs, wc = _workspace(dh, link, recs0, bc)
    for k in range(Q.shape[0]):
        _pose(Q[k], dh, modified, world0, link, local, bc, F, recs, wc)
        for p in range(pairs.shape[0]):
            i, j = pairs[p, 0], pairs[p, 1]
            if _gap(wc, br, i, j) >= threshold:
                out[k, p] = False
            else:
                out[k, p] = pair_distance(kinds[i], recs[i], kinds[j], recs[j], verts, threshold)[0] < threshold
