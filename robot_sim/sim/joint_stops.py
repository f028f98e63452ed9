"""Joint stops as impacts and constraints consistent with the mass matrix.

A stop is a one-sided constraint, q_i ≥ q_min,i or q_i ≤ q_max,i.  A joint that sits on a
stop has a *push direction*, +1 on its min stop and −1 on its max stop (see
:func:`stop_push`): the only sign of torque the stop can exert on it and the only sign of
velocity or acceleration that leaves it.

Two things happen at stops, both solved over the *active set* A of joints the stops hold:

* **Impact** (:func:`impact`).  A joint arriving with its velocity into a stop receives
  the impulse p that brings its velocity to zero, and through M the coupled joints change
  velocity with it: ``M (q̇⁺ − q̇) = E_A p`` with ``q̇⁺_A = 0`` (E_A: the unit columns e_i,
  i ∈ A).  For one joint i this is ``Δq̇ = −M⁻¹ e_i (e_iᵀ M⁻¹ e_i)⁻¹ q̇_i``.
* **Resting** (:func:`hold`).  A joint on its stop at zero velocity whose acceleration
  would push into it is locked: ``M q̈ = τ − b + E_A λ`` with ``q̈_A = 0``, so the others
  move with the constrained dynamics and λ is the stop's reaction torque.

Which joints are active is the linear complementarity problem of a one-sided contact:
each candidate joint is either held (its rate is zero and its stop pushes, push·μ ≥ 0) or
free (its stop exerts nothing and its rate does not go into the stop, push·x ≥ 0); a
candidate with push 0 (a one-point range) is always held.
``E_Aᵀ M⁻¹ E_A`` is symmetric positive definite, a P-matrix, so the problem has exactly one
solution and Murty's least-index principal pivoting (:func:`_active_set`) finds it in a
finite number of pivots (one or two in practice).

Both solves use the rows and columns of the free joints (F): ``x_F = M_FF⁻¹ (r_F − M_FA
x_A)``, so held joints get exactly zero rate, not round-off.

Arrays in, arrays out, one configuration: (n,) vectors, (n, n) M [kg·m², kg]; rates in
rad/s (m/s), accelerations in rad/s² (m/s²), torques in N·m (N), impulses in N·m·s (N·s).
No state and no robot: :class:`~robot_sim.sim.simulation.Simulation` calls these with
the mass matrix and bias torque of ``dynamics``; a batched simulation calls them for the
configurations that touch a stop.
"""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: A held joint is released only when its stop would pull by more than this fraction of
#: the magnitude of the generalized force (or momentum) in the problem, and a free
#: candidate held only when it goes into its stop by more than this fraction of the
#: magnitude of the rates: round-off on a reaction that is really zero must not make a
#: joint chatter on and off its stop.
RELEASE_TOLERANCE = 1e-12


def stop_push(q: FloatArray, q_min: FloatArray, q_max: FloatArray) -> FloatArray:
    """Per joint: +1.0 if q is exactly on its min stop, −1.0 on its max stop, else 0.0
    (the direction the stop can push).  q, q_min, q_max (n,) [rad or m].  A joint whose
    range is one point (q_min = q_max) gets 0.0: as a candidate it is held both ways."""
    return (q == q_min).astype(float) - (q == q_max)


def _locked_solve(
    M: FloatArray, rhs: FloatArray, locked: BoolArray, x_locked: FloatArray | None = None
) -> tuple[FloatArray, FloatArray]:
    """x with ``M x = rhs + E_A μ`` and ``x_A = x_locked`` (zero if None), and μ (zero
    off A), A = ``locked``: the free rows and columns of M solved, the held ones read off."""
    free = ~locked
    r = rhs[free]
    if x_locked is None:
        x = np.zeros_like(rhs)
    else:
        x = np.where(locked, x_locked, 0.0)
        r -= M[free] @ x
    if r.size:
        x[free] = np.linalg.solve(M[free][:, free], r)
    return x, (M @ x - rhs) * locked


def _active_set(
    M: FloatArray, rhs: FloatArray, base: FloatArray | None, push: FloatArray, candidates: BoolArray
) -> tuple[FloatArray, FloatArray, BoolArray]:
    """The complementary active set A ⊆ ``candidates`` and its solution: x with
    ``M x = rhs + E_A μ``, ``base_A + x_A = 0``, ``push·μ ≥ 0`` on A and
    ``push·(base + x) ≥ 0`` on the other candidates (``base`` None: zero).  Murty's
    least-index rule: flip the first candidate that breaks its condition and solve again
    (finite for a P-matrix).  Should round-off keep it from settling, the last solve is
    returned: it still holds every joint of its A at rest, which is all the energy
    argument of :func:`impact` needs."""
    if base is None:
        locked, x_locked, force = candidates.copy(), None, rhs
    else:
        locked, x_locked, force = candidates & (push * base <= 0.0), -base, M @ base
    tol_mu = RELEASE_TOLERANCE * math.sqrt(force @ force)
    for _ in range(1 << np.count_nonzero(candidates)):
        x, mu = _locked_solve(M, rhs, locked, x_locked)
        rate = x if base is None else base + x  # zero on A, as μ is off A
        tol_rate = RELEASE_TOLERANCE * math.sqrt(rate @ rate)
        broken = candidates & ((push * mu < -tol_mu) | (push * rate < -tol_rate))
        if not broken.any():
            return x, mu, locked
        first = int(np.argmax(broken))
        locked[first] = not locked[first]
    x, mu = _locked_solve(M, rhs, locked, x_locked)
    return x, mu, locked


def hold(
    M: FloatArray, rhs: FloatArray, push: FloatArray, candidates: BoolArray
) -> tuple[FloatArray, FloatArray, BoolArray]:
    """Accelerations q̈ (n,) [rad/s², m/s²], stop reactions λ (n,) [N·m, N] and the held
    joints (n,) bool, for joints resting on their stops.

    ``M`` (n, n) the mass matrix, ``rhs`` = τ − C q̇ − g (− friction + Jᵀ f) the net
    generalized force, ``push`` from :func:`stop_push`, ``candidates`` the joints on a stop
    at zero velocity.  A candidate is held (q̈_i = 0, push·λ_i ≥ 0: the stop pushes) or
    free (λ_i = 0, push·q̈_i ≥ 0: it accelerates off the stop); ``M q̈ = rhs + λ``.
    The reaction does no work (held joints do not move), so holding adds no energy."""
    return _active_set(M, rhs, None, push, candidates)


def impact(
    M: FloatArray,
    qd: FloatArray,
    push: FloatArray,
    candidates: BoolArray,
    restitution: float = 0.0,
    hold_speed: float = 0.0,
) -> tuple[FloatArray, FloatArray, BoolArray]:
    """Velocities after the stops' impact q̇⁺⁺ (n,), the joint impulses the stops apply
    (n,) [N·m·s, N·s] and the joints the impact stopped (n,) bool.

    ``M`` (n, n) the mass matrix at the impact configuration, ``qd`` the velocities before,
    ``push`` from :func:`stop_push` and ``candidates`` the joints on a stop (arriving with
    q̇ into it, resting, or leaving).  The compression phase is the inelastic impact over
    the complementary active set A: ``M (q̇⁺ − q̇) = E_A p``, ``q̇⁺_A = 0``, push·p ≥ 0 on A
    and the others not driven into their stops.  Restitution ``e`` ∈ [0, 1] (Poisson's
    hypothesis) then adds the impulse e·p: ``q̇⁺⁺ = q̇⁺ + e (q̇⁺ − q̇)``, total impulse
    (1 + e) p, arriving joints leave at e times their approach speed.

    ``hold_speed`` [rad/s, m/s] ≥ 0: candidates that the compression phase would leave
    moving off their stops slower than this are held as well (their impulse may then
    pull).  Without it, two coupled joints pressed onto their stops knock each other off
    ever more gently, infinitely often in finite time (a Zeno sequence).

    Kinetic energy never increases.  Let T = ½ q̇ᵀ M q̇ and d = q̇⁺ − q̇, so M d = E_A p.
    Then q̇⁺ᵀ M d = (q̇⁺_A)ᵀ p = 0 because q̇⁺_A = 0, and

        T = ½ (q̇⁺ − d)ᵀ M (q̇⁺ − d) = T⁺ − q̇⁺ᵀ M d + ½ dᵀ M d = T⁺ + ½ dᵀ M d,

    so T⁺ = T − ½ dᵀ M d ≤ T (M positive definite; Carnot: the energy lost is that of the
    velocity jump).  With restitution, T⁺⁺ = ½ (q̇⁺ + e d)ᵀ M (q̇⁺ + e d)
    = T⁺ + e q̇⁺ᵀ M d + ½ e² dᵀ M d = T − ½ (1 − e²) dᵀ M d ≤ T for 0 ≤ e ≤ 1.  The proof
    uses only q̇⁺_A = 0, so it holds for whatever A the pivoting and ``hold_speed`` settle
    on."""
    if not 0.0 <= restitution <= 1.0:
        raise ValueError(f"restitution must be in [0, 1], got {restitution!r}")
    if not hold_speed >= 0.0:
        raise ValueError(f"hold_speed must be >= 0 (rad/s or m/s), got {hold_speed!r}")
    zero = np.zeros_like(qd)
    jump, impulse, locked = _active_set(M, zero, qd, push, candidates)
    slow = candidates & ~locked & (push * (qd + jump) < hold_speed)
    while slow.any():  # grows the held set: at most n solves
        locked |= slow
        jump, impulse = _locked_solve(M, zero, locked, -qd)
        slow = candidates & ~locked & (push * (qd + jump) < hold_speed)
    after = qd + jump
    after[locked] = 0.0
    if restitution > 0.0:
        after += restitution * (after - qd)
        impulse *= 1.0 + restitution
    return after, impulse, locked
