"""A compiled atan2 within 1 ulp of the C library's, one pair at a time (:func:`atan2`) or
a row of pairs at once on the vector registers (:func:`atan2_row`).

The analytic IK (:mod:`robot_sim.ik`) turns every angle it solves into a number by atan2,
some thirty to fifty per pose; glibc's (IBM's correctly rounded one, about 20 ns a call
here) was a fifth of a batch's time, and a row at once costs about 2.6 ns a pair.  For
finite (y, x) with max(|x|, |y|) in [2⁻⁹⁶⁰, 2⁹⁶⁰] (the fast path; the rest goes to the
C library):

1. Octant: n = min(|x|, |y|), d = max(|x|, |y|), so that the angle of (d, n) is in [0, π/4].
2. Table: k = round(64 n/d) (k = 1 taken as 0, see below), and the angle is
   atan(k/64) + atan(u) with u = (64n − kd)/(64d + kn) exactly, |u| ≤ 1/128 (k ≥ 2) or
   u = n/d < 1.5/64 (k = 0).  Numerator and denominator are each one fused multiply-add
   (one rounding), so u is within 1.5 ulp.
3. atan(u) = u − u³/3 + u⁵/5 − u⁷/7 + u⁹/9 within |u|¹¹/11 < 2⁻⁵⁷|u| (alternating series).
4. Quadrant and table angle in one constant, C = Q ± atan(k/64) (Q = 0, π/2 or π) held
   as a pair hi + lo (computed at import to 40 digits), and the answer rounded once:
   hi + (lo ± atan(u)), its sign that of y.

Where C ≠ 0 the rounded u weighs at most a third of the answer (k = 1 is skipped so that
|atan(u)| ≤ atan(k/64)/3 for k ≥ 2), so the error stays near the final rounding's half
ulp.  Zeros on both axes, infinities, NaN and extreme magnitudes go to the C library,
which keeps its signed zeros and special values.  Measured against ``math.atan2`` on 10⁶
pairs and more (tests/ik/test_atan2.py): at most 1 ulp, a few pairs in a hundred off by that.
"""
from __future__ import annotations

import math
from decimal import Decimal, localcontext

import numpy as np
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic

from robot_sim.kernels.jit import INLINE, njit

#: Table steps per unit of tan: the table holds atan(k/STEPS), k = 0..STEPS.
STEPS = 64
#: The fast path's range of max(|x|, |y|): products by STEPS² neither overflow nor underflow.
_LOW, _HIGH = 2.0 ** -960, 2.0 ** 960
_A3, _A5, _A7, _A9 = -1.0 / 3.0, 1.0 / 5.0, -1.0 / 7.0, 1.0 / 9.0


@intrinsic
def fma(typingctx, a, b, c):  # noqa: ANN001, ANN201 - numba's intrinsic signature
    """a·b + c rounded once (LLVM's fma: the processor's instruction where it has one)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):  # noqa: ANN001, ANN202
        f64 = ir.DoubleType()
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(f64, [f64] * 3), "llvm.fma.f64")
        return builder.call(fn, args)

    return sig, codegen


def _atan(x: Decimal) -> Decimal:
    """atan x for 0 ≤ x ≤ 1 to about 45 digits: halved until x ≤ 0.1 by
    atan x = 2 atan(x / (1 + √(1 + x²))), then its Taylor series."""
    with localcontext() as ctx:
        ctx.prec = 50
        halvings = 0
        while x > Decimal("0.1"):
            x = x / (1 + (1 + x * x).sqrt())
            halvings += 1
        term, total, x2, k = x, x, x * x, 1
        while abs(term) > Decimal("1e-48"):
            term = -term * x2
            total += term / (2 * k + 1)
            k += 1
        return total * (2 ** halvings)


def _tables() -> tuple[np.ndarray, np.ndarray]:
    """hi, lo (4·(STEPS + 1),): C = Q + s·atan(k/STEPS) at q·(STEPS + 1) + k for the four
    cases q = 2·(x < 0) + (|y| > |x|): (Q, s) = (0, +), (π/2, −), (π, −), (π/2, +)."""
    pi = 4 * _atan(Decimal(1))
    hi, lo = np.empty(4 * (STEPS + 1)), np.empty(4 * (STEPS + 1))
    with localcontext() as ctx:
        ctx.prec = 50
        for q, (base, sign) in enumerate(((0, 1), (pi / 2, -1), (pi, -1), (pi / 2, 1))):
            for k in range(STEPS + 1):
                c = base + sign * _atan(Decimal(k) / STEPS)
                h = float(c)
                hi[q * (STEPS + 1) + k], lo[q * (STEPS + 1) + k] = h, float(c - Decimal(h))
    return hi, lo


_HI, _LO = _tables()
_SIGN = np.array([1.0, -1.0, -1.0, 1.0])


@njit(**INLINE)
def _fast_path(y: float, x: float) -> bool:
    """Whether (y, x) is in the fast path's range (finite, max(|x|, |y|) in [2⁻⁹⁶⁰, 2⁹⁶⁰])."""
    ax, ay = abs(x), abs(y)
    n, d = (ax, ay) if ay > ax else (ay, ax)
    return _LOW <= d <= _HIGH and n <= d  # (False for NaN in either)


@njit(**INLINE)
def _fast(y: float, x: float) -> float:
    """The fast path (module docstring); any number (and no memory outside the tables)
    for pairs outside its range, which :func:`_fast_path` tells.  For callers compiled
    with NumPy's error model (:data:`~robot_sim.kernels.jit.JIT`): 0/0 gives NaN there."""
    ax, ay = abs(x), abs(y)
    swap = ay > ax
    n, d = (ax, ay) if swap else (ay, ax)
    t = n / d
    t = t if t <= 1.0 else 0.0  # (NaN too: the table index stays in bounds)
    k = int(t * STEPS + 0.5)
    if k < 2:
        k = 0
    kf = float(k)
    u = fma(-kf, d, STEPS * n) / fma(kf, n, STEPS * d)
    z = u * u
    p = u + u * (z * (_A3 + z * (_A5 + z * (_A7 + z * _A9))))
    q = (2 if x < 0.0 else 0) + (1 if swap else 0)
    at = q * (STEPS + 1) + k
    return math.copysign(_HI[at] + (_LO[at] + _SIGN[q] * p), y)


@njit(**INLINE)
def atan2(y: float, x: float) -> float:
    """The angle [rad] of the point (x, y), in [−π, π], as ``math.atan2`` (module docstring)."""
    if not _fast_path(y, x):  # zeros, infinities, NaN, extreme magnitudes
        return math.atan2(y, x)
    return _fast(y, x)


@njit(**INLINE)
def atan2_row(Y: np.ndarray, y_row: int, X: np.ndarray, x_row: int, out: np.ndarray, out_row: int, m: int) -> None:
    """out[out_row, k] = atan2(Y[y_row, k], X[x_row, k]) for k < m: the fast path for all
    in one loop free of calls (which the compiler runs on vector registers), then, if any
    pair is outside its range, the C library's for those.  (A call inside the first loop
    would be made for every pair: the compiler computes both sides of a branch there.)"""
    slow = 0
    for k in range(m):
        out[out_row, k] = _fast(Y[y_row, k], X[x_row, k])
        slow += not _fast_path(Y[y_row, k], X[x_row, k])
    if slow == 0:
        return
    for k in range(m):
        if not _fast_path(Y[y_row, k], X[x_row, k]):
            out[out_row, k] = math.atan2(Y[y_row, k], X[x_row, k])


__all__ = ["STEPS", "atan2", "atan2_row", "fma"]
