"""Robot parameters: joint types, DH conventions and :class:`RobotParams` (immutable, SI units).

For a revolute joint the joint variable q is added to θ (``theta = dh_th + q``); for a prismatic
joint it is added to d (``d = dh_d + q``).  Robot files are read by :mod:`robot_sim.io.robot_file`.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from robot_sim.model.arrays import frozen
from robot_sim.model.inertials import Drives, LinkInertials
from robot_sim.model.messages import clip_repr
from robot_sim.model.shapes import Box, Capsule, Cylinder, Mesh, Sphere
from robot_sim.transforms import HomogeneousTransform, is_rigid_transform

JTYPE_REVOLUTE = 0
JTYPE_PRISMATIC = 1
JTYPE_NAMES = {"revolute": JTYPE_REVOLUTE, "prismatic": JTYPE_PRISMATIC}

#: DH conventions.  Standard: ``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``, joint i turns
#: about z of frame i-1.  Modified (Craig): row i holds (a_{i-1}, α_{i-1}, θ_i, d_i),
#: ``A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)``, joint i turns about z of frame i.
CONVENTION_STANDARD = "standard"
CONVENTION_MODIFIED = "modified"
CONVENTIONS = (CONVENTION_STANDARD, CONVENTION_MODIFIED)

DEFAULT_COM_FRACTION = 0.5
BASE_LINK_NAME = "base"


def link_names(n_dofs: int) -> tuple[str, ...]:
    """Names of the links of an n-joint robot: ``"base"``, then ``"link1"`` .. ``"linkN"``."""
    return (BASE_LINK_NAME,) + tuple(f"link{i}" for i in range(1, n_dofs + 1))

#: Shapes a link may be made of (a half-space is an obstacle, never part of a link).
LINK_SHAPE_TYPES = (Box, Sphere, Cylinder, Capsule, Mesh)
LinkShape = Box | Sphere | Cylinder | Capsule | Mesh


class RobotDefinitionError(ValueError):
    """A robot description could not be loaded; the message names file, field and value."""


@dataclass(frozen=True, eq=False)
class RobotParams:
    """Kinematic description of a fixed-base serial manipulator (DH table, SI units).

    Arrays have one entry per joint, ordered from the base.  ``convention`` says how the
    table reads: ``"standard"`` (row i = a_i, α_i, θ_i, d_i of
    ``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``; joint i turns about z_{i-1}) or
    ``"modified"`` (Craig: row i = a_{i-1}, α_{i-1}, θ_i, d_i of
    ``A_i = Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)``; joint i turns about z_i).  ``base_tf`` maps frame 0 to the
    robot's base (world when the robot is not moved), ``tool_tf`` maps the endeffector
    (tool) frame to frame n.  Limits are ±inf where a joint is unlimited.  Instances are
    immutable and compare by identity (they key per-robot caches).  ``inertials`` (mass
    properties of each link in its frame) and ``drives`` (motor inertia, gearing, friction,
    limits) are None when the file gives none; see :mod:`inertials`.

    Geometry (:mod:`robot_sim.model.shapes`): ``visuals`` and ``collisions`` hold one tuple
    of shapes per link i, posed in frame i of the convention (frame i is the frame after
    joint i); ``base_visuals`` and ``base_collisions`` are the base's, posed in frame 0.
    Empty tuples where a description has none (``()`` is taken as n empty tuples).
    :func:`~robot_sim.model.convert.to_standard`/``to_modified`` move them with the frames.
    ``collision_allow`` holds pairs of link names (:attr:`link_names`) never checked for
    collision, from the file's ``[collision] allow`` table.  ``notes``: one-line remarks on
    where the values came from (a calibration's date, poses and residuals), which
    :func:`~robot_sim.io.robot_writer.save_robot` writes as comments; never read from files.
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
    tool_tf: HomogeneousTransform = field(default_factory=HomogeneousTransform)
    source: str = ""
    description: str = ""
    convention: str = CONVENTION_STANDARD
    inertials: LinkInertials | None = None
    drives: Drives | None = None
    control: dict[str, Any] = field(default_factory=dict)
    visuals: tuple[tuple[LinkShape, ...], ...] = ()
    collisions: tuple[tuple[LinkShape, ...], ...] = ()
    base_visuals: tuple[LinkShape, ...] = ()
    base_collisions: tuple[LinkShape, ...] = ()
    collision_allow: tuple[tuple[str, str], ...] = ()
    notes: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not isinstance(self.convention, str) or self.convention not in CONVENTIONS:
            raise ValueError(
                f"convention must be 'standard' or 'modified', got {clip_repr(self.convention)}"
            )
        n = len(self.dh_a)
        for key in ("visuals", "collisions"):
            per_link = getattr(self, key)
            if isinstance(per_link, (tuple, list)) and len(per_link) == 0:
                per_link = ((),) * n
            if not isinstance(per_link, (tuple, list)) or len(per_link) != n:
                size = len(per_link) if isinstance(per_link, (tuple, list)) else clip_repr(per_link)
                raise ValueError(f"{key}: expected {n} tuples of shapes (one per link), got {size}")
            object.__setattr__(self, key, tuple(_shapes(f"{key}[{i}]", s) for i, s in enumerate(per_link)))
        for key in ("base_visuals", "base_collisions"):
            object.__setattr__(self, key, _shapes(key, getattr(self, key)))

    def __str__(self) -> str:
        """The DH table, as the Robotics Toolbox prints a robot (model.table_text.dh_table)."""
        from robot_sim.model.table_text import dh_table

        return dh_table(self)

    def __repr__(self) -> str:
        return f"<RobotParams {self.name!r}: {self.n_dofs} joints, {self.convention} DH>"

    @property
    def has_visuals(self) -> bool:
        """True if the base or any link carries a visual shape (else it is drawn from its DH table)."""
        return bool(self.base_visuals) or any(self.visuals)

    @property
    def has_collisions(self) -> bool:
        """True if the base or any link carries a collision shape."""
        return bool(self.base_collisions) or any(self.collisions)

    @functools.cached_property
    def size(self) -> float:
        """The robot's characteristic size [m], the one rule every consumer scales by (IK
        step scaling, drawn part sizes, estimated link radii): the sum of |a| and of |d| over
        the joints, a prismatic joint's d taken at its largest finite stroke (its home when
        unlimited), plus the tool offset.  Computed once per robot."""
        prismatic = self.jtype == JTYPE_PRISMATIC
        upper = np.where(np.isfinite(self.q_max), self.q_max, self.q_home)
        lower = np.where(np.isfinite(self.q_min), self.q_min, self.q_home)
        reach_d = np.maximum(np.abs(self.dh_d + upper), np.abs(self.dh_d + lower))
        d = np.where(prismatic, reach_d, np.abs(self.dh_d))
        return float(np.abs(self.dh_a).sum() + d.sum() + np.linalg.norm(self.tool_tf.mat[:3, 3]))

    @functools.cached_property
    def reach(self) -> float:
        """An upper bound [m] on the distance from frame 0's origin (the base) to the tool
        point over every configuration within the joint limits: each joint moves the next
        frame's origin by a along one axis and d along a perpendicular one, so by at most
        √(a² + d²), with a prismatic joint's d at the end of its stroke; plus the tool
        offset.  Infinite when a prismatic joint is unlimited.  Computed once per robot."""
        prismatic = self.jtype == JTYPE_PRISMATIC
        with np.errstate(invalid="ignore"):
            stroke = np.maximum(np.abs(self.dh_d + self.q_max), np.abs(self.dh_d + self.q_min))
        d = np.where(prismatic, stroke, np.abs(self.dh_d))
        return float(np.hypot(self.dh_a, d).sum() + np.linalg.norm(self.tool_tf.mat[:3, 3]))

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
    def link_names(self) -> tuple[str, ...]:
        """Names of the links: ``"base"`` (frame 0), then ``"link1"`` .. ``"linkN"`` (frame i)."""
        return link_names(self.n_dofs)

    @property
    def is_revolute(self) -> NDArray[np.bool_]:
        """Boolean mask (n,) of revolute joints."""
        return self.jtype == JTYPE_REVOLUTE

    @property
    def has_tool(self) -> bool:
        """True if the tool transform is not the identity."""
        return not np.allclose(self.tool_tf.mat, np.eye(4))

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
        tool_tf: HomogeneousTransform | None = None,
        convention: str = CONVENTION_STANDARD,
        inertials: LinkInertials | None = None,
        drives: Drives | None = None,
        visuals: Any = (),
        collisions: Any = (),
        base_visuals: Any = (),
        base_collisions: Any = (),
    ) -> "RobotParams":
        """Build parameters from arrays in SI units (for programmatic robots and tests).

        Defaults: home at 0, unlimited joints, link COMs at mid-link, identity base and
        tool, standard DH (``convention="modified"`` reads the rows as Craig's), no inertials,
        no drives and no geometry (shapes per link as in the class docstring).
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
            dh_a=frozen(a),
            dh_alpha=frozen(_real_vector("dh_alpha", dh_alpha, n)),
            dh_d=frozen(_real_vector("dh_d", dh_d, n)),
            dh_th=frozen(_real_vector("dh_th", dh_th, n)),
            jtype=frozen(dtype=np.int64, values=_joint_types(jtype, n)),
            q_home=frozen(home),
            q_min=frozen(q_lo),
            q_max=frozen(q_hi),
            link_com_frac=frozen(com),
            base_tf=_rigid("base_tf", base_tf),
            tool_tf=_rigid("tool_tf", tool_tf),
            convention=convention,
            inertials=inertials,
            drives=drives,
            visuals=visuals,
            collisions=collisions,
            base_visuals=base_visuals,
            base_collisions=base_collisions,
        )


def _shapes(name: str, values: Any) -> tuple[LinkShape, ...]:
    """``values`` as a tuple of link shapes; ValueError naming ``name`` otherwise."""
    if not isinstance(values, (tuple, list)):
        raise ValueError(f"{name}: expected a tuple of shapes, got {clip_repr(values)}")
    for k, shape in enumerate(values):
        if not isinstance(shape, LINK_SHAPE_TYPES):
            raise ValueError(f"{name}[{k}]: expected a Box, Sphere, Cylinder, Capsule or Mesh, got {clip_repr(shape)}")
    return tuple(values)


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


def require_robot(robot: Any, what: str = "robot") -> RobotParams:
    """``robot`` itself if it is a :class:`RobotParams`; TypeError naming ``what`` otherwise,
    saying how to get one (a robot's name is loaded by ``rs.load_robot``, which this
    layer cannot call)."""
    if not isinstance(robot, RobotParams):
        hint = f" (load it first: rs.load_robot({clip_repr(robot)}))" if isinstance(robot, str) else ""
        raise TypeError(f"{what} must be a RobotParams{hint}, got {type(robot).__name__} {clip_repr(robot)}")
    return robot
