"""The DH table shown (and edited) in the window's dock, without Qt.

One row per joint, columns :data:`COLUMNS`.  θ and d show the *current* DH values: for a
revolute joint θ = offset + q and d is a constant, for a prismatic joint d = offset + q
and θ is a constant; the cell holding the joint variable is read-only (sliders and boxes
move joints) and ``offset`` is the file's constant part of it (``theta`` of a revolute
joint, ``d`` of a prismatic one).  Angles are shown and typed in degrees, lengths in
metres.  An edit becomes a new :class:`~robot_sim.model.params.RobotParams` through
:func:`robot_sim.io.robot_writer.with_dh_value`, so a value is accepted exactly when the saved file
would load; otherwise :class:`ValueError` carries the reason to show in place.
"""
from __future__ import annotations

import math
import re
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robot_sim.model.params import JTYPE_NAMES, JTYPE_PRISMATIC, RobotParams
from robot_sim.io.robot_writer import with_dh_value

#: Column keys, in order, and their headers.
COLUMNS = ("type", "theta", "d", "a", "alpha", "offset", "limits", "home")
HEADERS = ("type", "θ", "d [m]", "a [m]", "α [°]", "offset", "limits", "home")
#: Column names in messages.
NAMES = ("type", "θ", "d", "a", "α", "offset", "limits", "home")
_ABBREVIATIONS = {"r": "revolute", "p": "prismatic"}
_UNLIMITED = ("", "none", "unlimited", "-")
_NUMBER_FORMAT = "{:.10g}"


def _is_prismatic(robot: RobotParams, row: int) -> bool:
    return int(robot.jtype[row]) == JTYPE_PRISMATIC


def variable_column(robot: RobotParams, row: int) -> str:
    """The column holding joint ``row``'s variable: ``"d"`` if prismatic, else ``"theta"``."""
    return "d" if _is_prismatic(robot, row) else "theta"


def _field_of(robot: RobotParams, row: int, column: str) -> str:
    """The robot file key a cell edits (``offset`` is theta or d by joint type)."""
    if column == "offset":
        return variable_column(robot, row)
    return column


def _q_unit(robot: RobotParams, row: int) -> tuple[float, str]:
    """(SI per display unit, unit suffix) of joint ``row``'s variable."""
    return (1.0, " m") if _is_prismatic(robot, row) else (math.pi / 180.0, "°")


def _number(value: float) -> str:
    return _NUMBER_FORMAT.format(value + 0.0)


def is_editable(robot: RobotParams, row: int, column: str) -> bool:
    """False only for the cell showing the joint variable (θ or d)."""
    return column != variable_column(robot, row)


def cell_text(robot: RobotParams, q: NDArray[np.float64], row: int, column: str) -> str:
    """Text of one cell for joint ``row`` at joint values ``q`` (SI, (n,))."""
    scale, unit = _q_unit(robot, row)
    if column == "type":
        return "prismatic" if _is_prismatic(robot, row) else "revolute"
    if column == variable_column(robot, row):  # offset + q, to the joint panel's precision
        if _is_prismatic(robot, row):
            return f"{robot.dh_d[row] + q[row]:.4f} (q{row + 1})"
        return f"{math.degrees(robot.dh_th[row] + q[row]) + 0.0:.2f} (q{row + 1})"
    if column == "theta":
        return _number(math.degrees(robot.dh_th[row]))
    if column == "d":
        return _number(robot.dh_d[row])
    if column == "a":
        return _number(robot.dh_a[row])
    if column == "alpha":
        return _number(math.degrees(robot.dh_alpha[row]))
    if column == "offset":
        offset = robot.dh_d[row] if _is_prismatic(robot, row) else math.degrees(robot.dh_th[row])
        return _number(offset) + unit
    if column == "limits":
        lo, hi = robot.q_min[row], robot.q_max[row]
        if not (math.isfinite(lo) or math.isfinite(hi)):
            return "unlimited"
        return f"{_number(lo / scale)} .. {_number(hi / scale)}{unit}"
    if column == "home":
        return _number(robot.q_home[row] / scale) + unit
    raise ValueError(f"column must be one of {', '.join(COLUMNS)}, got {column!r}")


def _parse_number(text: str) -> float:
    cleaned = re.sub(r"\s*(°|deg|m)$", "", text.strip())
    try:
        value = float(cleaned)
    except ValueError:
        raise ValueError(f"'{text.strip()}' is not a number") from None
    if not math.isfinite(value):
        raise ValueError(f"'{text.strip()}' is not a finite number")
    return value


def _parse_limits(text: str, scale: float) -> tuple[float, float] | None:
    stripped = text.strip()
    if stripped.lower() in _UNLIMITED:
        return None
    parts = [p for p in re.split(r"\s*(?:\.\.|,|;|\s)\s*", re.sub(r"\s*(°|deg|m)$", "", stripped)) if p]
    if len(parts) != 2:
        raise ValueError(f"expected 'min .. max' or 'unlimited', got '{stripped}'")
    lo, hi = (_parse_number(p) for p in parts)
    return lo * scale, hi * scale


def edit_cell(robot: RobotParams, row: int, column: str, text: str) -> RobotParams:
    """The robot with cell (``row``, ``column``) set from the typed ``text`` (display units).

    ValueError ``"joint N COLUMN: reason"`` for a read-only cell, text that is not a value
    of the column, or a value the robot file would refuse (see
    :func:`robot_sim.io.robot_writer.with_dh_value`; limits and home in the file's units).
    """
    if column not in COLUMNS:
        raise ValueError(f"column must be one of {', '.join(COLUMNS)}, got {column!r}")
    try:
        return _edited(robot, row, column, text)
    except ValueError as exc:
        reason = re.sub(r"^(joints\[\d+\]\.)?\w+: ", "", str(exc))
        raise ValueError(f"joint {row + 1} {NAMES[COLUMNS.index(column)]}: {reason}") from None


def _edited(robot: RobotParams, row: int, column: str, text: str) -> RobotParams:
    if not is_editable(robot, row, column):
        raise ValueError("it is the joint variable: move it with the slider or type it in the joint box")
    field = _field_of(robot, row, column)
    scale, _ = _q_unit(robot, row)
    value: Any
    if column == "type":
        value = _ABBREVIATIONS.get(text.strip().lower(), text.strip().lower())
        if value not in JTYPE_NAMES:
            raise ValueError(f"expected 'revolute' (R) or 'prismatic' (P), got '{text.strip()}'")
    elif column == "limits":
        value = _parse_limits(text, scale)
    elif column == "home":
        value = _parse_number(text) * scale
    elif field in ("theta", "alpha"):
        value = math.radians(_parse_number(text))
    else:
        value = _parse_number(text)
    return with_dh_value(robot, row, field, value)


def carry_joint_values(old: RobotParams, q: NDArray[np.float64], new: RobotParams) -> NDArray[np.float64]:
    """Joint values (n,) for ``new`` after it replaced ``old`` at ``q`` (SI): ``q`` kept
    where the number of joints and the joint's type are unchanged (clipped into the new
    limits), home elsewhere."""
    if new.n_dofs != old.n_dofs:
        return np.array(new.q_home)
    kept = np.clip(np.asarray(q, dtype=float), new.q_min, new.q_max)
    return np.where(new.jtype == old.jtype, kept, new.q_home)
