"""Forward kinematics of a URDF computed from its joint origins and axes alone, on the
model parsed by the independent ``urdf_parser_py`` (never by this package's importer)."""
from __future__ import annotations

import numpy as np
from urdf_parser_py.urdf import URDF

from kin_helpers import h_rot_x, h_rot_z, h_trans, rodrigues


def h_rot_y(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]], dtype=float)


def parse(text: str) -> URDF:
    return URDF.from_xml_string(text)


def origin_matrix(origin) -> np.ndarray:
    """URDF <origin>: translation xyz, then rotation Rz(yaw) Ry(pitch) Rx(roll)."""
    if origin is None:
        return np.eye(4)
    xyz = origin.xyz if origin.xyz is not None else [0.0, 0.0, 0.0]
    roll, pitch, yaw = origin.rpy if origin.rpy is not None else [0.0, 0.0, 0.0]
    return h_trans(*xyz) @ h_rot_z(yaw) @ h_rot_y(pitch) @ h_rot_x(roll)


def chain(model: URDF, tip: str) -> list:
    """Joints from the root link to ``tip``."""
    parent = {j.child: j for j in model.joints}
    joints, link = [], tip
    while link in parent:
        joints.append(parent[link])
        link = parent[link].parent
    return joints[::-1]


def moving(joints: list) -> list:
    return [j for j in joints if j.type != "fixed"]


def urdf_fk(model: URDF, tip: str, q: np.ndarray) -> np.ndarray:
    """Pose of link ``tip`` in the root link at joint values q (one per moving joint of
    the chain, in order): Π origin · motion, motion a rotation about or a slide along the
    joint's axis."""
    T, k = np.eye(4), 0
    for joint in chain(model, tip):
        T = T @ origin_matrix(joint.origin)
        if joint.type == "fixed":
            continue
        axis = np.array(joint.axis if joint.axis is not None else [1.0, 0.0, 0.0])
        axis = axis / np.linalg.norm(axis)
        motion = np.eye(4)
        if joint.type == "prismatic":
            motion[:3, 3] = axis * q[k]
        else:
            motion[:3, :3] = rodrigues(q[k], axis)
        T = T @ motion
        k += 1
    return T


def vee(S: np.ndarray) -> np.ndarray:
    return np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]]) / 2


def urdf_mass_matrix(model: URDF, tip: str, q: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """Joint-space mass matrix Σ m Jvᵀ Jv + Jωᵀ (R I Rᵀ) Jω over the inertials of the links
    on the chain to ``tip`` after its first moving joint, with each COM's Jacobian taken by
    central differences of :func:`urdf_fk` (the URDF alone)."""
    n = len(q)
    M = np.zeros((n, n))
    joints = chain(model, tip)
    for k, joint in enumerate(joints):
        link = model.link_map[joint.child]
        if link.inertial is None or not moving(joints[: k + 1]):
            continue
        offset = origin_matrix(link.inertial.origin)
        used = len(moving(joints[: k + 1]))

        def com_pose(qq: np.ndarray) -> np.ndarray:
            return urdf_fk(model, joint.child, qq[:used]) @ offset

        T = com_pose(q)
        Jv, Jw = np.zeros((3, n)), np.zeros((3, n))
        for j in range(n):
            e = np.eye(n)[j] * h
            Tp, Tm = com_pose(q + e), com_pose(q - e)
            Jv[:, j] = (Tp[:3, 3] - Tm[:3, 3]) / (2 * h)
            Jw[:, j] = vee((Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ T[:3, :3].T)
        i = link.inertial.inertia
        I = np.array([[i.ixx, i.ixy, i.ixz], [i.ixy, i.iyy, i.iyz], [i.ixz, i.iyz, i.izz]])
        R = T[:3, :3]
        M += link.inertial.mass * Jv.T @ Jv + Jw.T @ (R @ I @ R.T) @ Jw
    return M
