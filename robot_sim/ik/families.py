"""Closed-form solvers of the IK families (compiled), on a chain of screws
(:mod:`robot_sim.ik.geometry`): ``E_0(q_0) ⋯ E_{m-1}(q_{m-1}) M = T``.

Each solver solves a block of G poses, loaded into the scratch ``W``
(:mod:`robot_sim.ik.block`), and writes the K branches of each pose there (values, and
their posture bits into ``C``); K is the family's (:data:`robot_sim.ik.family.BRANCHES`),
and a pair of branches may repeat at a singular pose.  All but :func:`parallel_axes`
give each angle by its cosine and sine, as the subproblems give them, and NaN for its
value: the angles are taken by atan2 a block of branches at once
(:func:`robot_sim.ik.pipeline.pass1`); the value is that of a slide.
:func:`parallel_axes` writes every value, and NaN for the cosines and sines.  ``A`` holds the constant points and
directions the classification prepared (rows listed per solver).  Angles that a singular
pose leaves free take their value in q0: ``D`` (m, 2) holds their cosines and sines.

Each solver is a few loops over the poses whose bodies are straight-line code (every
subproblem inlined, each branch a select): the compiler runs them a pose per vector
lane, eight poses at once (AVX-512), about three times faster than a pose at a time.
So the chain's constants are read into registers before the loops (a read of an array
in the loop would be a read per pose), and each loop writes branches in pairs.

The solvers (and :func:`robot_sim.ik.position.arm_position`) count no references to their
arrays (:data:`~robot_sim.kernels.jit.UNCOUNTED`): they allocate nothing, and the counting
at each call took about 3 % of a batch's CPU.

* :func:`spherical_wrist` (Pieper): axes 3, 4, 5 meet at the wrist centre w, so
  joints 0–2 place w (:func:`robot_sim.ik.position.arm_position`, up to 4 ways) and the
  wrist turns the rest: R_3 R_4 h_5 = R_w h_5 is SP2 (2 ways), then q_5 by SP1.
* :func:`three_parallel` (the UR family): axes 1, 2, 3 parallel, axes 4 and 5 meet at o.
  Turns about the parallel axes keep components along h_1, so
  h_1ᵀ E_0⁻¹ (T M⁻¹ o) = h_1ᵀ o gives q_0 (SP4), h_1ᵀ R_0ᵀ R h_5 = h_1ᵀ R_4 h_5 gives q_4
  (SP4) and R_5ᵀ R_4ᵀ h_1 = Rᵀ R_0 h_1 gives q_5 (SP1); the sum q_1 + q_2 + q_3 follows
  by SP1, and the planar pair by SP3 and SP1 (up to 8 ways).
* :func:`parallel_axes` (planar arms, SCARA): every revolute axis parallel to h, a
  prismatic joint along h: the turn about h (SP1), the slide (a projection on h), the
  planar pair (SP3, SP1) — 2 ways.
* :func:`position_only`: three joints place the tool point (4 ways).
"""
from __future__ import annotations

import math

import numba
import numpy as np

from robot_sim.ik.block import CS_ROWS, LANES, MAX_JOINTS, OUT_ROWS, POSES, pose_of, put, put6
from robot_sim.ik.position import (ELBOW_DOWN, WRIST_FLIPPED, apply, arm_axes, arm_of, arm_positions, free_cs,
                                   matrix_pose, posture_bits, rmul, row, rtmul, turn_cs)
from robot_sim.ik.subproblems import Vec, rot, rot_cs, sp1, sp1_cs, sp2, sp3, sp4
from robot_sim.kernels.algebra import add, cross, dot, norm, perp, sub
from robot_sim.kernels.atan2 import atan2
from robot_sim.kernels.jit import JIT, UNCOUNTED

SPHERICAL_WRIST, THREE_PARALLEL, PARALLEL_AXES, POSITION_ONLY = range(4)


#: Axes closer than this (sine of their angle, or cosine for ⟂) count as aligned (or ⟂).
ALIGNED = 1e-12


@numba.njit(inline="always", **JIT)
def wrist_axes(H: np.ndarray) -> tuple:
    """The wrist's axes h_3, h_4, h_5 and what :func:`wrist_bit` and :func:`wrist` ask of
    them: (h3, h4, h5, nᵀh_5, nᵀ(h_4 × h_5), zyz) with n = h_3 × h_4, and whether h_5 = ±h_3
    with h_4 ⟂ h_3 (a ZYZ wrist).  Taken once per block of poses."""
    h3, h4, h5 = row(H, 3), row(H, 4), row(H, 5)
    n = cross(h3, h4)
    zyz = norm(cross(h3, h5)) < ALIGNED and abs(dot(h3, h4)) < ALIGNED
    return h3, h4, h5, dot(n, h5), dot(n, cross(h4, h5)), zyz


@numba.njit(inline="always", **JIT)
def wrist_bit(axes: tuple, c5: float, s5: float) -> int:
    """Flipped when (h_3 × R_3 h_4)ᵀ R_3 R_4 h_5 > 0: the wrist's two postures differ in
    that sign, and Siciliano's first wrist solution (sin θ5 > 0 on his anthropomorphic arm
    with spherical wrist) is the one not flipped.  R_3 drops out (R_3ᵀ(h_3 × R_3 h_4) =
    h_3 × h_4), and with n = h_3 × h_4 ⟂ h_4 Rodrigues' formula leaves
    nᵀR_4 h_5 = c5 nᵀh_5 + s5 nᵀ(h_4 × h_5), c5 and s5 the cosine and sine of joint 4
    (``axes``: :func:`wrist_axes`)."""
    return WRIST_FLIPPED if c5 * axes[3] + s5 * axes[4] > 0.0 else 0


@numba.njit(inline="always", **JIT)
def _branch(W: np.ndarray, C: np.ndarray, plane: int, lane: int, values: tuple, bits: int, cs12: tuple) -> None:
    """A branch of a 6-joint chain into its plane and lane of W and C: its values (NaN for
    a turn), bits and the cosines and sines of its joints."""
    put6(W, OUT_ROWS + plane * MAX_JOINTS, lane, values)
    C[plane * LANES + lane] = bits
    put6(W, CS_ROWS + 2 * plane * MAX_JOINTS, lane, cs12[:6])
    put6(W, CS_ROWS + 2 * plane * MAX_JOINTS + 6, lane, cs12[6:])


@numba.njit(inline="always", **JIT)
def wrist(axes: tuple, w6: Vec, wx: Vec, x6: Vec, f3: tuple, f4: tuple, f5: tuple) -> tuple:
    """The two wrists (c4, s4, c5, s5, c6, s6) with R_3 R_4 R_5 = R_w, given R_w h_5 and
    R_w x6 (x6 ⟂ h_5); f3, f4, f5 the (cos, sin) of q0's wrist angles (f3 negated)."""
    h3, h4, h5, zyz = axes[0], axes[1], axes[2], axes[5]
    # h_5 = ±h_3 and h_4 ⟂ h_3 (a ZYZ wrist): R_3(q4 + π) R_4(−q5) R_5(q6 + π) = R_3(q4) R_4(q5) R_5(q6),
    # since R_3(π) turns h_4 into −h_4 and R_3(π) R_5(π) = I; the second wrist follows from the first
    (c5a, s5a), m4a, (c5b, s5b), m4b, _ = sp2(h4, h5, h3, w6, f4, f3, not zyz)
    c4a, s4a = m4a[0], -m4a[1]
    c6a, s6a = sp1_cs(h5, x6, rot_cs(h4, c5a, -s5a, rot_cs(h3, c4a, -s4a, wx)), f5)
    c4b, s4b = m4b[0], -m4b[1]
    c6b, s6b = sp1_cs(h5, x6, rot_cs(h4, c5b, -s5b, rot_cs(h3, c4b, -s4b, wx)), f5)
    if zyz:
        c4b, s4b, c5b, s5b, c6b, s6b = -c4a, -s4a, c5a, -s5a, -c6a, -s6a
    return (c4a, s4a, c5a, s5a, c6a, s6a), (c4b, s4b, c5b, s5b, c6b, s6b)


@numba.njit(**UNCOUNTED)
def spherical_wrist(case: int, H: np.ndarray, P: np.ndarray, rev: np.ndarray, A: np.ndarray, G: int, D: np.ndarray,
                    W: np.ndarray, C: np.ndarray) -> None:
    """rev: nonzero for the revolute joints.  A: 0 wrist centre w, 1 M⁻¹w, 2 R_Mᵀh_5, 3 x6 ⟂ h_5, 4 R_Mᵀx6, 5 meeting point o
    of the arm axes, 6 the shoulder direction f0.  Arm solution j (lane j·POSES + g)
    gives branches 2j, 2j + 1 (its two wrists)."""
    arm_positions(case, H, P, row(A, 5), row(A, 0), row(A, 1), False, G, D, W)
    h0, h1, h2 = row(H, 0), row(H, 1), row(H, 2)
    a1, a2, a4, f0, x6 = row(A, 1), row(A, 2), row(A, 4), row(A, 6), row(A, 3)
    axes, axes0 = wrist_axes(H), arm_axes(H, P)
    p0 = row(P, 0)
    r0, r1, r2 = rev[0] != 0, rev[1] != 0, rev[2] != 0  # (R_0 R_1 R_2)ᵀ: the arm's turn undone (a slide does not turn)
    f3, f4, f5 = free_cs(D, 3, -1.0), free_cs(D, 4, 1.0), free_cs(D, 5, 1.0)
    nan = np.nan
    for j in range(4):
        for g in range(G):
            lane = j * POSES + g
            T = pose_of(W, lane)
            pw, r6, rx = apply(T, a1), rmul(T, a2), rmul(T, a4)
            t3, c0, s0, c1, s1, c2, s2 = arm_of(W, lane)
            bits = posture_bits(axes0, f0, c1, s1, turn_cs(h0, p0, c0, -s0, pw))
            arm_cs = (c0, s0, c1, s1, c2, s2)
            c0, s0 = (c0, s0) if r0 else (1.0, 0.0)
            c1, s1 = (c1, s1) if r1 else (1.0, 0.0)
            c2, s2 = (c2, s2) if r2 else (1.0, 0.0)
            w6 = rot_cs(h2, c2, -s2, rot_cs(h1, c1, -s1, rot_cs(h0, c0, -s0, r6)))
            wx = rot_cs(h2, c2, -s2, rot_cs(h1, c1, -s1, rot_cs(h0, c0, -s0, rx)))
            a, b = wrist(axes, w6, wx, x6, f3, f4, f5)
            values = (nan, nan, t3, nan, nan, nan)
            _branch(W, C, 0, lane, values, bits | wrist_bit(axes, a[2], a[3]), arm_cs + a)
            _branch(W, C, 1, lane, values, bits | wrist_bit(axes, b[2], b[3]), arm_cs + b)


@numba.njit(inline="always", **JIT)
def _planar_branch(W: np.ndarray, C: np.ndarray, plane: int, lane: int, planar: tuple, t3: tuple, axes0: tuple,
                   f0: Vec, c1: float, s1: float, wbit: int, wrist_cs: tuple) -> None:
    """A branch of :func:`three_parallel` for the root t3 = (cos, sin) of q_2: q_1 by SP1,
    q_3 from the sum (``planar``: h_1, h_2, p_1, p_2, p_3, y, q0's free (cos, sin) of q_1,
    the sum's (cos, sin), g2, g3)."""
    h1, h2, p1, p2, p3, y, f1, ct, st, g2, g3 = planar
    c3, s3 = t3
    c2, s2 = sp1_cs(h1, sub(turn_cs(h2, p2, c3, s3, p3), p1), sub(y, p1), f1)
    c, s = ct * c2 + st * s2, st * c2 - ct * s2  # of the sum less q_2, then less g2 q_3: g3 q_4
    c4, s4 = c * c3 + g2 * s * s3, g3 * (s * c3 - g2 * c * s3)
    nan = np.nan
    _branch(W, C, plane, lane, (nan, nan, nan, nan, nan, nan), posture_bits(axes0, f0, c2, s2, y) | wbit,
            (c1, s1, c2, s2, c3, s3, c4, s4) + wrist_cs)


@numba.njit(**UNCOUNTED)
def three_parallel(H: np.ndarray, P: np.ndarray, M: np.ndarray, A: np.ndarray, G: int, q0: np.ndarray,
                   D: np.ndarray, W: np.ndarray, C: np.ndarray) -> None:
    """A: 0 the meeting point o of axes 4 and 5, 1 M⁻¹o, 2 R_Mᵀh_5, 3 x1 ⟂ h_1, 4 f0.
    Branch 4a + 2b + c: the a-th root of q_0, the b-th of q_4, the c-th of q_2 (lane
    (2a + b)·POSES + g, plane c).  q0 (m,): q0's values of the chain's joints."""
    h0, h1, h2, h3, h4, h5 = row(H, 0), row(H, 1), row(H, 2), row(H, 3), row(H, 4), row(H, 5)
    p0, p1, p2, p3, p4, p5 = row(P, 0), row(P, 1), row(P, 2), row(P, 3), row(P, 4), row(P, 5)
    g2, g3 = (1.0 if dot(h1, h2) > 0.0 else -1.0), (1.0 if dot(h1, h3) > 0.0 else -1.0)
    axes, axes0 = wrist_axes(H), arm_axes(H, P)
    Mt = matrix_pose(M)
    a0, a1, a2, x1, f0 = row(A, 0), row(A, 1), row(A, 2), row(A, 3), row(A, 4)
    a3, b3 = perp(h1, sub(p3, p2)), perp(h1, sub(p2, p1))
    d0 = dot(h1, sub(a0, p0))
    f1, f5 = free_cs(D, 1, 1.0), free_cs(D, 5, -1.0)
    total = q0[1] + g2 * q0[2] + g3 * q0[3]
    fs = (math.cos(total), math.sin(total))  # (free: the sum q_1 + g2 q_2 + g3 q_3 of q0)
    for ab in range(4):
        for g in range(G):
            lane = ab * POSES + g
            T = pose_of(W, lane)
            po, r6 = apply(T, a1), rmul(T, a2)
            t1a, t1b, _, _ = sp4(h1, h0, sub(po, p0), d0)
            ct1, st1 = t1a if ab < 2 else t1b
            c1, s1 = ct1, -st1
            t5a, t5b, _, _ = sp4(h1, h4, h5, dot(h1, rot_cs(h0, c1, -s1, r6)))
            c5, s5 = t5a if ab % 2 == 0 else t5b
            back = rmul(Mt, rtmul(T, rot_cs(h0, c1, s1, h1)))  # Rᵀ R_0 h_1 with R = R_T R_Mᵀ
            c6, s6 = sp1_cs(h5, rot_cs(h4, c5, -s5, h1), back, f5)
            s6 = -s6
            v = rot_cs(h0, c1, -s1, rmul(T, rtmul(Mt, rot_cs(h5, c6, -s6, rot_cs(h4, c5, -s5, x1)))))
            ct, st = sp1_cs(h1, x1, v, fs)  # of q_1 + g2 q_2 + g3 q_3
            # y = E_0⁻¹ T M⁻¹ E_5⁻¹ E_4⁻¹ p3, the point on axis 3 that joints 1 and 2 must reach
            z = turn_cs(h5, p5, c6, -s6, turn_cs(h4, p4, c5, -s5, p3))
            z = rtmul(Mt, sub(z, (Mt[9], Mt[10], Mt[11])))
            y = turn_cs(h0, p0, c1, -s1, apply(T, z))
            t3a, t3b, _, _ = sp3(h2, a3, b3, norm(perp(h1, sub(y, p1))))
            planar = (h1, h2, p1, p2, p3, y, f1, ct, st, g2, g3)
            bits = wrist_bit(axes, c5, s5)
            wrist_cs = (c5, s5, c6, s6)
            _planar_branch(W, C, 0, lane, planar, t3a, axes0, f0, c1, s1, bits, wrist_cs)
            _planar_branch(W, C, 1, lane, planar, t3b, axes0, f0, c1, s1, bits, wrist_cs)


@numba.njit(**UNCOUNTED)
def parallel_axes(idx: np.ndarray, H: np.ndarray, P: np.ndarray, A: np.ndarray, G: int, q0: np.ndarray,
                  m: int, W: np.ndarray, C: np.ndarray) -> None:
    """idx: the two arm joints a, b, the turning joint c and the slide s (−1 if none).
    A: 0 a point c on axis c (the tool point if none), 1 M⁻¹c, 2 x ⟂ h, 3 R_Mᵀx.  Angles
    by atan2 here, so a pose at a time (q0 (m,): the chain's values of q0, for free
    angles); branch n of pose g in plane n of lane g, its cosines and sines NaN."""
    a, b, c, s = idx[0], idx[1], idx[2], idx[3]
    h, ha, hb = row(H, a), row(H, a), row(H, b)
    pa, pb = row(P, a), row(P, b)
    sb = 1.0 if dot(h, hb) > 0.0 else -1.0
    point, a1, a2, a3 = row(A, 0), row(A, 1), row(A, 2), row(A, 3)
    hs = row(H, s) if s >= 0 else (0.0, 0.0, 0.0)
    sc = (1.0 if dot(h, row(H, c)) > 0.0 else -1.0) if c >= 0 else 1.0
    for g in range(G):
        T = pose_of(W, g)
        target = apply(T, a1)
        slide = 0.0
        if s >= 0:
            slide = dot(h, sub(target, point)) / dot(h, hs)
            target = sub(target, (slide * hs[0], slide * hs[1], slide * hs[2]))
        total = 0.0
        if c >= 0:
            total = sp1(h, a2, rmul(T, a3), q0[a] + sb * q0[b] + sc * q0[c])
        dist = norm(perp(h, sub(target, pa)))
        tba, tbb, _, _ = sp3(hb, perp(h, sub(point, pb)), perp(h, sub(pb, pa)), dist)
        for n, (cb, sb_) in enumerate((tba, tbb)):
            qb = atan2(sb_, cb)
            elbow = sub(turn_cs(hb, pb, cb, sb_, point), pa)
            qa = sp1(ha, elbow, sub(target, pa), q0[a])
            v = OUT_ROWS + n * MAX_JOINTS
            for j in range(m):
                put(W, v + j, g, 0.0)
                put(W, CS_ROWS + 2 * n * MAX_JOINTS + 2 * j, g, np.nan)
                put(W, CS_ROWS + 2 * n * MAX_JOINTS + 2 * j + 1, g, np.nan)
            put(W, v + a, g, qa)
            put(W, v + b, g, qb)
            if s >= 0:
                put(W, v + s, g, slide)
            if c >= 0:
                put(W, v + c, g, sc * (total - qa - sb * qb))
            upper = rot(ha, qa, sub(pb, pa))
            C[n * LANES + g] = ELBOW_DOWN if dot(h, cross(upper, sub(target, add(pa, upper)))) > 0.0 else 0


@numba.njit(**UNCOUNTED)
def position_only(case: int, H: np.ndarray, P: np.ndarray, A: np.ndarray, G: int, D: np.ndarray, W: np.ndarray,
                  C: np.ndarray) -> None:
    """A: 0 the tool point at q = 0, 5 meeting point o, 6 f0 (the rows of spherical_wrist).
    Branch k is arm solution k (plane k mod 2, lane (k div 2)·POSES + g)."""
    arm_positions(case, H, P, row(A, 5), row(A, 0), row(A, 1), True, G, D, W)
    h0, p0, f0 = row(H, 0), row(P, 0), row(A, 6)
    axes0 = arm_axes(H, P)
    for k in range(4):
        plane, at = k % 2, (k // 2) * POSES
        v, c = OUT_ROWS + plane * MAX_JOINTS, CS_ROWS + 2 * plane * MAX_JOINTS
        for g in range(G):
            lane = k * POSES + g
            T = pose_of(W, lane)
            t3, c0, s0, c1, s1, c2, s2 = arm_of(W, lane)
            y = turn_cs(h0, p0, c0, -s0, (T[9], T[10], T[11]))
            C[plane * LANES + at + g] = posture_bits(axes0, f0, c1, s1, y)
            put(W, v, at + g, np.nan)
            put(W, v + 1, at + g, np.nan)
            put(W, v + 2, at + g, t3)
            put(W, c, at + g, c0)
            put(W, c + 1, at + g, s0)
            put(W, c + 2, at + g, c1)
            put(W, c + 3, at + g, s1)
            put(W, c + 4, at + g, c2)
            put(W, c + 5, at + g, s2)
