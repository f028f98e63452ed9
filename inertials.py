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

The robot-file tables ``[joints.inertial]`` and ``[joints.drive]`` are parsed here (called
by :mod:`robot_defs`); :func:`estimate_inertials` supplies mass properties for a robot
whose file has none.  This module imports neither Qt nor OpenGL.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from messages import clip_repr

if TYPE_CHECKING:
    from robot_defs import RobotParams, _Checker

FloatArray = NDArray[np.float64]

INERTIAL_KEYS = {"mass", "com", "inertia"}
DRIVE_KEYS = {"motor_inertia", "gear_ratio", "viscous", "coulomb", "effort_limit", "velocity_limit"}
#: Value of each scalar drive field when a file or caller omits it (an ideal direct drive
#: without friction or limits); Coulomb friction defaults to [0, 0].
DRIVE_DEFAULTS = {"motor_inertia": 0.0, "gear_ratio": 1.0, "viscous": 0.0,
                  "effort_limit": math.inf, "velocity_limit": math.inf}

#: Default density of :func:`estimate_inertials` [kg/m³]: an arm is mostly hollow, so its
#: links, modelled as solid cylinders, weigh about as much as water would.
DEFAULT_DENSITY = 1000.0
#: Cylinder radius of :func:`estimate_inertials` as a fraction of the robot's size (the sum
#: of |a| and |d| over the joints plus the tool offset).
ESTIMATE_RADIUS_FRAC = 0.04

_REL_TOL = 1e-9  # relative tolerance of the positive-semidefinite and triangle checks


def _frozen(values: Any, shape: tuple[int, ...]) -> FloatArray:
    arr = np.array(values, dtype=float).reshape(shape)
    arr.setflags(write=False)
    return arr


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
    def from_arrays(cls, mass: ArrayLike, com: ArrayLike, inertia: ArrayLike, estimated: bool = False) -> "LinkInertials":
        """Validated inertials from arrays (SI).  ValueError naming the argument, the link
        and the value for a wrong shape, a non-finite or negative mass, or a tensor that
        is not symmetric or not a rigid body's inertia."""
        m = np.asarray(mass, dtype=float)
        if m.ndim != 1 or not np.isfinite(m).all():
            raise ValueError(f"mass must be a finite (n,) array, got {mass!r}")
        n = m.shape[0]
        c = np.asarray(com, dtype=float)
        inertia_arr = np.asarray(inertia, dtype=float)
        if c.shape != (n, 3) or not np.isfinite(c).all():
            raise ValueError(f"com must be a finite ({n}, 3) array, got shape {c.shape}")
        if inertia_arr.shape != (n, 3, 3) or not np.isfinite(inertia_arr).all():
            raise ValueError(f"inertia must be a finite ({n}, 3, 3) array, got shape {inertia_arr.shape}")
        for i in range(n):
            if m[i] < 0.0:
                raise ValueError(f"mass of link {i + 1} is negative: {m[i]!r}")
            if not np.allclose(inertia_arr[i], inertia_arr[i].T, rtol=0.0, atol=1e-12 * max(1.0, np.abs(inertia_arr[i]).max())):
                raise ValueError(f"inertia of link {i + 1} is not symmetric:\n{inertia_arr[i]}")
            problem = inertia_problem(inertia_arr[i])
            if problem:
                raise ValueError(f"inertia of link {i + 1} {problem}")
        return cls(_frozen(m, (n,)), _frozen(c, (n, 3)), _frozen(inertia_arr, (n, 3, 3)), bool(estimated))


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
            arrays[key] = _frozen(arr, shape)
        return cls(**arrays)

    @property
    def reflected_inertia(self) -> FloatArray:
        """G²·Jm (n,): the motor inertia seen at the joint [kg·m² or kg]."""
        return self.gear_ratio**2 * self.motor_inertia


# ------------------------------------------------------------------ robot-file tables


def parse_joint_tables(check: "_Checker", joints: list[dict[str, Any]]) -> tuple[LinkInertials | None, Drives | None]:
    """Inertials and drives from the ``[joints.inertial]`` and ``[joints.drive]`` tables of
    already-checked joint tables.  Every joint or none must have an inertial table, and a
    joint may not give both the scalar ``com`` fraction and an inertial table.  Raises
    RobotDefinitionError (through ``check``) naming file, joint, field and value."""
    with_inertial = [i for i, joint in enumerate(joints) if "inertial" in joint]
    inertials = None
    if with_inertial:
        missing = [i for i in range(len(joints)) if i not in with_inertial]
        if missing:
            raise check.fail(
                f"joints[{missing[0]}].inertial",
                f"missing, but joints[{with_inertial[0]}] has one; give [joints.inertial] "
                "for every joint or for none",
            )
        rows = [_parse_inertial(check, joint, f"joints[{i}]") for i, joint in enumerate(joints)]
        inertials = LinkInertials(
            _frozen([r[0] for r in rows], (len(rows),)),
            _frozen([r[1] for r in rows], (len(rows), 3)),
            _frozen([r[2] for r in rows], (len(rows), 3, 3)),
        )
    drives = None
    if any("drive" in joint for joint in joints):
        columns = [_parse_drive(check, joint.get("drive", {}), f"joints[{i}].drive") for i, joint in enumerate(joints)]
        drives = Drives.from_arrays(len(joints), *(np.array([c[k] for c in columns]) for k in range(6)))
    return inertials, drives


def _table(check: "_Checker", value: Any, where: str, keys: set[str]) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise check.fail(where, f"expected a table with keys {', '.join(sorted(keys))}, got {clip_repr(value)}")
    check.keys(value, keys, where)
    return value


def _parse_inertial(check: "_Checker", joint: dict[str, Any], where: str) -> tuple[float, list[float], FloatArray]:
    if "com" in joint:
        raise check.fail(
            f"{where}.com",
            f"ambiguous: both the com fraction {joint['com']!r} and [joints.inertial] are given; "
            "remove com (the inertial's com places the centre of mass)",
        )
    where = f"{where}.inertial"
    table = _table(check, joint["inertial"], where, INERTIAL_KEYS)
    for key in ("mass", "com", "inertia"):
        if key not in table:
            raise check.fail(f"{where}.{key}", "missing required field")
    mass = check.number(table["mass"], f"{where}.mass")
    if mass < 0.0:
        raise check.fail(f"{where}.mass", f"mass {table['mass']!r} is negative; accepted: a mass >= 0 (kg)")
    com = check.vector(table["com"], 3, f"{where}.com")
    elements = check.vector(table["inertia"], 6, f"{where}.inertia")
    inertia = inertia_from_elements(*elements)
    problem = inertia_problem(inertia)
    if problem:
        raise check.fail(
            f"{where}.inertia",
            f"{table['inertia']!r} {problem}; accepted: [Ixx, Iyy, Izz, Ixy, Iyz, Ixz] (kg m^2) of a "
            "positive semi-definite tensor whose principal moments obey the triangle inequality",
        )
    return mass, com, inertia


def _parse_drive(check: "_Checker", value: Any, where: str) -> tuple[float, float, float, list[float], float, float]:
    table = _table(check, value, where, DRIVE_KEYS)

    def number(key: str, default: float, ok: Any, accepted: str) -> float:
        if key not in table:
            return default
        v = check.number(table[key], f"{where}.{key}")
        if not ok(v):
            raise check.fail(f"{where}.{key}", f"{key} {table[key]!r} is out of range; accepted: {accepted}")
        return v

    jm = number("motor_inertia", DRIVE_DEFAULTS["motor_inertia"], lambda v: v >= 0.0, "a motor inertia >= 0 (kg m^2)")
    gear = number("gear_ratio", DRIVE_DEFAULTS["gear_ratio"], lambda v: v != 0.0, "a non-zero gear ratio")
    viscous = number("viscous", DRIVE_DEFAULTS["viscous"], lambda v: v >= 0.0, "a viscous friction coefficient >= 0")
    coulomb = [0.0, 0.0]
    if "coulomb" in table:
        coulomb = check.vector(table["coulomb"], 2, f"{where}.coulomb")
        if coulomb[0] < 0.0 or coulomb[1] > 0.0:
            raise check.fail(
                f"{where}.coulomb",
                f"coulomb {table['coulomb']!r} is out of range; accepted: [Tc+, Tc-] with Tc+ >= 0 and Tc- <= 0",
            )
    effort = number("effort_limit", DRIVE_DEFAULTS["effort_limit"], lambda v: v > 0.0, "an effort limit > 0")
    velocity = number("velocity_limit", DRIVE_DEFAULTS["velocity_limit"], lambda v: v > 0.0, "a velocity limit > 0")
    return jm, gear, viscous, coulomb, effort, velocity


# ------------------------------------------------------------------ estimate from geometry


def _cylinder(p0: FloatArray, p1: FloatArray, radius: float, density: float) -> tuple[float, FloatArray, FloatArray]:
    """Mass, centroid and inertia about the centroid of a solid cylinder from p0 to p1."""
    axis = p1 - p0
    length = float(np.linalg.norm(axis))
    mass = density * math.pi * radius**2 * length
    u = axis / length if length > 0.0 else np.array([0.0, 0.0, 1.0])
    along = 0.5 * mass * radius**2
    across = mass * (3.0 * radius**2 + length**2) / 12.0
    inertia = across * np.eye(3) + (along - across) * np.outer(u, u)
    return mass, 0.5 * (p0 + p1), inertia


def _combine(parts: list[tuple[float, FloatArray, FloatArray]]) -> tuple[float, FloatArray, FloatArray]:
    """Mass, COM and inertia about the COM of rigidly joined parts (parallel-axis theorem)."""
    mass = sum(p[0] for p in parts)
    com = sum(p[0] * p[1] for p in parts) / mass
    inertia = np.zeros((3, 3))
    for m, c, i_c in parts:
        r = c - com
        inertia += i_c + m * (float(r @ r) * np.eye(3) - np.outer(r, r))
    return mass, com, inertia


def _segment_length_d(robot: "RobotParams", i: int) -> float:
    """d of joint i for the estimate: a prismatic joint's d at its largest finite limit
    (the sliding member is at least that long), else at home."""
    if robot.is_revolute[i]:
        return float(robot.dh_d[i])
    q = robot.q_max[i] if np.isfinite(robot.q_max[i]) else robot.q_home[i]
    return float(robot.dh_d[i] + q)


def estimate_inertials(robot: "RobotParams", density: float = DEFAULT_DENSITY) -> "RobotParams":
    """A copy of ``robot`` whose ``inertials`` are estimated from its link geometry
    (``estimated=True``), for a robot whose file gives none.

    Each link is the union of solid cylinders of ``density`` [kg/m³] and radius
    ``ESTIMATE_RADIUS_FRAC`` × the robot's size (Σ|a| + Σ|d| + tool offset):

    * one along each DH segment the link carries, in frame i of the robot's convention:
      standard DH — d_i along z_{i−1} from frame i−1's origin, then a_i along x_i to frame
      i's origin; modified DH — a_i along x_i from frame i's origin, then d_{i+1} along
      z_{i+1} (the last link carries the tool offset instead).  A prismatic joint's d is
      taken at its largest finite limit;
    * a motor housing: a cylinder as long as its diameter, centred on frame i's origin
      along z_i, so that every link, even one of zero length, has mass and inertia.

    COM and inertia follow from the parallel-axis theorem.  Raises ValueError for a
    density that is not positive and finite.
    """
    if not (math.isfinite(density) and density > 0.0):
        raise ValueError(f"density must be a positive finite number (kg/m^3), got {density!r}")
    n = robot.n_dofs
    modified = robot.is_modified
    size = float(
        np.sum(np.abs(robot.dh_a))
        + sum(abs(_segment_length_d(robot, i)) for i in range(n))
        + np.linalg.norm(robot.endeff_tf.t())
    )
    radius = ESTIMATE_RADIUS_FRAC * max(size, 1e-3)
    masses, coms, inertias = [], [], []
    origin = np.zeros(3)
    for i in range(n):
        if modified:
            if i + 1 < n:
                a, sa, ca = robot.dh_a[i + 1], math.sin(robot.dh_alpha[i + 1]), math.cos(robot.dh_alpha[i + 1])
                corner = np.array([a, 0.0, 0.0])
                points = [origin, corner, corner + _segment_length_d(robot, i + 1) * np.array([0.0, -sa, ca])]
            else:
                points = [origin, robot.endeff_tf.t()]
        else:
            a, sa, ca = robot.dh_a[i], math.sin(robot.dh_alpha[i]), math.cos(robot.dh_alpha[i])
            corner = np.array([-a, 0.0, 0.0])
            points = [corner - _segment_length_d(robot, i) * np.array([0.0, sa, ca]), corner, origin]
        parts = [
            _cylinder(p0, p1, radius, density)
            for p0, p1 in zip(points[:-1], points[1:])
            if np.linalg.norm(p1 - p0) > 1e-12
        ]
        parts.append(_cylinder(np.array([0.0, 0.0, -radius]), np.array([0.0, 0.0, radius]), radius, density))
        mass, com, inertia = _combine(parts)
        masses.append(mass)
        coms.append(com)
        inertias.append(0.5 * (inertia + inertia.T))
    inertials = LinkInertials.from_arrays(masses, coms, inertias, estimated=True)
    return dataclasses.replace(robot, inertials=inertials)
