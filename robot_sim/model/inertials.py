"""Mass properties of the links and the drives of the joints.

:class:`LinkInertials` holds, for each link i (the body that joint i moves), its mass [kg],
its centre of mass [m] in frame i and its inertia tensor [kg·m²] about that centre of mass,
in frame-i axes.  Frame i is the frame of the robot's convention (standard DH: at the far
end of link i, joint i turning about z of frame i−1; modified DH: on joint i's axis).

:class:`Drives` holds the motor side of each joint in the Robotics Toolbox's convention:
motor inertia Jm [kg·m²], gear ratio G (joint velocity × G = motor velocity), viscous
friction B [N·m·s/rad at the motor] and Coulomb friction Tc± [N·m at the motor].  At the
joint this is a reflected inertia G²·Jm added to the mass matrix's diagonal and a friction
torque −G²·B·q̇ − |G|·Tc±, Tc+ when q̇ > 0, Tc− when q̇ < 0 and none at rest.  Effort
[N·m or N] and velocity [rad/s or m/s] limits are at the joint, inf where unknown.

The robot-file tables ``[joints.inertial]`` and ``[joints.drive]`` are parsed by
:mod:`robot_sim.io.inertial_tables`; :func:`robot_sim.model.estimate.estimate_inertials` supplies mass properties for a robot
whose file has none.  This module imports neither Qt nor OpenGL.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.model.arrays import frozen

FloatArray = NDArray[np.float64]

INERTIAL_KEYS = {"mass", "com", "inertia"}
DRIVE_KEYS = {"motor_inertia", "gear_ratio", "viscous", "coulomb", "effort_limit", "velocity_limit"}
#: Value of each scalar drive field when a file or caller omits it (an ideal direct drive
#: without friction or limits); Coulomb friction defaults to [0, 0].
DRIVE_DEFAULTS = {"motor_inertia": 0.0, "gear_ratio": 1.0, "viscous": 0.0,
                  "effort_limit": math.inf, "velocity_limit": math.inf}


_REL_TOL = 1e-9  # relative tolerance of the positive-semidefinite and triangle checks
#: Said after a triangle-inequality violation: how to accept such a table.
BALANCE_HINT = "; balance_inertia raises the smallest moment just enough (a keyword, or balance_inertia = true in a robot file)"


def inertia_problem(inertia: FloatArray) -> str | None:
    """Why a symmetric (3, 3) tensor [kg·m²] is not the inertia of a rigid body about a
    point, or None if it is one: its principal moments must be >= 0 and obey the
    triangle inequality (each at most the sum of the other two)."""
    moments = np.linalg.eigvalsh(inertia)
    tol = _REL_TOL * max(float(np.abs(moments).max()), 1e-300)
    if moments[0] < -tol:
        return f"has a negative principal moment {moments[0]:.6g} (principal moments {_fmt(moments)})"
    if moments[2] > moments[0] + moments[1] + tol:
        return (
            f"principal moments {_fmt(moments)} violate the triangle inequality "
            f"({moments[2]:.6g} > {moments[0]:.6g} + {moments[1]:.6g})"
        )
    return None


class InertiaBalancedWarning(UserWarning):
    """An inertia was changed by ``balance_inertia`` (the message names the link and the
    principal moments before and after)."""


def balanced_inertia(inertia: FloatArray) -> FloatArray | None:
    """The tensor with its smallest principal moment raised just enough to satisfy the
    triangle inequality (MuJoCo's ``balanceinertia`` fixes the same tables), same
    principal axes; None when ``inertia`` already satisfies it or has a negative moment
    (which no balancing makes physical).  A moment a <= b <= c with c > a + b becomes
    c - b, so c = a + b holds: the body is a flat plate, the nearest valid tensor with
    those axes and the larger moments kept."""
    moments, axes = np.linalg.eigh(inertia)
    tol = _REL_TOL * max(float(np.abs(moments).max()), 1e-300)
    if moments[0] < -tol or moments[2] <= moments[0] + moments[1] + tol:
        return None
    moments = moments.copy()
    moments[0] = moments[2] - moments[1]
    out = (axes * moments) @ axes.T
    return 0.5 * (out + out.T)


def balance_link_inertias(inertia: FloatArray, names: list[str]) -> FloatArray:
    """``inertia`` (n, 3, 3) with each tensor that violates the triangle inequality
    balanced (:func:`balanced_inertia`), one InertiaBalancedWarning per change naming
    ``names[i]`` and the principal moments before and after [kg·m²]."""
    out = np.array(inertia, dtype=float)
    for i, tensor in enumerate(out):
        fixed = balanced_inertia(tensor)
        if fixed is not None:
            warnings.warn(f"inertia of {names[i]}: principal moments {_fmt(np.linalg.eigvalsh(tensor))} raised to "
                          f"{_fmt(np.linalg.eigvalsh(fixed))} kg m^2 (balance_inertia: the smallest moment raised "
                          "just enough for the triangle inequality)", InertiaBalancedWarning, stacklevel=3)
            out[i] = fixed
    return out


def _fmt(values: FloatArray) -> str:
    return "[" + ", ".join(f"{v:.6g}" for v in values) + "]"


def inertia_from_elements(ixx: float, iyy: float, izz: float, ixy: float, iyz: float, ixz: float) -> FloatArray:
    """Symmetric (3, 3) tensor from its elements in URDF order (Ixx, Iyy, Izz, Ixy, Iyz, Ixz)."""
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


@dataclass(frozen=True, eq=False)
class LinkInertials:
    """Mass properties of links 1..n: ``mass`` (n,) [kg], ``com`` (n, 3) [m] in frame i,
    ``inertia`` (n, 3, 3) [kg·m²] about the COM in frame-i axes.  ``estimated`` is True
    when :func:`estimate_inertials` made them from the link geometry."""

    mass: FloatArray
    com: FloatArray
    inertia: FloatArray
    estimated: bool = False

    @classmethod
    def from_arrays(cls, mass: ArrayLike, com: ArrayLike, inertia: ArrayLike, estimated: bool = False, *,
                    balance_inertia: bool = False) -> "LinkInertials":
        """Validated inertials from arrays (SI).  ValueError naming the argument, the link
        and the value for a wrong shape, a non-finite or negative mass, or a tensor that
        is not symmetric or not a rigid body's inertia.  With ``balance_inertia`` a tensor
        that only violates the triangle inequality (published tables such as the PUMA 560's
        of Armstrong et al. 1986) has its smallest principal moment raised just enough
        (:func:`balanced_inertia`), reported by an InertiaBalancedWarning per link."""
        m = np.asarray(mass, dtype=float)
        if m.ndim != 1 or not np.isfinite(m).all():
            raise ValueError(f"mass must be a finite (n,) array, got {mass!r}")
        n = m.shape[0]
        c = np.asarray(com, dtype=float)
        inertia_arr = np.array(inertia, dtype=float)  # a copy: balancing changes it
        if c.shape != (n, 3) or not np.isfinite(c).all():
            raise ValueError(f"com must be a finite ({n}, 3) array, got shape {c.shape}")
        if inertia_arr.shape != (n, 3, 3) or not np.isfinite(inertia_arr).all():
            raise ValueError(f"inertia must be a finite ({n}, 3, 3) array, got shape {inertia_arr.shape}")
        for i in range(n):
            if m[i] < 0.0:
                raise ValueError(f"mass of link {i + 1} is negative: {m[i]!r}")
            if not np.allclose(inertia_arr[i], inertia_arr[i].T, rtol=0.0, atol=1e-12 * max(1.0, np.abs(inertia_arr[i]).max())):
                raise ValueError(f"inertia of link {i + 1} is not symmetric:\n{inertia_arr[i]}")
            if balance_inertia:
                inertia_arr[i] = balance_link_inertias(inertia_arr[i:i + 1], [f"link {i + 1}"])[0]
            problem = inertia_problem(inertia_arr[i])
            if problem:
                hint = "" if balance_inertia else BALANCE_HINT
                raise ValueError(f"inertia of link {i + 1} {problem}{hint if 'triangle' in problem else ''}")
        return cls(frozen(m, (n,)), frozen(c, (n, 3)), frozen(inertia_arr, (n, 3, 3)), bool(estimated))


@dataclass(frozen=True, eq=False)
class Drives:
    """Joint drives (n,) each: ``motor_inertia`` Jm [kg·m²], ``gear_ratio`` G,
    ``viscous`` B [N·m·s/rad, motor side], ``coulomb`` (n, 2) Tc+ >= 0 and Tc− <= 0
    [N·m, motor side], ``effort_limit`` [N·m or N] and ``velocity_limit`` [rad/s or m/s]
    at the joint (inf where unknown).  See the module docstring for the joint-side terms."""

    motor_inertia: FloatArray
    gear_ratio: FloatArray
    viscous: FloatArray
    coulomb: FloatArray
    effort_limit: FloatArray
    velocity_limit: FloatArray

    @classmethod
    def default(cls, n: int) -> "Drives":
        """Drives that add nothing: Jm 0, G 1, no friction, unlimited effort and velocity."""
        return cls.from_arrays(n)

    @classmethod
    def from_arrays(
        cls,
        n: int,
        motor_inertia: ArrayLike | None = None,
        gear_ratio: ArrayLike | None = None,
        viscous: ArrayLike | None = None,
        coulomb: ArrayLike | None = None,
        effort_limit: ArrayLike | None = None,
        velocity_limit: ArrayLike | None = None,
    ) -> "Drives":
        """Drives of n joints; omitted arrays take the defaults of :meth:`default`."""
        values = {
            "motor_inertia": (motor_inertia, DRIVE_DEFAULTS["motor_inertia"], (n,)),
            "gear_ratio": (gear_ratio, DRIVE_DEFAULTS["gear_ratio"], (n,)),
            "viscous": (viscous, DRIVE_DEFAULTS["viscous"], (n,)),
            "coulomb": (coulomb, 0.0, (n, 2)),
            "effort_limit": (effort_limit, DRIVE_DEFAULTS["effort_limit"], (n,)),
            "velocity_limit": (velocity_limit, DRIVE_DEFAULTS["velocity_limit"], (n,)),
        }
        arrays = {}
        for key, (value, default, shape) in values.items():
            arr = np.full(shape, default) if value is None else np.asarray(value, dtype=float)
            if arr.shape != shape or np.isnan(arr).any():
                raise ValueError(f"{key} must be a {shape} array without NaN, got {value!r}")
            arrays[key] = frozen(arr, shape)
        return cls(**arrays)

    @property
    def reflected_inertia(self) -> FloatArray:
        """G²·Jm (n,): the motor inertia seen at the joint [kg·m² or kg]."""
        return self.gear_ratio**2 * self.motor_inertia


def _combine(parts: list[tuple[float, FloatArray, FloatArray]]) -> tuple[float, FloatArray, FloatArray]:
    """Mass, COM and inertia about the COM of rigidly joined parts (parallel-axis theorem)."""
    mass = sum(p[0] for p in parts)
    com = sum(p[0] * p[1] for p in parts) / mass
    inertia = np.zeros((3, 3))
    for m, c, i_c in parts:
        r = c - com
        inertia += i_c + m * (float(r @ r) * np.eye(3) - np.outer(r, r))
    return mass, com, inertia
