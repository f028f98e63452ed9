"""A robot as text: ``print(robot)`` shows its DH table as the Robotics Toolbox does
(name, convention, one row a joint: θ, d, a, α, offset, limits; then base and tool).

Numbers are snapped first: a value within 1e-15 (relative, at least absolute) of a
number with ten decimals or fewer is written as that number, so an imported URDF's
tool offset of 2.5e-32 m reads 0 and 0.1 + 0.2 reads 0.3.  Angles are snapped in
radians, then written in degrees.  Lengths in metres.
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from robot_sim.transforms import HomogeneousTransform

#: Relative distance to a round number below which a value is that number.
SNAP_TOLERANCE = 1e-15
#: Decimals of the round numbers snapped to.
SNAP_DECIMALS = 10
#: Significant digits written.
DIGITS = 6


def snap(value: float) -> float:
    """``value``, or the round number (SNAP_DECIMALS decimals) it is within
    SNAP_TOLERANCE of; never -0.0."""
    value = float(value)
    if not math.isfinite(value):
        return value
    rounded = round(value, SNAP_DECIMALS)
    if abs(value - rounded) <= SNAP_TOLERANCE * max(1.0, abs(value)):
        value = rounded
    return value + 0.0


def number(value: float) -> str:
    """A snapped value with DIGITS significant digits ("inf", "-inf" when unbounded)."""
    value = snap(value)
    if not math.isfinite(value):
        return "inf" if value > 0 else ("-inf" if value < 0 else "nan")
    return f"{value:.{DIGITS}g}"


def degrees(radians: float) -> str:
    """An angle given in radians, snapped, written in degrees with a degree sign."""
    return number(math.degrees(snap(radians))) + "°"


def frame_text(tf: HomogeneousTransform) -> str:
    """``xyz [x, y, z] m, rpy [r, p, y] deg`` of a pose (snapped)."""
    roll, pitch, yaw = (number(math.degrees(snap(v))) for v in tf.rpy())
    return f"xyz [{', '.join(number(v) for v in tf.t())}] m, rpy [{roll}, {pitch}, {yaw}] deg"


def boxed(rows: Sequence[Sequence[str]]) -> str:
    """Rows (the first is the heading) in a box-drawn table, columns left-aligned."""
    widths = [max(len(row[c]) for row in rows) for c in range(len(rows[0]))]

    def line(left: str, mid: str, right: str) -> str:
        return left + mid.join("─" * (w + 2) for w in widths) + right

    def cells(row: Sequence[str]) -> str:
        return "│" + "│".join(f" {cell.ljust(w)} " for cell, w in zip(row, widths)) + "│"

    body = [cells(row) for row in rows[1:]]
    return "\n".join([line("┌", "┬", "┐"), cells(rows[0]), line("├", "┼", "┤"), *body, line("└", "┴", "┘")])


def dh_table(robot: object) -> str:
    """The DH table of ``robot`` (a RobotParams) as ``print(robot)`` shows it: a title
    line (name, joint count and types, convention), one row a joint (θ, d, a, α, offset,
    limits; the joint variable written qj), then base and tool poses."""
    modified = robot.convention == "modified"
    a_head, alpha_head = ("a(j-1)", "α(j-1)") if modified else ("a(j)", "α(j)")
    rows = [("j", "θ", "d", a_head, alpha_head, "offset", "limits")]
    letters = []
    for j in range(robot.n_dofs):
        revolute = bool(robot.is_revolute[j])
        letters.append("R" if revolute else "P")
        theta = f"q{j + 1}" if revolute else degrees(robot.dh_th[j])
        d = number(robot.dh_d[j]) if revolute else f"q{j + 1}"
        offset = degrees(robot.dh_th[j]) if revolute else number(robot.dh_d[j])
        lo, hi = robot.q_min[j], robot.q_max[j]
        if not (np.isfinite(lo) or np.isfinite(hi)):
            limits = "unlimited"
        elif revolute:
            limits = f"{degrees(lo)} .. {degrees(hi)}"
        else:
            limits = f"{number(lo)} .. {number(hi)} m"
        rows.append((str(j + 1), theta, d, number(robot.dh_a[j]), degrees(robot.dh_alpha[j]), offset, limits))
    title = (f"{robot.name}: {robot.n_dofs} joints ({''.join(letters)}), {robot.convention} DH"
             f" (lengths in m, angles in degrees)")
    return "\n".join([title, boxed(rows), f"base: {frame_text(robot.base_tf)}", f"tool: {frame_text(robot.tool_tf)}"])
