"""Reading a serial arm from URDF (behind :mod:`urdf`): :func:`load_urdf`.

Steps, each refusing bad input with one :class:`~robot_sim.model.params.RobotDefinitionError` before
anything is built:

1. **Parse** UTF-8 text with the standard library's ElementTree, refusing any
   ``<!DOCTYPE``/``<!ENTITY`` (so no entity expansion can happen; the bytes are decoded
   first, so a declared encoding cannot hide one), malformed XML and a root that is not
   ``<robot>``.
2. **Tree**: every joint's parent and child must be declared links, no link may have two
   parents, the tree must have one root and no loop.  The chain runs from the root to
   ``tip`` (a link name) or, without ``tip``, to the only leaf; several leaves need ``tip``.
   Floating, planar and mimic joints are refused in the chain.
3. **Axes**: walking the chain at q = 0, fixed joints fold into the running transform; each
   moving joint gives a line in the root frame (point = its joint frame's origin,
   direction = its axis).
4. **Common normals** (modified DH frames): frame i has z along joint i's axis and x along
   the common normal to joint i+1's axis, with its origin where that normal leaves axis i.
   Intersecting axes: x = ±z_i × z_{i+1}, a = 0.  Parallel axes: the normal is taken from
   the point of axis i where the previous normal arrived (d_i = 0).  Where x is free
   (coincident axes, the last joint) or only its sign is (intersecting axes), it follows
   the URDF joint frame's x axis.  The last frame sits where x_{n-1} meets its axis.  Frame 0
   is frame 1 at q = 0, so a_0 = α_0 = θ_1 = d_1 = 0; the base transform is its pose in the
   root frame, the tool transform carries the tip link from frame n.
5. **Table**: a_{i-1}, α_{i-1}, θ_i, d_i read off Rx(α) Tx(a) Rz(θ) Tz(d) between successive
   frames; the joint variable q_i equals the URDF joint value (z_i points along the URDF
   axis).  ``convention="standard"`` then converts exactly (:mod:`robot_sim.model.convert`).

Limits carry over (continuous joints unlimited); effort and velocity limits become the
robot's drives (0 counts as unknown).  Inertials carry over: the links of one rigid body
(a moving joint's child and every link fixed to it along the chain) are lumped into one
mass, COM and inertia (parallel-axis theorem) and expressed in that body's DH frame; links
off the chain and before the first moving joint are left out.

Geometry carries over the same way (:mod:`robot_sim.io.urdf_shapes`): the ``<visual>`` and
``<collision>`` elements of every link of a body, and of the links fixed to them off the
chain (a camera bracket), are moved into that body's DH frame; the root link's and those
before the first moving joint become the base's, in frame 0.  Mesh files are resolved and
read (:mod:`robot_sim.io.meshes`) before the robot is built: one that cannot be found or
read is an error naming the URDF, the link and the URI, or with ``skip_missing_meshes`` a
warning (once per file) and a robot without it.  Links on branches behind moving joints are
left out with their geometry.
"""
from __future__ import annotations

import codecs
import dataclasses
import errno
import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from robot_sim.model.axes_dh import GEOMETRY_TOL, dh_frames_from_axes, modified_row
from robot_sim.model.convert import to_convention
from robot_sim.io.checker import MAX_JOINTS
from robot_sim.io.files import FileReadError, read_regular_file
from robot_sim.io.meshes import MeshReader
from robot_sim.io.urdf_shapes import LinkGeometry, MeshRef, Shape, link_geometry, materials, placed
from robot_sim.model.inertials import Drives, LinkInertials, _combine, inertia_from_elements
from robot_sim.model.params import (
    CONVENTION_MODIFIED,
    CONVENTIONS,
    JTYPE_PRISMATIC,
    JTYPE_REVOLUTE,
    RobotDefinitionError,
    RobotParams,
)
from robot_sim.model.messages import clip
from robot_sim.transforms import HomogeneousTransform, dh_transform

#: Joint types a chain may hold, and the ones refused there.
MOVING_TYPES = {"revolute": JTYPE_REVOLUTE, "continuous": JTYPE_REVOLUTE, "prismatic": JTYPE_PRISMATIC}
REFUSED_TYPES = ("floating", "planar")
JOINT_TYPES = (*MOVING_TYPES, "fixed", *REFUSED_TYPES)
#: Largest URDF file read (bytes): arm descriptions are far smaller.
MAX_URDF_BYTES = 16 << 20
#: The DH table must reproduce the URDF's joint frames to this (m, or rad).
CONSTRUCTION_TOL = 1e-9
_DECLARATION = re.compile(r"<!\s*(DOCTYPE|ENTITY)", re.IGNORECASE)


@dataclass(frozen=True)
class _Joint:
    name: str
    kind: str
    parent: str
    child: str
    origin: np.ndarray  # (4, 4) parent link → joint frame at q = 0
    axis: np.ndarray  # (3,) unit, in the joint frame
    lower: float
    upper: float
    effort: float
    velocity: float
    mimic: bool


@dataclass(frozen=True)
class _Inertial:
    mass: float  # kg
    origin: np.ndarray  # (4, 4) link frame → inertial frame (COM at its origin)
    inertia: np.ndarray  # (3, 3) about the COM, inertial-frame axes


class _Reader:
    """Checks one URDF document; every error names the file and the element."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def fail(self, where: str, message: str) -> RobotDefinitionError:
        return RobotDefinitionError(f"{self.path}: {where}: {message}")

    def floats(self, element: ET.Element | None, attr: str, count: int, default: list[float], where: str) -> np.ndarray:
        text = None if element is None else element.get(attr)
        if text is None:
            return np.array(default, dtype=float)
        try:
            values = [float(v) for v in text.split()]
        except ValueError:
            values = []
        if len(values) != count or not all(math.isfinite(v) for v in values):
            raise self.fail(f"{where} {attr}", f"expected {count} finite numbers, got {text!r}")
        return np.array(values)

    def joint(self, element: ET.Element, links: set[str]) -> _Joint:
        name = element.get("name", "")
        where = f"joint '{name}'"
        kind = element.get("type")
        if kind not in JOINT_TYPES:
            raise self.fail(where, f"unknown joint type {kind!r}; accepted: {', '.join(JOINT_TYPES)}")
        ends = {}
        for end in ("parent", "child"):
            tag = element.find(end)
            link = None if tag is None else tag.get("link")
            if link is None:
                raise self.fail(where, f"missing <{end} link=...>")
            if link not in links:
                raise self.fail(where, f"{end} link '{link}' is not declared as a <link>")
            ends[end] = link
        origin_tag = element.find("origin")
        xyz = self.floats(origin_tag, "xyz", 3, [0.0, 0.0, 0.0], f"{where} origin")
        rpy = self.floats(origin_tag, "rpy", 3, [0.0, 0.0, 0.0], f"{where} origin")
        origin = HomogeneousTransform.from_xyz_rpy(xyz, rpy).mat
        axis = self.floats(element.find("axis"), "xyz", 3, [1.0, 0.0, 0.0], f"{where} axis")
        norm = float(np.linalg.norm(axis))
        if kind in MOVING_TYPES and norm < GEOMETRY_TOL:
            raise self.fail(f"{where} axis", "the axis has zero length")
        lower, upper = -math.inf, math.inf
        limit = element.find("limit")
        if kind in ("revolute", "prismatic"):
            if limit is None:
                raise self.fail(where, f"a {kind} joint needs <limit lower=... upper=...>")
            lower, upper = (float(self.floats(limit, key, 1, [0.0], f"{where} limit")[0]) for key in ("lower", "upper"))
            if lower > upper:
                raise self.fail(f"{where} limit", f"lower {lower} > upper {upper}")
        effort, velocity = (float(self.floats(limit, key, 1, [0.0], f"{where} limit")[0]) for key in ("effort", "velocity"))
        return _Joint(name, kind, ends["parent"], ends["child"], origin, axis / max(norm, GEOMETRY_TOL),
                      lower, upper, abs(effort), abs(velocity), element.find("mimic") is not None)

    def inertial(self, link: ET.Element) -> _Inertial | None:
        element = link.find("inertial")
        if element is None:
            return None
        where = f"link '{link.get('name')}' inertial"
        origin_tag = element.find("origin")
        xyz = self.floats(origin_tag, "xyz", 3, [0.0, 0.0, 0.0], f"{where} origin")
        rpy = self.floats(origin_tag, "rpy", 3, [0.0, 0.0, 0.0], f"{where} origin")
        mass = float(self.floats(element.find("mass"), "value", 1, [0.0], f"{where} mass")[0])
        if mass < 0.0:
            raise self.fail(f"{where} mass", f"the mass is negative: {mass}")
        tensor = element.find("inertia")
        elements = [float(self.floats(tensor, key, 1, [0.0], f"{where} inertia")[0])
                    for key in ("ixx", "iyy", "izz", "ixy", "iyz", "ixz")]
        return _Inertial(mass, HomogeneousTransform.from_xyz_rpy(xyz, rpy).mat, inertia_from_elements(*elements))


def _parse(
    raw: bytes, path: Path
) -> tuple[str, list[str], list[_Joint], dict[str, _Inertial | None], dict[str, LinkGeometry]]:
    reader = _Reader(path)
    try:  # decoded here, so no declared encoding can hide a DOCTYPE from the check below
        text = raw.removeprefix(codecs.BOM_UTF8).decode("utf-8")
    except UnicodeDecodeError as exc:
        raise RobotDefinitionError(
            f"{path}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); save the URDF as UTF-8"
        ) from None
    if _DECLARATION.search(text):
        raise RobotDefinitionError(f"{path}: DOCTYPE and ENTITY declarations are not accepted in a URDF")
    try:
        root = ET.fromstring(text)
    except ET.ParseError as exc:
        raise RobotDefinitionError(f"{path}: malformed XML: {exc}") from None
    if root.tag != "robot":
        raise RobotDefinitionError(f"{path}: the root element is <{root.tag}>, expected <robot>")
    names = [link.get("name", "") for link in root.findall("link")]
    seen: set[str] = set()
    for name in names:
        if not name or name in seen:
            raise reader.fail(f"link '{name}'", "every <link> needs a unique non-empty name")
        seen.add(name)
    joint_elements = root.findall("joint")
    if not joint_elements:
        raise RobotDefinitionError(f"{path}: no joints: a URDF arm needs <joint> elements")
    joints = [reader.joint(j, seen) for j in joint_elements]
    inertials = {link.get("name", ""): reader.inertial(link) for link in root.findall("link")}
    named = materials(reader, root)
    geometry = {link.get("name", ""): link_geometry(reader, link, named) for link in root.findall("link")}
    return root.get("name", path.stem), names, joints, inertials, geometry


def _chain(path: Path, names: list[str], joints: list[_Joint], tip: str | None) -> list[_Joint]:
    """Joints from the root link to the tip link, checking that the links form a tree."""
    parent_joint: dict[str, _Joint] = {}
    for joint in joints:
        if joint.child in parent_joint:
            raise RobotDefinitionError(
                f"{path}: link '{joint.child}' has two parent joints ('{parent_joint[joint.child].name}' and "
                f"'{joint.name}'): URDF links must form a tree (a loop is not allowed)"
            )
        parent_joint[joint.child] = joint
    roots = [n for n in names if n not in parent_joint]
    if len(roots) != 1:
        if not roots:
            raise RobotDefinitionError(f"{path}: the joints form a loop: no link is the root")
        raise RobotDefinitionError(f"{path}: several root links ({clip(', '.join(roots))}): the links must form one tree")
    reaches_root = {roots[0]}  # links whose walk up ends at the root: each walked once, O(links)
    for name in names:  # a loop not through the root: walking up never reaches it
        walk, on_walk, link = [], set(), name
        while link not in reaches_root:
            if link in on_walk:
                raise RobotDefinitionError(f"{path}: the joints form a loop through link '{clip(link)}'")
            walk.append(link)
            on_walk.add(link)
            link = parent_joint[link].parent
        reaches_root.update(walk)
    if tip is None:
        has_child = {j.parent for j in joints}
        leaves = [n for n in names if n not in has_child]
        if len(leaves) > 1:
            raise RobotDefinitionError(
                f"{path}: the tree has several tips ({clip(', '.join(leaves))}); choose one with tip= (--tip LINK)"
            )
        tip = leaves[0]
    elif tip not in names:
        raise RobotDefinitionError(f"{path}: tip link '{clip(tip)}' is not declared; links: {clip(', '.join(names))}")
    chain, link = [], tip
    while link in parent_joint:
        chain.append(parent_joint[link])
        link = parent_joint[link].parent
    chain.reverse()
    for joint in chain:
        if joint.kind in REFUSED_TYPES:
            raise RobotDefinitionError(f"{path}: joint '{joint.name}': {joint.kind} joints cannot be part of a DH chain")
        if joint.mimic:
            raise RobotDefinitionError(f"{path}: joint '{joint.name}': mimic joints are not supported in the chain")
    if not any(j.kind in MOVING_TYPES for j in chain):
        raise RobotDefinitionError(f"{path}: no joints: the chain to '{tip}' has no revolute, continuous or prismatic joint")
    return chain


def load_urdf(
    path: str | Path, tip: str | None = None, convention: str = "standard", skip_missing_meshes: bool = False,
    contents: bytes | None = None,
) -> RobotParams:
    """A serial arm from a URDF file, as a DH robot in ``convention`` (see the module
    docstring for the construction), with its visual and collision geometry.  Raises
    RobotDefinitionError naming the file for anything it cannot load; a mesh file that
    cannot be found or read is left out with a MeshSkippedWarning when
    ``skip_missing_meshes``.  ``contents``, when given, is the URDF text of ``path`` (a
    xacro file's expansion): the file is not read, its folder anchors mesh paths."""
    path = Path(path)
    if convention not in CONVENTIONS:
        raise ValueError(f"convention must be 'standard' or 'modified', got {convention!r}")
    try:
        text = read_regular_file(path, MAX_URDF_BYTES) if contents is None else contents
    except FileReadError as exc:
        reason = "URDF file not found" if exc.errno == errno.ENOENT else f"cannot read URDF file: {exc.reason}"
        raise RobotDefinitionError(f"{path}: {reason}") from None
    name, names, joints, link_inertials, geometry = _parse(text, path)
    chain = _chain(path, names, joints, tip)
    moving = sum(j.kind in MOVING_TYPES for j in chain)
    if moving > MAX_JOINTS:  # before the geometry and the DH construction, which take time per joint
        raise RobotDefinitionError(f"{path}: {moving} joints; at most {MAX_JOINTS} are accepted")
    try:
        with np.errstate(all="ignore"):  # absurd numbers end as a refused value, not a warning
            robot = _build(path, name, chain, link_inertials)
            robot = _with_geometry(robot, path, chain, joints, geometry, MeshReader(_Reader(path).fail, skip_missing_meshes))
    except RobotDefinitionError:
        raise
    except ValueError as exc:  # values RobotParams or LinkInertials refuse (non-physical inertia, ...)
        raise RobotDefinitionError(f"{path}: {exc}") from None
    return to_convention(_with_source(robot, path, chain), convention)


def _build(path: Path, name: str, chain: list[_Joint], link_inertials: dict[str, _Inertial | None]) -> RobotParams:
    """The modified DH robot of a checked chain (root frame at q = 0)."""
    running = np.eye(4)
    points, axes, joint_x, moving = [], [], [], []
    parts: list[list[tuple[float, np.ndarray, np.ndarray]]] = []  # per body, in the root frame
    for joint in chain:
        running = running @ joint.origin
        if joint.kind in MOVING_TYPES:
            points.append(running[:3, 3].copy())
            axes.append(running[:3, :3] @ joint.axis)
            joint_x.append(running[:3, 0].copy())
            moving.append(joint)
            parts.append([])
        inertial = link_inertials[joint.child]
        if parts and inertial is not None:
            pose = running @ inertial.origin
            parts[-1].append((inertial.mass, pose[:3, 3], pose[:3, :3] @ inertial.inertia @ pose[:3, :3].T))
    tip_pose = running
    frames = dh_frames_from_axes(np.array(points), np.array(axes), np.array(joint_x))
    if not (np.isfinite(frames).all() and np.isfinite(tip_pose).all()):
        raise RobotDefinitionError(
            f"{path}: the joint origins add up to positions beyond floating point (inf or NaN); "
            "lengths must be metres of a real arm"
        )
    n = len(moving)
    rows = [(0.0, 0.0, 0.0, 0.0)] + [modified_row(np.linalg.inv(frames[i - 1]) @ frames[i]) for i in range(1, n)]
    a, alpha, theta, d = (np.array(col) for col in zip(*rows))
    _check_rows(path, frames, dh_transform(theta, d, a, alpha, "modified"))
    jtype = [MOVING_TYPES[j.kind] for j in moving]
    lo = np.array([j.lower for j in moving])
    hi = np.array([j.upper for j in moving])
    return RobotParams.from_arrays(
        name, a, alpha, d, theta, jtype,
        q_home=np.clip(0.0, lo, hi), q_min=lo, q_max=hi,
        base_tf=HomogeneousTransform(frames[0]),
        tool_tf=HomogeneousTransform(np.linalg.inv(frames[-1]) @ tip_pose),
        convention=CONVENTION_MODIFIED,
        inertials=_body_inertials(parts, frames),
        drives=_drives(moving),
    )


def _with_geometry(robot: RobotParams, path: Path, chain: list[_Joint], joints: list[_Joint],
                   geometry: dict[str, LinkGeometry], meshes: MeshReader) -> RobotParams:
    """The modified DH robot ``robot`` of ``chain`` with the geometry of its links (and of
    the links fixed to them off the chain) moved into the DH frames, meshes read."""
    frames = [robot.base_tf.mat]  # frame 0 in the root frame, then frame i at q = 0
    for i in range(robot.n_dofs):
        frames.append(frames[-1] @ dh_transform(robot.dh_th[i], robot.dh_d[i], robot.dh_a[i], robot.dh_alpha[i], "modified"))
    fixed_children: dict[str, list[_Joint]] = {}
    for joint in joints:
        if joint.kind == "fixed":
            fixed_children.setdefault(joint.parent, []).append(joint)
    on_chain = {chain[0].parent, *(j.child for j in chain)}
    bodies: list[list[tuple[str, np.ndarray]]] = [[] for _ in range(robot.n_dofs + 1)]  # (link, pose in root)

    def add(body: int, link: str, pose: np.ndarray) -> None:
        """``link`` and the links fixed to it off the chain (depth first) into ``body``."""
        stack = [(link, pose)]
        while stack:
            link, pose = stack.pop()
            bodies[body].append((link, pose))
            stack += [(j.child, pose @ j.origin) for j in reversed(fixed_children.get(link, [])) if j.child not in on_chain]

    running, body = np.eye(4), 0
    add(0, chain[0].parent, running)
    for joint in chain:
        running = running @ joint.origin
        body += joint.kind in MOVING_TYPES
        add(body, joint.child, running)
    out: dict[str, list[tuple[Shape, ...]]] = {"visuals": [], "collisions": []}
    for i, links in enumerate(bodies):
        to_frame = np.linalg.inv(frames[i])
        for key in out:
            items: list[tuple[np.ndarray, Shape | MeshRef]] = [
                (to_frame @ pose, item) for link, pose in links for item in getattr(geometry[link], key)
            ]
            out[key].append(placed(items, path.parent, meshes))
    return dataclasses.replace(robot, base_visuals=out["visuals"][0], base_collisions=out["collisions"][0],
                               visuals=tuple(out["visuals"][1:]), collisions=tuple(out["collisions"][1:]))


def _body_inertials(parts: list[list[tuple[float, np.ndarray, np.ndarray]]], frames: np.ndarray) -> LinkInertials | None:
    """Each body's parts (mass, COM, inertia about it; root frame at q = 0) lumped and
    expressed in its DH frame; None when the chain has no inertial at all."""
    if not any(parts):
        return None
    n = len(parts)
    mass, com, inertia = np.zeros(n), np.zeros((n, 3)), np.zeros((n, 3, 3))
    for i, body in enumerate(parts):
        R, o = frames[i][:3, :3], frames[i][:3, 3]
        if not body:
            continue
        if sum(m for m, _, _ in body) > 0.0:
            m, c, tensor = _combine(body)
        else:  # massless parts may still carry rotor-like inertia: no parallel-axis terms
            m, c, tensor = 0.0, o, sum(part[2] for part in body)
        mass[i], com[i] = m, R.T @ (c - o)
        local = R.T @ tensor @ R
        inertia[i] = 0.5 * (local + local.T)
    return LinkInertials.from_arrays(mass, com, inertia)


def _drives(moving: list[_Joint]) -> Drives | None:
    """Effort and velocity limits of the moving joints (0 = unknown = inf); None if all
    are unknown."""
    effort = np.array([j.effort or math.inf for j in moving])
    velocity = np.array([j.velocity or math.inf for j in moving])
    if not (np.isfinite(effort).any() or np.isfinite(velocity).any()):
        return None
    return Drives.from_arrays(len(moving), effort_limit=effort, velocity_limit=velocity)


def _check_rows(path: Path, frames: np.ndarray, links: np.ndarray) -> None:
    """The table's link transforms ``links`` (n, 4, 4) must rebuild the frames (a guard on
    the construction, which holds by design)."""
    rebuilt = frames[0]
    for i in range(1, len(frames)):
        rebuilt = rebuilt @ links[i]
        if not np.allclose(rebuilt, frames[i], atol=CONSTRUCTION_TOL):
            raise RobotDefinitionError(f"{path}: internal error: the DH table does not reproduce joint {i + 1}'s frame")


def _with_source(robot: RobotParams, path: Path, chain: list[_Joint]) -> RobotParams:
    return dataclasses.replace(
        robot, source=str(path),
        description=f"imported from URDF {path.name}: chain {chain[0].parent} → {chain[-1].child}",
    )

