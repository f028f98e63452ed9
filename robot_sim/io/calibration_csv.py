"""Calibration measurements as CSV: :func:`load_calibration_data` and :func:`save_calibration_csv`.

The header names every column with its unit in brackets::

    q1 [deg], q2 [deg], ..., qn [deg], x [mm], y [mm], z [mm], qw, qx, qy, qz

``q1`` .. ``qn``: joint values, ``deg`` or ``rad`` for revolute joints, ``m`` or ``mm`` for
prismatic ones; ``x``, ``y``, ``z``: the measured tool point in the instrument's frame,
``m`` or ``mm``; ``qw, qx, qy, qz`` (optional, all four or none): the measured tool
orientation as a unit quaternion.  ``robot-sim calibration-poses`` writes the joint
columns only (the poses to measure).  Blank lines and lines starting with ``#`` are
skipped.  Errors name the file, the line, the column and the value (cut to 80 characters)
and say what is accepted; the number of rows is bounded before any array is allocated.
"""
from __future__ import annotations

import math
import os
import re
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.io.files import read_regular_file, write_atomic
from robot_sim.model.calibration_data import MAX_JOINTS, MAX_POSES, CalibrationData, CalibrationDataError
from robot_sim.model.messages import clip_repr
from robot_sim.transforms import quaternion_from_rot

#: Largest calibration CSV read [bytes].
MAX_BYTES = 64 * 1024 * 1024
ANGLE_UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
LENGTH_UNITS = {"m": 1.0, "mm": 1e-3}
QUATERNION = ("qw", "qx", "qy", "qz")
#: Largest accepted |norm − 1| of a measured quaternion.
QUATERNION_TOLERANCE = 1e-3
_COLUMN = re.compile(r"^(q[1-9][0-9]{0,2}|x|y|z)\s*\[(deg|rad|m|mm)\]$")
_ACCEPTED = ("q1 .. qn [deg|rad|m|mm], x [m|mm], y [m|mm], z [m|mm], then optionally qw, qx, qy, qz")


def _header(path: str, cells: list[str], line: int, measured: bool) -> tuple[int, dict[str, int], list[float], list[str]]:
    """(n joints, column of each name, SI scale of each column, joint unit kinds) of a header."""
    where: dict[str, int] = {}
    scale: list[float] = []
    for c, cell in enumerate(cells):
        text = cell.strip()
        match = _COLUMN.match(text)
        name = match.group(1) if match else text if text in QUATERNION else None
        if name is None:
            raise CalibrationDataError(f"{path} line {line}, column {c + 1}: unknown column {clip_repr(text)}; "
                                       f"accepted: {_ACCEPTED}")
        if name in where:
            raise CalibrationDataError(f"{path} line {line}, column {c + 1}: {name} appears twice")
        unit = match.group(2) if match else ""
        if name in ("x", "y", "z") and unit not in LENGTH_UNITS:
            raise CalibrationDataError(f"{path} line {line}, column {c + 1}: {name} [{unit}]: positions are in m or mm")
        where[name] = c
        scale.append(1.0 if not match else ANGLE_UNITS.get(unit) or LENGTH_UNITS[unit])
    joints = sorted(int(name[1:]) for name in where if name[0] == "q" and name[1:].isdigit())
    n = len(joints)
    if n == 0 or joints != list(range(1, n + 1)) or n > MAX_JOINTS:
        missing = next((f"q{i}" for i in range(1, n + 2) if i not in joints), "q1")
        raise CalibrationDataError(f"{path} line {line}: joint columns must be q1 .. qn (n <= {MAX_JOINTS}); "
                                   f"{missing} is missing")
    wanted = ("x", "y", "z") if measured else ()
    missing = [name for name in wanted if name not in where]
    quaternion = [name for name in QUATERNION if name in where]
    if quaternion and len(quaternion) < 4:
        missing += [name for name in QUATERNION if name not in where]
    if quaternion and not measured or missing:
        what = ", ".join(missing) if missing else "measured columns"
        raise CalibrationDataError(f"{path} line {line}: missing column(s) {what}; expected {_ACCEPTED}")
    kinds = ["angle" if _COLUMN.match(cells[where[f"q{j}"]].strip()).group(2) in ANGLE_UNITS else "length"
             for j in range(1, n + 1)]
    return n, where, scale, kinds


def _rows(path: str, max_bytes: int) -> tuple[list[tuple[int, list[str]]], int, list[str]]:
    """(line number, cells) of each data row, the header's line and its cells."""
    raw = read_regular_file(path, max_bytes)
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise CalibrationDataError(f"{path}: not UTF-8 text (byte {exc.start})") from None
    lines = [(k + 1, s) for k, s in enumerate(text.splitlines()) if s.strip() and not s.lstrip().startswith("#")]
    if not lines:
        raise CalibrationDataError(f"{path}: no header line; expected {_ACCEPTED}")
    if len(lines) - 1 > MAX_POSES:
        raise CalibrationDataError(f"{path}: {len(lines) - 1} rows; at most {MAX_POSES} poses are accepted")
    (head_line, head), body = lines[0], lines[1:]
    return [(k, s.split(",")) for k, s in body], head_line, head.split(",")


def _numbers(path: str, rows: list[tuple[int, list[str]]], names: list[str]) -> NDArray[np.float64]:
    """The rows' values (N, columns) as floats; an error names line, column and value."""
    out = np.empty((len(rows), len(names)))
    for i, (line, cells) in enumerate(rows):
        if len(cells) != len(names):
            raise CalibrationDataError(f"{path} line {line}: expected {len(names)} values, got {len(cells)}")
        for c, cell in enumerate(cells):
            try:
                value = float(cell)
            except ValueError:
                raise CalibrationDataError(f"{path} line {line}, column {names[c]}: expected a number, "
                                           f"got {clip_repr(cell.strip())}") from None
            if not math.isfinite(value):
                raise CalibrationDataError(f"{path} line {line}, column {names[c]}: expected a finite number, "
                                           f"got {clip_repr(cell.strip())}")
            out[i, c] = value
    return out


def _rotations(quaternions: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation matrices (N, 3, 3) of unit quaternions (N, 4) (w, x, y, z)."""
    w, x, y, z = quaternions.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
    ], axis=1)


def load_calibration_data(path: str | os.PathLike[str], max_bytes: int = MAX_BYTES) -> CalibrationData:
    """Measurements from a CSV file (module docstring), in SI units.  Raises
    CalibrationDataError (a ValueError) naming file, line, column and value for a bad
    header (unknown, repeated or missing columns, wrong units), rows of the wrong length,
    values that are not finite numbers or quaternions that are not of unit length;
    FileReadError when the file cannot be read or exceeds ``max_bytes``."""
    shown = os.fspath(path)
    rows, head_line, head = _rows(shown, max_bytes)
    n, where, scale, kinds = _header(shown, head, head_line, measured=True)
    if not rows:
        raise CalibrationDataError(f"{shown}: no measurements after the header")
    names = [""] * len(head)
    for name, c in where.items():
        names[c] = name
    values = _numbers(shown, rows, names) * np.array(scale)
    q = values[:, [where[f"q{j}"] for j in range(1, n + 1)]]
    positions = values[:, [where[k] for k in ("x", "y", "z")]]
    lines = np.array([line for line, _ in rows])
    if "qw" not in where:
        return CalibrationData(q, positions=positions, source=shown, lines=lines, joint_units=tuple(kinds))
    quats = values[:, [where[k] for k in QUATERNION]]
    norms = np.linalg.norm(quats, axis=1)
    bad = np.abs(norms - 1.0) > QUATERNION_TOLERANCE
    if bad.any():
        i = int(np.argmax(bad))
        raise CalibrationDataError(f"{shown} line {lines[i]}: qw, qx, qy, qz must be a unit quaternion "
                                   f"(norm within {QUATERNION_TOLERANCE:g} of 1), got norm {norms[i]:.6g}")
    poses = np.zeros((len(q), 4, 4))
    poses[:, :3, :3] = _rotations(quats / norms[:, None])
    poses[:, :3, 3] = positions
    poses[:, 3, 3] = 1.0
    return CalibrationData(q, poses=poses, source=shown, lines=lines, joint_units=tuple(kinds))


def calibration_csv_text(q: ArrayLike, revolute: ArrayLike, positions: ArrayLike | None = None,
                         poses: ArrayLike | None = None) -> str:
    """CSV text of joint values q (N, n) [rad, m] (degrees for the ``revolute`` (n,) joints,
    millimetres for the others) and, when given, measured positions (N, 3) [m] or poses
    (N, 4, 4), written in mm and as quaternions; numbers round-trip exactly."""
    Q = np.asarray(q, dtype=float)
    rev = np.asarray(revolute, dtype=bool)
    header = [f"q{j + 1} [{'deg' if rev[j] else 'mm'}]" for j in range(Q.shape[1])]
    columns = [np.where(rev, np.degrees(Q), Q * 1e3)]
    if poses is not None:
        P = np.asarray(poses, dtype=float)
        positions = P[:, :3, 3]
    if positions is not None:
        header += ["x [mm]", "y [mm]", "z [mm]"]
        columns.append(np.asarray(positions, dtype=float) * 1e3)
    if poses is not None:
        header += list(QUATERNION)
        columns.append(np.array([quaternion_from_rot(R) for R in P[:, :3, :3]]))
    table = np.hstack(columns)
    return "\n".join([", ".join(header)] + [", ".join(repr(float(v)) for v in row) for row in table]) + "\n"


def save_calibration_csv(path: str | os.PathLike[str], q: ArrayLike, revolute: ArrayLike,
                         positions: ArrayLike | None = None, poses: ArrayLike | None = None) -> None:
    """Write :func:`calibration_csv_text` to ``path`` atomically (FileWriteError naming it)."""
    write_atomic(Path(path), calibration_csv_text(q, revolute, positions, poses))
