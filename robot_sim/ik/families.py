"""Closed-form solvers of the IK families (compiled), on a chain of screws
(:mod:`robot_sim.ik.geometry`): ``E_0(q_0) ⋯ E_{m-1}(q_{m-1}) M = T``.

Each solver writes every branch of one pose into ``out`` (K, m) and its posture bits into
``code`` (K,), and returns how many it wrote.  All but :func:`parallel_axes` give each
angle by its cosine and sine in ``cs`` (K, 2m: cos q_j at 2j, sin q_j at 2j + 1), as the
subproblems give them, and NaN in ``out`` for it: the angles are taken by atan2 a block of
branches at once (:func:`robot_sim.ik.pipeline.pass1`); ``out`` holds the value of a
slide.  :func:`parallel_axes` writes every value to ``out``.  ``A`` holds the constant
points and directions the classification prepared (rows listed per solver).  Angles that a singular
pose leaves free take their value in ``q0``.

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

import numba
import numpy as np

from robot_sim.ik.position import ELBOW_DOWN, WRIST_FLIPPED, arm_position, posture_bits, row, turn_cs
from robot_sim.ik.subproblems import add, dot, norm, perp, rot, rot_cs, sp1, sp1_cs, sp2, sp3, sp4, sub
from robot_sim.kernels.algebra import cross
from robot_sim.kernels.atan2 import atan2
from robot_sim.kernels.jit import JIT, UNCOUNTED

SPHERICAL_WRIST, THREE_PARALLEL, PARALLEL_AXES, POSITION_ONLY = range(4)


@numba.njit(inline="always", **JIT)
def rmul(T: np.ndarray, x: tuple) -> tuple[float, float, float]:
    """Rotation block of T times x."""
    return (T[0, 0] * x[0] + T[0, 1] * x[1] + T[0, 2] * x[2],
            T[1, 0] * x[0] + T[1, 1] * x[1] + T[1, 2] * x[2],
            T[2, 0] * x[0] + T[2, 1] * x[1] + T[2, 2] * x[2])


@numba.njit(inline="always", **JIT)
def rtmul(T: np.ndarray, x: tuple) -> tuple[float, float, float]:
    """Transposed rotation block of T times x."""
    return (T[0, 0] * x[0] + T[1, 0] * x[1] + T[2, 0] * x[2],
            T[0, 1] * x[0] + T[1, 1] * x[1] + T[2, 1] * x[2],
            T[0, 2] * x[0] + T[1, 2] * x[1] + T[2, 2] * x[2])


@numba.njit(inline="always", **JIT)
def apply(T: np.ndarray, x: tuple) -> tuple[float, float, float]:
    return add(rmul(T, x), (T[0, 3], T[1, 3], T[2, 3]))


#: Axes closer than this (sine of their angle, or cosine for ⟂) count as aligned (or ⟂).
ALIGNED = 1e-12


@numba.njit(inline="always", **JIT)
def wrist_axes(H: np.ndarray) -> tuple:
    """The wrist's axes h_3, h_4, h_5 and what :func:`wrist_bit` and :func:`wrist` ask of
    them: (h3, h4, h5, nᵀh_5, nᵀ(h_4 × h_5), zyz) with n = h_3 × h_4, and whether h_5 = ±h_3
    with h_4 ⟂ h_3 (a ZYZ wrist).  Taken once per pose, not once per branch (the compiler
    cannot tell that H stays put while the branches are written)."""
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
def wrist(axes: tuple, arm: tuple, arm_cs: tuple, bits: int, rw6: tuple, rwx: tuple, x6: tuple,
          q0: np.ndarray, out: np.ndarray, code: np.ndarray, cs: np.ndarray, n: int) -> None:
    """The two wrists (q_3, q_4, q_5) with R_3 R_4 R_5 = R_w, given R_w h_5 and R_w x6
    (x6 ⟂ h_5); rows n, n+1 of out get the arm's joint values ``arm`` (NaN for a turn:
    its angle comes from its cosine and sine) and NaN for the wrist's, of code the arm's
    posture ``bits`` with the wrist's, and of cs the arm's ``arm_cs`` (6 numbers) with the
    wrist's."""
    h3, h4, h5, zyz = axes[0], axes[1], axes[2], axes[5]
    # h_5 = ±h_3 and h_4 ⟂ h_3 (a ZYZ wrist): R_3(q4 + π) R_4(−q5) R_5(q6 + π) = R_3(q4) R_4(q5) R_5(q6),
    # since R_3(π) turns h_4 into −h_4 and R_3(π) R_5(π) = I; the second wrist follows from the first
    q5a, m4a, q5b, m4b, _ = sp2(h4, h5, h3, rw6, q0[4], -q0[3], not zyz)
    for k, (m4, (c5, s5)) in enumerate(((m4a, q5a), (m4b, q5b))):
        c4, s4 = m4[0], -m4[1]
        if k == 1 and zyz:
            c4, s4, c5, s5, c6, s6 = -cs[n, 6], -cs[n, 7], cs[n, 8], -cs[n, 9], -cs[n, 10], -cs[n, 11]
        else:
            c6, s6 = sp1_cs(h5, x6, rot_cs(h4, c5, -s5, rot_cs(h3, c4, -s4, rwx)), q0[5])
        out[n + k, 0], out[n + k, 1], out[n + k, 2] = arm
        out[n + k, 3], out[n + k, 4], out[n + k, 5] = np.nan, np.nan, np.nan
        code[n + k] = bits | wrist_bit(axes, c5, s5)
        cs[n + k, 0], cs[n + k, 1], cs[n + k, 2], cs[n + k, 3], cs[n + k, 4], cs[n + k, 5] = arm_cs
        cs[n + k, 6], cs[n + k, 7], cs[n + k, 8], cs[n + k, 9], cs[n + k, 10], cs[n + k, 11] = c4, s4, c5, s5, c6, s6


@numba.njit(**UNCOUNTED)
def spherical_wrist(case: int, H: np.ndarray, P: np.ndarray, rev: np.ndarray, A: np.ndarray, T: np.ndarray,
                    q0: np.ndarray, out: np.ndarray, code: np.ndarray, cs: np.ndarray) -> int:
    """rev: nonzero for the revolute joints.  A: 0 wrist centre w, 1 M⁻¹w, 2 R_Mᵀh_5, 3 x6 ⟂ h_5, 4 R_Mᵀx6, 5 meeting point o
    of the arm axes, 6 the shoulder direction f0."""
    pw = apply(T, row(A, 1))
    r6, rx = rmul(T, row(A, 2)), rmul(T, row(A, 4))
    f0, x6 = row(A, 6), row(A, 3)
    h0, h1, h2 = row(H, 0), row(H, 1), row(H, 2)
    axes = wrist_axes(H)
    arm = arm_position(case, H, P, row(A, 5), row(A, 0), pw, q0, out, cs)
    for j in range(arm - 1, -1, -1):  # from the last: arm solution j becomes rows 2j, 2j + 1
        q = (out[j, 0], out[j, 1], out[j, 2])
        c0, s0, c1, s1, c2, s2 = cs[j, 0], cs[j, 1], cs[j, 2], cs[j, 3], cs[j, 4], cs[j, 5]
        bits = posture_bits(H, P, f0, c1, s1, turn_cs(h0, row(P, 0), c0, -s0, pw))
        if rev[0] == 0 or rev[1] == 0 or rev[2] == 0:  # (R_0 R_1 R_2)ᵀ: the arm's turn undone (a slide does not turn)
            c0, s0 = (c0, s0) if rev[0] != 0 else (1.0, 0.0)
            c1, s1 = (c1, s1) if rev[1] != 0 else (1.0, 0.0)
            c2, s2 = (c2, s2) if rev[2] != 0 else (1.0, 0.0)
        w6 = rot_cs(h2, c2, -s2, rot_cs(h1, c1, -s1, rot_cs(h0, c0, -s0, r6)))
        wx = rot_cs(h2, c2, -s2, rot_cs(h1, c1, -s1, rot_cs(h0, c0, -s0, rx)))
        wrist(axes, q, (c0, s0, c1, s1, c2, s2), bits, w6, wx, x6, q0, out, code, cs, 2 * j)
    return 2 * arm


@numba.njit(**UNCOUNTED)
def three_parallel(H: np.ndarray, P: np.ndarray, M: np.ndarray, A: np.ndarray, T: np.ndarray,
                   q0: np.ndarray, out: np.ndarray, code: np.ndarray, cs: np.ndarray) -> int:
    """A: 0 the meeting point o of axes 4 and 5, 1 M⁻¹o, 2 R_Mᵀh_5, 3 x1 ⟂ h_1, 4 f0."""
    h0, h1, h2, h3, h4, h5 = row(H, 0), row(H, 1), row(H, 2), row(H, 3), row(H, 4), row(H, 5)
    p0, p1, p2, p3, p4, p5 = row(P, 0), row(P, 1), row(P, 2), row(P, 3), row(P, 4), row(P, 5)
    g2, g3 = (1.0 if dot(h1, h2) > 0.0 else -1.0), (1.0 if dot(h1, h3) > 0.0 else -1.0)
    axes = wrist_axes(H)
    po = apply(T, row(A, 1))
    r6 = rmul(T, row(A, 2))
    x1, f0 = row(A, 3), row(A, 4)
    a3, b3 = perp(h1, sub(p3, p2)), perp(h1, sub(p2, p1))
    n = 0
    t1a, t1b, _, _ = sp4(h1, h0, sub(po, p0), dot(h1, sub(row(A, 0), p0)))
    for ct1, st1 in (t1a, t1b):
        c1, s1 = ct1, -st1
        t5a, t5b, _, _ = sp4(h1, h4, h5, dot(h1, rot_cs(h0, c1, -s1, r6)))
        back = rmul(M, rtmul(T, rot_cs(h0, c1, s1, h1)))  # Rᵀ R_0 h_1 with R = R_T R_Mᵀ
        for c5, s5 in (t5a, t5b):
            c6, s6 = sp1_cs(h5, rot_cs(h4, c5, -s5, h1), back, -q0[5])
            s6 = -s6
            v = rot_cs(h0, c1, -s1, rmul(T, rtmul(M, rot_cs(h5, c6, -s6, rot_cs(h4, c5, -s5, x1)))))
            ct, st = sp1_cs(h1, x1, v, q0[1] + g2 * q0[2] + g3 * q0[3])  # of q_1 + g2 q_2 + g3 q_3
            # y = E_0⁻¹ T M⁻¹ E_5⁻¹ E_4⁻¹ p3, the point on axis 3 that joints 1 and 2 must reach
            z = turn_cs(h5, p5, c6, -s6, turn_cs(h4, p4, c5, -s5, p3))
            z = rtmul(M, sub(z, (M[0, 3], M[1, 3], M[2, 3])))
            y = turn_cs(h0, p0, c1, -s1, apply(T, z))
            t3a, t3b, _, _ = sp3(h2, a3, b3, norm(perp(h1, sub(y, p1))))
            for c3, s3 in (t3a, t3b):
                c2, s2 = sp1_cs(h1, sub(turn_cs(h2, p2, c3, s3, p3), p1), sub(y, p1), q0[1])
                for j in range(6):
                    out[n, j] = np.nan
                c, s = ct * c2 + st * s2, st * c2 - ct * s2  # of the sum less q_2, then less g2 q_3: g3 q_4
                c4, s4 = c * c3 + g2 * s * s3, g3 * (s * c3 - g2 * c * s3)
                code[n] = posture_bits(H, P, f0, c2, s2, y) | wrist_bit(axes, c5, s5)
                cs[n, 0], cs[n, 1], cs[n, 2], cs[n, 3], cs[n, 4], cs[n, 5] = c1, s1, c2, s2, c3, s3
                cs[n, 6], cs[n, 7], cs[n, 8], cs[n, 9], cs[n, 10], cs[n, 11] = c4, s4, c5, s5, c6, s6
                n += 1
    return n


@numba.njit(**UNCOUNTED)
def parallel_axes(idx: np.ndarray, H: np.ndarray, P: np.ndarray, A: np.ndarray, T: np.ndarray,
                  q0: np.ndarray, out: np.ndarray, code: np.ndarray) -> int:
    """idx: the two arm joints a, b, the turning joint c and the slide s (−1 if none).
    A: 0 a point c on axis c (the tool point if none), 1 M⁻¹c, 2 x ⟂ h, 3 R_Mᵀx."""
    a, b, c, s = idx[0], idx[1], idx[2], idx[3]
    h, ha, hb = row(H, a), row(H, a), row(H, b)
    pa, pb = row(P, a), row(P, b)
    sb = 1.0 if dot(h, hb) > 0.0 else -1.0
    point = row(A, 0)
    target = apply(T, row(A, 1))
    slide = 0.0
    if s >= 0:
        hs = row(H, s)
        slide = dot(h, sub(target, point)) / dot(h, hs)
        target = sub(target, (slide * hs[0], slide * hs[1], slide * hs[2]))
    total, sc = 0.0, 1.0
    if c >= 0:
        sc = 1.0 if dot(h, row(H, c)) > 0.0 else -1.0
        total = sp1(h, row(A, 2), rmul(T, row(A, 3)), q0[a] + sb * q0[b] + sc * q0[c])
    dist = norm(perp(h, sub(target, pa)))
    tba, tbb, _, _ = sp3(hb, perp(h, sub(point, pb)), perp(h, sub(pb, pa)), dist)
    n = 0
    for cb, sb_ in (tba, tbb):
        qb = atan2(sb_, cb)
        elbow = sub(turn_cs(hb, pb, cb, sb_, point), pa)
        qa = sp1(ha, elbow, sub(target, pa), q0[a])
        out[n, :] = 0.0
        out[n, a], out[n, b] = qa, qb
        if s >= 0:
            out[n, s] = slide
        if c >= 0:
            out[n, c] = sc * (total - qa - sb * qb)
        upper = rot(ha, qa, sub(pb, pa))
        code[n] = ELBOW_DOWN if dot(h, cross(upper, sub(target, add(pa, upper)))) > 0.0 else 0
        n += 1
    return n


@numba.njit(**UNCOUNTED)
def position_only(case: int, H: np.ndarray, P: np.ndarray, A: np.ndarray, T: np.ndarray, q0: np.ndarray,
                  out: np.ndarray, code: np.ndarray, cs: np.ndarray) -> int:
    """A: 0 the tool point at q = 0, 5 meeting point o, 6 f0 (the rows of spherical_wrist)."""
    pw = (T[0, 3], T[1, 3], T[2, 3])
    n = arm_position(case, H, P, row(A, 5), row(A, 0), pw, q0, out, cs)
    for k in range(n):
        y = turn_cs(row(H, 0), row(P, 0), cs[k, 0], -cs[k, 1], pw)
        code[k] = posture_bits(H, P, row(A, 6), cs[k, 2], cs[k, 3], y)
    return n

