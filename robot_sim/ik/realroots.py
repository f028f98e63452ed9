"""Every real root of a real polynomial (compiled), by isolation through its derivatives.

The real roots of p are separated by those of p′ (Rolle): between two consecutive roots
of p′ (or beyond the outermost, up to Cauchy's bound 1 + max|aᵢ/aₙ|) p is monotone and
changes sign at most once, so each such interval holds at most one root, found by Newton
steps kept inside the bracket (bisection when a step leaves it).  Starting from the
linear (n − 1)-th derivative and climbing one derivative at a time gives every real root
in O(n³) operations, with no eigenvalue problem (a textbook method; see e.g. Collins &
Loos, "Real zeros of polynomials", in Computer Algebra, Springer 1982).

Critical points of p where |p| is below ``near`` times the sum of the magnitudes of its
terms, with no root found on either side, are returned as well: a double root, or a pair
of complex roots that rounding has pushed off the real axis, shows no sign change.
"""
from __future__ import annotations

import numba
import numpy as np

from robot_sim.kernels.jit import INLINE, JIT


@numba.njit(**INLINE)
def horner(c: np.ndarray, n: int, x: float) -> float:
    """c[0] + c[1] x + … + c[n] xⁿ."""
    v = c[n]
    for i in range(n - 1, -1, -1):
        v = v * x + c[i]
    return v


@numba.njit(**JIT)
def _bracketed(c: np.ndarray, d: np.ndarray, n: int, lo: float, hi: float, flo: float) -> float:
    """The root of c (degree n, derivative d) in [lo, hi], where it changes sign once."""
    x = 0.5 * (lo + hi)
    for _ in range(200):
        fx = horner(c, n, x)
        if fx == 0.0:
            return x
        if (fx < 0.0) == (flo < 0.0):
            lo = x
        else:
            hi = x
        dfx = horner(d, n - 1, x)
        step = fx / dfx if dfx != 0.0 else np.inf
        xn = x - step
        if not (lo < xn < hi):
            xn = 0.5 * (lo + hi)
        if abs(xn - x) <= 4e-16 * max(1.0, abs(x)) or hi - lo <= 4e-16 * max(1.0, abs(lo), abs(hi)):
            return xn
        x = xn
    return x


@numba.njit(**JIT)
def real_roots(p: np.ndarray, near: float, roots: np.ndarray, crit: np.ndarray) -> tuple[int, int]:
    """Real roots of p[0] + p[1] x + … (ascending coefficients) into ``roots`` (sorted,
    then the near-double ones), and the critical points of p into ``crit``; returns
    (roots found, critical points).  ``roots`` needs 2·(len(p) − 1) entries, ``crit``
    len(p) − 1.  Coefficients
    below 1e-14 of the largest at the top are dropped (a lower degree)."""
    n = p.shape[0] - 1
    big = 0.0
    for i in range(n + 1):
        big = max(big, abs(p[i]))
    while n > 0 and abs(p[n]) <= 1e-14 * big:
        n -= 1
    if n == 0 or big == 0.0:
        return 0, 0
    D = np.zeros((n + 1, n + 1))  # D[k] = k-th derivative of p / p[n]
    bound = 0.0
    for i in range(n + 1):
        D[0, i] = p[i] / p[n]
        if i < n:
            bound = max(bound, abs(D[0, i]))
    bound += 1.0
    for k in range(1, n + 1):
        for i in range(n - k + 1):
            D[k, i] = D[k - 1, i + 1] * (i + 1)
    cur = np.empty(n)
    nxt = np.empty(2 * n)
    ncur = 1
    cur[0] = -D[n - 1, 0] / D[n - 1, 1]
    for k in range(n - 2, -1, -1):
        deg = n - k
        count = 0
        hit = np.zeros(ncur + 1, dtype=np.bool_)  # a root in interval j (left of cur[j])
        lo = -bound
        flo = horner(D[k], deg, lo)
        for j in range(ncur + 1):
            hi = cur[j] if j < ncur else bound
            fhi = horner(D[k], deg, hi)
            if flo == 0.0:
                hit[j] = True
                if count == 0 or nxt[count - 1] != lo:
                    nxt[count] = lo
                    count += 1
            elif (flo < 0.0) != (fhi < 0.0) and fhi != 0.0:
                hit[j] = True
                nxt[count] = _bracketed(D[k], D[k + 1], deg, lo, hi, flo)
                count += 1
            lo, flo = hi, fhi
        if k == 0:
            for j in range(ncur):
                crit[j] = cur[j]
            found = count
            for j in range(ncur):  # near-tangent critical points, no root on either side
                if hit[j] or hit[j + 1]:
                    continue
                x = cur[j]
                size, xi = 0.0, 1.0
                for i in range(n + 1):
                    size += abs(D[0, i]) * xi
                    xi *= abs(x)
                if abs(horner(D[0], n, x)) <= near * size:
                    nxt[found] = x
                    found += 1
            for j in range(found):
                roots[j] = nxt[j]
            return found, ncur
        ncur = count
        for j in range(count):
            cur[j] = nxt[j]
    roots[0] = cur[0]  # degree 1
    return 1, 0
