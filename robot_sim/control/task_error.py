"""The task-space error of the tool and the exact time derivatives of its rotation part.

The error of a tool pose (R, p) from a desired one (R_d, p_d) is ``e = [p_d − p; φ]`` with
``φ = log(R_d Rᵀ)`` (world frame, metres and radians), the convention of inverse
kinematics.  Its position part differentiates plainly (ė = v_d − v).  Its rotation part
does not: with ``R_e = R_d Rᵀ`` turning at the world angular velocity ``ω_e = ω_d − R_e ω``,

    φ̇ = J_l(φ)⁻¹ ω_e,     J_l(φ) = I + a(θ) [φ]ₓ + b(θ) [φ]ₓ²,  θ = |φ|,
    a = (1 − cos θ)/θ²,   b = (θ − sin θ)/θ³,

J_l the left Jacobian of SO(3) (``Ṙ_e R_eᵀ = [J_l φ̇]ₓ``).  :func:`rotation_command`
inverts this to second order: the angular acceleration that gives φ a chosen φ̈, so a
controller can impose ``ë + K_d ė + K_p e = 0`` exactly at any angle below π and for a
moving reference (ω̇ = ω̇_d + K_d (ω_d − ω) + K_p φ is its small-error limit).

Arrays are batched: (N, 3) vectors and (N, 3, 3) rotations.  Inside, the maths runs on
three components, Python floats for one configuration (far cheaper than NumPy calls on
tiny arrays) or (N,) arrays for a batch.
Near θ = 0 the coefficients come from their Taylor series (below :data:`SERIES_ANGLE`,
where the closed forms lose digits to cancellation).  No Qt, no OpenGL.
"""
from __future__ import annotations

import math
from typing import Sequence, Union

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Angle [rad] below which the SO(3) coefficients use their series (error < 1e-12 there).
SERIES_ANGLE = 0.1
#: Below this |2 sin θ| an angle near π takes its axis from the symmetric part of R.
_NEAR_PI_SIN = 1e-3


def rotation_logs(R: FloatArray) -> FloatArray:
    """Rotation vectors θ·k (N, 3) of rotations R (N, 3, 3), |θ| in [0, π]; the angle from
    atan2 (well conditioned at 0 and π), the axis near π from the symmetric part of R."""
    w = np.stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]], axis=1)
    two_sin = np.sqrt(np.einsum("ni,ni->n", w, w))
    cos = 0.5 * (R[:, 0, 0] + R[:, 1, 1] + R[:, 2, 2] - 1.0)
    angle = np.arctan2(0.5 * two_sin, cos)
    tiny = two_sin < 1e-12
    scale = np.where(tiny, 0.5, angle / np.where(tiny, 1.0, two_sin))
    out = scale[:, None] * w
    near_pi = (two_sin <= _NEAR_PI_SIN) & (cos < 0.0)
    if near_pi.any():
        Rp, wp, cp = R[near_pi], w[near_pi], cos[near_pi]
        kk = (0.5 * (Rp + Rp.transpose(0, 2, 1)) - cp[:, None, None] * np.eye(3)) / (1.0 - cp)[:, None, None]
        i = np.argmax(np.diagonal(kk, axis1=1, axis2=2), axis=1)
        k = np.take_along_axis(kk, i[:, None, None], axis=2)[:, :, 0]
        k /= np.sqrt(np.einsum("ni,ni->n", k, k))[:, None]
        k *= np.where(np.einsum("ni,ni->n", k, wp) < 0.0, -1.0, 1.0)[:, None]
        out[near_pi] = angle[near_pi, None] * k
    return out


Scalar = Union[float, FloatArray]  # one configuration's component, or N of them
Vec = Sequence[Scalar]  # three components


def _cross(a: Vec, b: Vec) -> tuple[Scalar, Scalar, Scalar]:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _coefficients(theta: Scalar) -> tuple[Scalar, Scalar, Scalar, Scalar, Scalar]:
    """(a, b, c, a'/θ, b'/θ) at θ: J_l = I + a[φ] + b[φ]², J_l⁻¹ = I − [φ]/2 + c[φ]²."""
    if isinstance(theta, float):
        return _series(theta) if theta < SERIES_ANGLE else _closed(theta, math.sin(theta), math.cos(theta))
    small = theta < SERIES_ANGLE
    safe = np.where(small, 1.0, theta)  # keeps the closed forms finite where the series applies
    closed = _closed(safe, np.sin(safe), np.cos(safe))
    return tuple(np.where(small, s, c) for s, c in zip(_series(theta), closed))  # type: ignore[return-value]


def _closed(t: Scalar, s: Scalar, c: Scalar) -> tuple[Scalar, Scalar, Scalar, Scalar, Scalar]:
    t2 = t * t
    return (
        (1.0 - c) / t2,
        (t - s) / (t2 * t),
        1.0 / t2 - (1.0 + c) / (2.0 * t * s),
        (t * s - 2.0 * (1.0 - c)) / (t2 * t2),
        ((1.0 - c) * t - 3.0 * (t - s)) / (t2 * t2 * t),
    )


def _series(t: Scalar) -> tuple[Scalar, Scalar, Scalar, Scalar, Scalar]:
    t2 = t * t
    t4 = t2 * t2
    return (
        0.5 - t2 / 24.0 + t4 / 720.0,
        1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0,
        1.0 / 12.0 + t2 / 720.0 + t4 / 30240.0,
        -1.0 / 12.0 + t2 / 180.0 - t4 / 6720.0,
        -1.0 / 60.0 + t2 / 1260.0 - t4 / 60480.0,
    )


def rotation_command(
    R_e: FloatArray, phi: FloatArray, omega: FloatArray, omega_d: FloatArray, alpha_d: FloatArray, kp: float, kd: float
) -> tuple[FloatArray, FloatArray]:
    """(φ̇, ω̇) (N, 3) each for the rotation errors φ = log(R_e) (N, 3), R_e = R_d Rᵀ
    (N, 3, 3): their rate [rad/s] and the tool angular acceleration [rad/s²] that makes
    ``φ̈ = −kd φ̇ − kp φ`` exactly.

    ``omega``, ``omega_d``, ``alpha_d`` (N, 3): the tool's and the desired angular velocity
    and the desired angular acceleration, world frame.  ``kp`` [1/s²], ``kd`` [1/s].  From
    ω_e = ω_d − R_e ω and φ̇ = J_l⁻¹ ω_e:  ``R_e ω̇ = ω̇_d − ω_e × (R_e ω) − J_l φ̈ − J̇_l φ̇``
    with ``J̇_l φ̇ = (φ·φ̇)(a'/θ φ × φ̇ + b'/θ φ × (φ × φ̇)) + b φ̇ × (φ × φ̇)``.
    """
    if R_e.shape[0] == 1:
        phi_dot, alpha = _rotation_command(
            R_e[0].tolist(), *(x[0].tolist() for x in (phi, omega, omega_d, alpha_d)), kp, kd
        )
        return np.array([phi_dot]), np.array([alpha])
    phi_dot, alpha = _rotation_command(R_e.transpose(1, 2, 0), *(x.T for x in (phi, omega, omega_d, alpha_d)), kp, kd)
    return np.array(phi_dot).T, np.array(alpha).T


def _rotation_command(
    R_e: Sequence[Vec], phi: Vec, omega: Vec, omega_d: Vec, alpha_d: Vec, kp: float, kd: float
) -> tuple[tuple[Scalar, Scalar, Scalar], tuple[Scalar, Scalar, Scalar]]:
    """:func:`rotation_command` on components (R_e as rows of components)."""
    px, py, pz = phi
    sq = px * px + py * py + pz * pz
    a, b, c, da, db = _coefficients(math.sqrt(sq) if isinstance(sq, float) else np.sqrt(sq))
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = R_e
    wx, wy, wz = omega
    rw = (r00 * wx + r01 * wy + r02 * wz, r10 * wx + r11 * wy + r12 * wz, r20 * wx + r21 * wy + r22 * wz)  # R_e ω
    ex, ey, ez = omega_d[0] - rw[0], omega_d[1] - rw[1], omega_d[2] - rw[2]  # ω_e
    # φ̇ = J_l⁻¹ ω_e = ω_e − φ × ω_e / 2 + c φ × (φ × ω_e)
    p_w = _cross(phi, (ex, ey, ez))
    pp_w = _cross(phi, p_w)
    phi_dot = (ex - 0.5 * p_w[0] + c * pp_w[0], ey - 0.5 * p_w[1] + c * pp_w[1], ez - 0.5 * p_w[2] + c * pp_w[2])
    f = tuple(-kd * phi_dot[k] - kp * phi[k] for k in range(3))  # φ̈
    p_f = _cross(phi, f)
    pp_f = _cross(phi, p_f)
    p_d = _cross(phi, phi_dot)
    pp_d = _cross(phi, p_d)
    dp_d = _cross(phi_dot, p_d)
    e_w = _cross((ex, ey, ez), rw)
    rate = px * phi_dot[0] + py * phi_dot[1] + pz * phi_dot[2]
    ra, rb = rate * da, rate * db
    # R_e ω̇ = ω̇_d − ω_e × (R_e ω) − J_l φ̈ − J̇_l φ̇
    rhs = tuple(alpha_d[k] - e_w[k] - (f[k] + a * p_f[k] + b * pp_f[k]) - (ra * p_d[k] + rb * pp_d[k] + b * dp_d[k])
                for k in range(3))
    alpha = (r00 * rhs[0] + r10 * rhs[1] + r20 * rhs[2], r01 * rhs[0] + r11 * rhs[1] + r21 * rhs[2],
             r02 * rhs[0] + r12 * rhs[1] + r22 * rhs[2])
    return phi_dot, alpha
