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

Each case gives four solutions (two pairs; a pair may repeat at a singular pose), with
branch bits: shoulder (the point behind axis 0 as seen along ``f0``, the arm's reach
direction at q = 0) and elbow (the elbow, on axis 2, below the line from the shoulder,
on axis 1, to the point, "below" along h_0).  Where an angle is free (a singular pose)
it takes its value in ``q0``.

:func:`arm_positions` solves a block of poses: a loop over them per pair of solutions,
whose body (straight-line code, :mod:`robot_sim.ik.subproblems`) the compiler runs a
pose per vector lane.
"""
from __future__ import annotations

import math

import numba
import numpy as np

from robot_sim.ik.subproblems import Vec, rot_cs, sp1_cs, sp2, sp3, sp4
from robot_sim.kernels.algebra import add, dot, norm, perp, scale, sub
from robot_sim.ik.block import ARM_ROWS, POSES, get, pose_of, put, put6
from robot_sim.kernels.jit import JIT, UNCOUNTED

ONE_TWO_MEET, ONE_TWO_MEET_SLIDE, TWO_THREE_PARALLEL, ONE_TWO_PARALLEL, TWO_THREE_MEET = range(5)
#: Branch bits of an arm posture.
SHOULDER_LEFT, ELBOW_DOWN, WRIST_FLIPPED = 4, 2, 1


@numba.njit(**JIT)
def row(A: np.ndarray, i: int) -> tuple[float, float, float]:
    return (A[i, 0], A[i, 1], A[i, 2])


@numba.njit(**JIT)
def turn_cs(h: tuple, p: tuple, c: float, s: float, x: tuple) -> tuple[float, float, float]:
    """E(q) x for a revolute joint about the line (p, h), given c = cos q and s = sin q."""
    return add(rot_cs(h, c, s, sub(x, p)), p)


@numba.njit(inline="always", **JIT)
def posture_bits(arm: tuple, f0: Vec, c1: float, s1: float, y: Vec) -> int:
    """Shoulder and elbow bits of an arm reaching the point pw, given y = E_0(q_0)⁻¹ pw
    (the point with joint 0's turn undone) and joint 1's cosine and sine; ``arm`` is
    (h_0, p_0, h_1, p_1, p_2) (:func:`arm_axes`).  Joint 0's turn fixes h_0 and keeps
    lengths, so both bits are judged before it: the point behind axis 0,
    f0ᵀ(y − p_0) < 0, and the elbow E_1 p_2 below the line from the shoulder p_1 to y
    along h_0 (one turn, not four)."""
    h0, p0, h1, p1, p2 = arm
    bits = SHOULDER_LEFT if dot(f0, sub(y, p0)) < 0.0 else 0
    v, line = rot_cs(h1, c1, s1, sub(p2, p1)), sub(y, p1)
    ll = dot(line, line)
    if ll > 0.0:
        v = sub(v, scale(line, dot(v, line) / ll))
    return bits | (ELBOW_DOWN if dot(v, h0) < 0.0 else 0)


@numba.njit(**JIT)
def arm_axes(H: np.ndarray, P: np.ndarray) -> tuple:
    """(h_0, p_0, h_1, p_1, p_2) of a chain, as :func:`posture_bits` takes them."""
    return row(H, 0), row(P, 0), row(H, 1), row(P, 1), row(P, 2)


@numba.njit(**JIT)
def matrix_pose(M: np.ndarray) -> tuple:
    """The rigid transform M (4, 4) as a pose tuple (r00, r01, r02, r10, …, r22, t0, t1, t2)."""
    return (M[0, 0], M[0, 1], M[0, 2], M[1, 0], M[1, 1], M[1, 2], M[2, 0], M[2, 1], M[2, 2], M[0, 3], M[1, 3], M[2, 3])


@numba.njit(**JIT)
def rmul(T: tuple, x: Vec) -> Vec:
    """Rotation of the pose tuple T times x."""
    return (T[0] * x[0] + T[1] * x[1] + T[2] * x[2],
            T[3] * x[0] + T[4] * x[1] + T[5] * x[2],
            T[6] * x[0] + T[7] * x[1] + T[8] * x[2])


@numba.njit(**JIT)
def rtmul(T: tuple, x: Vec) -> Vec:
    """Transposed rotation of the pose tuple T times x."""
    return (T[0] * x[0] + T[3] * x[1] + T[6] * x[2],
            T[1] * x[0] + T[4] * x[1] + T[7] * x[2],
            T[2] * x[0] + T[5] * x[1] + T[8] * x[2])


@numba.njit(**JIT)
def apply(T: tuple, x: Vec) -> Vec:
    """The pose tuple T applied to the point x."""
    return add(rmul(T, x), (T[9], T[10], T[11]))


@numba.njit(**JIT)
def free_cs(D: np.ndarray, j: int, sign: float) -> tuple[float, float]:
    """(cos, sin) of sign · q0_j from D (m, 2) = cos q0, sin q0 of the chain's joints."""
    return D[j, 0], sign * D[j, 1]


@numba.njit(inline="always", **JIT)
def _put_arm(W: np.ndarray, lane: int, sol: tuple) -> None:
    """An arm solution (:data:`~robot_sim.ik.block.ARM` floats) into its lane of W."""
    put(W, ARM_ROWS, lane, sol[0])
    put6(W, ARM_ROWS + 1, lane, sol[1:])


@numba.njit(inline="always", **JIT)
def _target(W: np.ndarray, lane: int, tool_point: bool, wt: Vec) -> Vec:
    """The point pw a lane's pose asks the arm to reach: the pose's origin with
    ``tool_point``, else the pose applied to wt."""
    T = pose_of(W, lane)
    return (T[9], T[10], T[11]) if tool_point else apply(T, wt)


@numba.njit(inline="always", **JIT)
def arm_of(W: np.ndarray, lane: int) -> tuple:
    """The arm solution of a lane: (slide, c0, s0, c1, s1, c2, s2)."""
    return (get(W, ARM_ROWS, lane), get(W, ARM_ROWS + 1, lane), get(W, ARM_ROWS + 2, lane),
            get(W, ARM_ROWS + 3, lane), get(W, ARM_ROWS + 4, lane), get(W, ARM_ROWS + 5, lane),
            get(W, ARM_ROWS + 6, lane))


@numba.njit(**UNCOUNTED)
def arm_positions(case: int, H: np.ndarray, P: np.ndarray, o: Vec, w: Vec, wt: Vec, tool_point: bool, G: int,
                  D: np.ndarray, W: np.ndarray) -> None:
    """The four (q_0, q_1, q_2) putting w at pw for each pose g < G of the block W
    (:mod:`robot_sim.ik.block`): pw is the pose's origin with ``tool_point``, else the
    pose applied to wt.  Solution k goes to lane k·POSES + g: the slide of
    ``ONE_TWO_MEET_SLIDE`` (NaN for a turn), then cos q_j, sin q_j as the subproblems give
    them (a slide's are 1, 0: it does not turn; the angles follow by atan2,
    :func:`robot_sim.ik.pipeline.pass1`).  D (m, 2): cos and sin of q0's values, taken
    where an angle is free.  Solutions 2h and 2h + 1 share the first choice (h: its
    root)."""
    h0, h1, h2 = row(H, 0), row(H, 1), row(H, 2)
    p0, p1, p2 = row(P, 0), row(P, 1), row(P, 2)
    f0, f1, f2 = free_cs(D, 0, 1.0), free_cs(D, 1, 1.0), free_cs(D, 2, 1.0)
    f0n, f1n = free_cs(D, 0, -1.0), free_cs(D, 1, -1.0)  # (read before the loops: no array is read in them but W)
    nan = np.nan
    for half in range(2):
        lane0 = 2 * half * POSES  # the lanes of solution 2h; 2h + 1 is POSES further
        if case == ONE_TWO_MEET or case == ONE_TWO_MEET_SLIDE:
            slide = case == ONE_TWO_MEET_SLIDE
            wo, w2 = sub(w, p2), sub(w, o)
            b, ww = dot(h2, w2), dot(w2, w2)
            for g in range(G):
                pw = _target(W, lane0 + g, tool_point, wt)
                dist = norm(sub(pw, o))
                (c3a, s3a), (c3b, s3b), _, _ = sp3(h2, wo, sub(p2, o), dist)
                c3, s3 = (c3a, s3a) if half == 0 else (c3b, s3b)
                disc = b * b - ww + dist * dist
                root = math.sqrt(disc) if disc > 0.0 else 0.0
                t3 = (-b + root if half == 0 else -b - root) if slide else nan
                c3, s3 = (1.0, 0.0) if slide else (c3, s3)  # a slide: (1, 0) as it does not turn
                x = sub(add(w, scale(h2, t3)), o) if slide else sub(turn_cs(h2, p2, c3, s3, w), o)
                q2a, m1a, q2b, m1b, _ = sp2(h1, x, h0, sub(pw, o), f1, f0n, True)
                _put_arm(W, lane0 + g, (t3, m1a[0], -m1a[1], q2a[0], q2a[1], c3, s3))
                _put_arm(W, lane0 + POSES + g, (t3, m1b[0], -m1b[1], q2b[0], q2b[1], c3, s3))
        elif case == TWO_THREE_PARALLEL:
            for g in range(G):
                pw = _target(W, lane0 + g, tool_point, wt)
                t1a, t1b, _, _ = sp4(h1, h0, sub(pw, p0), dot(h1, sub(w, p0)))
                c1, s1 = t1a if half == 0 else t1b
                y = turn_cs(h0, p0, c1, s1, pw)
                dist = norm(perp(h1, sub(y, p1)))
                t3a, t3b, _, _ = sp3(h2, perp(h1, sub(w, p2)), perp(h1, sub(p2, p1)), dist)
                c2a, s2a = sp1_cs(h1, sub(turn_cs(h2, p2, t3a[0], t3a[1], w), p1), sub(y, p1), f1)
                c2b, s2b = sp1_cs(h1, sub(turn_cs(h2, p2, t3b[0], t3b[1], w), p1), sub(y, p1), f1)
                _put_arm(W, lane0 + g, (nan, c1, -s1, c2a, s2a, t3a[0], t3a[1]))
                _put_arm(W, lane0 + POSES + g, (nan, c1, -s1, c2b, s2b, t3b[0], t3b[1]))
        elif case == ONE_TWO_PARALLEL:
            for g in range(G):
                pw = _target(W, lane0 + g, tool_point, wt)
                t3a, t3b, _, _ = sp4(h0, h2, sub(w, p2), dot(h0, sub(pw, p2)))
                c3, s3 = t3a if half == 0 else t3b
                dist = norm(perp(h0, sub(pw, p0)))
                x = turn_cs(h2, p2, c3, s3, w)
                t2a, t2b, _, _ = sp3(h1, perp(h0, sub(x, p1)), perp(h0, sub(p1, p0)), dist)
                c1a, s1a = sp1_cs(h0, sub(turn_cs(h1, p1, t2a[0], t2a[1], x), p0), sub(pw, p0), f0)
                c1b, s1b = sp1_cs(h0, sub(turn_cs(h1, p1, t2b[0], t2b[1], x), p0), sub(pw, p0), f0)
                _put_arm(W, lane0 + g, (nan, c1a, s1a, t2a[0], t2a[1], c3, s3))
                _put_arm(W, lane0 + POSES + g, (nan, c1b, s1b, t2b[0], t2b[1], c3, s3))
        else:  # TWO_THREE_MEET
            x = sub(w, o)
            for g in range(G):
                pw = _target(W, lane0 + g, tool_point, wt)
                t1a, t1b, _, _ = sp3(h0, sub(pw, p0), sub(p0, o), norm(x))
                c1, s1 = t1a if half == 0 else t1b
                y = sub(turn_cs(h0, p0, c1, s1, pw), o)
                q3a, m2a, q3b, m2b, _ = sp2(h2, x, h1, y, f2, f1n, True)
                _put_arm(W, lane0 + g, (nan, c1, -s1, m2a[0], -m2a[1], q3a[0], q3a[1]))
                _put_arm(W, lane0 + POSES + g, (nan, c1, -s1, m2b[0], -m2b[1], q3b[0], q3b[1]))
