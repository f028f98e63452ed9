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

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from transforms import HomogeneousTransform

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
TOP_KEYS = {"name", "description", "units", "convention", "joints", "base", "tool"}
REQUIRED_TOP_KEYS = ("name", "units", "joints")
JOINT_KEYS = {"type", "a", "alpha", "d", "theta", "home", "limits", "com"}
DH_KEYS = ("a", "alpha", "d", "theta")
FRAME_KEYS = {"xyz", "rpy"}
DEFAULT_COM_FRACTION = 0.5


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
    immutable and compare by identity (they key per-robot caches).
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

    def __post_init__(self) -> None:
        if self.convention not in CONVENTIONS:
            raise ValueError(
                f"convention must be 'standard' or 'modified', got {self.convention!r}"
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
    ) -> "RobotParams":
        """Build parameters from arrays in SI units (for programmatic robots and tests).

        Defaults: home at 0, unlimited joints, link COMs at mid-link, identity base and
        tool, standard DH (``convention="modified"`` reads the rows as Craig's).
        """
        n = len(dh_a)
        arrays = {"dh_alpha": dh_alpha, "dh_d": dh_d, "dh_th": dh_th, "jtype": jtype}
        for key, values in arrays.items():
            if len(values) != n:
                raise ValueError(f"{key} has {len(values)} entries, dh_a has {n}")
        return cls(
            name=name,
            dh_a=_frozen(dh_a),
            dh_alpha=_frozen(dh_alpha),
            dh_d=_frozen(dh_d),
            dh_th=_frozen(dh_th),
            jtype=_frozen_int(jtype),
            q_home=_frozen(np.zeros(n) if q_home is None else q_home),
            q_min=_frozen(np.full(n, -np.inf) if q_min is None else q_min),
            q_max=_frozen(np.full(n, np.inf) if q_max is None else q_max),
            link_com_frac=_frozen(
                np.full(n, DEFAULT_COM_FRACTION) if link_com_frac is None else link_com_frac
            ),
            base_tf=base_tf or HomogeneousTransform(),
            endeff_tf=endeff_tf or HomogeneousTransform(),
            convention=convention,
        )


def _frozen_int(values: Any) -> NDArray[np.int64]:
    arr = np.array(values, dtype=np.int64)
    arr.setflags(write=False)
    return arr


def available_robots() -> list[str]:
    """Names of the robots shipped in ``robots/`` (sorted)."""
    return sorted(p.stem for p in ROBOTS_DIR.glob("*.toml"))


def resolve_robot_path(name_or_path: str | Path) -> Path:
    """Path of a robot file given a shipped robot's name or a path to a ``.toml`` file.

    Raises RobotDefinitionError for an unknown name (listing the available robots) or a
    missing file.
    """
    text = str(name_or_path)
    if text.endswith(".toml") or "/" in text or "\\" in text:
        path = Path(text)
        if not path.is_file():
            raise RobotDefinitionError(f"{path}: robot file not found")
        return path
    path = ROBOTS_DIR / f"{text}.toml"
    if not path.is_file():
        raise RobotDefinitionError(
            f"unknown robot '{text}'; available robots: {', '.join(available_robots())}"
        )
    return path


def load_robot(name_or_path: str | Path) -> RobotParams:
    """Load and validate a robot by shipped name (``"puma560"``) or ``.toml`` path."""
    path = resolve_robot_path(name_or_path)
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except tomllib.TOMLDecodeError as exc:
        raise RobotDefinitionError(f"{path}: invalid TOML: {exc}") from None
    except OSError as exc:
        raise RobotDefinitionError(f"{path}: cannot read robot file: {exc.strerror}") from None
    return _parse_robot(data, path)


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
                f"{where}.{unknown[0]}" if where else unknown[0],
                f"unknown key '{unknown[0]}'; accepted keys: {', '.join(sorted(allowed))}",
            )

    def number(self, value: Any, where: str) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(where, f"expected a number, got {value!r}")
        if not math.isfinite(value):
            raise self.fail(where, f"expected a finite number, got {value!r}")
        return float(value)

    def vector(self, value: Any, length: int, where: str) -> list[float]:
        if not isinstance(value, list) or len(value) != length:
            raise self.fail(where, f"expected a list of {length} numbers, got {value!r}")
        return [self.number(v, f"{where}[{i}]") for i, v in enumerate(value)]

    def frame(self, table: Any, where: str, to_rad: float) -> HomogeneousTransform:
        if not isinstance(table, dict):
            raise self.fail(where, f"expected a table with keys xyz and rpy, got {table!r}")
        self.keys(table, FRAME_KEYS, where)
        xyz = self.vector(table.get("xyz", [0.0, 0.0, 0.0]), 3, f"{where}.xyz")
        rpy = self.vector(table.get("rpy", [0.0, 0.0, 0.0]), 3, f"{where}.rpy")
        return HomogeneousTransform.from_xyz_rpy(xyz, np.array(rpy) * to_rad)


def _parse_robot(data: dict[str, Any], path: Path) -> RobotParams:
    check = _Checker(path)
    check.keys(data, TOP_KEYS, "")
    for key in REQUIRED_TOP_KEYS:
        if key not in data:
            raise check.fail(key, "missing required field")
    name = data["name"]
    if not isinstance(name, str) or not name.strip():
        raise check.fail("name", f"expected a non-empty string, got {name!r}")
    units = data["units"]
    if units not in UNITS:
        raise check.fail("units", f"unknown units {units!r}; accepted: 'deg' or 'rad'")
    to_rad = UNITS[units]
    convention = data.get("convention", CONVENTION_STANDARD)
    if convention not in CONVENTIONS:
        raise check.fail(
            "convention", f"unknown convention {convention!r}; accepted: 'standard' or 'modified'"
        )
    joints = data["joints"]
    if not isinstance(joints, list) or not joints:
        raise check.fail("joints", "no joints: add one [[joints]] table per joint")

    columns: dict[str, list[float]] = {k: [] for k in ("a", "alpha", "d", "theta", "home", "lo", "hi", "com")}
    jtypes: list[int] = []
    for i, joint in enumerate(joints):
        where = f"joints[{i}]"
        if not isinstance(joint, dict):
            raise check.fail(where, f"expected a table, got {joint!r}")
        check.keys(joint, JOINT_KEYS, where)
        jname = joint.get("type")
        if jname not in JTYPE_NAMES:
            raise check.fail(
                f"{where}.type", f"unknown joint type {jname!r}; accepted: 'revolute' or 'prismatic'"
            )
        jtype = JTYPE_NAMES[jname]
        for key in DH_KEYS:
            if key not in joint:
                raise check.fail(f"{where}.{key}", "missing DH value")
        a = check.number(joint["a"], f"{where}.a")
        d = check.number(joint["d"], f"{where}.d")
        alpha = check.number(joint["alpha"], f"{where}.alpha") * to_rad
        theta = check.number(joint["theta"], f"{where}.theta") * to_rad
        # The joint variable is an angle for revolute joints and a length for prismatic ones.
        q_scale = to_rad if jtype == JTYPE_REVOLUTE else 1.0
        lo, hi = -math.inf, math.inf
        if "limits" in joint:
            lo, hi = (v * q_scale for v in check.vector(joint["limits"], 2, f"{where}.limits"))
            if lo > hi:
                raise check.fail(f"{where}.limits", f"min {joint['limits'][0]} > max {joint['limits'][1]}")
        home = check.number(joint.get("home", 0.0), f"{where}.home") * q_scale
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

    base_tf = check.frame(data["base"], "base", to_rad) if "base" in data else HomogeneousTransform()
    tool_tf = check.frame(data["tool"], "tool", to_rad) if "tool" in data else HomogeneousTransform()
    description = data.get("description", "")
    if not isinstance(description, str):
        raise check.fail("description", f"expected a string, got {description!r}")

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
    )
