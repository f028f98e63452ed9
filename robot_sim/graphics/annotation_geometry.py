"""The DH parameters of one joint drawn in the 3D view: dimensions and arcs between
frames i−1 and i, each labelled with its value (pure NumPy, no GL; drawn by
items/annotation.py and the browser view).

Standard DH, joint i (``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``): d_i as a dimension
along z_{i−1} from o_{i−1}, θ_i as an arc about z_{i−1} from x_{i−1} to x_i (at the foot
of the common normal), a_i as a dimension along x_i to o_i, α_i as an arc about x_i
from z_{i−1} to z_i at o_i.  Modified DH (Craig, ``A_i = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i)
Tz(d_i)``): α_{i−1} as an arc about x_{i−1} from z_{i−1} to z_i at o_{i−1}, a_{i−1} along
x_{i−1}, θ_i as an arc about z_i from x_{i−1} to x_i, d_i along z_i to o_i.

Every value is read off the two world frames (a signed length is a projection, an
angle an atan2 about its axis), so what is drawn and written is what the kinematics
computed.  World frame, metres; angles written in degrees.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.robot_parts import dh_segments

RGBA = tuple[float, float, float, float]


@dataclass
class Annotation:
    """Polylines (points (k, 3), rgba, dashed) and labels (anchor (3,), text, rgba)."""

    lines: list[tuple[NDArray[np.float64], RGBA, bool]] = field(default_factory=list)
    labels: list[tuple[NDArray[np.float64], str, RGBA]] = field(default_factory=list)


def _shown(value: float, digits: int) -> str:
    """``value`` with ``digits`` decimals, never "-0.000": a length or angle read off the
    frames as −1e−17 is shown as 0."""
    return f"{round(value, digits) + 0.0:.{digits}f}"


def signed_angle(u: NDArray, v: NDArray, axis: NDArray) -> float:
    """Angle (rad) turning unit ``u`` into unit ``v`` about unit ``axis`` (both ⊥ axis)."""
    return math.atan2(float(np.dot(np.cross(u, v), axis)), float(np.dot(u, v)))


def _perpendicular(axis: NDArray, *hints: NDArray) -> NDArray:
    """A unit vector ⊥ ``axis``: the first hint with a part across it, else any."""
    for hint in (*hints, np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])):
        across = hint - np.dot(hint, axis) * axis
        if np.linalg.norm(across) > 1e-6:
            return across / np.linalg.norm(across)
    raise AssertionError("unreachable: x or y is across any axis")


def _dimension(out: Annotation, start: NDArray, end: NDArray, side: NDArray, offset: float, tick: float,
               text: str, rgba: RGBA) -> None:
    """A dimension from ``start`` to ``end`` drawn ``offset`` metres to ``side`` (unit),
    with extension lines and end ticks, labelled ``text`` at its middle."""
    a, b = start + offset * side, end + offset * side
    out.lines += [(np.array([start, a + 0.3 * offset * side]), rgba, True),
                  (np.array([end, b + 0.3 * offset * side]), rgba, True),
                  (np.array([a, b]), rgba, False)]
    length = np.linalg.norm(end - start)
    if length > gd.MIN_LINK_LENGTH:
        along = (end - start) / length
        for p, sign in ((a, 1.0), (b, -1.0)):  # arrowheads pointing outwards
            out.lines.append((np.array([p + sign * tick * along + 0.5 * tick * side, p,
                                        p + sign * tick * along - 0.5 * tick * side]), rgba, False))
    out.labels.append((0.5 * (a + b) + 0.4 * offset * side, text, rgba))


def _arc(out: Annotation, centre: NDArray, axis: NDArray, start: NDArray, end: NDArray, radius: float,
         text: str, rgba: RGBA) -> None:
    """An arc of ``radius`` about ``axis`` through ``centre`` from direction ``start`` to
    ``end`` (units ⊥ axis), with both directions drawn as dashed spokes, labelled at its
    middle."""
    angle = signed_angle(start, end, axis)
    t = np.linspace(0.0, angle, max(2, int(abs(angle) / (2 * math.pi) * gd.ANNOTATION_ARC_SEGMENTS) + 2))
    other = np.cross(axis, start)
    points = centre + radius * (np.cos(t)[:, None] * start + np.sin(t)[:, None] * other)
    out.lines += [(points, rgba, False),
                  (np.array([centre, centre + gd.ANNOTATION_SPOKE_RATIO * radius * start]), rgba, True),
                  (np.array([centre, centre + gd.ANNOTATION_SPOKE_RATIO * radius * end]), rgba, True)]
    mid = 0.5 * angle
    direction = math.cos(mid) * start + math.sin(mid) * other
    out.labels.append((centre + 1.15 * radius * direction, text, rgba))


def dh_annotation(frames: NDArray[np.float64], joint: int, modified: bool, scale: float) -> Annotation:
    """The annotation of joint ``joint`` (1..n) from world ``frames`` (n+1, 4, 4) (frames
    0..n) of a standard or (``modified``) Craig DH chain; ``scale`` (m) sizes arcs and
    offsets (the robot's frame axis length).  Raises ValueError for a joint out of range."""
    n = len(frames) - 1
    if not 1 <= joint <= n:
        raise ValueError(f"annotate_joint: expected a joint number 1..{n}, got {joint}")
    f0, f1 = frames[joint - 1], frames[joint]
    o0, x0, z0 = f0[:3, 3], f0[:3, 0], f0[:3, 2]
    o1, x1, z1 = f1[:3, 3], f1[:3, 0], f1[:3, 2]
    offset, tick, radius = (gd.ANNOTATION_OFFSET_FRAC * scale, gd.ANNOTATION_TICK_FRAC * scale,
                            gd.ANNOTATION_ARC_FRAC * scale)
    out = Annotation()
    colors = gd.ANNOTATION_COLORS
    seg = dh_segments(frames[joint - 1:joint + 1], modified)  # the link's d and a, as drawn
    d, a, bend = float(seg.d[0]), float(seg.a[0]), seg.bend[0]
    if modified:
        i = joint - 1  # Craig's a and α carry the index of the frame they start from
        alpha, theta = signed_angle(z0, z1, x0), signed_angle(x0, x1, z1)
        _arc(out, o0, x0, z0, z1, radius, f"α{i} = {_shown(math.degrees(alpha), 1)}°", colors["alpha"])
        _dimension(out, o0, bend, _perpendicular(x0, -z0), offset, tick, f"a{i} = {_shown(a, 3)} m", colors["a"])
        _arc(out, bend, z1, x0, x1, radius, f"θ{joint} = {_shown(math.degrees(theta), 1)}°", colors["theta"])
        _dimension(out, bend, o1, _perpendicular(z1, -x1, -x0), offset, tick, f"d{joint} = {_shown(d, 3)} m", colors["d"])
        return out
    theta, alpha = signed_angle(x0, x1, z0), signed_angle(z0, z1, x1)
    _dimension(out, o0, bend, _perpendicular(z0, -x1, -x0), offset, tick, f"d{joint} = {_shown(d, 3)} m", colors["d"])
    _arc(out, bend, z0, x0, x1, radius, f"θ{joint} = {_shown(math.degrees(theta), 1)}°", colors["theta"])
    _dimension(out, bend, o1, _perpendicular(x1, (1.0 if d >= 0 else -1.0) * z0, z1), offset, tick,
               f"a{joint} = {_shown(a, 3)} m", colors["a"])
    _arc(out, o1, x1, z0, z1, radius, f"α{joint} = {_shown(math.degrees(alpha), 1)}°", colors["alpha"])
    return out
