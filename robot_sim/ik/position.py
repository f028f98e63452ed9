"""Position of a point carried by three joints, in closed form (compiled).

Joints 0, 1, 2 of a screw chain (:mod:`robot_sim.ik.geometry`) carry the point ``w``
(world, q = 0) to ``pw``: ``E_0(q_0) E_1(q_1) E_2(q_2) w = pw``.  Which closed form
applies depends on how the axes meet (the case is chosen by :mod:`robot_sim.ik.classify`):

* ``ONE_TWO_MEET``: axes 0 and 1 meet at ``o``, joint 2 revolute.  Joints 0 and 1 keep
  the distance to o, so ‖E_2 w − o‖ = ‖pw − o‖ gives q_2 (SP3), then SP2 gives q_0, q_1.
* ``ONE_TWO_MEET_SLIDE``: the same with joint 2 prismatic: ‖w + q_2 h_2 − o‖ = ‖pw − o‖
  is a quadratic in q_2 (the Stanford arm).
* ``TWO_THREE_PARALLEL``: axes 1 and 2 parallel.  Turns about them keep the component
  along h_1, so h_1ᵀ E_0⁻¹ pw = h_1ᵀ w gives q_0 (SP4); the planar pair then gives q_2 by
  the distance to axis 1 (SP3 in the plane ⟂ h_1) and q_1 by SP1.
* ``ONE_TWO_PARALLEL``: axes 0 and 1 parallel: h_0ᵀ E_2 w = h_0ᵀ pw gives q_2 (SP4), then
  the planar pair q_1 (SP3), q_0 (SP1).
* ``TWO_THREE_MEET``: axes 1 and 2 meet at o: ‖E_0⁻¹ pw − o‖ = ‖w − o‖ gives q_0 (SP3),
  then SP2 gives q_1, q_2.

Each case gives up to four solutions, with branch bits: shoulder (the point behind
axis 0 as seen along ``f0``, the arm's reach direction at q = 0) and elbow (the elbow,
on axis 2, below the line from the shoulder, on axis 1, to the point, "below" along h_0).
Where an angle is free (a singular pose) it takes its value in ``q0``.
"""
from __future__ import annotations

import math

import numba
import numpy as np

from robot_sim.ik.subproblems import add, dot, norm, perp, rot_cs, scale, sp1_cs, sp2, sp3, sp4, sub
from robot_sim.kernels.jit import JIT, UNCOUNTED

ONE_TWO_MEET, ONE_TWO_MEET_SLIDE, TWO_THREE_PARALLEL, ONE_TWO_PARALLEL, TWO_THREE_MEET = range(5)
#: Branch bits of an arm posture.
SHOULDER_LEFT, ELBOW_DOWN, WRIST_FLIPPED = 4, 2, 1


@numba.njit(inline="always", **JIT)
def row(A: np.ndarray, i: int) -> tuple[float, float, float]:
    return (A[i, 0], A[i, 1], A[i, 2])


@numba.njit(inline="always", **JIT)
def turn_cs(h: tuple, p: tuple, c: float, s: float, x: tuple) -> tuple[float, float, float]:
    """E(q) x for a revolute joint about the line (p, h), given c = cos q and s = sin q."""
    return add(rot_cs(h, c, s, sub(x, p)), p)


@numba.njit(inline="always", **JIT)
def posture_bits(H: np.ndarray, P: np.ndarray, f0: tuple, c1: float, s1: float, y: tuple) -> int:
    """Shoulder and elbow bits of an arm reaching the point pw, given y = E_0(q_0)⁻¹ pw
    (the point with joint 0's turn undone) and joint 1's cosine and sine.  Joint 0's turn
    fixes h_0 and keeps lengths, so both bits are judged before it: the point behind
    axis 0, f0ᵀ(y − p_0) < 0, and the elbow E_1 p_2 below the line from the shoulder p_1
    to y along h_0 (one turn, not four)."""
    h0, p0, h1, p1 = row(H, 0), row(P, 0), row(H, 1), row(P, 1)
    bits = SHOULDER_LEFT if dot(f0, sub(y, p0)) < 0.0 else 0
    v, line = rot_cs(h1, c1, s1, sub(row(P, 2), p1)), sub(y, p1)
    ll = dot(line, line)
    if ll > 0.0:
        v = sub(v, scale(dot(v, line) / ll, line))
    return bits | (ELBOW_DOWN if dot(v, h0) < 0.0 else 0)


@numba.njit(**UNCOUNTED)
def arm_position(case: int, H: np.ndarray, P: np.ndarray, o: tuple, w: tuple, pw: tuple,
                 q0: np.ndarray, out: np.ndarray, cs: np.ndarray) -> int:
    """Every (q_0, q_1, q_2) putting w at pw: cos q_j, sin q_j in cs[k, 2j], cs[k, 2j + 1]
    as the subproblems give them (the angles follow by atan2,
    :func:`robot_sim.ik.pipeline.pass1`), out[k, 0:3] NaN but for the slide of
    ``ONE_TWO_MEET_SLIDE`` (out[k, 2], with cosine and sine 1, 0: it does not turn);
    returns how many."""
    h0, h1, h2 = row(H, 0), row(H, 1), row(H, 2)
    p0, p1, p2 = row(P, 0), row(P, 1), row(P, 2)
    n = 0
    if case == ONE_TWO_MEET or case == ONE_TWO_MEET_SLIDE:
        dist = norm(sub(pw, o))
        if case == ONE_TWO_MEET:
            (c3a, s3a), (c3b, s3b), _, _ = sp3(h2, sub(w, p2), sub(p2, o), dist)
            t3a, t3b = (np.nan, c3a, s3a), (np.nan, c3b, s3b)
        else:
            b = dot(h2, sub(w, o))
            disc = b * b - dot(sub(w, o), sub(w, o)) + dist * dist
            root = math.sqrt(disc) if disc > 0.0 else 0.0
            t3a, t3b = (-b + root, 1.0, 0.0), (-b - root, 1.0, 0.0)  # a slide: (1, 0) as it does not turn
        y = sub(pw, o)
        for t3, c3, s3 in (t3a, t3b):
            if case == ONE_TWO_MEET_SLIDE:
                x = sub(add(w, scale(t3, h2)), o)
            else:
                x = sub(turn_cs(h2, p2, c3, s3, w), o)
            q2a, m1a, q2b, m1b, _ = sp2(h1, x, h0, y, q0[1], -q0[0], True)
            for m1, q2 in ((m1a, q2a), (m1b, q2b)):
                out[n, 0], out[n, 1], out[n, 2] = np.nan, np.nan, t3
                cs[n, 0], cs[n, 1], cs[n, 2], cs[n, 3], cs[n, 4], cs[n, 5] = m1[0], -m1[1], q2[0], q2[1], c3, s3
                n += 1
        return n
    if case == TWO_THREE_PARALLEL:
        t1a, t1b, _, _ = sp4(h1, h0, sub(pw, p0), dot(h1, sub(w, p0)))
        for c1, s1 in (t1a, t1b):
            y = turn_cs(h0, p0, c1, s1, pw)
            dist = norm(perp(h1, sub(y, p1)))
            t3a, t3b, _, _ = sp3(h2, perp(h1, sub(w, p2)), perp(h1, sub(p2, p1)), dist)
            for c3, s3 in (t3a, t3b):
                c2, s2 = sp1_cs(h1, sub(turn_cs(h2, p2, c3, s3, w), p1), sub(y, p1), q0[1])
                cs[n, 0], cs[n, 1], cs[n, 2], cs[n, 3], cs[n, 4], cs[n, 5] = c1, -s1, c2, s2, c3, s3
                n += 1
    elif case == ONE_TWO_PARALLEL:
        t3a, t3b, _, _ = sp4(h0, h2, sub(w, p2), dot(h0, sub(pw, p2)))
        dist = norm(perp(h0, sub(pw, p0)))
        for c3, s3 in (t3a, t3b):
            x = turn_cs(h2, p2, c3, s3, w)
            t2a, t2b, _, _ = sp3(h1, perp(h0, sub(x, p1)), perp(h0, sub(p1, p0)), dist)
            for c2, s2 in (t2a, t2b):
                c1, s1 = sp1_cs(h0, sub(turn_cs(h1, p1, c2, s2, x), p0), sub(pw, p0), q0[0])
                cs[n, 0], cs[n, 1], cs[n, 2], cs[n, 3], cs[n, 4], cs[n, 5] = c1, s1, c2, s2, c3, s3
                n += 1
    else:  # TWO_THREE_MEET
        t1a, t1b, _, _ = sp3(h0, sub(pw, p0), sub(p0, o), norm(sub(w, o)))
        x = sub(w, o)
        for c1, s1 in (t1a, t1b):
            y = sub(turn_cs(h0, p0, c1, s1, pw), o)
            q3a, m2a, q3b, m2b, _ = sp2(h2, x, h1, y, q0[2], -q0[1], True)
            for m2, q3 in ((m2a, q3a), (m2b, q3b)):
                cs[n, 0], cs[n, 1], cs[n, 2], cs[n, 3], cs[n, 4], cs[n, 5] = c1, -s1, m2[0], -m2[1], q3[0], q3[1]
                n += 1
    for k in range(n):
        out[k, 0], out[k, 1], out[k, 2] = np.nan, np.nan, np.nan
    return n
