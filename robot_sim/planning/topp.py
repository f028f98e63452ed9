"""Time-optimal path parameterisation by reachability analysis (TOPP-RA, Pham & Pham,
IEEE T-RO 2018), the solver behind :func:`robot_sim.planning.retime.retime`.

The path is q(s), s on a grid s_0 < ... < s_N.  The unknowns are x_i = ṡ² at the grid
points and u_i = s̈ on [s_i, s_{i+1}], so x_{i+1} = x_i + 2 Δ_i u_i.  The constraints at
grid point i are one-sided rows

    a u + b x + d √x <= g,   0 <= x <= x_max,

(√x carries viscous friction, linear in ṡ).  Interval i must meet the rows of both of its
ends with its one u (TOPP-RA's first-order interpolation: the rows at s_{i+1} taken at
x_i + 2 Δ_i u_i), so the limits hold at both ends of every interval, not just at the
grid points.

The backward pass computes the controllable sets K_i = [lo_i, hi_i] (every x_i from
which rest at s_N can be reached) from K_{i+1}.  For a fixed x the feasible u form an
interval between lines; K_i is where no lower line passes an upper one.  The bounds from
line pairs of one grid point are found for all points at once by a Newton iteration on
the concave piecewise-linear gap min(upper) − max(lower); the bounds that involve
K_{i+1} are affine in lo_{i+1} and hi_{i+1}.  There √x is replaced by affine bounds that
keep K_i inside the true set (a tangent from above, the chord from 0 to x_max from
below).  The forward pass starts at rest and takes the largest u that keeps x_{i+1} in
K_{i+1}.  Units: s in rad or m of path, x in (per s)².
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: |a| below this (relative to the row's scale) makes a row a bound on x alone.
A_TOL = 1e-12
#: Relative slack allowed when a computed set comes out empty by rounding.
EMPTY_TOL = 1e-9
#: Chords (halving intervals of √x) that bound a viscous term from below.
SQRT_CHORDS = 6
#: Newton steps on the gap function (it is piecewise linear: a few steps are exact).
NEWTON_STEPS = 60


class InfeasiblePath(ValueError):
    """No time law meets the constraints (e.g. gravity alone exceeds an effort limit);
    ``index`` is the grid point where it fails."""

    def __init__(self, message: str, index: int) -> None:
        super().__init__(message)
        self.index = index


@dataclass(frozen=True)
class Rows:
    """Constraints at the N+1 grid points: ``a``, ``b``, ``d``, ``g`` (N+1, R) as in the
    module docstring and ``x_max`` (N+1,)."""

    a: FloatArray
    b: FloatArray
    d: FloatArray
    g: FloatArray
    x_max: FloatArray


@dataclass(frozen=True)
class _Lines:
    """Per interval i, rows in (u, x_i): α u + β x <= γ (N, R'), the rows of both ends."""

    alpha: FloatArray
    beta: FloatArray
    gamma: FloatArray

    def split(self) -> tuple[FloatArray, ...]:
        """Upper lines u <= pU + qU x (α > 0), lower lines u >= pL + qL x (α < 0), the rest
        neutral (pU = +inf, pL = −inf, q = 0); and x-only bounds xlo <= x <= xhi."""
        al, be, ga = self.alpha, self.beta, self.gamma
        up, low = al > A_TOL, al < -A_TOL
        zero = ~up & ~low
        with np.errstate(divide="ignore", invalid="ignore"):
            p, q = ga / al, -be / al
            bound = ga / be
        pU, qU = np.where(up, p, np.inf), np.where(up, q, 0.0)
        pL, qL = np.where(low, p, -np.inf), np.where(low, q, 0.0)
        xhi = np.min(np.where(zero & (be > 0), bound, np.inf), axis=1)
        xlo = np.max(np.where(zero & (be < 0), bound, -np.inf), axis=1)
        bad = np.any(zero & (be == 0) & (ga < 0), axis=1)
        return pU, qU, pL, qL, np.where(bad, -np.inf, xhi), xlo


def _linearised(rows: Rows, x_ref: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Rows with d √x replaced by affine bounds valid for 0 <= x <= x_max: (a, b, g), each
    (N+1, R'), the rows without a viscous term anywhere first, as they are, then C rows
    for each row with one.  d > 0: the tangent at ``x_ref`` (√x lies below every
    tangent).  d < 0: the chords of √x on [0, x_max/4^(C−1)], ..., [x_max/4, x_max], one
    row each (√x lies above each chord on its interval, and the rows together bound the
    term on all of [0, x_max]).  Without viscous terms the rows are returned as they are."""
    viscous = np.any(rows.d != 0.0, axis=0)
    if not viscous.any():
        return rows.a, rows.b, rows.g
    d = rows.d[:, viscous, None]
    ref = np.sqrt(np.maximum(x_ref, 1e-12))[:, None, None]
    ends = np.sqrt(rows.x_max)[:, None] * 2.0 ** -np.arange(SQRT_CHORDS, -1, -1)  # √ of the breakpoints
    ends[:, 0] = 0.0
    r0, r1 = ends[:, None, :-1], ends[:, None, 1:]
    slope = np.where(d > 0, 1.0 / (2.0 * ref), 1.0 / (r0 + r1))
    offset = np.where(d > 0, ref / 2.0, r0 * r1 / (r0 + r1))
    M, plain = rows.a.shape[0], ~viscous
    b = (rows.b[:, viscous, None] + d * slope).reshape(M, -1)
    g = (rows.g[:, viscous, None] - d * offset).reshape(M, -1)
    a = np.repeat(rows.a[:, viscous], SQRT_CHORDS, axis=1)
    return (np.hstack([rows.a[:, plain], a]), np.hstack([rows.b[:, plain], b]),
            np.hstack([rows.g[:, plain], g]))


def _interval_lines(rows: Rows, ds: FloatArray, x_ref: FloatArray, exact_own: bool) -> _Lines:
    """Rows of interval i in (u, x_i): its start's rows (√x linearised unless
    ``exact_own``, then their d √x_i is left out, to be added by the caller) and its end's
    rows at x_i + 2Δ_i u (√x linearised)."""
    N = ds.shape[0]
    a_lin, b_lin, g_lin = _linearised(rows, x_ref)
    own_a, own_b, own_g = (rows.a[:N], rows.b[:N], rows.g[:N]) if exact_own else (a_lin[:N], b_lin[:N], g_lin[:N])
    two_d = 2.0 * ds[:, None]
    alpha = np.hstack([own_a, a_lin[1:] + two_d * b_lin[1:]])
    beta = np.hstack([own_b, b_lin[1:]])
    gamma = np.hstack([own_g, g_lin[1:]])
    return _Lines(alpha, beta, gamma)


def _gap_root(pU: FloatArray, qU: FloatArray, pL: FloatArray, qL: FloatArray, x0: FloatArray,
              upward: bool) -> FloatArray:
    """Per row of the arrays, the x nearest ``x0`` (moving down, or up with ``upward``) where
    the gap F(x) = min(pU + qU x) − max(pL + qL x) is >= 0; −inf (down) or +inf (up) when
    there is none.  F is concave and piecewise linear, so each Newton step from a point
    with F < 0 lands between it and the root, and a few steps are exact."""
    x = x0.copy()
    live = np.flatnonzero(np.isfinite(x))
    for _ in range(NEWTON_STEPS):
        xl = x[live, None]
        U, L = pU[live] + qU[live] * xl, pL[live] + qL[live] * xl
        ju, kl = np.argmin(U, axis=1), np.argmax(L, axis=1)
        r = np.arange(live.shape[0])
        F = U[r, ju] - L[r, kl]
        neg = F < -EMPTY_TOL * np.maximum(1.0, np.abs(U[r, ju]))
        if not neg.any():
            return x
        slope = qU[live, ju] - qL[live, kl]
        ok = neg & ((slope > 0) if upward else (slope < 0))
        x[live[neg & ~ok]] = np.inf if upward else -np.inf
        x[live[ok]] -= F[ok] / slope[ok]
        live = live[ok]
    return x


def controllable_sets(rows: Rows, ds: FloatArray, x_ref: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Backward pass: lo, hi (N+1,) of the sets from which rest at the end is reachable.
    ``ds`` (N,) grid steps; ``x_ref`` (N+1,) where √x is linearised from above."""
    N = ds.shape[0]
    pU, qU, pL, qL, xhi, xlo = _interval_lines(rows, ds, x_ref, exact_own=False).split()
    hi0 = np.minimum(xhi, rows.x_max[:N])
    lo0 = np.maximum(xlo, 0.0)
    s_hi = _gap_root(pU, qU, pL, qL, hi0, upward=False)
    s_lo = _gap_root(pU, qU, pL, qL, lo0, upward=True)
    bad = np.flatnonzero(~(s_lo <= s_hi + EMPTY_TOL * np.maximum(1.0, np.abs(np.nan_to_num(s_hi)))))
    if bad.size:
        raise InfeasiblePath(f"no feasible speed at grid point {bad[-1]}", int(bad[-1]))
    # bounds involving K_{i+1}: lower lines below (hi - x)h, upper lines above (lo - x)h
    h = (0.5 / ds)[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        c_low, c_up = qL + h, -h - qU
        a_low, r_low = h / c_low, -pL / c_low  # x vs a·hi_{i+1} + r
        a_up, r_up = -h / c_up, pU / c_up  # x vs a·lo_{i+1} + r
    fin_low, fin_up = np.isfinite(pL), np.isfinite(pU)
    zeros = np.zeros_like(pU)
    Ah = np.hstack([np.where(fin_low & (c_low > 0), a_low, 0.0), zeros])
    Bh = np.hstack([zeros, np.where(fin_up & (c_up > 0), a_up, 0.0)])
    Ch = np.hstack([np.where(fin_low & (c_low > 0), r_low, np.inf), np.where(fin_up & (c_up > 0), r_up, np.inf)])
    Al = np.hstack([np.where(fin_low & (c_low < 0), a_low, 0.0), zeros])
    Bl = np.hstack([zeros, np.where(fin_up & (c_up < 0), a_up, 0.0)])
    Cl = np.hstack([np.where(fin_low & (c_low < 0), r_low, -np.inf), np.where(fin_up & (c_up < 0), r_up, -np.inf)])
    # with lo_{i+1} = 0 (the usual case) the terms in lo_{i+1} are constants per grid point,
    # and of the lines in hi_{i+1} only those that can bound x for 0 <= hi_{i+1} <= its
    # static bound are kept (a few per grid point: the loop below runs over Python floats)
    Wh, Wl = Ah.shape[1] // 2, Al.shape[1] // 2
    s_hi0 = np.minimum(s_hi, np.min(Ch[:, Wh:], axis=1)).tolist()
    s_lo0 = np.maximum(s_lo, np.max(Cl[:, Wl:], axis=1)).tolist()
    top = np.append(s_hi[1:], 0.0)
    zero = np.zeros(N)
    Ah_, Ch_ = (m.tolist() for m in _envelope(Ah[:, :Wh], Ch[:, :Wh], zero, top, lowest=True))
    Al_, Cl_ = (m.tolist() for m in _envelope(Al[:, :Wl], Cl[:, :Wl], zero, top, lowest=False))
    lo, hi = np.zeros(N + 1), np.zeros(N + 1)
    lo_next = hi_next = 0.0
    for i in range(N - 1, -1, -1):
        if lo_next == 0.0:
            xh = min([s_hi0[i]] + [a * hi_next + c for a, c in zip(Ah_[i], Ch_[i])])
            xl = max([s_lo0[i]] + [a * hi_next + c for a, c in zip(Al_[i], Cl_[i])])
        else:
            xh = min(s_hi[i], (Ah[i] * hi_next + Bh[i] * lo_next + Ch[i]).min())
            xl = max(s_lo[i], (Al[i] * hi_next + Bl[i] * lo_next + Cl[i]).max())
        if xl > xh:
            if xl - xh > EMPTY_TOL * max(1.0, abs(xh)):
                raise InfeasiblePath(f"no feasible speed at grid point {i}", i)
            xl = xh
        lo[i], hi[i] = lo_next, hi_next = xl, xh
        if hi_next <= 0.0 and i > 0:
            raise InfeasiblePath(f"the path can only be followed by stopping at grid point {i}", i)
    return lo, hi


def _envelope(A: FloatArray, C: FloatArray, t0: FloatArray, t1: FloatArray, lowest: bool
              ) -> tuple[FloatArray, FloatArray]:
    """Of the lines y = A t + C (N, W), per row those that can be the lowest (or, without
    ``lowest``, the highest) somewhere on [t0, t1] (N,): the lines not above (below) the
    extreme line at both ends.  Compacted to (N, K) columns, padded with lines that are
    never extreme (A = 0, C = ±inf)."""
    sign = 1.0 if lowest else -1.0
    with np.errstate(invalid="ignore"):
        y0, y1 = sign * (A * t0[:, None] + C), sign * (A * t1[:, None] + C)
    y0, y1 = np.nan_to_num(y0, nan=np.inf), np.nan_to_num(y1, nan=np.inf)
    rows = np.arange(A.shape[0])
    keep = np.zeros(A.shape, dtype=bool)
    for best in (np.argmin(y0, axis=1), np.argmin(y1, axis=1)):
        keep |= (y0 < y0[rows, best][:, None]) | (y1 < y1[rows, best][:, None])
        keep[rows, best] = True
    K = int(keep.sum(axis=1).max())
    order = np.argsort(~keep, axis=1, kind="stable")[:, :K]
    kept = np.take_along_axis(keep, order, axis=1)
    pad = np.inf if lowest else -np.inf
    return (np.where(kept, np.take_along_axis(A, order, axis=1), 0.0),
            np.where(kept, np.take_along_axis(C, order, axis=1), pad))


def forward_pass(rows: Rows, ds: FloatArray, lo: FloatArray, hi: FloatArray,
                 x_ref: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Greedy forward pass from rest: x (N+1,) and u (N,); the rows of each interval's
    start exact at the known x_i, those of its end linearised at ``x_ref``."""
    N = ds.shape[0]
    if lo[0] > 0.0:
        raise InfeasiblePath("the path cannot start at rest", 0)
    lines = _interval_lines(rows, ds, x_ref, exact_own=True)
    R = rows.a.shape[1]
    dsq = np.hstack([rows.d[:N], np.zeros((N, lines.alpha.shape[1] - R))])  # exact √x_i terms of the own rows
    al = lines.alpha
    with np.errstate(divide="ignore", invalid="ignore"):
        G, B, D = lines.gamma / al, lines.beta / al, dsq / al
    up = al > A_TOL
    Gu, Bu, Du = np.where(up, G, np.inf), np.where(up, B, 0.0), np.where(up, D, 0.0)
    x, u = np.zeros(N + 1), np.zeros(N)
    if Du.any():  # viscous terms: u bounds not linear in x, all lines evaluated
        xi = 0.0
        for i in range(N):
            h = 0.5 / ds[i]
            ui = min((hi[i + 1] - xi) * h, (Gu[i] - Bu[i] * xi - Du[i] * xi**0.5).min())
            x[i + 1] = xi = min(max(xi + 2.0 * ds[i] * ui, lo[i + 1], 0.0), hi[i + 1])
            u[i] = (xi - x[i]) * h
        return x, u
    # u <= G − B x: only the lines that can be the lowest for x in [lo_i, hi_i] matter
    Ak, Ck = (m.tolist() for m in _envelope(-Bu, Gu, lo[:N], hi[:N], lowest=True))
    h_, hi_, lo_, ds_ = (0.5 / ds).tolist(), hi.tolist(), lo.tolist(), ds.tolist()
    xs, us = [0.0], []
    xi = 0.0
    for i in range(N):
        # the largest u of the upper lines; x_i in K_i leaves a feasible u at or below it,
        # and rounding is absorbed by keeping x_{i+1} in K_{i+1}
        ui = min([(hi_[i + 1] - xi) * h_[i]] + [c + a * xi for a, c in zip(Ak[i], Ck[i])])
        x_next = min(max(xi + 2.0 * ds_[i] * ui, lo_[i + 1], 0.0), hi_[i + 1])
        us.append((x_next - xi) * h_[i])
        xs.append(x_next)
        xi = x_next
    return np.array(xs), np.array(us)


def solve(rows: Rows, ds: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Time-optimal x (N+1,) and u (N,) on the grid with steps ``ds`` (N,); with viscous
    terms solved twice, the second time linearised at the first solution."""
    x_ref = rows.x_max
    lo, hi = controllable_sets(rows, ds, x_ref)
    x, u = forward_pass(rows, ds, lo, hi, x_ref)
    if rows.d.any():
        x_ref = np.maximum(x, 1e-6 * np.max(x))
        lo, hi = controllable_sets(rows, ds, x_ref)
        x, u = forward_pass(rows, ds, lo, hi, x_ref)
    return x, u
