"""Canonical geometric subproblems of inverse kinematics, compiled (numba), on 3-vectors
held as tuples (no heap allocation in the solvers' inner loops).  Each angle is given
by its cosine and sine: what the solvers turn by next, and all that the check by forward
kinematics needs.  The angle itself is taken by atan2 where it is asked
(:func:`robot_sim.ik.pipeline.pass1` takes those of a block of branches at once, in
vector registers).

Every function is inlined into its caller and free of calls and of stores: the solvers
run them in loops over poses (:mod:`robot_sim.ik.families`) that the compiler turns into
vector loops, a pose per lane, where a branch becomes a select of both sides.  So an
angle that a degenerate input leaves free comes as its cosine and sine (``free``,
computed once per call of a solver from q0), not as an angle whose cosine would be a
call in the loop.

The definitions are IK-Geo's (A. J. Elias and J. T. Wen, "IK-Geo: Unified robot inverse
kinematics using subproblem decomposition", Mechanism and Machine Theory 209, 2025,
arXiv:2211.05737, section 3); the solutions below are derived here.  ``R(k, θ)`` is the
turn by θ about the unit axis k (right hand), by Rodrigues' formula.

* SP1: θ with R(k, θ) p1 = p2 (least squares in the plane ⟂ k when none exists).
* SP4: θ with hᵀ R(k, θ) p = d (two roots, or the closest one when |d| is out of reach).
* SP3: θ with ‖R(k, θ) p1 − p2‖ = δ reduces to SP4 (see the solvers).
* SP2: θ1, θ2 with R(k1, θ1) p1 = R(k2, θ2) p2 (two solutions, or the closest pair).
"""
from __future__ import annotations

import math

import numba

from robot_sim.kernels.algebra import add, cross, dot, norm, perp, scale, sub
from robot_sim.kernels.atan2 import atan2
from robot_sim.kernels.jit import JIT

Vec = tuple[float, float, float]


@numba.njit(**JIT)
def rot_cs(k: Vec, c: float, s: float, x: Vec) -> Vec:
    """R(k, θ) x by Rodrigues' formula, given c = cos θ and s = sin θ (so that solvers
    turning by one angle many times take its cosine and sine once)."""
    kx = dot(k, x) * (1.0 - c)
    w = cross(k, x)
    return (c * x[0] + s * w[0] + kx * k[0], c * x[1] + s * w[1] + kx * k[1], c * x[2] + s * w[2] + kx * k[2])


@numba.njit(**JIT)
def rot(k: Vec, theta: float, x: Vec) -> Vec:
    """R(k, θ) x by Rodrigues' formula."""
    return rot_cs(k, math.cos(theta), math.sin(theta), x)


#: Below this length a vector has no direction (the subproblem's angle is free).
DEGENERATE = 1e-12


@numba.njit(inline="always", **JIT)
def _angle(k: Vec, a: Vec, b: Vec, free: tuple[float, float]) -> tuple[float, float]:
    """(cos θ, sin θ) for the θ that turns a onto b about k, both ⟂ k; ``free`` (cos θ,
    sin θ of the value to take) when either vanishes.  They come from the vectors (a
    square root and a division, not cos and sin of θ)."""
    y, x = dot(k, cross(a, b)), dot(a, b)
    r = 1.0 / math.sqrt(x * x + y * y)
    if dot(a, a) < DEGENERATE * DEGENERATE or dot(b, b) < DEGENERATE * DEGENERATE:
        return free
    return x * r, y * r


@numba.njit(inline="always", **JIT)
def sp1_cs(k: Vec, p1: Vec, p2: Vec, free: tuple[float, float]) -> tuple[float, float]:
    """(cos θ, sin θ) for the θ that turns p1 about k onto p2 (their projections on the
    plane ⟂ k); ``free`` (cos θ, sin θ) when either projection vanishes (any θ does)."""
    return _angle(k, perp(k, p1), perp(k, p2), free)


@numba.njit(inline="always", **JIT)
def sp1(k: Vec, p1: Vec, p2: Vec, default: float) -> float:
    """θ of :func:`sp1_cs` (in [−π, π])."""
    c, s = _angle(k, perp(k, p1), perp(k, p2), (math.cos(default), math.sin(default)))
    return atan2(s, c)


@numba.njit(inline="always", **JIT)
def sp4(h: Vec, k: Vec, p: Vec, d: float) -> tuple:
    """Both θ with hᵀ R(k, θ) p = d: (θa, θb, exact, free), each angle as (cos θ, sin θ).

    hᵀR(k, θ)p = A cos θ + B sin θ + C with A = hᵀ(p − k kᵀp), B = hᵀ(k × p),
    C = (hᵀk)(kᵀp), so θ = φ ± δ with (cos φ, sin φ) = (A, B)/√(A² + B²) and
    cos δ = (d − C)/√(A² + B²); the roots' cosines and sines follow by the angle sum.  Out
    of reach the two roots merge into the closest θ and ``exact`` is False; ``free`` when
    A = B = 0 (θ = 0)."""
    A = dot(h, perp(k, p))
    B = dot(h, cross(k, p))
    C = dot(h, k) * dot(k, p)
    r = math.sqrt(A * A + B * B)  # not hypot: A, B are lengths of an arm (no overflow; below DEGENERATE either way)
    if r < DEGENERATE:
        zero = (1.0, 0.0)
        return zero, zero, abs(d - C) < 1e-9, True
    inv = 1.0 / r
    cp, sp = A * inv, B * inv
    c = (d - C) * inv
    if c > 1.0:
        return (cp, sp), (cp, sp), c < 1.0 + 1e-9, False
    if c < -1.0:
        return (-cp, -sp), (-cp, -sp), c > -1.0 - 1e-9, False
    s = math.sqrt((1.0 - c) * (1.0 + c))
    return (cp * c - sp * s, sp * c + cp * s), (cp * c + sp * s, sp * c - cp * s), True, False


@numba.njit(inline="always", **JIT)
def sp2(k1: Vec, p1: Vec, k2: Vec, p2: Vec, free1: tuple[float, float], free2: tuple[float, float],
        both: bool) -> tuple:
    """Both (θ1, θ2) with R(k1, θ1) p1 = R(k2, θ2) p2 for non-parallel unit k1, k2:
    (θ1a, θ2a, θ1b, θ2b, exact), each angle as (cos θ, sin θ); without ``both`` only the
    first pair is solved (the second repeats it).

    The common image v = α k1 + β k2 ± γ k1×k2 satisfies k1ᵀv = k1ᵀp1, k2ᵀv = k2ᵀp2 and
    ‖v‖ = ‖p1‖ (directions only: p1 and p2 are normalised).  Out of reach γ = 0 (the
    closest pair).  ``free1``, ``free2`` are the (cos θ, sin θ) taken where an angle is
    free (p on its axis)."""
    n1, n2 = norm(p1), norm(p2)
    if n1 < DEGENERATE or n2 < DEGENERATE:
        return free1, free2, free1, free2, n1 < DEGENERATE and n2 < DEGENERATE
    u1, u2 = scale(p1, 1.0 / n1), scale(p2, 1.0 / n2)
    k12 = dot(k1, k2)
    det = 1.0 - k12 * k12
    a1, a2 = dot(k1, u1), dot(k2, u2)
    alpha = (a1 - k12 * a2) / det
    beta = (a2 - k12 * a1) / det
    v0 = add(scale(k1, alpha), scale(k2, beta))
    n = cross(k1, k2)
    g2 = (1.0 - dot(v0, v0)) / det
    exact = g2 > -1e-9
    g = math.sqrt(g2) if g2 > 0.0 else 0.0
    va, vb = add(v0, scale(n, g)), sub(v0, scale(n, g))
    a1, a2 = perp(k1, u1), perp(k2, u2)  # SP1 four times, sharing what it can
    first, second = _angle(k1, a1, perp(k1, va), free1), _angle(k2, a2, perp(k2, va), free2)
    if not both:
        return first, second, first, second, exact
    return first, second, _angle(k1, a1, perp(k1, vb), free1), _angle(k2, a2, perp(k2, vb), free2), exact


@numba.njit(inline="always", **JIT)
def sp3(k: Vec, p1: Vec, p2: Vec, delta: float) -> tuple:
    """Both θ with ‖R(k, θ) p1 + p2‖ = δ, by ‖R p1 + p2‖² = ‖p1‖² + ‖p2‖² + 2 p2ᵀR p1 (SP4),
    as SP4 gives them."""
    return sp4(p2, k, p1, 0.5 * (delta * delta - dot(p1, p1) - dot(p2, p2)))
