"""Writing a robot as URDF (behind :mod:`urdf`): :func:`to_urdf`.

The URDF's link frames are the robot's *modified* DH frames (each on its joint's axis,
where URDF puts a joint frame), whatever convention the robot uses:

* link ``world`` (the root) → fixed joint ``base_joint`` (origin = ``base_tf``) → link
  ``link0`` = frame 0;
* joint ``joint{i}`` (revolute, continuous when unlimited, or prismatic) from ``link{i-1}``
  to ``link{i}`` with origin Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i) (the table at q = 0) and
  axis z: the URDF joint value is our q_i, in radians or metres;
* fixed joint ``tool_joint`` from ``link{n}`` to link ``tool0`` (origin = the tool transform,
  which for a standard robot also holds the last row's Tx(a_n) Rx(α_n)).

Limits are written when finite (position, and effort/velocity when the robot carries
drives with finite values; URDF requires the two attributes, so unknown ones are written as
0, which this package's importer reads back as unknown).  Inertials, when the robot has
them, are written in the URDF link frames.  So is the robot's geometry (base shapes on
``link0``, link i's on ``link{i}``; :mod:`robot_sim.io.urdf_shapes`), mesh filenames
relative to the URDF's folder when its path is given (capsules as ``<capsule>``, which
this package reads back).  A robot without geometry gets, so that other viewers show it, a
cylinder along each joint axis and one along the segment to the next joint at q = 0
(visual and collision alike), named ``dh_drawing`` so the importer leaves them out.
Numbers are written with ``repr`` (17 significant digits), so reading the file back loses
nothing.
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from robot_sim.model.convert import to_modified
from robot_sim.io.robot_file import MAX_LENGTH
from robot_sim.io.urdf_shapes import DH_DRAWING_NAME, write_shapes
from robot_sim.io.urdf_shapes import num_text as _num, write_origin as _origin
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.transforms import EPS_NORM, dh_transform, rotations_z_onto

#: Export geometry (metres): cylinder radius and length of a joint, radius of a link.
URDF_JOINT_RADIUS = 0.04
URDF_JOINT_LENGTH = 0.1
URDF_LINK_RADIUS = 0.025
#: Stroke (m) written for a prismatic joint without limits (URDF requires limits there).
URDF_UNLIMITED_STROKE = MAX_LENGTH  # the longest stroke a robot file (and load_robot) accepts


def _cylinder(link: ET.Element, mat: np.ndarray, radius: float, length: float) -> None:
    """Visual and collision cylinder of ``radius`` and ``length`` placed by ``mat`` (its
    centre and z axis) in the link frame."""
    for kind in ("visual", "collision"):
        element = ET.SubElement(link, kind, name=DH_DRAWING_NAME)
        _origin(element, mat)
        geometry = ET.SubElement(element, "geometry")
        ET.SubElement(geometry, "cylinder", radius=_num(radius), length=_num(length))


def _segment_cylinder(link: ET.Element, end: np.ndarray) -> None:
    """Cylinder from the link frame's origin to the point ``end`` (link coordinates)."""
    length = float(np.linalg.norm(end))
    if length < EPS_NORM:
        return
    mat = np.eye(4)
    mat[:3, :3] = rotations_z_onto(end)[0]
    mat[:3, 3] = 0.5 * end
    _cylinder(link, mat, URDF_LINK_RADIUS, length)


def _inertial(link: ET.Element, mass: float, com: np.ndarray, inertia: np.ndarray) -> None:
    element = ET.SubElement(link, "inertial")
    ET.SubElement(element, "origin", xyz=_num(com), rpy="0.0 0.0 0.0")
    ET.SubElement(element, "mass", value=_num(mass))
    I = inertia
    ET.SubElement(
        element, "inertia",
        ixx=_num(I[0, 0]), ixy=_num(I[0, 1]), ixz=_num(I[0, 2]), iyy=_num(I[1, 1]), iyz=_num(I[1, 2]), izz=_num(I[2, 2]),
    )


def _limit_values(robot: RobotParams, i: int) -> tuple[float, float]:
    """Effort and velocity limits of joint i from ``robot.drives`` (0 when unknown)."""
    drives = robot.drives
    if drives is None:
        return 0.0, 0.0
    effort, velocity = float(drives.effort_limit[i]), float(drives.velocity_limit[i])
    return (effort if np.isfinite(effort) else 0.0), (velocity if np.isfinite(velocity) else 0.0)


def to_urdf(robot: RobotParams, path: str | Path | None = None) -> str:
    """URDF text (an XML document) describing ``robot``: see the module docstring for the
    links and joints it holds.  Its forward kinematics equals the robot's (link ``tool0``
    is the endeffector) for every joint vector; joint values are the robot's q.  ``path``
    is where the text will be written: mesh filenames are relative to its folder
    (absolute when None).  ValueError for a mesh given as arrays (it has no file)."""
    mod = to_modified(robot)
    n = mod.n_dofs
    root = ET.Element("robot", name=robot.name)
    root.append(ET.Comment(
        f" written by robot-sim from a {robot.convention} DH table; link frames are the "
        "modified (Craig) DH frames, joint values are the robot's q (rad, m) "
    ))
    ET.SubElement(root, "link", name="world")
    links = [ET.SubElement(root, "link", name=f"link{i}") for i in range(n + 1)]
    ET.SubElement(root, "link", name="tool0")
    # joint origins at q = 0: Rx(α_{i-1}) Tx(a_{i-1}) Rz(θ_i) Tz(d_i)
    origins = dh_transform(mod.dh_th, mod.dh_d, mod.dh_a, mod.dh_alpha, "modified")
    inertials = getattr(mod, "inertials", None)
    directory = None if path is None else Path(path).parent
    drawn = mod.has_visuals or mod.has_collisions
    for i in range(n + 1):
        link = links[i]
        if i > 0 and inertials is not None:
            _inertial(link, inertials.mass[i - 1], inertials.com[i - 1], inertials.inertia[i - 1])
        if drawn:
            write_shapes(link, "visual", mod.visuals[i - 1] if i else mod.base_visuals, directory)
            write_shapes(link, "collision", mod.collisions[i - 1] if i else mod.base_collisions, directory)
            continue
        if i > 0:
            _cylinder(link, np.eye(4), URDF_JOINT_RADIUS, URDF_JOINT_LENGTH)
        end = origins[i][:3, 3] if i < n else mod.tool_tf.t()
        _segment_cylinder(link, np.asarray(end, dtype=float))

    def joint(name: str, kind: str, parent: str, child: str, mat: np.ndarray) -> ET.Element:
        element = ET.SubElement(root, "joint", name=name, type=kind)
        _origin(element, mat)
        ET.SubElement(element, "parent", link=parent)
        ET.SubElement(element, "child", link=child)
        return element

    joint("base_joint", "fixed", "world", "link0", mod.base_tf.mat)
    for i in range(n):
        revolute = mod.jtype[i] == JTYPE_REVOLUTE
        lo, hi = float(mod.q_min[i]), float(mod.q_max[i])
        limited = bool(np.isfinite(lo) and np.isfinite(hi))
        kind = "prismatic" if not revolute else ("revolute" if limited else "continuous")
        element = joint(f"joint{i + 1}", kind, f"link{i}", f"link{i + 1}", origins[i])
        ET.SubElement(element, "axis", xyz="0.0 0.0 1.0")
        effort, velocity = _limit_values(mod, i)
        if kind != "continuous":
            if not limited:  # an unlimited prismatic joint: URDF has no way to say so
                lo, hi = -URDF_UNLIMITED_STROKE, URDF_UNLIMITED_STROKE
            ET.SubElement(element, "limit", lower=_num(lo), upper=_num(hi), effort=_num(effort), velocity=_num(velocity))
        elif effort or velocity:
            ET.SubElement(element, "limit", effort=_num(effort), velocity=_num(velocity))
    joint("tool_joint", "fixed", f"link{n}", "tool0", mod.tool_tf.mat)
    ET.indent(root)
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"

