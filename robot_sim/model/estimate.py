"""Mass properties estimated from a robot's geometry, for robots whose file gives none: each
link a solid cylinder of uniform density along its DH d and a segments (SI units, link frames)."""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from robot_sim.model.inertials import FloatArray, LinkInertials, _combine
from robot_sim.model.params import RobotParams

#: Cylinder radius of :func:`estimate_inertials` as a fraction of the robot's size (the sum
#: of |a| and |d| over the joints plus the tool offset).
ESTIMATE_RADIUS_FRAC = 0.04
#: Default density of :func:`estimate_inertials` [kg/m³]: an arm is mostly hollow, so its
#: links, modelled as solid cylinders, weigh about as much as water would.
DEFAULT_DENSITY = 1000.0


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


def _segment_length_d(robot: RobotParams, i: int) -> float:
    """d of joint i for the estimate: a prismatic joint's d at its largest finite limit
    (the sliding member is at least that long), else at home."""
    if robot.is_revolute[i]:
        return float(robot.dh_d[i])
    q = robot.q_max[i] if np.isfinite(robot.q_max[i]) else robot.q_home[i]
    return float(robot.dh_d[i] + q)


def estimate_inertials(robot: RobotParams, density: float = DEFAULT_DENSITY) -> RobotParams:
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
    radius = ESTIMATE_RADIUS_FRAC * max(robot.size, 1e-3)
    masses, coms, inertias = [], [], []
    origin = np.zeros(3)
    for i in range(n):
        if modified:
            if i + 1 < n:
                a, sa, ca = robot.dh_a[i + 1], math.sin(robot.dh_alpha[i + 1]), math.cos(robot.dh_alpha[i + 1])
                corner = np.array([a, 0.0, 0.0])
                points = [origin, corner, corner + _segment_length_d(robot, i + 1) * np.array([0.0, -sa, ca])]
            else:
                points = [origin, robot.tool_tf.t()]
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
