"""From identified motions back to a robot: an exact DH table of the robot's convention.

A Hayati row ``Rz(θ) Tz(d) Tx(a) Rx(α) Ry(β)`` puts joint j+1's axis on a line that a DH row
reaches only through the common normal of the two axes: its foot on joint j's axis sets d,
its direction x' sets θ, its length a and the angle between the axes α.  For axes within a
fraction of a degree of parallel that foot lies far away, so d is large (metres to
kilometres) and the next row's d cancels it, as in Universal Robots' factory calibration.
The DH frame differs from the Hayati one by a screw about the same axis, Rz(φ) Tz(δ), which
commutes with the next joint's motion and is absorbed into the next row's θ and d; so the
table's forward kinematics equals the identified model for every q, to rounding of order
1e-16 times the largest d.  Base and tool come from their xyz and roll-pitch-yaw values.

A tilt so small that the foot lies beyond :data:`~robot_sim.io.checker.MAX_LENGTH` (1 km, the
longest length a robot file holds; for a 0.4 m link, axes within 0.02° of parallel) has no
DH table that a file can hold or that float64 evaluates exactly: that row keeps its
Hayati-free values (beta dropped), and :attr:`CalibrationResult.table_error` reports the
difference this makes at the measured poses (a tilt β moves the tool by at most β times
the reach beyond the row).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from robot_sim.calibration.chain import Chain
from robot_sim.io.checker import MAX_LENGTH
from robot_sim.model.arrays import frozen
from robot_sim.model.params import RobotParams
from robot_sim.transforms import HomogeneousTransform, dh_transform, rot_y


def _near(angle: float, reference: float) -> float:
    """``angle`` plus the multiple of 2π that brings it nearest to ``reference``."""
    return angle + 2.0 * math.pi * round((reference - angle) / (2.0 * math.pi))


def common_normal(M: np.ndarray, x_ref: np.ndarray) -> tuple[float, float, float, float]:
    """(θ, d, a, α) of the standard DH row from the z axis to the z axis of ``M`` (4, 4) (a
    line through M's origin, not parallel to z): x' along the common normal, turned to
    point along ``x_ref`` (a direction perpendicular to z), at height d on the z axis."""
    o, u = M[:3, 3], M[:3, 2]
    nx, ny = -u[1], u[0]  # z × u
    sin2 = nx * nx + ny * ny
    norm = math.sqrt(sin2)
    x = np.array([nx, ny, 0.0]) / norm
    if x @ x_ref < 0.0:
        x = -x
    s = -(o[0] * u[0] + o[1] * u[1]) / sin2  # foot on the line: o + s u (no cancellation)
    d = o[2] + s * u[2]
    y = np.array([-x[1], x[0], 0.0])
    return math.atan2(x[1], x[0]), d, float(o @ x), math.atan2(-float(u @ y), float(u[2]))


def to_robot(chain: Chain) -> RobotParams:
    """The robot of ``chain``'s values: same convention, limits, inertials and geometry as
    ``chain.robot``; Hayati rows converted as the module docstring says."""
    robot = chain.robot
    n = robot.n_dofs
    value = dict(zip(chain.name, chain.value.tolist()))
    th = [value[f"theta_offset{j + 1}"] for j in range(n)]
    d = [value[f"d{j + 1}"] for j in range(n)]
    a = [value[f"a{r + 1}"] for r in range(n)]
    alpha = [value[f"alpha{r + 1}"] for r in range(n)]
    for j in range(n - 1):
        r = j + 1 if robot.is_modified else j  # the row holding the (a, α) after joint j
        beta = value.get(f"beta{r + 1}", 0.0)
        if beta == 0.0:
            continue
        M = dh_transform(th[j], d[j], a[r], alpha[r])
        M[:3, :3] = M[:3, :3] @ rot_y(beta)
        new_th, new_d, new_a, new_alpha = common_normal(M, np.array([math.cos(th[j]), math.sin(th[j]), 0.0]))
        if abs(new_d) > MAX_LENGTH:
            continue  # beyond a robot file's lengths (and float precision): the table keeps beta = 0
        new_th, a[r], alpha[r] = _near(new_th, th[j]), new_a, new_alpha
        C = np.linalg.solve(dh_transform(new_th, new_d, a[r], alpha[r]), M)  # Rz(φ) Tz(δ)
        th[j], d[j] = new_th, new_d
        th[j + 1] = _near(th[j + 1] + math.atan2(C[1, 0], C[0, 0]), th[j + 1])
        d[j + 1] += C[2, 3]
    return dataclasses.replace(
        robot,
        dh_th=frozen(th), dh_d=frozen(d), dh_a=frozen(a), dh_alpha=frozen(alpha),
        base_tf=_frame(chain, "base", robot.base_tf), tool_tf=_frame(chain, "tool", robot.tool_tf),
    )


def _frame(chain: Chain, prefix: str, nominal: HomogeneousTransform) -> HomogeneousTransform:
    """The base or tool transform of the chain's values (``nominal`` itself if unchanged)."""
    keys = ("x", "y", "z", "rx", "ry", "rz")
    index = [chain.name.index(f"{prefix}.{k}") for k in keys]
    if np.array_equal(chain.value[index], chain.nominal[index]):
        return nominal
    return HomogeneousTransform.from_xyz_rpy(chain.value[index[:3]], chain.value[index[3:]])
