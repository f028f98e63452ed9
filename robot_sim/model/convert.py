"""Exact conversion between the standard and the modified (Craig) DH conventions.

Both conventions build the same chain from the same four motions per joint, only grouped
differently along it: the standard product Rz(θ_1)Tz(d_1) · [Tx(a_1)Rx(α_1) Rz(θ_2)Tz(d_2)] ⋯
[Tx(a_{n-1})Rx(α_{n-1}) Rz(θ_n)Tz(d_n)] · Tx(a_n)Rx(α_n) is the modified one with
a_{i-1}, α_{i-1} of modified row i equal to a_{i-1}, α_{i-1} of standard row i-1 (Tx and Rx
commute).  So θ, d, joint types, joint variables, limits and home stay as they are; the
a and α columns shift by one row, and what has no row on the other side goes into the
base or the tool:

* standard → modified: modified row 1 gets a_0 = α_0 = 0 and the tool absorbs the last
  standard row's Tx(a_n)Rx(α_n);
* modified → standard: the base absorbs modified row 1's Rx(α_0)Tx(a_0) and the last
  standard row gets a_n = α_n = 0.

The endeffector pose is the same for every q (to rounding).  Intermediate frames differ:
with (a_i, α_i) of *standard* row i, standard frame i = modified frame i · Tx(a_i)Rx(α_i),
that is standard frame i has the z axis of joint i+1 (modified z_{i+1}) and sits where the
common normal from joint i meets joint i+1, while modified frame i sits on joint i's own
axis.  Frame 0 agrees except after modified → standard when modified row 1 has a_0 or
α_0 ≠ 0 (the base absorbs them: new frame 0 = old frame 0 · Rx(α_0)Tx(a_0)).
Link inertials (given in frame i of the robot's convention) move with the frames: the
COM and the inertia tensor of link i are re-expressed through that constant
Tx(a_i)Rx(α_i), so dynamics agree too.  ``link_com_frac`` (a drawing aid: the fraction
between the origins of frames i-1 and i) is kept as it is.
"""
from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import NDArray

from robot_sim.model.arrays import frozen
from robot_sim.model.inertials import LinkInertials
from robot_sim.model.params import CONVENTION_MODIFIED, CONVENTION_STANDARD, RobotParams
from robot_sim.transforms import HomogeneousTransform, dh_transform


def _x_motion(a: float, alpha: float) -> HomogeneousTransform:
    """Tx(a) Rx(α) (= Rx(α) Tx(a)) as a transform."""
    return HomogeneousTransform(dh_transform(0.0, 0.0, a, alpha))


def _moved_inertials(
    inertials: LinkInertials | None, a: NDArray[np.float64], alpha: NDArray[np.float64], inverse: bool
) -> LinkInertials | None:
    """Inertials re-expressed from standard frames i to modified frames i (``inverse``
    False: p_mod = S_i p_std with S_i = Tx(a_i)Rx(α_i) of standard row i) or back."""
    if inertials is None:
        return None
    S = dh_transform(0.0, 0.0, a, alpha)  # (n, 4, 4)
    R, t = S[:, :3, :3], S[:, :3, 3]
    if inverse:
        com = np.einsum("nji,nj->ni", R, inertials.com - t)
        inertia = np.swapaxes(R, 1, 2) @ inertials.inertia @ R
    else:
        com = np.einsum("nij,nj->ni", R, inertials.com) + t
        inertia = R @ inertials.inertia @ np.swapaxes(R, 1, 2)
    inertia = 0.5 * (inertia + np.swapaxes(inertia, 1, 2))  # exactly symmetric
    return LinkInertials.from_arrays(inertials.mass, com, inertia, inertials.estimated)


def _moved_geometry(robot: RobotParams, a: NDArray[np.float64], alpha: NDArray[np.float64], inverse: bool) -> dict:
    """Link shapes re-posed from standard frames i to modified frames i (``inverse``
    False: pose_mod = S_i pose_std with S_i = Tx(a_i)Rx(α_i) of standard row i) or back
    (pose_std = S_i⁻¹ pose_mod, and the base's shapes by (Rx(α_0)Tx(a_0))⁻¹ of modified
    row 1, which the new base absorbs): the fields to replace."""
    sign = -1.0 if inverse else 1.0  # (Tx(a)Rx(α))⁻¹ = Tx(-a)Rx(-α)
    S = dh_transform(0.0, 0.0, sign * a, sign * alpha)  # (n, 4, 4)
    fields = {key: tuple(tuple(shape.moved(S[i]) for shape in shapes) for i, shapes in enumerate(getattr(robot, key)))
              for key in ("visuals", "collisions")}
    if inverse:
        to_base = dh_transform(0.0, 0.0, -robot.dh_a[0], -robot.dh_alpha[0])
        fields.update({key: tuple(shape.moved(to_base) for shape in getattr(robot, key))
                       for key in ("base_visuals", "base_collisions")})
    return fields


def to_modified(robot: RobotParams) -> RobotParams:
    """The same robot as a modified (Craig) DH table; returned unchanged if it is one.

    Modified row i takes a_{i-1}, α_{i-1} from standard row i-1 (row 1 gets 0, 0); the tool
    absorbs the last standard row's Tx(a_n)Rx(α_n).  θ, d, joints, limits and the base are
    kept.  Modified frame i = standard frame i · (Tx(a_i)Rx(α_i))⁻¹ (on joint i's axis);
    inertials are re-expressed in it and link shapes re-posed (frame 0 and the base's
    shapes stay).
    """
    if robot.is_modified:
        return robot
    return dataclasses.replace(
        robot,
        inertials=_moved_inertials(robot.inertials, robot.dh_a, robot.dh_alpha, inverse=False),
        dh_a=frozen(np.concatenate([[0.0], robot.dh_a[:-1]])),
        dh_alpha=frozen(np.concatenate([[0.0], robot.dh_alpha[:-1]])),
        tool_tf=_x_motion(robot.dh_a[-1], robot.dh_alpha[-1]) @ robot.tool_tf,
        convention=CONVENTION_MODIFIED,
        **_moved_geometry(robot, robot.dh_a, robot.dh_alpha, inverse=False),
    )


def to_standard(robot: RobotParams) -> RobotParams:
    """The same robot as a standard DH table; returned unchanged if it is one.

    Standard row i takes a_i, α_i from modified row i+1 (the last row gets 0, 0); the base
    absorbs modified row 1's Rx(α_0)Tx(a_0).  θ, d, joints, limits and the tool are kept.
    Standard frame i = modified frame i · Tx(a_i)Rx(α_i) (with the new row i's a_i, α_i):
    z along joint i+1's axis; inertials are re-expressed in it and link shapes re-posed,
    the base's shapes into the new frame 0.
    """
    if not robot.is_modified:
        return robot
    a, alpha = np.concatenate([robot.dh_a[1:], [0.0]]), np.concatenate([robot.dh_alpha[1:], [0.0]])
    return dataclasses.replace(
        robot,
        inertials=_moved_inertials(robot.inertials, a, alpha, inverse=True),
        dh_a=frozen(a),
        dh_alpha=frozen(alpha),
        base_tf=robot.base_tf @ _x_motion(robot.dh_a[0], robot.dh_alpha[0]),
        convention=CONVENTION_STANDARD,
        **_moved_geometry(robot, a, alpha, inverse=True),
    )


def to_convention(robot: RobotParams, convention: str) -> RobotParams:
    """:func:`to_standard` or :func:`to_modified` by name; ValueError for another name."""
    if convention == CONVENTION_STANDARD:
        return to_standard(robot)
    if convention == CONVENTION_MODIFIED:
        return to_modified(robot)
    raise ValueError(f"convention must be 'standard' or 'modified', got {convention!r}")
