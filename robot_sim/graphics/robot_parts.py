"""The robot drawn as it is built from its DH table (pure NumPy here, no GL).

Every link is drawn as its DH segments, so offsets and columns show as they are:

* standard DH, ``A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)``: from frame i−1's origin along
  z_{i−1} by d_i (the *axis segment*, on joint i's axis), then along x_i by a_i (the
  *offset segment*) to frame i's origin; joint i sits at frame i−1's origin on z_{i−1};
* modified DH (Craig), ``A_i = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θ_i) Tz(d_i)``: from frame
  i−1's origin along x_{i−1} by a_{i−1} (offset segment), then along z_i by d_i (axis
  segment) to frame i's origin; joint i sits where the axis segment starts, on z_i.

Both are read off the world frames (``d`` and ``a`` are projections of the step between
two origins), so the picture is exactly what the kinematics computed.  Revolute joints
are closed cylinders on their axes; a prismatic joint is a sleeve fixed to the previous
link that is as long as the stroke and ends where the joint's travel starts, and a rod
of the same length whose tip is the moving end of the axis segment (so the rod sticks
out of the sleeve by how far the joint has travelled).

Part sizes (:class:`RobotLook`) come from each link's own dimensions, clamped to
fractions of the robot's reach, and are shrunk at the home pose until no joint reaches
into a neighbouring joint or the endeffector.  World frame, metres.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.graphics import defs as gd
from robot_sim.graphics.placements import along, spheres
from robot_sim.kernels.model import per_robot
from robot_sim.kinematics import Kinematics, forward_kinematics
from robot_sim.model.params import CONVENTION_STANDARD, JTYPE_PRISMATIC, RobotParams

RGBA = tuple[float, float, float, float]


def robot_reach(robot: RobotParams) -> float:
    """Size of ``robot`` for drawing [m]: :attr:`RobotParams.size` clamped to
    [``REACH_MIN``, ``REACH_MAX``]."""
    return float(np.clip(robot.size, gd.REACH_MIN, gd.REACH_MAX))


@dataclass(frozen=True)
class DHSegments:
    """The DH construction of every link from world frames 0..n (n joints), arrays (n, ...).

    ``joint`` (n, 3): where joint i sits; ``axis_frame`` (n, 4, 4): the frame whose z is
    joint i's axis (frame i−1 standard, frame i modified); ``axis_start``/``axis_end``
    (n, 3): the axis segment (length |d_i|); ``offset_start``/``offset_end`` (n, 3): the
    offset segment (length |a_i| standard, |a_{i−1}| modified); ``d`` and ``a`` (n,): the
    signed lengths along the axis and along the offset direction; ``bend`` (n, 3): the
    point between the two segments.
    """

    joint: NDArray[np.float64]
    axis_frame: NDArray[np.float64]
    axis_start: NDArray[np.float64]
    axis_end: NDArray[np.float64]
    offset_start: NDArray[np.float64]
    offset_end: NDArray[np.float64]
    d: NDArray[np.float64]
    a: NDArray[np.float64]
    bend: NDArray[np.float64]

    @property
    def axis(self) -> NDArray[np.float64]:
        """Unit joint axes (n, 3), world."""
        return self.axis_frame[:, :3, 2]


def dh_segments(frames: NDArray[np.float64], modified: bool) -> DHSegments:
    """The DH segments of the links between world ``frames`` (n+1, 4, 4) (frames 0..n) of
    a standard or (``modified``) Craig DH chain.  Batched over the joints."""
    frames = np.asarray(frames, dtype=float)
    prev, nxt = frames[:-1], frames[1:]
    o0, o1 = prev[:, :3, 3], nxt[:, :3, 3]
    step = o1 - o0
    if modified:
        x_prev = prev[:, :3, 0]
        a = np.einsum("ij,ij->i", step, x_prev)
        bend = o0 + a[:, None] * x_prev
        axis_frame = nxt
        d = np.einsum("ij,ij->i", o1 - bend, nxt[:, :3, 2])
        return DHSegments(bend, axis_frame, bend, o1, o0, bend, d, a, bend)
    z_prev = prev[:, :3, 2]
    d = np.einsum("ij,ij->i", step, z_prev)
    bend = o0 + d[:, None] * z_prev
    a = np.einsum("ij,ij->i", o1 - bend, nxt[:, :3, 0])
    return DHSegments(o0, prev, o0, bend, bend, o1, d, a, bend)


def _prismatic_travel(robot: RobotParams, reach: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Per joint (n,): the d at the start of a prismatic joint's travel (its lower limit)
    and the stroke (upper − lower limit; ``UNLIMITED_STROKE_FRAC`` of the reach when a
    limit is infinite); zeros for revolute joints."""
    prismatic = robot.jtype == JTYPE_PRISMATIC
    limited = np.isfinite(robot.q_min) & np.isfinite(robot.q_max)
    lower = np.where(np.isfinite(robot.q_min), robot.q_min, robot.q_home)
    stroke = np.where(limited, robot.q_max - robot.q_min, gd.UNLIMITED_STROKE_FRAC * reach)
    return np.where(prismatic, robot.dh_d + lower, 0.0), np.where(prismatic, stroke, 0.0)


@dataclass(frozen=True)
class RobotLook:
    """Part sizes (metres) of one robot, fixed for it (computed at its home pose).

    ``joint_radius`` and ``joint_half_length`` (n,): revolute cylinders (a prismatic
    sleeve's half width is ``PRISMATIC_SLEEVE_RATIO`` times the radius);
    ``link_radius`` (n + 1,): the segments of link i (index i − 1) and the tool segment
    (index n); ``endeff_radius``, ``com_radius`` (n,) and ``base_radius``; ``travel_start``
    and ``stroke`` (n,) of prismatic joints (0 for revolute); ``frame_length``: axis
    length of a drawn frame; ``reach``: the robot's scale.
    """

    reach: float
    joint_radius: NDArray[np.float64]
    joint_half_length: NDArray[np.float64]
    link_radius: NDArray[np.float64]
    endeff_radius: float
    com_radius: NDArray[np.float64]
    base_radius: float
    travel_start: NDArray[np.float64]
    stroke: NDArray[np.float64]
    frame_length: float


def robot_look(robot: RobotParams) -> RobotLook:
    """The part sizes of ``robot``, computed once and kept with its compiled model
    (robot_sim.kernels.model.per_robot, the package's one per-robot cache)."""
    return per_robot(robot, "graphics.robot_look", _robot_look)


def _robot_look(robot: RobotParams) -> RobotLook:
    """The part sizes of ``robot``: each joint sized from the link it moves, or a
    fraction ``JOINT_INCOMING_WEIGHT`` of the link it sits on if that is more
    (``JOINT_RADIUS_LOCAL_FRAC``), clamped to [``JOINT_RADIUS_MIN_FRAC``,
    ``JOINT_RADIUS_MAX_FRAC``] of the reach, then shrunk at home until its radius is at
    most ``JOINT_CLEARANCE`` of the distance to any other joint (two joints' cylinders
    may cross, neither swallows the other); a joint near the
    endeffector and the endeffector sphere shrink together until they do not meet (an
    endeffector sitting in a joint is drawn a little wider than the joint instead, and
    the joint a little longer, so both show)."""
    n, reach = robot.n_dofs, robot_reach(robot)
    floor = gd.PART_MIN_FRAC * reach
    home = forward_kinematics(robot, robot.q_home, all_frames=True)
    seg = dh_segments(home[:-1], robot.is_modified)
    travel_start, stroke = _prismatic_travel(robot, reach)
    link_length = np.abs(seg.d) + np.abs(seg.a) + stroke
    local = np.maximum(link_length, gd.JOINT_INCOMING_WEIGHT * np.r_[0.0, link_length[:-1]])
    radius = np.clip(gd.JOINT_RADIUS_LOCAL_FRAC * local, gd.JOINT_RADIUS_MIN_FRAC * reach, gd.JOINT_RADIUS_MAX_FRAC * reach)
    half = gd.JOINT_HALF_LENGTH_RATIO * radius
    bound = np.hypot(radius, half)

    centres, endeff = seg.joint, home[-1, :3, 3]
    gaps = np.linalg.norm(centres[:, None] - centres[None], axis=-1)
    gaps[gaps <= max(gd.MIN_LINK_LENGTH, gd.JOINT_CROSSING_FRAC * reach)] = np.inf  # joints (nearly) at one point cross
    shrink = np.minimum(1.0, gd.JOINT_CLEARANCE * gaps.min(axis=1) / radius)
    radius, half, bound = radius * shrink, half * shrink, bound * shrink

    endeff_radius = max(gd.ENDEFF_RADIUS_RATIO * float(radius[-1]) if n else 0.0, gd.ENDEFF_MIN_FRAC * reach)
    to_endeff = np.linalg.norm(centres - endeff, axis=1)
    inside = to_endeff < gd.ENDEFF_COINCIDENT_RATIO * endeff_radius
    # a joint near the endeffector and the sphere both shrink until they do not meet
    fit = np.where(inside, 1.0, np.minimum(1.0, to_endeff / (bound + endeff_radius)))
    radius, half = radius * fit, half * fit
    endeff_radius *= float(fit.min()) if n else 1.0
    if inside.any():  # the endeffector sits in a joint: a sphere wider than it, the joint longer
        endeff_radius = max(endeff_radius, gd.ENDEFF_NEAR_RATIO * float(radius[inside].max()))
        half = np.where(inside, np.maximum(half, gd.ENDEFF_NEAR_RATIO * endeff_radius + to_endeff), half)
    radius, half = np.maximum(radius, floor), np.maximum(half, floor)

    ends = np.r_[radius, endeff_radius]
    link_radius = np.maximum(gd.LINK_RADIUS_RATIO * np.minimum(ends[:-1], ends[1:]), floor)
    link_radius = np.r_[link_radius, max(gd.LINK_RADIUS_RATIO * endeff_radius, floor)]
    return RobotLook(
        reach=reach,
        joint_radius=radius,
        joint_half_length=half,
        link_radius=link_radius,
        endeff_radius=float(max(endeff_radius, floor)),
        com_radius=gd.COM_RADIUS_RATIO * link_radius[:-1],
        base_radius=gd.BASE_PLATE_RATIO * float(radius[0]) if n else floor,
        travel_start=travel_start,
        stroke=stroke,
        frame_length=gd.FRAME_LENGTH_FRAC * reach,
    )


@dataclass(frozen=True)
class Part:
    """Copies of one unit mesh in one colour: ``mesh`` names a unit mesh
    (``robot_sim.graphics.meshes.unit_meshes``), ``placements`` (N, 4, 4) place it in the world."""

    mesh: str
    color: RGBA
    placements: NDArray[np.float64]


def _boxes(frames: NDArray[np.float64], start: NDArray, length: NDArray, half_width: NDArray) -> NDArray[np.float64]:
    """Placements (N, 4, 4) of unit boxes along the z axes of ``frames`` (N, 4, 4), from
    ``start`` to ``start + length`` (N,) along z, ``2 * half_width`` (N,) across."""
    mats = frames.copy()
    scale = np.stack([2.0 * half_width, 2.0 * half_width, np.abs(length)], axis=-1)
    mats[:, :3, :3] = frames[:, :3, :3] * scale[:, None, :]
    mats[:, :3, 3] = frames[:, :3, 3] + (start + 0.5 * length)[:, None] * frames[:, :3, 2]
    return mats


def _rods(origins: NDArray, vecs: NDArray, radii: NDArray) -> NDArray[np.float64]:
    """Placements of unit cylinders from ``origins`` along ``vecs`` (N, 3); zero-length
    ones are dropped."""
    lengths = np.linalg.norm(vecs, axis=1)
    keep = lengths >= gd.MIN_LINK_LENGTH
    return along(origins[keep], vecs[keep], np.asarray(radii)[keep], lengths[keep])


def robot_parts(robot: RobotParams, frames: NDArray[np.float64], endeff: NDArray[np.float64],
                link_com: NDArray[np.float64] | None = None) -> list[Part]:
    """Everything drawn for ``robot`` posed at world ``frames`` (n+1, 4, 4) with the
    endeffector pose ``endeff`` (4, 4): base plate, links as DH segments, revolute joint
    cylinders, prismatic sleeves and rods, tool segment, endeffector sphere, and, when
    ``link_com`` (n+1, 3) is given, the centres of mass of links 1..n (row 0, the base,
    is not drawn)."""
    look = robot_look(robot)
    seg = dh_segments(frames, robot.is_modified)
    prismatic = robot.jtype == JTYPE_PRISMATIC
    r = look.joint_radius
    link_r = look.link_radius[:-1]
    base = frames[0].copy()
    base_thickness = gd.BASE_PLATE_THICKNESS_RATIO * look.base_radius
    base[:3, :3] = base[:3, :3] @ np.diag([look.base_radius, look.base_radius, base_thickness])
    base[:3, 3] -= frames[0, :3, 2] * base_thickness
    axis_vecs = seg.axis_end - seg.axis_start
    at_joint = seg.axis_frame.copy()  # joint i's axis frame moved to where the joint sits
    at_joint[:, :3, 3] = seg.joint
    rev = ~prismatic
    half = look.joint_half_length[rev]
    cylinders = at_joint[rev]
    cylinders[:, :3, :3] = cylinders[:, :3, :3] * np.stack([r[rev], r[rev], 2.0 * half], -1)[:, None, :]
    cylinders[:, :3, 3] -= half[:, None] * seg.axis[rev]
    # a prismatic joint's sleeve ends where its travel starts and is as long as the
    # stroke; its rod, as long too, ends at the moving end of the axis segment; a link
    # piece joins the joint to a sleeve that starts farther out
    start, stroke, axis = look.travel_start[prismatic], look.stroke[prismatic], seg.axis[prismatic]
    sleeves = _boxes(at_joint[prismatic], start - stroke, stroke, gd.PRISMATIC_SLEEVE_RATIO * r[prismatic])
    rod_tip = seg.axis_end[prismatic]
    rods = np.concatenate([
        _rods(rod_tip - stroke[:, None] * axis, stroke[:, None] * axis, gd.PRISMATIC_ROD_RATIO * r[prismatic]),
        _rods(seg.joint[prismatic], np.maximum(start - stroke, 0.0)[:, None] * axis, link_r[prismatic]),
    ])
    link_segments = np.concatenate([
        _rods(seg.axis_start[rev], axis_vecs[rev], link_r[rev]),
        _rods(seg.offset_start, seg.offset_end - seg.offset_start, link_r),
        _rods(frames[-1:, :3, 3], endeff[None, :3, 3] - frames[-1:, :3, 3], look.link_radius[-1:]),
    ])
    return [
        Part("joint", gd.BASE_COLOR, base[None]),
        Part("cylinder", gd.LINK_COLOR, link_segments),
        Part("cylinder", gd.LINK_COLOR, rods),
        Part("joint", gd.JOINT_COLOR, cylinders),
        Part("box", gd.JOINT_COLOR, sleeves),
        Part("sphere", gd.ENDEFF_COLOR, spheres(endeff[:3, 3], look.endeff_radius)),
    ] + ([] if link_com is None else [Part("sphere", gd.COM_COLOR, spheres(link_com[1:], look.com_radius))])


def differing_masks(parts: list[Part], reference: list[Part], tol: float = gd.GHOST_TOLERANCE) -> list[NDArray[np.bool_]]:
    """Per part of ``parts``, which copies (N,) ``reference`` (the same robot's parts in
    another pose, in the same order) has nowhere within ``tol`` of the same placement."""
    out = []
    for part, ref in zip(parts, reference):
        if len(part.placements) and len(ref.placements):
            gap = np.abs(part.placements[:, None, :3, :] - ref.placements[None, :, :3, :]).max(axis=(2, 3))
            out.append(gap.min(axis=1) > tol)
        else:
            out.append(np.ones(len(part.placements), dtype=bool))
    return out


def differing(parts: list[Part], reference: list[Part], tol: float = gd.GHOST_TOLERANCE) -> list[Part]:
    """``parts`` without the copies that ``reference`` has at the same placement within
    ``tol`` (:func:`differing_masks`): what a ghost shows where it differs from the arm."""
    return [Part(part.mesh, part.color, part.placements[keep])
            for part, keep in zip(parts, differing_masks(parts, reference, tol))]


def branch_label_point(kinematics: Kinematics) -> np.ndarray:
    """Where a drawn branch's name is written (world, m): on the axis of its middle joint
    j = ceil(n / 2) (the elbow of a 6-joint arm: where the arm postures differ most), at
    the origin of the frame that joint turns (standard DH: frame j - 1; modified: frame j)."""
    joint = (kinematics.robot.n_dofs + 1) // 2
    index = joint - 1 if kinematics.robot.convention == CONVENTION_STANDARD else joint
    return np.asarray(kinematics.frames[index][:3, 3], dtype=float)


# corners of the unit meshes' bounding boxes (see robot_sim.graphics.meshes): z from 0 to 1 for the
# cylinder-like ones, centred for the sphere and the box
_MESH_CORNERS = {
    "sphere": np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float),
    "box": 0.5 * np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float),
}
_MESH_CORNERS["cylinder"] = _MESH_CORNERS["joint"] = _MESH_CORNERS["cone"] = _MESH_CORNERS["sphere"] * (1, 1, 0.5) + (0, 0, 0.5)


def part_corners(parts: list[Part]) -> NDArray[np.float64]:
    """World corners (N, 3) of the bounding boxes of every copy in ``parts``."""
    out = [np.einsum("nij,kj->nki", p.placements[:, :3, :3], _MESH_CORNERS[p.mesh]) + p.placements[:, None, :3, 3]
           for p in parts if len(p.placements)]
    return np.concatenate([c.reshape(-1, 3) for c in out]) if out else np.zeros((0, 3))
