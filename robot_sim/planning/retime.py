"""Time-optimal retiming of a joint path: :func:`retime`.

The path's geometry is the spline of :mod:`robot_sim.planning.spline` through its
waypoints (a waypoint given twice is a stop: the spline is cut there and the arm comes to
rest).  Along it, :mod:`robot_sim.planning.topp` finds the fastest time law s(t) under

* joint speed |q'(s) ṡ| <= v_max,
* joint acceleration |q'(s) s̈ + q''(s) ṡ²| <= a_max,
* with ``effort``, joint torque |τ| <= the drives' effort limits, τ from
  :func:`robot_sim.dynamics.inverse_dynamics` (gravity, reflected motor inertia and friction
  included): τ = A(s) s̈ + B(s) ṡ² + V(s) ṡ + C(s).

The time law is exact between grid points (s̈ constant on each), so q, q̇ = q' ṡ and
q̈ = q' s̈ + q'' ṡ² are consistent at every sample.  The limits hold at the grid points by
construction; the samples between are checked, and the limits are tightened and the
problem solved again until they hold there too (to LIMIT_RTOL relative).  SI units.
No Qt, no OpenGL.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.dynamics import gravity_torque, inverse_dynamics
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotParams
from robot_sim.planning.cartesian import qd_limits, qdd_limits
from robot_sim.planning.profiles import check_in_limits, positive_vector
from robot_sim.planning.spline import DUPLICATE_TOL, JointSpline
from robot_sim.planning.topp import InfeasiblePath, Rows, solve
from robot_sim.planning.trajectory import Trajectory, sample_times

FloatArray = NDArray[np.float64]

#: First grid of the reachability analysis: about this step along the path [rad or m],
#: between MIN_GRID and MAX_GRID intervals.
GRID_STEP = 0.002
#: Shortest sample spacing of a retimed trajectory [s] (1 MHz).
MIN_DT = 1e-6
MIN_GRID = 100
MAX_GRID = 3000
#: The samples meet the limits to this relative tolerance.
LIMIT_RTOL = 1e-7
#: Grid refinement: rounds, intervals each poor one is cut into, largest grid; a sample
#: counts as poor when no limit is within ACTIVE_TOL of active or one is exceeded.
REFINE_ROUNDS = 3
REFINE_SPLIT = 4
REFINE_MAX = 12000
ACTIVE_TOL = 2e-2
#: Rounds of slowing the law down uniformly until the samples between grid points meet
#: the limits too (the excess there is of the order of the grid step squared).
SLOWDOWN_ROUNDS = 6


def _effort_limits(robot: RobotParams) -> FloatArray:
    drives = robot.drives
    return np.full(robot.n_dofs, np.inf) if drives is None else np.asarray(drives.effort_limit, dtype=float)


def _dynamics_terms(robot: RobotParams, q: FloatArray, dq: FloatArray, ddq: FloatArray) -> tuple[FloatArray, ...]:
    """A, B, V, C (M, n) of τ = A s̈ + B ṡ² + V ṡ + C along the path (C: gravity and the
    Coulomb friction for ṡ > 0, none at the first and last point, where the arm is at rest)."""
    zero = np.zeros_like(q)
    g0 = np.zeros(3)
    A = inverse_dynamics(robot, q, zero, dq, gravity=g0)
    Mpp = inverse_dynamics(robot, q, zero, ddq, gravity=g0)
    f1 = inverse_dynamics(robot, q, dq, zero, gravity=g0)  # Q + V + K
    drives = robot.drives
    if drives is not None and (np.any(drives.viscous) or np.any(drives.coulomb)):
        f2 = inverse_dynamics(robot, q, 2 * dq, zero, gravity=g0)
        f3 = inverse_dynamics(robot, q, 3 * dq, zero, gravity=g0)
        Q = (f3 - 2 * f2 + f1) / 2
        V = f2 - f1 - 3 * Q
        K = f1 - Q - V
    else:
        Q, V, K = f1, zero, zero
    C = gravity_torque(robot, q) + K
    C[[0, -1]] -= K[[0, -1]]  # the path starts and ends at rest: no Coulomb friction there
    return A, Mpp + Q, V, C


@dataclass(frozen=True)
class _PathTerms:
    """The path at the grid: q' (M, n), q'' (M, n) and, for effort limits, A, B, V, C of
    the joints that have one (M, n_limited)."""

    dq: FloatArray
    ddq: FloatArray
    torque: tuple[FloatArray, FloatArray, FloatArray, FloatArray] | None

    @classmethod
    def at(cls, spline: JointSpline, s: FloatArray, robot: RobotParams | None, limited: NDArray[np.bool_]
           ) -> "_PathTerms":
        q, dq, ddq = spline.evaluate(s)
        torque = None
        if robot is not None and limited.any():
            A, B, V, C = (arr[:, limited] for arr in _dynamics_terms(robot, q, dq, ddq))
            torque = (A, B, V, C)
        return cls(dq, ddq, torque)

    def rows(self, vmax: FloatArray, amax: FloatArray, tmax: FloatArray) -> Rows:
        """Constraint rows for speed ``vmax``, acceleration ``amax`` and effort ``tmax``
        (of the limited joints) limits, each (n,) or per grid point (M, n)."""
        dq, ddq = self.dq, self.ddq
        with np.errstate(divide="ignore"):
            x_max = np.min((vmax / np.abs(dq)) ** 2, axis=1)
        a, b, g = [dq, -dq], [ddq, -ddq], [np.broadcast_to(amax, dq.shape)] * 2
        d = [np.zeros_like(dq)] * 2
        if self.torque is not None:
            A, B, V, C = self.torque
            t = np.broadcast_to(tmax, A.shape)
            a, b, d, g = a + [A, -A], b + [B, -B], d + [V, -V], g + [t - C, t + C]
        return Rows(np.hstack(a), np.hstack(b), np.hstack(d), np.hstack(g), x_max)


def _sampled(spline: JointSpline, s: FloatArray, x: FloatArray, u: FloatArray, dt: float
             ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Sample the time law (s̈ = u_i on [s_i, s_{i+1}]) at most ``dt`` apart: t, s, q, q̇, q̈."""
    ds = np.diff(s)
    v = np.sqrt(x)
    dur = 2.0 * ds / (v[:-1] + v[1:])
    knots = np.concatenate([[0.0], np.cumsum(dur)])
    t = sample_times(float(knots[-1]), 1.0 / dt)
    i = np.clip(np.searchsorted(knots, t, side="right") - 1, 0, ds.shape[0] - 1)
    tau = np.clip(t - knots[i], 0.0, dur[i])
    sd = v[i] + u[i] * tau
    ss = np.minimum(s[i] + v[i] * tau + 0.5 * u[i] * tau * tau, s[-1])
    ss[-1], sd[-1] = s[-1], 0.0
    q, dq, ddq = spline.evaluate(ss)
    return t, ss, q, dq * sd[:, None], dq * u[i][:, None] + ddq * (sd * sd)[:, None]


def _ratios(robot: RobotParams | None, q: FloatArray, qd: FloatArray, qdd: FloatArray,
            vmax: FloatArray, amax: FloatArray, tmax: FloatArray) -> FloatArray:
    """(3, M): per sample the largest |q̇|/v_max, |q̈|/a_max and |τ|/τ_max over the joints
    (τ of :func:`robot_sim.dynamics.inverse_dynamics`; 0 without effort limits)."""
    out = np.zeros((3, q.shape[0]))
    out[0] = np.max(np.abs(qd) / vmax, axis=1)
    out[1] = np.max(np.abs(qdd) / amax, axis=1)
    limited = np.isfinite(tmax)
    if robot is not None and limited.any():
        tau = inverse_dynamics(robot, q, qd, qdd)
        out[2] = np.max(np.abs(tau[:, limited]) / tmax[limited], axis=1)
    return out


def _explained(exc: InfeasiblePath, spline: JointSpline, s: FloatArray, terms: "_PathTerms",
               tmax: FloatArray, limited: NDArray[np.bool_]) -> InfeasiblePath:
    """``exc`` with where it happens on the path and, if a joint cannot even hold still
    there (gravity and friction beyond its effort limit), which one."""
    i = min(exc.index, s.shape[0] - 1)
    seg = int(np.clip(np.searchsorted(spline.knots, s[i], side="right") - 1, 0, spline.knots.shape[0] - 2))
    where = f"at path parameter s = {s[i]:.4g} of {spline.length:.4g} (between waypoints {seg} and {seg + 1})"
    why = str(exc)
    if terms.torque is not None:
        static = np.abs(terms.torque[3][i])  # gravity and Coulomb friction at rest
        joints = np.flatnonzero(limited)
        over = np.flatnonzero(static > tmax[limited])
        if over.size:
            j = int(over[0])
            why = (f"joint {joints[j] + 1} needs {static[j]:.4g} N·m (or N) against gravity and friction alone, "
                   f"above its effort limit {tmax[joints[j]]:.4g}")
    return InfeasiblePath(f"retime: no time law follows the path {where}: {why}", i)


def _refined(s: FloatArray, cells: NDArray[np.int64]) -> FloatArray:
    """The grid ``s`` with each listed interval cut into REFINE_SPLIT equal ones."""
    cells = np.unique(cells)
    f = np.arange(1, REFINE_SPLIT) / REFINE_SPLIT
    new = (s[cells, None] + f * (s[cells + 1] - s[cells])[:, None]).ravel()
    return np.union1d(s, new)


def _retime_piece(spline: JointSpline, vmax: FloatArray, amax: FloatArray, tmax: FloatArray,
                  robot: RobotParams | None, dt: float) -> Trajectory:
    """TOPP-RA along one spline.  The grid is refined where a sample between grid points
    has no limit within ACTIVE_TOL of active or exceeds one (switches, fast changes), and
    the excess left is removed by slowing the law down uniformly."""
    N = int(np.clip(np.ceil(spline.length / GRID_STEP), MIN_GRID, MAX_GRID))
    s = np.linspace(0.0, spline.length, N + 1)
    limited = np.isfinite(tmax)
    for rnd in range(REFINE_ROUNDS + 1):
        terms = _PathTerms.at(spline, s, robot, limited)
        try:
            x, u = solve(terms.rows(vmax, amax, tmax[limited]), np.diff(s))
        except InfeasiblePath as exc:
            raise _explained(exc, spline, s, terms, tmax, limited) from None
        t, ss, q, qd, qdd = _sampled(spline, s, x, u, dt)
        act = _ratios(robot, q, qd, qdd, vmax, amax, tmax).max(axis=0)
        poor = (act < 1.0 - ACTIVE_TOL) | (act > 1.0 + LIMIT_RTOL)
        cells = np.unique(np.clip(np.searchsorted(s, ss[poor], side="right") - 1, 0, s.shape[0] - 2))
        if not cells.size or rnd == REFINE_ROUNDS or s.shape[0] + REFINE_SPLIT * cells.size > REFINE_MAX:
            break
        s = _refined(s, cells)
    lam = 1.0  # speed scales with 1/λ, acceleration and the dynamic torque with 1/λ²
    for _ in range(SLOWDOWN_ROUNDS):
        worst = _ratios(robot, q, qd, qdd, vmax, amax, tmax).max(axis=1)
        if worst.max() <= 1.0 + LIMIT_RTOL:
            return Trajectory(t, q, qd, qdd)
        lam *= max(worst[0], np.sqrt(worst[1]), np.sqrt(worst[2])) * (1.0 + LIMIT_RTOL)
        t, _, q, qd, qdd = _sampled(spline, s, x / lam**2, u / lam**2, dt)
    ratio = _ratios(robot, q, qd, qdd, vmax, amax, tmax)
    kind, k = np.unravel_index(np.argmax(ratio), ratio.shape)
    raise InfeasiblePath(
        f"{('speed', 'acceleration', 'effort')[kind]} limit exceeded by {ratio[kind, k] - 1:.3g} (relative) "
        f"at t = {t[k]:.4f} s however slowly the path is followed", int(k))


def _pieces(P: FloatArray) -> list[FloatArray]:
    """``P`` cut at repeated waypoints (stops), each piece with both of its ends."""
    same = np.flatnonzero(np.linalg.norm(np.diff(P, axis=0), axis=1) <= DUPLICATE_TOL)
    cuts = [0] + [int(k) for k in same] + [P.shape[0] - 1]
    out = [P[a : b + 1] for a, b in zip(cuts[:-1], cuts[1:])]
    return [p for p in out if p.shape[0] > 1 and np.ptp(p, axis=0).any()] or [P[:1]]


def retime(robot: RobotParams, path: ArrayLike, *, v_max: ArrayLike | None = None,
           a_max: ArrayLike | None = None, effort: bool = True, dt: float = 1e-3) -> Trajectory:
    """The fastest trajectory along ``path`` (K, n) joint waypoints [rad or m] from rest to
    rest, under joint speed ``v_max`` [rad/s or m/s], acceleration ``a_max`` [/s²] and,
    with ``effort``, the drives' effort limits [N·m or N] through inverse dynamics.

    The geometry is the not-a-knot cubic spline through the waypoints by chord length
    (:class:`JointSpline`), cut and brought to rest at repeated waypoints.  Limits are
    (n,) or scalars; None takes :func:`robot_sim.planning.cartesian.qd_limits` and
    :func:`robot_sim.planning.cartesian.qdd_limits`.
    Sampled at most ``dt`` s apart (at least MIN_DT, and at most MAX_SAMPLES samples:
    checked before they are allocated), the last sample at the end.  ValueError for bad
    input (shape, a single waypoint, NaN, waypoints outside the joint limits, non-positive
    limits or dt) or a path
    no time law can follow (:class:`InfeasiblePath`: e.g. gravity alone beyond an effort
    limit), naming the grid point or sample, the time and the joint where it can.
    """
    n = robot.n_dofs
    P = np.asarray(path, dtype=float)
    if P.ndim != 2 or P.shape[1] != n or P.shape[0] == 0:
        raise ValueError(f"path must be (K, {n}) joint waypoints for {robot.name}, got shape {P.shape}")
    if P.shape[0] == 1:
        raise ValueError("path holds one waypoint: retiming needs at least 2 (to stay at q, use hold(q, duration))")
    JointSpline.through(P)  # NaN and shape errors, named
    check_in_limits(robot, P, "path")
    vmax = positive_vector("v_max", qd_limits(robot) if v_max is None else v_max, n)
    amax = positive_vector("a_max", qdd_limits(robot) if a_max is None else a_max, n)
    step = float(dt)
    if not (np.isfinite(step) and step >= MIN_DT):
        raise ValueError(f"dt must be a number of seconds >= {MIN_DT:g}, got {clip_repr(dt)}")
    tmax = _effort_limits(robot) if effort else np.full(n, np.inf)
    dyn = robot if effort and np.isfinite(tmax).any() else None
    traj: Trajectory | None = None
    for piece in _pieces(P):
        if piece.shape[0] == 1:
            z = np.zeros((1, n))
            part = Trajectory(np.zeros(1), piece, z, z)
        else:
            part = _retime_piece(JointSpline.through(piece), vmax, amax, tmax, dyn, step)
        traj = part if traj is None else traj.then(part)
    assert traj is not None
    return traj
