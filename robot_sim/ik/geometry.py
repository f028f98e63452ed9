"""A DH chain as joint screws at the zero configuration (product of exponentials).

Every DH table (standard or modified, base and tool included) is the same product
``T(q) = E_1(q_1) ⋯ E_n(q_n) · M`` in the world frame of the robot (``robot.base_tf`` is
folded in, the robot standing at the world origin): ``E_i`` turns by q_i about the line
through ``P[i]`` with unit direction ``H[i]`` (revolute), or shifts by q_i along ``H[i]``
(prismatic), and ``M`` is the tool frame at q = 0.  Axis directions and points are where
the joints sit at q = 0, in metres.  The analytic solvers work on this form only, so
they never see which DH convention a table used.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.transforms import dh_transform

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class Screws:
    """Joint screws of a chain at q = 0 (world frame): ``H`` (m, 3) unit axis directions,
    ``P`` (m, 3) a point on each axis [m], ``revolute`` (m,) joint kinds, ``M`` (4, 4) the
    tool frame at q = 0."""

    H: FloatArray
    P: FloatArray
    revolute: NDArray[np.bool_]
    M: FloatArray

    @property
    def n(self) -> int:
        return int(self.H.shape[0])

    def reversed(self) -> "Screws":
        """The chain read from the tool back to the base: ``T(q)⁻¹ = E'_n(q_n) ⋯ E'_1(q_1) M⁻¹``
        with ``E'_i`` about the axis moved by M⁻¹ and turned around (so q keeps its sign)."""
        Minv = _inverse(self.M)
        R = Minv[:3, :3]
        H = -(self.H @ R.T)[::-1]
        P = (self.P @ R.T + Minv[:3, 3])[::-1]
        return Screws(np.ascontiguousarray(H), np.ascontiguousarray(P), self.revolute[::-1].copy(), Minv)

    def folded(self, joint: int, value: float) -> "Screws":
        """The chain with joint ``joint`` held at ``value``: the joints after it are moved by
        its motion ``E_joint(value)``, and so is the tool frame."""
        E = motion(self.H[joint], self.P[joint], bool(self.revolute[joint]), value)
        keep = np.arange(self.n) != joint
        after = np.arange(self.n) > joint
        H, P = self.H.copy(), self.P.copy()
        H[after] = H[after] @ E[:3, :3].T
        P[after] = P[after] @ E[:3, :3].T + E[:3, 3]
        return Screws(H[keep], P[keep], self.revolute[keep].copy(), E @ self.M)


def _inverse(T: FloatArray) -> FloatArray:
    out = np.eye(4)
    out[:3, :3] = T[:3, :3].T
    out[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return out


def motion(h: FloatArray, p: FloatArray, revolute: bool, value: float) -> FloatArray:
    """4×4 motion of one joint screw: a turn by ``value`` [rad] about the line (p, h) by
    Rodrigues' formula, or a shift by ``value`` [m] along h."""
    out = np.eye(4)
    if not revolute:
        out[:3, 3] = value * h
        return out
    K = np.array([[0.0, -h[2], h[1]], [h[2], 0.0, -h[0]], [-h[1], h[0], 0.0]])
    R = np.eye(3) + np.sin(value) * K + (1.0 - np.cos(value)) * (K @ K)
    out[:3, :3] = R
    out[:3, 3] = p - R @ p
    return out


def screws(robot: RobotParams) -> Screws:
    """The robot's joint screws at q = 0 in the world frame (base and tool folded in).

    Standard DH: joint i turns about z of frame i-1, through its origin.  Modified DH:
    about z of frame i, whose origin lies on the axis at d_i from frame i-1·Rx(α)Tx(a)."""
    n = robot.n_dofs
    frame = robot.base_tf.mat.copy()
    H, P = np.empty((n, 3)), np.empty((n, 3))
    links = dh_transform(robot.dh_th, robot.dh_d, robot.dh_a, robot.dh_alpha, robot.convention)
    for i in range(n):
        if robot.is_modified:
            on_axis = frame @ dh_transform(0.0, 0.0, robot.dh_a[i], robot.dh_alpha[i])
            H[i], P[i] = on_axis[:3, 2], on_axis[:3, 3]
        else:
            H[i], P[i] = frame[:3, 2], frame[:3, 3]
        frame = frame @ links[i]
    H /= np.linalg.norm(H, axis=1, keepdims=True)
    return Screws(H, P, robot.jtype == JTYPE_REVOLUTE, frame @ robot.tool_tf.mat)
