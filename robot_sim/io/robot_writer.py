"""Writing robots back to TOML files, and validated edits of one DH value.

:func:`to_toml` turns a :class:`~robot_sim.model.params.RobotParams` into the text of a robot file that
:func:`~robot_sim.model.params.load_robot` loads back to the same arrays.  Given a *template* (the text
of the file the robot came from) it edits that document in place with tomlkit, a
style-preserving TOML library: comments, source citations, key order, blank lines and the
file's units stay as they were, and only values that no longer load to the robot's value
are rewritten.  :func:`with_dh_value` applies one edit the way the DH table dock does: it
writes the value into the robot's document and loads it through the loader, so an edit is
accepted exactly when the saved file would load.

Values are SI inside (metres, radians); a file in ``units = "deg"`` gets degrees for α, θ,
revolute home and limits and base/tool rpy.  Numbers are written with the fewest digits
that load back to the identical float where such a decimal exists.
"""
from __future__ import annotations

import dataclasses
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
import tomlkit
from tomlkit.items import AoT

from robot_sim.io.files import read_regular_file, write_atomic
from robot_sim.model.inertials import DRIVE_DEFAULTS
from robot_sim.model.params import (
    CONVENTION_STANDARD,
    DEFAULT_COM_FRACTION,
    JTYPE_NAMES,
    JTYPE_REVOLUTE,
    RobotDefinitionError,
    RobotParams,
)
from robot_sim.io.robot_file import ANGLE_BOUNDS, MAX_FILE_BYTES, UNITS, parse_robot
from robot_sim.io.shape_tables import GEOMETRY_KEYS, sync_shape_tables
from robot_sim.transforms import HomogeneousTransform, rpy_from_rot

#: Fields :func:`with_dh_value` edits (the keys of a ``[[joints]]`` table).
EDITABLE_FIELDS = ("type", "theta", "d", "a", "alpha", "home", "limits", "com")
_TYPE_NAMES = {code: name for name, code in JTYPE_NAMES.items()}
_DEFAULT_UNITS = "deg"


def file_number(value: float, scale: float) -> float:
    """The number to write for the SI ``value`` in a file unit worth ``scale`` SI units.

    Returns the float with the shortest decimal form whose product with ``scale`` is exactly
    ``value`` (``90.0`` for π/2 in degrees), or the nearest one when none exists.
    """
    if scale == 1.0 or value == 0.0:
        return float(value) + 0.0  # no "-0.0" in files
    nearest = value / scale
    for digits in range(1, 18):
        candidate = float(f"{nearest:.{digits}g}")
        if candidate * scale == value:
            return candidate
    return nearest


def _loads_to(doc_value: Any, scale: float, value: float) -> bool:
    """True if a number read from the file loads (times ``scale``) exactly to ``value``."""
    return (
        isinstance(doc_value, (int, float))
        and not isinstance(doc_value, bool)
        and float(doc_value) * scale == value
    )


def _set_number(table: Any, key: str, value: float, scale: float) -> None:
    if not _loads_to(table.get(key), scale, value):
        table[key] = file_number(value, scale)


def _set_optional(table: Any, key: str, value: float, scale: float, default: float) -> None:
    """Write ``key`` unless it is absent and ``value`` is the loader's default."""
    if key not in table and value == default:
        return
    _set_number(table, key, value, scale)


def _set_limits(table: Any, lo: float, hi: float, scale: float, where: str) -> None:
    if math.isinf(lo) and math.isinf(hi) and lo < 0 < hi:
        if "limits" in table:
            del table["limits"]
        return
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ValueError(
            f"{where}.limits: a robot file holds two finite limits or none, got [{lo}, {hi}]"
        )
    current = table.get("limits")
    if isinstance(current, list) and len(current) == 2 and all(
        _loads_to(c, scale, v) for c, v in zip(current, (lo, hi))
    ):
        return
    table["limits"] = [file_number(lo, scale), file_number(hi, scale)]


def _frame_loads_to(table: Any, scale: float, tf: HomogeneousTransform) -> bool:
    try:
        xyz = [float(v) for v in table.get("xyz", [0.0, 0.0, 0.0])]
        rpy = [float(v) * scale for v in table.get("rpy", [0.0, 0.0, 0.0])]
        return bool(np.array_equal(HomogeneousTransform.from_xyz_rpy(xyz, rpy).mat, tf.mat))
    except (TypeError, ValueError, AttributeError):
        return False


def _set_frame(doc: Any, key: str, tf: HomogeneousTransform, scale: float) -> None:
    """Write ``xyz`` and ``rpy`` of the ``[base]`` or ``[tool]`` table for ``tf``; for the
    identity remove them, and the table too unless it holds geometry."""
    if key in doc and _frame_loads_to(doc[key], scale, tf):
        return
    table = doc[key] if key in doc else tomlkit.table()
    if np.array_equal(tf.mat, np.eye(4)):
        for field in ("xyz", "rpy"):
            table.pop(field, None)
        if key in doc and not any(field in table for field in GEOMETRY_KEYS):
            del doc[key]
        return
    table["xyz"] = [float(v) for v in tf.t()]
    table["rpy"] = [file_number(v, scale) for v in rpy_from_rot(tf.R())]
    doc[key] = table


def _sync_joint(table: Any, robot: RobotParams, i: int, to_rad: float, place: "_Place") -> None:
    where = f"joints[{i}]"
    jtype = int(robot.jtype[i])
    if table.get("type") != _TYPE_NAMES[jtype]:
        table["type"] = _TYPE_NAMES[jtype]
    q_scale = to_rad if jtype == JTYPE_REVOLUTE else 1.0
    _set_number(table, "a", float(robot.dh_a[i]), 1.0)
    _set_number(table, "alpha", float(robot.dh_alpha[i]), to_rad)
    _set_number(table, "d", float(robot.dh_d[i]), 1.0)
    _set_number(table, "theta", float(robot.dh_th[i]), to_rad)
    _set_optional(table, "home", float(robot.q_home[i]), q_scale, 0.0)
    _set_limits(table, float(robot.q_min[i]), float(robot.q_max[i]), q_scale, where)
    _set_optional(table, "com", float(robot.link_com_frac[i]), 1.0, DEFAULT_COM_FRACTION)
    _sync_mass_properties(table, robot, i)
    place.sync(table, {"visual": robot.visuals[i], "collision": robot.collisions[i]})


@dataclasses.dataclass(frozen=True)
class _Place:
    """Where a document's mesh paths point: written relative to ``directory`` (absolute
    when None), read from ``template_dir`` (the template's folder), angles in ``units``."""

    directory: Path | None
    template_dir: Path
    units: str

    def sync(self, table: Any, shapes: dict[str, tuple]) -> None:
        sync_shape_tables(table, shapes, self.directory, self.template_dir, UNITS[self.units],
                          ANGLE_BOUNDS[self.units], file_number)


def _set_vector(table: Any, key: str, values: Any) -> None:
    current = table.get(key)
    if isinstance(current, list) and len(current) == len(values) and all(
        _loads_to(c, 1.0, float(v)) for c, v in zip(current, values)
    ):
        return
    table[key] = [float(v) + 0.0 for v in values]


def _sub_table(table: Any, key: str, keep: bool) -> Any:
    """The joint's ``[joints.KEY]`` table (created when missing), or None after removing it."""
    if not keep:
        if key in table:
            del table[key]
        return None
    if key not in table:
        table[key] = tomlkit.table()
    return table[key]


def _sync_mass_properties(table: Any, robot: RobotParams, i: int) -> None:
    """``[joints.inertial]`` and ``[joints.drive]`` of joint i from the robot's data; an
    estimate (``inertials.estimated``) is not written, so a file stays without data."""
    li = robot.inertials
    inertial = _sub_table(table, "inertial", li is not None and not li.estimated)
    if inertial is not None:
        inertia = li.inertia[i]
        _set_number(inertial, "mass", float(li.mass[i]), 1.0)
        _set_vector(inertial, "com", li.com[i])
        _set_vector(inertial, "inertia", [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[1, 2], inertia[0, 2]])
    dr = robot.drives
    drive = _sub_table(table, "drive", dr is not None and (
        "drive" in table or dr.coulomb[i].any() or any(
            getattr(dr, key)[i] != default for key, default in DRIVE_DEFAULTS.items()
        )
    ))
    if drive is None:
        return
    for key, default in DRIVE_DEFAULTS.items():
        value = float(getattr(dr, key)[i])
        if math.isinf(value) or (key not in drive and value == default):
            if key in drive:
                del drive[key]
            continue
        _set_number(drive, key, value, 1.0)
    if "coulomb" in drive or dr.coulomb[i].any():
        _set_vector(drive, "coulomb", dr.coulomb[i])


def _sync_joints(doc: Any, robot: RobotParams, to_rad: float, place: _Place) -> None:
    joints = doc.get("joints")
    if not isinstance(joints, AoT):
        joints = tomlkit.aot()
        doc["joints"] = joints
    while len(joints) > robot.n_dofs:
        del joints[-1]
    while len(joints) < robot.n_dofs:
        joints.append(tomlkit.table())
        joints[-1].trivia.indent = "\n"
    for i in range(robot.n_dofs):
        _sync_joint(joints[i], robot, i, to_rad, place)


def robot_document(
    robot: RobotParams, template: str | None = None, directory: str | os.PathLike[str] | None = None
) -> tomlkit.TOMLDocument:
    """The tomlkit document of ``robot``: ``template`` parsed and brought up to date, or a
    new document in degrees.  Mesh paths are written relative to ``directory`` (the folder
    the file goes to; absolute when None); the template's own paths are read from that
    folder, or from the robot's source's when None.  ValueError for a robot no file can
    hold (one-sided limits, a mesh without a file)."""
    if template is None:
        doc = tomlkit.document()
        origin = Path(robot.source).name if robot.source else "a robot built in code"
        doc.add(tomlkit.comment(f"Written by robot-sim from {origin}"))
    else:
        doc = tomlkit.parse(template)
    if doc.get("name") != robot.name:
        doc["name"] = robot.name
    if robot.description or "description" in doc:
        if doc.get("description") != robot.description:
            doc["description"] = robot.description
    if doc.get("units") not in UNITS:
        doc["units"] = _DEFAULT_UNITS
    to_rad = UNITS[doc["units"]]
    if doc.get("convention", CONVENTION_STANDARD) != robot.convention:
        doc["convention"] = robot.convention
    folder = None if directory is None else Path(os.path.abspath(directory))
    place = _Place(folder, folder or Path(os.path.abspath(robot.source or ".")).parent, doc["units"])
    _sync_joints(doc, robot, to_rad, place)
    base_shapes = {"visual": robot.base_visuals, "collision": robot.base_collisions}
    if any(base_shapes.values()) and "base" not in doc:
        doc["base"] = tomlkit.table()
    if "base" in doc:
        place.sync(doc["base"], base_shapes)
    _set_frame(doc, "base", robot.base_tf, to_rad)
    _set_frame(doc, "tool", robot.tool_tf, to_rad)
    _set_collision(doc, robot)
    return doc


def _set_collision(doc: Any, robot: RobotParams) -> None:
    """The ``[collision] allow`` pairs of ``robot`` (the table removed when it has none)."""
    pairs = [list(pair) for pair in robot.collision_allow]
    table = doc.get("collision")
    current = table.get("allow", []) if isinstance(table, dict) else None
    if current is not None and [list(p) for p in current] == pairs:
        return
    if not pairs:
        if "collision" in doc:
            del doc["collision"]
        return
    if not isinstance(table, dict):
        doc["collision"] = tomlkit.table()
    doc["collision"]["allow"] = pairs


def to_toml(robot: RobotParams, template: str | None = None, directory: str | os.PathLike[str] | None = None) -> str:
    """Text of a robot file that loads back to ``robot``.

    With ``template`` (the original file's text) only the values that changed are
    rewritten; comments, citations and layout are kept.  Without it, a new file in degrees.
    Mesh paths are relative to ``directory``, the folder the file is written to (absolute
    when None).  The robot's ``notes`` become comment lines after the file's opening
    comments (each once).
    """
    text = tomlkit.dumps(robot_document(robot, template, directory))
    lines = text.splitlines(keepends=True)
    new = [f"# {' '.join(note.split())}\n" for note in robot.notes]
    new = [line for line in new if line not in lines]
    top = next((k for k, line in enumerate(lines) if not line.startswith("#")), len(lines))
    return "".join(lines[:top] + new + lines[top:])


def save_robot(robot: RobotParams, path: str | os.PathLike[str], template: str | None = None) -> None:
    """Write ``robot`` to ``path`` atomically (:func:`robot_sim.io.files.write_atomic`), style-preserving
    with ``template``, by default the text of the TOML file the robot was loaded from (its
    comments kept), mesh paths relative to the file's folder.  FileWriteError (an OSError)
    naming the path and the reason."""
    if template is None and robot.source.endswith(".toml") and Path(robot.source).is_file():
        template = read_regular_file(robot.source, MAX_FILE_BYTES).decode("utf-8-sig")
    write_atomic(path, to_toml(robot, template, Path(path).parent))


def _in_file_units(field: str, value: Any, jtype: int, to_rad: float) -> Any:
    if field == "type":
        return value
    if field in ("a", "d", "com"):
        return file_number(_finite(field, value), 1.0)
    scale = to_rad if field in ("alpha", "theta") or jtype == JTYPE_REVOLUTE else 1.0
    if field == "limits":
        if value is None:
            return None
        lo, hi = value
        return [file_number(_finite("limits", lo), scale), file_number(_finite("limits", hi), scale)]
    return file_number(_finite(field, value), scale)


def _finite(field: str, value: Any) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{field}: expected a number, got {value!r}") from None
    if not math.isfinite(number):
        raise ValueError(f"{field}: expected a finite number, got {value!r}")
    return number


def with_dh_value(robot: RobotParams, joint: int, field: str, value: Any) -> RobotParams:
    """A new robot equal to ``robot`` but with one value of joint ``joint`` (0-based) changed.

    ``field`` is a key of a ``[[joints]]`` table: ``"a"``, ``"d"`` (metres), ``"alpha"``,
    ``"theta"`` (radians), ``"home"`` (radians or metres), ``"limits"`` (a pair, radians or
    metres, or None for unlimited), ``"com"`` (fraction of the link) or ``"type"``
    (``"revolute"`` / ``"prismatic"``; changing it resets home to 0 and removes the limits,
    whose unit changes).  The edit goes through the loader, so it is accepted exactly when
    the saved file would load; otherwise ValueError with the loader's reason, e.g.
    ``joints[1].limits: min 10.0 > max -5.0`` (values in the file's units).
    """
    if not isinstance(joint, (int, np.integer)) or not 0 <= joint < robot.n_dofs:
        raise ValueError(f"joint must be an index in 0..{robot.n_dofs - 1}, got {joint!r}")
    if field not in EDITABLE_FIELDS:
        raise ValueError(f"field must be one of {', '.join(EDITABLE_FIELDS)}, got {field!r}")
    if field == "type" and value not in JTYPE_NAMES:
        raise ValueError(f"type: expected 'revolute' or 'prismatic', got {value!r}")
    doc = robot_document(robot)
    table = doc["joints"][joint]
    new_value = _in_file_units(field, value, int(robot.jtype[joint]), UNITS[doc["units"]])
    if field == "type":
        table.pop("home", None)
        table.pop("limits", None)
    if new_value is None:
        table.pop(field, None)
    else:
        table[field] = new_value
    where = Path(robot.source or "edit")
    try:
        edited = parse_robot(doc.unwrap(), where)
    except RobotDefinitionError as exc:
        raise ValueError(str(exc).removeprefix(f"{where}: ")) from None
    return dataclasses.replace(edited, source=robot.source)
