"""Robot descriptions: joint types, :class:`RobotParams` and the loader for ``robots/NAME.toml``.

A robot file is data, parsed with the standard library's ``tomllib`` (never executed).
Every value is validated before a :class:`RobotParams` is built, so a bad file raises
:class:`RobotDefinitionError` naming the file, the field, the value and what is accepted,
and nothing is half-loaded.  See README.md for the file format.

Internally everything is SI: metres and radians.  For a revolute joint the joint variable
q is added to θ (``theta = dh_th + q``); for a prismatic joint it is added to d
(``d = dh_d + q``).
"""
from __future__ import annotations

import codecs
import errno
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from fileio import FileReadError, read_regular_file
from inertials import Drives, LinkInertials, parse_joint_tables
from messages import clip, clip_repr
from transforms import HomogeneousTransform, is_rigid_transform

JTYPE_REVOLUTE = 0
JTYPE_PRISMATIC = 1
JTYPE_NAMES = {"revolute": JTYPE_REVOLUTE, "prismatic": JTYPE_PRISMATIC}

#: DH conventions.  Standard: ``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``, joint i turns
#: about z of frame i-1.  Modified (Craig): row i holds (a_{i-1}, α_{i-1}, θ_i, d_i),
#: ``A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)``, joint i turns about z of frame i.
CONVENTION_STANDARD = "standard"
CONVENTION_MODIFIED = "modified"
CONVENTIONS = (CONVENTION_STANDARD, CONVENTION_MODIFIED)

#: Directory holding the shipped robot files (installed alongside the modules).
ROBOTS_DIR = Path(__file__).resolve().parent / "robots"

UNITS = {"deg": math.pi / 180.0, "rad": 1.0}
TOP_KEYS = {"name", "description", "units", "convention", "joints", "base", "tool", "control"}
REQUIRED_TOP_KEYS = ("name", "units", "joints")
JOINT_KEYS = {"type", "a", "alpha", "d", "theta", "home", "limits", "com", "inertial", "drive"}
DH_KEYS = ("a", "alpha", "d", "theta")
FRAME_KEYS = {"xyz", "rpy"}
DEFAULT_COM_FRACTION = 0.5
#: Keys of the optional top-level ``[control]`` table (gains of control.py): ``bandwidth``
#: closed-loop natural frequency in Hz (> 0), ``damping`` ratio (> 0), ``kp`` and ``kd``
#: per-joint PD gains (n numbers ≥ 0; N·m/rad and N·m·s/rad, or N/m and N·s/m).
CONTROL_KEYS = {"bandwidth", "damping", "kp", "kd"}

# Bounds of a robot file (README, "Robot file format").  With at most MAX_JOINTS joints,
# lengths within ±MAX_LENGTH and angles within ±MAX_ANGLE_DEG, forward kinematics is
# finite everywhere inside the limits and every slider range fits a Qt slider's int range.
MAX_LENGTH = 1000.0  # m: |a|, |d|, base and tool xyz, prismatic home and limits
MAX_ANGLE_DEG = 1800.0  # deg (5 turns): alpha, theta, base and tool rpy, revolute home and limits
MAX_JOINTS = 100
MAX_FILE_BYTES = 1 << 20
MAX_NAME_CHARS = 200


class RobotDefinitionError(ValueError):
    """A robot description could not be loaded; the message names file, field and value."""


def _frozen(values: Any) -> NDArray[np.float64]:
    arr = np.array(values, dtype=float)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class RobotParams:
    """Kinematic description of a fixed-base serial manipulator (DH table, SI units).

    Arrays have one entry per joint, ordered from the base.  ``convention`` says how the
    table reads: ``"standard"`` (row i = a_i, α_i, θ_i, d_i of
    ``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``; joint i turns about z_{i-1}) or
    ``"modified"`` (Craig: row i = a_{i-1}, α_{i-1}, θ_i, d_i of
    ``A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)``; joint i turns about z_i).  ``base_tf`` maps frame 0 to the
    robot's base (world when the robot is not moved), ``endeff_tf`` maps the endeffector
    (tool) frame to frame n.  Limits are ±inf where a joint is unlimited.  Instances are
    immutable and compare by identity (they key per-robot caches).  ``inertials`` (mass
    properties of each link in its frame) and ``drives`` (motor inertia, gearing, friction,
    limits) are None when the file gives none; see :mod:`inertials`.
    """

    name: str
    dh_a: NDArray[np.float64]
    dh_alpha: NDArray[np.float64]
    dh_d: NDArray[np.float64]
    dh_th: NDArray[np.float64]
    jtype: NDArray[np.int64]
    q_home: NDArray[np.float64]
    q_min: NDArray[np.float64]
    q_max: NDArray[np.float64]
    link_com_frac: NDArray[np.float64]
    base_tf: HomogeneousTransform = field(default_factory=HomogeneousTransform)
    endeff_tf: HomogeneousTransform = field(default_factory=HomogeneousTransform)
    source: str = ""
    description: str = ""
    convention: str = CONVENTION_STANDARD
    inertials: LinkInertials | None = None
    drives: Drives | None = None
    control: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.convention, str) or self.convention not in CONVENTIONS:
            raise ValueError(
                f"convention must be 'standard' or 'modified', got {clip_repr(self.convention)}"
            )

    @property
    def is_modified(self) -> bool:
        """True for a modified (Craig) DH table: joint i turns about z of frame i."""
        return self.convention == CONVENTION_MODIFIED

    @property
    def n_dofs(self) -> int:
        """Number of joints (each contributes one degree of freedom)."""
        return int(self.dh_a.shape[0])

    @property
    def n_links(self) -> int:
        """Number of moving links (one per joint; link 0, the base, is not counted)."""
        return self.n_dofs

    @property
    def is_revolute(self) -> NDArray[np.bool_]:
        """Boolean mask (n,) of revolute joints."""
        return self.jtype == JTYPE_REVOLUTE

    @property
    def has_tool(self) -> bool:
        """True if the tool transform is not the identity."""
        return not np.allclose(self.endeff_tf.mat, np.eye(4))

    @classmethod
    def from_arrays(
        cls,
        name: str,
        dh_a: Any,
        dh_alpha: Any,
        dh_d: Any,
        dh_th: Any,
        jtype: Any,
        *,
        q_home: Any = None,
        q_min: Any = None,
        q_max: Any = None,
        link_com_frac: Any = None,
        base_tf: HomogeneousTransform | None = None,
        endeff_tf: HomogeneousTransform | None = None,
        convention: str = CONVENTION_STANDARD,
        inertials: LinkInertials | None = None,
        drives: Drives | None = None,
    ) -> "RobotParams":
        """Build parameters from arrays in SI units (for programmatic robots and tests).

        Defaults: home at 0, unlimited joints, link COMs at mid-link, identity base and
        tool, standard DH (``convention="modified"`` reads the rows as Craig's), no inertials
        and no drives.
        Raises ValueError naming the argument for anything else than finite real numbers
        of matching lengths (limits may be ±inf), joint types other than 0 and 1, limits
        with min > max, a home outside them, COM fractions outside [0, 1] or a base or
        tool that is not a rigid transform.  Lengths are not bounded as in robot files,
        so scaled copies of a robot can be built.
        """
        if not isinstance(name, str):
            raise ValueError(f"name must be a string, got {clip_repr(name)}")
        a = _real_vector("dh_a", dh_a)
        n = a.shape[0]
        if n == 0:
            raise ValueError(f"dh_a must hold at least one joint, got {clip_repr(dh_a)}")
        q_lo = _real_vector("q_min", np.full(n, -np.inf) if q_min is None else q_min, n, allow_inf=True)
        q_hi = _real_vector("q_max", np.full(n, np.inf) if q_max is None else q_max, n, allow_inf=True)
        home = _real_vector("q_home", np.zeros(n) if q_home is None else q_home, n)
        for i in range(n):
            if q_lo[i] > q_hi[i]:
                raise ValueError(f"q_min[{i}] = {q_lo[i]} > q_max[{i}] = {q_hi[i]}")
            if not q_lo[i] <= home[i] <= q_hi[i]:
                raise ValueError(f"q_home[{i}] = {home[i]} is outside [q_min, q_max] = [{q_lo[i]}, {q_hi[i]}]")
        com = _real_vector("link_com_frac", np.full(n, DEFAULT_COM_FRACTION) if link_com_frac is None else link_com_frac, n)
        if not ((com >= 0.0) & (com <= 1.0)).all():
            raise ValueError(f"link_com_frac must lie in [0, 1], got {clip_repr(link_com_frac)}")
        for key, table in (("inertials", inertials), ("drives", drives)):
            size = None if table is None else len(table.mass if key == "inertials" else table.gear_ratio)
            if size is not None and size != n:
                raise ValueError(f"{key} describe {size} joints, dh_a has {n}")
        return cls(
            name=name,
            dh_a=_frozen(a),
            dh_alpha=_frozen(_real_vector("dh_alpha", dh_alpha, n)),
            dh_d=_frozen(_real_vector("dh_d", dh_d, n)),
            dh_th=_frozen(_real_vector("dh_th", dh_th, n)),
            jtype=_frozen_int(_joint_types(jtype, n)),
            q_home=_frozen(home),
            q_min=_frozen(q_lo),
            q_max=_frozen(q_hi),
            link_com_frac=_frozen(com),
            base_tf=_rigid("base_tf", base_tf),
            endeff_tf=_rigid("endeff_tf", endeff_tf),
            convention=convention,
            inertials=inertials,
            drives=drives,
        )


def _real_vector(name: str, values: Any, n: int | None = None, allow_inf: bool = False) -> NDArray[np.float64]:
    """``values`` as a 1-D float array (of length n if given); ValueError naming ``name``
    for other shapes, non-real entries, NaN, or ±inf unless ``allow_inf``."""
    try:
        arr = np.asarray(values)
    except (ValueError, TypeError):
        raise ValueError(f"{name} must be a 1-D sequence of numbers, got {clip_repr(values)}") from None
    if arr.dtype.kind == "c":
        raise ValueError(f"{name} must hold real numbers, got {clip_repr(values)}")
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"{name} must be a 1-D sequence of numbers, got {clip_repr(values)}")
    if arr.ndim != 1:
        raise ValueError(f"{name} must be a 1-D sequence of numbers, got shape {arr.shape}")
    if n is not None and arr.shape[0] != n:
        raise ValueError(f"{name} has {arr.shape[0]} entries, dh_a has {n}")
    arr = arr.astype(float)
    if np.isnan(arr).any() or (not allow_inf and not np.isfinite(arr).all()):
        rule = "must not hold NaN" if allow_inf else "must hold finite numbers"
        raise ValueError(f"{name} {rule}, got {clip_repr(values)}")
    return arr


def _joint_types(values: Any, n: int) -> NDArray[np.int64]:
    """Joint types as ints, each JTYPE_REVOLUTE or JTYPE_PRISMATIC (ValueError otherwise)."""
    accepted = f"{JTYPE_REVOLUTE} (revolute) or {JTYPE_PRISMATIC} (prismatic)"
    try:
        arr = np.asarray(values)
    except (ValueError, TypeError):
        arr = np.asarray([None])
    if arr.dtype.kind not in "iuf" or arr.ndim != 1:
        raise ValueError(f"jtype must hold {accepted}, got {clip_repr(values)}")
    if arr.shape[0] != n:
        raise ValueError(f"jtype has {arr.shape[0]} entries, dh_a has {n}")
    for i, value in enumerate(arr.tolist()):
        if value not in (JTYPE_REVOLUTE, JTYPE_PRISMATIC):
            raise ValueError(f"jtype[{i}] must be {accepted}, got {value!r}")
    return arr.astype(np.int64)


def _rigid(name: str, tf: Any) -> HomogeneousTransform:
    """``tf`` (identity when None) if it is a rigid HomogeneousTransform, else ValueError."""
    if tf is None:
        return HomogeneousTransform()
    if not isinstance(tf, HomogeneousTransform) or not is_rigid_transform(tf.mat):
        raise ValueError(f"{name} must be a rigid HomogeneousTransform, got {clip_repr(tf)}")
    return tf


def _frozen_int(values: Any) -> NDArray[np.int64]:
    arr = np.array(values, dtype=np.int64)
    arr.setflags(write=False)
    return arr


def available_robots() -> list[str]:
    """Names of the robots shipped in ``robots/`` (sorted)."""
    return sorted(p.stem for p in ROBOTS_DIR.glob("*.toml"))


def resolve_robot_path(name_or_path: str | Path) -> Path:
    """Path of a robot file given a shipped robot's name or a path to a ``.toml`` or
    ``.urdf`` file.

    Raises RobotDefinitionError for an unknown name (listing the available robots) or a
    missing file.
    """
    text = str(name_or_path)
    if text.lower().endswith((".toml", ".urdf")) or "/" in text or "\\" in text:
        return Path(text)  # checked when read, so every reason is reported as it is
    if text not in available_robots():
        raise RobotDefinitionError(
            f"unknown robot {clip_repr(text)}; available robots: {', '.join(available_robots())}"
        )
    return ROBOTS_DIR / f"{text}.toml"


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
    name_or_path: str | Path, tip: str | None = None, convention: str | None = None
) -> RobotParams:
    """Load and validate a robot by shipped name (``"puma560"``), ``.toml`` path or
    ``.urdf`` path.

    A URDF becomes a DH robot (``urdf.load_urdf``): the chain from the root link to
    ``tip`` (needed when the tree branches), in ``convention`` (standard by default).  A
    TOML robot keeps its file's convention unless ``convention`` names the other one, to
    which it is converted exactly (``dh_convert``).  ``tip`` applies to URDF files only.
    """
    if convention is not None and convention not in CONVENTIONS:
        raise ValueError(f"convention must be 'standard' or 'modified', got {convention!r}")
    path = resolve_robot_path(name_or_path)
    if path.suffix.lower() == ".urdf":
        from urdf import load_urdf  # urdf builds on this module

        robot = load_urdf(path, tip=tip, convention=convention or CONVENTION_STANDARD)
        check_bounds(robot, path)
        return robot
    if tip is not None:
        raise ValueError(f"tip applies to URDF files only; {path} is a robot file")
    robot = _load_toml(path)
    if convention is None:
        return robot
    from dh_convert import to_convention  # dh_convert builds on this module

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
    for what, tf in (("base", robot.base_tf), ("tool", robot.endeff_tf)):
        offset = float(np.abs(tf.mat[:3, 3]).max())
        if not offset <= MAX_LENGTH:
            raise RobotDefinitionError(f"{path}: {what} offset {offset:g} m beyond the accepted ±{MAX_LENGTH:g} m")


def read_toml(path: Path, what: str = "robot file", error: type[ValueError] = RobotDefinitionError) -> dict[str, Any]:
    """The parsed TOML of ``what`` at ``path`` (robot and task files): read as by
    :func:`_read_text`; ``error`` starting with the path for any unreadable or invalid
    file (nesting too deep, an integer of more than 4300 digits included)."""
    text = _read_text(path, what, error)
    try:
        return tomllib.loads(text)
    except RecursionError:
        raise error(f"{path}: invalid TOML: arrays or tables nested too deeply") from None
    except ValueError as exc:  # TOMLDecodeError, or an integer of more than 4300 digits
        raise error(f"{path}: invalid TOML: {clip(str(exc), 200)}") from None


def _load_toml(path: Path) -> RobotParams:
    return _parse_robot(read_toml(path), path)


def parse_robot(data: dict[str, Any], path: str | Path) -> RobotParams:
    """Validate the parsed TOML ``data`` of a robot file and build its parameters.

    ``path`` names the file in error messages and becomes ``RobotParams.source``; raises
    RobotDefinitionError like :func:`load_robot` (which reads the file and calls this).
    """
    return _parse_robot(data, Path(path))


class _Checker:
    """Validates fields of one robot file; every error names the file and the field."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def fail(self, where: str, message: str) -> RobotDefinitionError:
        return RobotDefinitionError(f"{self.path}: {where}: {message}")

    def keys(self, table: dict[str, Any], allowed: set[str], where: str) -> None:
        unknown = sorted(set(table) - allowed)
        if unknown:
            raise self.fail(
                f"{where}.{clip(unknown[0])}" if where else clip(unknown[0]),
                f"unknown key {clip_repr(unknown[0])}; accepted keys: {', '.join(sorted(allowed))}",
            )

    def number(self, value: Any, where: str, bound: "_Bound | None" = None) -> float:
        """``value`` as a finite float, within ±``bound.limit`` when a bound is given."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(where, f"expected a number, got {clip_repr(value)}")
        if isinstance(value, float) and not math.isfinite(value):
            raise self.fail(where, f"expected a finite number, got {value!r}")
        try:
            number = float(value)
        except OverflowError:  # an integer beyond the float range
            number = math.inf if value > 0 else -math.inf
        if bound is not None and not abs(number) <= bound.limit:
            raise self.fail(where, f"expected {bound.what} within ±{bound.limit:g} {bound.unit}, got {clip_repr(value)}")
        if not math.isfinite(number):
            raise self.fail(where, f"expected a finite number, got {clip_repr(value)}")
        return number

    def vector(self, value: Any, length: int, where: str, bound: "_Bound | None" = None) -> list[float]:
        if not isinstance(value, list) or len(value) != length:
            raise self.fail(where, f"expected a list of {length} numbers, got {clip_repr(value)}")
        return [self.number(v, f"{where}[{i}]", bound) for i, v in enumerate(value)]

    def frame(self, table: Any, where: str, angle: "_Bound", to_rad: float) -> HomogeneousTransform:
        if not isinstance(table, dict):
            raise self.fail(where, f"expected a table with keys xyz and rpy, got {clip_repr(table)}")
        self.keys(table, FRAME_KEYS, where)
        xyz = self.vector(table.get("xyz", [0.0, 0.0, 0.0]), 3, f"{where}.xyz", LENGTH_BOUND)
        rpy = self.vector(table.get("rpy", [0.0, 0.0, 0.0]), 3, f"{where}.rpy", angle)
        return HomogeneousTransform.from_xyz_rpy(xyz, np.array(rpy) * to_rad)


@dataclass(frozen=True)
class _Bound:
    """Largest magnitude accepted for a value, with what it is and its unit (for messages)."""

    limit: float
    what: str
    unit: str


LENGTH_BOUND = _Bound(MAX_LENGTH, "a length", "m")
ANGLE_BOUNDS = {
    units: _Bound(float(f"{MAX_ANGLE_DEG * math.pi / 180.0 / to_rad:.6g}"), "an angle", units)
    for units, to_rad in UNITS.items()
}


def _parse_robot(data: dict[str, Any], path: Path) -> RobotParams:
    check = _Checker(path)
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

    inertials, drives = parse_joint_tables(check, joints)
    base_tf = check.frame(data["base"], "base", angle, to_rad) if "base" in data else HomogeneousTransform()
    tool_tf = check.frame(data["tool"], "tool", angle, to_rad) if "tool" in data else HomogeneousTransform()
    description = data.get("description", "")
    if not isinstance(description, str):
        raise check.fail("description", f"expected a string, got {clip_repr(description)}")
    control = _parse_control(check, data["control"], len(jtypes)) if "control" in data else {}

    return RobotParams(
        name=name,
        dh_a=_frozen(columns["a"]),
        dh_alpha=_frozen(columns["alpha"]),
        dh_d=_frozen(columns["d"]),
        dh_th=_frozen(columns["theta"]),
        jtype=_frozen_int(jtypes),
        q_home=_frozen(columns["home"]),
        q_min=_frozen(columns["lo"]),
        q_max=_frozen(columns["hi"]),
        link_com_frac=_frozen(columns["com"]),
        base_tf=base_tf,
        endeff_tf=tool_tf,
        source=str(path),
        description=description,
        convention=convention,
        inertials=inertials,
        drives=drives,
        control=control,
    )


def _parse_control(check: _Checker, table: Any, n: int) -> dict[str, Any]:
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
