"""The calibration model: a robot as one sequence of elementary motions, its batched forward
kinematics and its analytic parameter Jacobian.

Every DH row, the base and the tool are products of rotations and translations along a
local axis (x, y or z of the frame reached so far), so the whole chain is one list of
*motions*, each with a constant value (a parameter) to which a joint variable may be added::

    base:      Tx(base.x) Ty(base.y) Tz(base.z) Rz(base.rz) Ry(base.ry) Rx(base.rx)
    modified:  Tx(a1) Rx(alpha1)                      (Craig's a_0, α_0 of row 1)
    joint j:   Rz(theta_offset_j [+ q_j]) Tz(d_j [+ q_j]) Tx(a) Rx(alpha) [Ry(beta)]
    tool:      Tx(tool.x) Ty(tool.y) Tz(tool.z) Rz(tool.rz) Ry(tool.ry) Rx(tool.rx)

where the (a, α) after joint j are row j's in a standard table and row j+1's in a modified
one (Tx and Rx commute, so both conventions are this one sequence: see
:mod:`robot_sim.model.convert`).  The base and the tool are xyz and roll-pitch-yaw as in
robot files (``Rz(yaw) Ry(pitch) Rx(roll)``); the tool transform maps the tool frame to
frame n.  ``Ry(beta)`` is Hayati's extra rotation, present after a joint whose axis is
(nearly) parallel to the next one's; there the joint's d is held (it slides along both
axes) and beta, a tilt about the common normal's perpendicular, is identified instead.

The derivative of the tool pose with respect to one motion's value is that motion's unit
twist: a rotation about world axis u through point o moves the tool point by u × (p − o)
and turns the tool by u; a translation along u moves it by u.  So the parameter Jacobian
is built like the geometric joint Jacobian, from the frames of one walk along the chain,
vectorised over poses (the loop runs over motions, never over configurations).
Units: metres and radians; poses and positions are in the frame the base is given in
(the measuring instrument's).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.transforms import HomogeneousTransform, rpy_from_rot

FloatArray = NDArray[np.float64]

ROTATION, TRANSLATION = 0, 1
X, Y, Z = 0, 1, 2
#: Axes within this angle [rad] of parallel (α near 0 or π) get Hayati's beta (10°).
HAYATI_ANGLE = np.deg2rad(10.0)
#: Parameter groups of :func:`robot_sim.calibration.calibrate`'s ``identify``.
GROUPS = ("dh", "joint_offsets", "base", "tool")
_FRAME_MOTIONS = ((TRANSLATION, X, "x"), (TRANSLATION, Y, "y"), (TRANSLATION, Z, "z"),
                  (ROTATION, Z, "rz"), (ROTATION, Y, "ry"), (ROTATION, X, "rx"))


@dataclass(frozen=True)
class Chain:
    """A robot as K elementary motions (see the module docstring), arrays of length K.

    ``kind``: ROTATION or TRANSLATION; ``axis``: 0, 1, 2 for local x, y, z; ``joint``: the
    joint whose variable is added (-1 for none); ``value``: the constant [m or rad];
    ``name``: the parameter's name (``a3``, ``alpha2``, ``theta_offset4``, ``beta2``,
    ``base.x``, ``tool.rz``); ``group``: its entry in :data:`GROUPS`; ``held``: True for
    a Hayati row's d (never identified: it slides along two parallel axes).  ``row`` and
    ``field`` say where a DH value lives in the robot's table (row -1 for base, tool and
    beta)."""

    robot: RobotParams
    kind: NDArray[np.int64]
    axis: NDArray[np.int64]
    joint: NDArray[np.int64]
    value: FloatArray
    nominal: FloatArray
    name: tuple[str, ...]
    group: tuple[str, ...]
    held: NDArray[np.bool_]
    row: NDArray[np.int64]
    field: tuple[str, ...]

    @property
    def size(self) -> int:
        """Number of motions K."""
        return len(self.name)

    def with_values(self, value: FloatArray) -> "Chain":
        """The same chain with other constants (K,)."""
        return dataclasses.replace(self, value=np.asarray(value, dtype=float))

    @property
    def is_angle(self) -> NDArray[np.bool_]:
        """True for the motions whose value is an angle [rad]."""
        return self.kind == ROTATION


def hayati_rows(robot: RobotParams) -> list[int]:
    """Rows (0-based) of the table whose (a, α) join two (nearly) parallel joint axes,
    within :data:`HAYATI_ANGLE`: standard rows 1..n-1, modified rows 2..n."""
    rows = range(robot.n_dofs - 1) if not robot.is_modified else range(1, robot.n_dofs)
    return [r for r in rows if abs(np.sin(robot.dh_alpha[r])) < np.sin(HAYATI_ANGLE)]


def build_chain(robot: RobotParams) -> Chain:
    """The motions of ``robot`` (module docstring), with Hayati's beta (value 0) on every
    row of :func:`hayati_rows`."""
    n = robot.n_dofs
    tilted = set(hayati_rows(robot))
    items: list[tuple] = []  # (kind, axis, joint, value, name, group, held, row, field)

    def frame(prefix: str, tf: HomogeneousTransform) -> None:
        roll, pitch, yaw = rpy_from_rot(tf.R())
        values = dict(zip(("x", "y", "z", "rx", "ry", "rz"), (*tf.t(), roll, pitch, yaw)))
        for kind, axis, key in _FRAME_MOTIONS:
            items.append((kind, axis, -1, float(values[key]), f"{prefix}.{key}", prefix, False, -1, ""))

    def x_pair(r: int) -> None:
        items.append((TRANSLATION, X, -1, float(robot.dh_a[r]), f"a{r + 1}", "dh", False, r, "a"))
        items.append((ROTATION, X, -1, float(robot.dh_alpha[r]), f"alpha{r + 1}", "dh", False, r, "alpha"))
        if r in tilted:
            items.append((ROTATION, Y, -1, 0.0, f"beta{r + 1}", "dh", False, r, "beta"))

    frame("base", robot.base_tf)
    if robot.is_modified:
        x_pair(0)
    for j in range(n):
        revolute = robot.jtype[j] == JTYPE_REVOLUTE
        held = (j in tilted) if not robot.is_modified else (j + 1 in tilted)
        items.append((ROTATION, Z, j if revolute else -1, float(robot.dh_th[j]),
                      f"theta_offset{j + 1}", "joint_offsets" if revolute else "dh", False, j, "theta"))
        items.append((TRANSLATION, Z, -1 if revolute else j, float(robot.dh_d[j]),
                      f"d{j + 1}", "dh" if revolute else "joint_offsets", held and revolute, j, "d"))
        if not robot.is_modified:
            x_pair(j)
        elif j + 1 < n:
            x_pair(j + 1)
    frame("tool", robot.tool_tf)
    kind, axis, joint, value, name, group, held, row, field = zip(*items)
    values = np.array(value, dtype=float)
    return Chain(robot, np.array(kind), np.array(axis), np.array(joint), values, values.copy(),
                 tuple(name), tuple(group), np.array(held, dtype=bool), np.array(row), tuple(field))


def _turn(R: FloatArray, axis: int, angle: FloatArray) -> None:
    """R (N, 3, 3) ← R · R_axis(angle) in place: two columns rotate about the third."""
    a, b = (axis + 1) % 3, (axis + 2) % 3
    c, s = np.cos(angle)[:, None], np.sin(angle)[:, None]
    ca, cb = R[:, :, a].copy(), R[:, :, b]
    R[:, :, a] = c * ca + s * cb
    R[:, :, b] = c * cb - s * ca


def walk(chain: Chain, Q: FloatArray, keep: NDArray[np.bool_] | None = None
         ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Tool rotations (N, 3, 3) and positions (N, 3) for joint values Q (N, n), with the
    world axis (N, K', 3) and a point on it (N, K', 3) of each motion where ``keep`` (K,)
    is True (K' of them; all when None)."""
    N = Q.shape[0]
    R = np.broadcast_to(np.eye(3), (N, 3, 3)).copy()
    p = np.zeros((N, 3))
    keep = np.ones(chain.size, dtype=bool) if keep is None else keep
    axes = np.empty((N, int(keep.sum()), 3))
    points = np.empty_like(axes)
    slot = 0
    for k in range(chain.size):
        v = np.full(N, chain.value[k]) if chain.joint[k] < 0 else chain.value[k] + Q[:, chain.joint[k]]
        ax = chain.axis[k]
        if chain.kind[k] == ROTATION:
            _turn(R, ax, v)
        else:
            p += v[:, None] * R[:, :, ax]
        if keep[k]:
            axes[:, slot] = R[:, :, ax]
            points[:, slot] = p
            slot += 1
    return R, p, axes, points


def parameter_jacobian(chain: Chain, Q: FloatArray, columns: NDArray[np.int64], poses: bool
                       ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Tool rotations (N, 3, 3), positions (N, 3) and the Jacobian of the measured values
    with respect to the motions ``columns``: (N, 3, P) of positions [m per m or rad], or
    (N, 6, P) with the rotation rows [rad per m or rad] below when ``poses``.  A rotation
    column is [u × (p − o); u], a translation column [u; 0] (world axis u, point o)."""
    keep = np.zeros(chain.size, dtype=bool)
    keep[columns] = True
    order = np.argsort(np.argsort(columns))  # walk keeps motions in chain order
    R, p, axes, points = walk(chain, Q, keep)
    axes, points = axes[:, order], points[:, order]
    rotation = chain.kind[columns] == ROTATION
    J = np.zeros((Q.shape[0], 6 if poses else 3, len(columns)))
    lever = p[:, None, :] - points
    moved = np.cross(axes, lever)
    J[:, :3, :] = np.where(rotation[None, :, None], moved, axes).transpose(0, 2, 1)
    if poses:
        J[:, 3:, :] = np.where(rotation[None, :, None], axes, 0.0).transpose(0, 2, 1)
    return R, p, J
