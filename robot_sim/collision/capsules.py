"""Default collision geometry: capsules along the DH segments of every link.

Robots whose files give no collision shapes collide as the ``solid`` look draws them:
each DH segment of a link is a capsule, posed in that link's frame.

* Standard DH (``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``): link i (frame i) holds the
  axis segment (length |d_i| along z_{i-1}, which is (0, sin α_i, cos α_i) in frame i)
  and the offset segment (|a_i| along x_i) that ends at frame i's origin.
* Modified DH (``A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)``): the offset a_{i-1}
  along x_{i-1} is rigid in frame i-1, so it belongs to link i-1 (the base for i = 1);
  link i holds the axis segment (|d_i| along z_i, ending at frame i's origin).
* A prismatic joint is a sleeve on the link before it, as long as the stroke and ending
  where the travel starts (at the lower limit), and a rod as long on the moving link,
  ending at the moving end of the axis segment; a piece joins the joint to a sleeve
  that starts farther out.  An unlimited joint's stroke is ``UNLIMITED_STROKE_FRAC`` of
  the robot's size (RobotParams.size).
* The tool segment (frame n to the endeffector) belongs to link n.

Radii: one per link, ``RADIUS_FRAC`` of the link's total segment length, clamped to
[``RADIUS_MIN_FRAC``, ``RADIUS_MAX_FRAC``] of the robot's size (RobotParams.size) (the
rule that sizes the drawn joints), then shrunk at home until it is at most
``CLEARANCE`` of the gap between its segments and those of every non-adjacent link, so
the home pose is free of self-contact wherever the segments themselves do not meet.
"""
from __future__ import annotations


import numpy as np
from numpy.typing import NDArray

from robot_sim.kernels.model import per_robot
from robot_sim.kinematics import characteristic_length, forward_kinematics
from robot_sim.model.params import JTYPE_PRISMATIC, RobotParams
from robot_sim.model.shapes import Capsule

from robot_sim.collision.closest import segment_segment

FloatArray = NDArray[np.float64]

RADIUS_FRAC = 0.14  # capsule radius / the link's segment length ...
RADIUS_MIN_FRAC = 0.012  # ... at least this fraction of the robot's size (RobotParams.size) ...
RADIUS_MAX_FRAC = 0.035  # ... at most this one
RADIUS_FLOOR_FRAC = 0.003  # and after the clearance shrink never below this one
CLEARANCE = 0.45  # at home: radius <= this * the gap to any non-adjacent link's segments
UNLIMITED_STROKE_FRAC = 0.25  # stroke of a prismatic joint without both limits / the length
MIN_SEGMENT = 1e-6  # m: shorter segments get no capsule


def _prismatic_travel(robot: RobotParams, length: float) -> tuple[FloatArray, FloatArray]:
    """d at the start of each prismatic joint's travel (lower limit) and its stroke (n,)."""
    limited = np.isfinite(robot.q_min) & np.isfinite(robot.q_max)
    lower = np.where(np.isfinite(robot.q_min), robot.q_min, robot.q_home)
    stroke = np.where(limited, robot.q_max - robot.q_min, UNLIMITED_STROKE_FRAC * length)
    return robot.dh_d + lower, stroke


def dh_segments_local(robot: RobotParams) -> list[tuple[int, FloatArray, FloatArray]]:
    """The DH segments as (link index 0..n, start, end) with the ends (3,) in metres in
    that link's frame (0: the base, frame 0)."""
    n = robot.n_dofs
    start, stroke = _prismatic_travel(robot, characteristic_length(robot))
    out: list[tuple[int, FloatArray, FloatArray]] = []
    origin = np.zeros(3)
    for j in range(n):
        i = j + 1
        a, d = float(robot.dh_a[j]), float(robot.dh_d[j])
        sa, ca = np.sin(robot.dh_alpha[j]), np.cos(robot.dh_alpha[j])
        prismatic = robot.jtype[j] == JTYPE_PRISMATIC
        if robot.is_modified:
            out.append((i - 1, origin, np.array([a, 0.0, 0.0])))
            joint, axis_prev = np.array([a, 0.0, 0.0]), np.array([0.0, -sa, ca])
            tip, axis_here = origin, np.array([0.0, 0.0, 1.0])
            out_d = (i, np.array([0.0, 0.0, -d]), origin)
        else:
            joint, axis_prev = origin, np.array([0.0, 0.0, 1.0])
            tip, axis_here = np.array([-a, 0.0, 0.0]), np.array([0.0, sa, ca])
            out_d = (i, tip - d * axis_here, tip)
        if prismatic:
            s0, s1 = start[j] - stroke[j], start[j]
            out.append((i - 1, joint + s0 * axis_prev, joint + s1 * axis_prev))  # sleeve
            if s0 > 0.0:
                out.append((i - 1, joint, joint + s0 * axis_prev))  # joint to sleeve
            out.append((i, tip - stroke[j] * axis_here, tip))  # rod
        else:
            out.append(out_d)
        if not robot.is_modified:
            out.append((i, tip, origin))
    out.append((n, origin, np.asarray(robot.tool_tf.mat[:3, 3], dtype=float)))
    return [(k, p, q) for k, p, q in out if np.linalg.norm(q - p) >= MIN_SEGMENT]


def _capsule(p: FloatArray, q: FloatArray, radius: float) -> Capsule:
    axis = q - p
    length = float(np.linalg.norm(axis))
    z = axis / length
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = x, np.cross(z, x), z, 0.5 * (p + q)
    return Capsule(radius, length, pose)


def dh_capsules(robot: RobotParams) -> tuple[tuple[Capsule, ...], ...]:
    """Capsules along the DH segments (module docstring), a tuple of n + 1 tuples: index 0
    the base link posed in frame 0, index i link i posed in frame i.  Computed once per
    robot (kept with its compiled model)."""
    return per_robot(robot, "dh_capsules", _dh_capsules)


def _dh_capsules(robot: RobotParams) -> tuple[tuple[Capsule, ...], ...]:
    n, length = robot.n_dofs, characteristic_length(robot)
    segments = dh_segments_local(robot)
    seg_len = np.zeros(n + 1)
    for k, p, q in segments:
        seg_len[k] += np.linalg.norm(q - p)
    radius = np.clip(RADIUS_FRAC * seg_len, RADIUS_MIN_FRAC * length, RADIUS_MAX_FRAC * length)
    frames = forward_kinematics(robot, robot.q_home, all_frames=True)[: n + 1]
    world = [(k, frames[k, :3, :3] @ p + frames[k, :3, 3], frames[k, :3, :3] @ q + frames[k, :3, 3])
             for k, p, q in segments]
    for s, (ki, p1, q1) in enumerate(world):
        for kj, p2, q2 in world[s + 1:]:
            if abs(ki - kj) < 2:
                continue
            gap = segment_segment(tuple(p1), tuple(q1), tuple(p2), tuple(q2))[0]
            if gap > MIN_SEGMENT:
                radius[ki] = min(radius[ki], CLEARANCE * gap)
                radius[kj] = min(radius[kj], CLEARANCE * gap)
    radius = np.maximum(radius, RADIUS_FLOOR_FRAC * length)
    links: list[list[Capsule]] = [[] for _ in range(n + 1)]
    for k, p, q in segments:
        links[k].append(_capsule(p, q, float(radius[k])))
    return tuple(tuple(c) for c in links)
