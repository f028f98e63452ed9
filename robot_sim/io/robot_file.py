"""Robot files: the loader and validator of ``robots/NAME.toml`` (and the dispatch to URDF).

A robot file is data, parsed with the standard library's ``tomllib`` (never executed).
Every value is validated before a :class:`RobotParams` is built, so a bad file raises
:class:`RobotDefinitionError` naming the file, the field, the value and what is accepted,
and nothing is half-loaded.  See docs/robot-files.md for the file format.
"""
from __future__ import annotations

import codecs
import errno
import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

from robot_sim.model.arrays import frozen
from robot_sim.io.checker import LENGTH_BOUND, MAX_JOINTS, MAX_LENGTH, Bound, FieldChecker
from robot_sim.io.files import FileReadError, read_regular_file
from robot_sim.io.inertial_tables import parse_joint_tables
from robot_sim.io.meshes import MeshReader
from robot_sim.io.shape_tables import GEOMETRY_KEYS, ShapeTables
from robot_sim.io.robot_kind import ACCEPTED, SUFFIX_KINDS, robot_kind
from robot_sim.io.toml_depth import MAX_TOML_DEPTH, nesting_too_deep
from robot_sim.model.messages import clip, clip_middle, clip_repr
from robot_sim.model.params import (
    CONVENTION_STANDARD,
    CONVENTIONS,
    DEFAULT_COM_FRACTION,
    JTYPE_NAMES,
    JTYPE_REVOLUTE,
    RobotDefinitionError,
    RobotParams,
    link_names,
)
from robot_sim.transforms import HomogeneousTransform

def _robots_dir() -> Path:
    """The shipped robot files: ``robot_sim/robots`` in an installed wheel (package data), the
    checkout's top-level ``robots/`` when run from a source tree."""
    package = Path(__file__).resolve().parent.parent
    installed = package / "robots"
    return installed if installed.is_dir() else package.parent / "robots"


#: Directory holding the shipped robot files.
ROBOTS_DIR = _robots_dir()

UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
TOP_KEYS = {"name", "description", "units", "convention", "joints", "base", "tool", "control", "collision",
            "balance_inertia"}
REQUIRED_TOP_KEYS = ("name", "units", "joints")
JOINT_KEYS = {"type", "a", "alpha", "d", "theta", "home", "limits", "com", "inertial", "drive", *GEOMETRY_KEYS}
DH_KEYS = ("a", "alpha", "d", "theta")
#: Keys of the optional top-level ``[control]`` table (gains of robot_sim/control/controllers.py): ``bandwidth``
#: closed-loop natural frequency in Hz (> 0), ``damping`` ratio (> 0), ``kp`` and ``kd``
#: per-joint PD gains (n numbers ≥ 0; N·m/rad and N·m·s/rad, or N/m and N·s/m).
CONTROL_KEYS = {"bandwidth", "damping", "kp", "kd"}
#: Keys of the optional ``[collision]`` table: ``allow``, pairs of link names ("base",
#: "link1" .. "linkN") never checked for collision, e.g. ``allow = [["link2", "link4"]]``.
COLLISION_KEYS = {"allow"}

# Bounds of a robot file (README, "Robot file format").  With at most MAX_JOINTS joints,
# lengths within ±MAX_LENGTH and angles within ±MAX_ANGLE_DEG, forward kinematics is
# finite everywhere inside the limits and every slider range fits a Qt slider's int range.
MAX_ANGLE_DEG = 1800.0  # deg (5 turns): alpha, theta, base and tool rpy, revolute home and limits
MAX_FILE_BYTES = 1 << 20
MAX_NAME_CHARS = 200



def available_robots() -> list[str]:
    """Names of the robots shipped in ``robots/`` (sorted)."""
    return sorted(p.stem for p in ROBOTS_DIR.glob("*.toml"))


def resolve_robot_path(name_or_path: str | Path) -> Path:
    """Path of a robot description given a shipped robot's name or a path to a robot
    file, a URDF or a xacro file (any name: :func:`robot_sim.io.robot_kind.robot_kind`).

    Raises RobotDefinitionError for a name that is neither a shipped robot nor an
    existing file, saying what is accepted and listing the shipped robots.
    """
    text = str(name_or_path)
    if text in available_robots():
        return ROBOTS_DIR / f"{text}.toml"
    if Path(text).suffix.lower() in SUFFIX_KINDS or "/" in text or "\\" in text or Path(text).exists():
        return Path(text)  # checked when read, so every reason is reported as it is
    raise RobotDefinitionError(
        f"unknown robot {clip_repr(text)}: no such file and no shipped robot of that name; accepted: "
        f"{ACCEPTED}; available robots: {', '.join(available_robots())}"
    )


def _read_text(path: Path, what: str, error: type[ValueError]) -> str:
    """The text of ``what`` (e.g. "robot file") at ``path``: a regular file of at most
    MAX_FILE_BYTES, UTF-8 (a leading byte-order mark is dropped).  ``error`` starting
    with the path otherwise."""
    try:
        raw = read_regular_file(path, MAX_FILE_BYTES)
    except FileReadError as exc:
        reason = f"{what} not found" if exc.errno == errno.ENOENT else f"cannot read {what}: {exc.reason}"
        raise error(f"{path}: {reason}") from None
    body = raw.removeprefix(codecs.BOM_UTF8)
    try:
        return body.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = body.count(b"\n", 0, exc.start) + 1
        column = exc.start - body.rfind(b"\n", 0, exc.start)
        raise error(
            f"{path}: not UTF-8 text: byte 0x{body[exc.start]:02x} at line {line}, column {column}; "
            "save the file as UTF-8"
        ) from None


def load_robot(
    name_or_path: str | Path, tip: str | None = None, convention: str | None = None,
    skip_missing_meshes: bool = False, xacro_args: dict[str, str] | None = None,
) -> RobotParams:
    """Load and validate a robot by shipped name (``"puma560"``), robot-file path, URDF
    path or xacro path (any suffix: an XML file with a ``<robot>`` root is a URDF).

    A xacro file is expanded with the ``xacro`` package (optional: ``pip install xacro``)
    and ``xacro_args`` (``{"name": "value"}``, as ``xacro FILE name:=value``), then read
    as a URDF (:mod:`robot_sim.io.xacro_file`).

    A URDF becomes a DH robot (``urdf.load_urdf``): the chain from the root link to
    ``tip`` (needed when the tree branches), in ``convention`` (standard by default).  A
    TOML robot keeps its file's convention unless ``convention`` names the other one, to
    which it is converted exactly (``robot_sim.model.convert``).  ``tip`` applies to URDF files only.
    Mesh files are read with the robot: one that cannot be found or read is an error, or,
    with ``skip_missing_meshes``, a :class:`~robot_sim.io.meshes.MeshSkippedWarning` (once
    per file) and a robot without that mesh.
    """
    if convention is not None and convention not in CONVENTIONS:
        raise ValueError(f"convention must be 'standard' or 'modified', got {convention!r}")
    path = resolve_robot_path(name_or_path)
    kind = robot_kind(path)
    if xacro_args and kind != "xacro":
        raise ValueError(f"xacro_args apply to xacro files only; {clip_middle(str(path))} is a {kind} file")
    if kind in ("urdf", "xacro"):
        from robot_sim.io.urdf_in import load_urdf  # urdf builds on this module

        contents = None
        if kind == "xacro":
            from robot_sim.io.xacro_file import expand_xacro  # optional: needs the xacro package

            contents = expand_xacro(path, xacro_args)
        robot = load_urdf(path, tip=tip, convention=convention or CONVENTION_STANDARD,
                          skip_missing_meshes=skip_missing_meshes, contents=contents)
        check_bounds(robot, path)
        return robot
    if tip is not None:
        raise ValueError(f"tip applies to URDF files only; {path} is a robot file")
    robot = _parse_robot(read_toml(path), path, skip_missing_meshes)
    if convention is None:
        return robot
    from robot_sim.model.convert import to_convention  # robot_sim.model.convert builds on this module

    return to_convention(robot, convention)


def check_bounds(robot: RobotParams, path: Path | str) -> None:
    """RobotDefinitionError starting with ``path`` unless ``robot`` keeps the bounds of a
    robot file (MAX_JOINTS joints; lengths, prismatic limits and base and tool offsets
    within ±MAX_LENGTH; revolute limits within ±MAX_ANGLE_DEG).  For robots built from
    other sources (URDF), whose values the TOML checks never saw."""
    if robot.n_dofs > MAX_JOINTS:
        raise RobotDefinitionError(f"{path}: {robot.n_dofs} joints; at most {MAX_JOINTS} are accepted")
    max_angle = math.radians(MAX_ANGLE_DEG)
    revolute = robot.jtype == JTYPE_REVOLUTE
    checks = [("a", robot.dh_a, MAX_LENGTH), ("d", robot.dh_d, MAX_LENGTH)]
    for name, values in (("lower limit", robot.q_min), ("upper limit", robot.q_max)):
        finite = np.where(np.isfinite(values), values, 0.0)
        checks.append((name, np.where(revolute, finite / max_angle, finite / MAX_LENGTH), 1.0))
    for what, values, limit in checks:
        bad = np.flatnonzero(~(np.abs(values) <= limit))
        if bad.size:
            i = int(bad[0])
            raise RobotDefinitionError(
                f"{path}: joint {i + 1}: {what} beyond the accepted ±{MAX_LENGTH:g} m (lengths) "
                f"or ±{MAX_ANGLE_DEG:g} deg (angles)"
            )
    for what, tf in (("base", robot.base_tf), ("tool", robot.tool_tf)):
        offset = float(np.abs(tf.mat[:3, 3]).max())
        if not offset <= MAX_LENGTH:
            raise RobotDefinitionError(f"{path}: {what} offset {offset:g} m beyond the accepted ±{MAX_LENGTH:g} m")


def read_toml(path: Path, what: str = "robot file", error: type[ValueError] = RobotDefinitionError) -> dict[str, Any]:
    """The parsed TOML of ``what`` at ``path`` (robot and task files): read as by
    :func:`_read_text`; ``error`` starting with the path for any unreadable or invalid
    file (keys nested more than MAX_TOML_DEPTH levels, found by a pre-scan before
    parsing; an integer of more than 4300 digits included)."""
    text = _read_text(path, what, error)
    deep = nesting_too_deep(text)
    if deep is not None:
        raise error(f"{path}: line {deep}: keys, tables or arrays nested more than {MAX_TOML_DEPTH} levels deep")
    try:
        return tomllib.loads(text)
    except RecursionError:
        raise error(f"{path}: invalid TOML: arrays or tables nested too deeply") from None
    except ValueError as exc:  # TOMLDecodeError, or an integer of more than 4300 digits
        raise error(f"{path}: invalid TOML: {clip(str(exc), 200)}") from None


def parse_robot(data: dict[str, Any], path: str | Path, skip_missing_meshes: bool = False) -> RobotParams:
    """Validate the parsed TOML ``data`` of a robot file and build its parameters.

    ``path`` names the file in error messages and becomes ``RobotParams.source``; mesh
    paths start from its folder.  Raises RobotDefinitionError like :func:`load_robot`
    (which reads the file and calls this).
    """
    return _parse_robot(data, Path(path), skip_missing_meshes)


ANGLE_BOUNDS = {
    units: Bound(float(f"{MAX_ANGLE_DEG * math.pi / 180.0 / to_rad:.6g}"), "an angle", units)
    for units, to_rad in UNITS.items()
}


def _parse_robot(data: dict[str, Any], path: Path, skip_missing_meshes: bool = False) -> RobotParams:
    check = FieldChecker(path)
    check.keys(data, TOP_KEYS, "")
    for key in REQUIRED_TOP_KEYS:
        if key not in data:
            raise check.fail(key, "missing required field")
    name = data["name"]
    if not isinstance(name, str) or not name.strip():
        raise check.fail("name", f"expected a non-empty string, got {clip_repr(name)}")
    if len(name) > MAX_NAME_CHARS or not name.isprintable():
        raise check.fail("name", f"expected at most {MAX_NAME_CHARS} characters on one line, got {clip_repr(name)}")
    units = data["units"]
    if not isinstance(units, str) or units not in UNITS:
        raise check.fail("units", f"unknown units {clip_repr(units)}; accepted: 'deg' or 'rad'")
    to_rad, angle = UNITS[units], ANGLE_BOUNDS[units]
    convention = data.get("convention", CONVENTION_STANDARD)
    if not isinstance(convention, str) or convention not in CONVENTIONS:
        raise check.fail(
            "convention", f"unknown convention {clip_repr(convention)}; accepted: 'standard' or 'modified'"
        )
    joints = data["joints"]
    if not isinstance(joints, list) or not joints:
        raise check.fail("joints", "no joints: add one [[joints]] table per joint")
    if len(joints) > MAX_JOINTS:
        raise check.fail("joints", f"{len(joints)} joints; at most {MAX_JOINTS} are accepted")

    columns: dict[str, list[float]] = {k: [] for k in ("a", "alpha", "d", "theta", "home", "lo", "hi", "com")}
    jtypes: list[int] = []
    for i, joint in enumerate(joints):
        where = f"joints[{i}]"
        if not isinstance(joint, dict):
            raise check.fail(where, f"expected a table, got {clip_repr(joint)}")
        check.keys(joint, JOINT_KEYS, where)
        jname = joint.get("type")
        if not isinstance(jname, str) or jname not in JTYPE_NAMES:
            raise check.fail(
                f"{where}.type", f"unknown joint type {clip_repr(jname)}; accepted: 'revolute' or 'prismatic'"
            )
        jtype = JTYPE_NAMES[jname]
        for key in DH_KEYS:
            if key not in joint:
                raise check.fail(f"{where}.{key}", "missing DH value")
        a = check.number(joint["a"], f"{where}.a", LENGTH_BOUND)
        d = check.number(joint["d"], f"{where}.d", LENGTH_BOUND)
        alpha = check.number(joint["alpha"], f"{where}.alpha", angle) * to_rad
        theta = check.number(joint["theta"], f"{where}.theta", angle) * to_rad
        # The joint variable is an angle for revolute joints and a length for prismatic ones.
        q_scale, q_bound = (to_rad, angle) if jtype == JTYPE_REVOLUTE else (1.0, LENGTH_BOUND)
        lo, hi = -math.inf, math.inf
        if "limits" in joint:
            lo, hi = (v * q_scale for v in check.vector(joint["limits"], 2, f"{where}.limits", q_bound))
            if lo > hi:
                raise check.fail(f"{where}.limits", f"min {joint['limits'][0]} > max {joint['limits'][1]}")
        home = check.number(joint.get("home", 0.0), f"{where}.home", q_bound) * q_scale
        if not lo <= home <= hi:
            raise check.fail(
                f"{where}.home",
                f"home {joint.get('home', 0.0)} is outside the limits {joint['limits']}",
            )
        com = check.number(joint.get("com", DEFAULT_COM_FRACTION), f"{where}.com")
        if not 0.0 <= com <= 1.0:
            raise check.fail(f"{where}.com", f"com fraction {com} is outside [0, 1]")
        jtypes.append(jtype)
        for key, value in zip(columns, (a, alpha, d, theta, home, lo, hi, com)):
            columns[key].append(value)

    balance = data.get("balance_inertia", False)
    if not isinstance(balance, bool):
        raise check.fail("balance_inertia", f"expected true or false, got {clip_repr(balance)}")
    inertials, drives = parse_joint_tables(check, joints, balance)
    base, base_tables = data.get("base", {}), {}
    if isinstance(base, dict):  # [base] holds frame 0's pose and the base's geometry
        check.keys(base, {"xyz", "rpy", *GEOMETRY_KEYS}, "base")
        base_tables = {key: value for key, value in base.items() if key in GEOMETRY_KEYS}
        base = {key: value for key, value in base.items() if key not in GEOMETRY_KEYS}
    base_tf = check.frame(base, "base", angle, to_rad) if "base" in data else HomogeneousTransform()
    tool_tf = check.frame(data["tool"], "tool", angle, to_rad) if "tool" in data else HomogeneousTransform()
    description = data.get("description", "")
    if not isinstance(description, str):
        raise check.fail("description", f"expected a string, got {clip_repr(description)}")
    control = _parse_control(check, data["control"], len(jtypes)) if "control" in data else {}
    tables = ShapeTables(check, Path(path).parent, to_rad, LENGTH_BOUND, angle, MeshReader(check.fail, skip_missing_meshes))
    geometry = {
        key: [tables.shapes(joint[key], f"joints[{i}].{key}", key) if key in joint else () for i, joint in enumerate(joints)]
        for key in GEOMETRY_KEYS
    }
    base_geometry = {key: tables.shapes(base_tables[key], f"base.{key}", key) if key in base_tables else ()
                     for key in GEOMETRY_KEYS}
    allow = _parse_collision(check, data["collision"], len(jtypes)) if "collision" in data else ()

    return RobotParams(
        name=name,
        dh_a=frozen(columns["a"]),
        dh_alpha=frozen(columns["alpha"]),
        dh_d=frozen(columns["d"]),
        dh_th=frozen(columns["theta"]),
        jtype=frozen(dtype=np.int64, values=jtypes),
        q_home=frozen(columns["home"]),
        q_min=frozen(columns["lo"]),
        q_max=frozen(columns["hi"]),
        link_com_frac=frozen(columns["com"]),
        base_tf=base_tf,
        tool_tf=tool_tf,
        source=str(path),
        description=description,
        convention=convention,
        inertials=inertials,
        drives=drives,
        control=control,
        visuals=tuple(geometry["visual"]),
        collisions=tuple(geometry["collision"]),
        base_visuals=base_geometry["visual"],
        base_collisions=base_geometry["collision"],
        collision_allow=allow,
    )


def _parse_control(check: FieldChecker, table: Any, n: int) -> dict[str, Any]:
    """The validated ``[control]`` table: positive ``bandwidth``/``damping``, kp/kd ≥ 0 of length n."""
    if not isinstance(table, dict):
        raise check.fail("control", f"expected a table with keys {', '.join(sorted(CONTROL_KEYS))}, got {clip_repr(table)}")
    check.keys(table, CONTROL_KEYS, "control")
    control: dict[str, Any] = {}
    for key in ("bandwidth", "damping"):
        if key in table:
            value = check.number(table[key], f"control.{key}")
            if value <= 0.0:
                raise check.fail(f"control.{key}", f"expected a positive number, got {clip_repr(table[key])}")
            control[key] = value
    for key in ("kp", "kd"):
        if key in table:
            gains = check.vector(table[key], n, f"control.{key}")
            if min(gains) < 0.0:
                raise check.fail(f"control.{key}", f"gains must be >= 0, got {clip_repr(table[key])}")
            control[key] = tuple(gains)
    return control


def _parse_collision(check: FieldChecker, table: Any, n: int) -> tuple[tuple[str, str], ...]:
    """The validated ``[collision]`` table: ``allow``, a list of [link, link] name pairs."""
    if not isinstance(table, dict):
        raise check.fail("collision", f"expected a table with key allow, got {clip_repr(table)}")
    check.keys(table, COLLISION_KEYS, "collision")
    pairs = table.get("allow", [])
    names = link_names(n)
    accepted = f"accepted link names: {', '.join(names)}"
    if not isinstance(pairs, list):
        raise check.fail("collision.allow", f"expected a list of [link, link] pairs, got {clip_repr(pairs)}")
    out: list[tuple[str, str]] = []
    for k, pair in enumerate(pairs):
        where = f"collision.allow[{k}]"
        if not (isinstance(pair, list) and len(pair) == 2):
            raise check.fail(where, f"expected a pair of link names like [\"link2\", \"link4\"], got {clip_repr(pair)}")
        for name in pair:
            if not isinstance(name, str) or name not in names:
                raise check.fail(where, f"unknown link {clip_repr(name)}; {accepted}")
        if pair[0] == pair[1]:
            raise check.fail(where, f"a link is never checked against itself: {clip_repr(pair)}")
        if tuple(pair) not in out and (pair[1], pair[0]) not in out:
            out.append((pair[0], pair[1]))
    return tuple(out)
