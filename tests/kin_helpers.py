"""Reference maths shared by the kinematics tests, written independently of the modules
under test (nothing here calls transforms.py or kinematics.py to produce expected values).

Conventions match the design: standard DH ``A = Rz(θ)·Tz(d)·Tx(a)·Rx(α)``, modified (Craig)
DH ``A = Rx(α)·Tx(a)·Rz(θ)·Tz(d)`` with the row's a_{i-1}, α_{i-1}, SI units, twists
``[v; ω]`` in the world frame.  Kinematic property tests run for both conventions: the
shipped robots in the convention of their file and converted to the other one
(dh_convert), random chains drawn directly in either.
"""
from __future__ import annotations

from functools import lru_cache
from typing import Callable, Sequence

import numpy as np
import pytest

from robot_sim.model.convert import to_convention
from robot_sim.model.inertials import LinkInertials
from robot_sim.model.params import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotParams
from robot_sim.io.robot_file import available_robots, load_robot
from robot_sim.transforms import HomogeneousTransform

#: Every robot shipped in robots/.
ROBOT_NAMES = available_robots()

#: Robots every robot-sweeping test runs on by default; the rest of a sweep is marked
#: ``slow`` and runs in ``make test-full`` (the default ``make test`` stays short).
DEFAULT_SWEEP = ("ur5", "panda", "humanoid7", "puma560", "stanford", "planar3")


def sweep(names: Sequence[str], keep: Sequence[str] = DEFAULT_SWEEP) -> list:
    """pytest parameters for ``names``: those in ``keep`` as they are, the others marked slow."""
    return [name if name in keep else pytest.param(name, marks=pytest.mark.slow) for name in names]


#: Both DH conventions, for parametrising kinematic tests.
CONVENTIONS = ("standard", "modified")


@lru_cache(maxsize=None)
def robot(name: str, convention: str | None = None) -> RobotParams:
    """Shipped robot, loaded once per test session (RobotParams compare by identity);
    with ``convention`` given, converted to it when its file uses the other one."""
    rob = load_robot(name)
    return rob if convention is None else to_convention(rob, convention)


# ------------------------------------------------------------------ elementary matrices


def h_rot_x(angle: float) -> np.ndarray:
    """4×4 rotation about x, written out by hand."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]], dtype=float)


def h_rot_z(angle: float) -> np.ndarray:
    """4×4 rotation about z, written out by hand."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]], dtype=float)


def h_trans(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    """4×4 pure translation."""
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def dh_by_hand(theta: float, d: float, a: float, alpha: float, convention: str = "standard") -> np.ndarray:
    """DH link transform as the product of its four elementary motions: standard
    Rz(θ)·Tz(d)·Tx(a)·Rx(α) or modified Rx(α)·Tx(a)·Rz(θ)·Tz(d)."""
    if convention == "modified":
        return h_rot_x(alpha) @ h_trans(x=a) @ h_rot_z(theta) @ h_trans(z=d)
    return h_rot_z(theta) @ h_trans(z=d) @ h_trans(x=a) @ h_rot_x(alpha)


def hand_chain(rob: RobotParams, q: np.ndarray, world: np.ndarray | None = None) -> list[np.ndarray]:
    """Frames 0..n and the endeffector of ``rob`` at ``q`` by multiplying elementary
    matrices: the reference for forward kinematics on arbitrary DH tables."""
    frame = (np.eye(4) if world is None else world) @ rob.base_tf.mat
    frames = [frame]
    for i in range(rob.n_dofs):
        revolute = rob.jtype[i] == JTYPE_REVOLUTE
        theta = rob.dh_th[i] + (q[i] if revolute else 0.0)
        d = rob.dh_d[i] + (0.0 if revolute else q[i])
        frame = frame @ dh_by_hand(theta, d, rob.dh_a[i], rob.dh_alpha[i], rob.convention)
        frames.append(frame)
    frames.append(frame @ rob.tool_tf.mat)
    return frames


def rodrigues(angle: float, axis: np.ndarray) -> np.ndarray:
    """Rotation (3, 3) of ``angle`` about the unit vector along ``axis``."""
    k = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def vee(S: np.ndarray) -> np.ndarray:
    """Axial vector (..., 3) of the skew part of (..., 3, 3) matrices."""
    A = 0.5 * (S - np.swapaxes(S, -1, -2))
    return np.stack([A[..., 2, 1], A[..., 0, 2], A[..., 1, 0]], axis=-1)


def assert_rotations(R: np.ndarray, atol: float = 1e-10) -> None:
    """Every (..., 3, 3) block is orthonormal with determinant +1."""
    RtR = np.swapaxes(R, -1, -2) @ R
    np.testing.assert_allclose(RtR, np.broadcast_to(np.eye(3), RtR.shape), atol=atol)
    np.testing.assert_allclose(np.linalg.det(R), 1.0, atol=atol)


# ------------------------------------------------------------------ random inputs


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """Uniformly random rotation (3, 3) from a normalised Gaussian quaternion."""
    w, x, y, z = _unit(rng.normal(size=4))
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def random_rigid(rng: np.random.Generator, scale: float = 1.0) -> np.ndarray:
    """Random rigid transform (4, 4) with translation entries in ±scale."""
    m = np.eye(4)
    m[:3, :3] = random_rotation(rng)
    m[:3, 3] = rng.uniform(-scale, scale, 3)
    return m


#: Twist angles the batched kernel special-cases, plus general values drawn at random.
SPECIAL_ALPHAS = (0.0, np.pi / 2, -np.pi / 2, np.pi)


def random_dh_robot(
    rng: np.random.Generator, n: int, base_and_tool: bool = True, convention: str = "standard"
) -> RobotParams:
    """Random serial chain in either DH convention: both joint types, special and general
    twists, random offsets, and (optionally) random base and tool transforms."""
    alphas = [
        SPECIAL_ALPHAS[k] if k < len(SPECIAL_ALPHAS) else rng.uniform(-np.pi, np.pi)
        for k in rng.integers(0, len(SPECIAL_ALPHAS) + 2, n)
    ]
    jtype = rng.choice([JTYPE_REVOLUTE, JTYPE_REVOLUTE, JTYPE_PRISMATIC], n)
    return RobotParams.from_arrays(
        "random",
        dh_a=rng.uniform(-0.5, 0.5, n) * (rng.random(n) < 0.7),
        dh_alpha=alphas,
        dh_d=rng.uniform(-0.5, 0.5, n) * (rng.random(n) < 0.7),
        dh_th=rng.uniform(-np.pi, np.pi, n) * (rng.random(n) < 0.5),
        jtype=jtype,
        link_com_frac=rng.random(n),
        base_tf=HomogeneousTransform(random_rigid(rng)) if base_and_tool else None,
        tool_tf=HomogeneousTransform(random_rigid(rng, 0.2)) if base_and_tool else None,
        convention=convention,
    )


def expected_coms(rob: RobotParams, frames: np.ndarray) -> np.ndarray:
    """(n+1, 3) COMs by the documented rule from world frames 0..n (n+1, 4, 4): the base at
    frame 0's origin; link i at ``inertials.com[i-1]`` in frame i when the robot has
    inertial data, else at fraction ``link_com_frac[i-1]`` from frame i-1 to frame i."""
    origins = frames[:, :3, 3]
    if rob.inertials is not None:
        com = origins[1:] + np.einsum("nij,nj->ni", frames[1:, :3, :3], rob.inertials.com)
    else:
        f = rob.link_com_frac[:, None]
        com = origins[:-1] + f * (origins[1:] - origins[:-1])
    return np.vstack([origins[:1], com])


def random_inertials(rng: np.random.Generator, n: int) -> LinkInertials:
    """Random physical inertials of n links: each the mass distribution of a few random
    point masses around a random COM (so every tensor obeys the triangle inequality)."""
    mass, com, inertia = rng.uniform(0.2, 3.0, n), rng.uniform(-0.3, 0.3, (n, 3)), np.empty((n, 3, 3))
    for i in range(n):
        pts = rng.normal(0.0, 0.1, (4, 3))
        pts -= pts.mean(axis=0)
        w = mass[i] / 4
        inertia[i] = sum(w * (p @ p * np.eye(3) - np.outer(p, p)) for p in pts)
    return LinkInertials.from_arrays(mass, com, inertia)


def random_q(rob: RobotParams, rng: np.random.Generator, size: int | None = None) -> np.ndarray:
    """Joint vectors uniformly inside the limits (unlimited revolute joints in ±π,
    unlimited prismatic joints in [-0.5, 0.5] m): shape (n,) or (size, n)."""
    lo = np.where(np.isfinite(rob.q_min), rob.q_min, np.where(rob.is_revolute, -np.pi, -0.5))
    hi = np.where(np.isfinite(rob.q_max), rob.q_max, np.where(rob.is_revolute, np.pi, 0.5))
    shape = (rob.n_dofs,) if size is None else (size, rob.n_dofs)
    return lo + (hi - lo) * rng.random(shape)


# ------------------------------------------------------------------ finite differences

#: Central-difference step: truncation error ~h², rounding ~1e-16/h, both ≪ 1e-6.
FD_STEP = 1e-5


def fd_pose_rates(pose_at: Callable[[float], np.ndarray], h: float = FD_STEP) -> tuple[np.ndarray, np.ndarray]:
    """Linear and angular velocity of the pose(s) ``pose_at(t)`` (..., 4, 4) at t = 0 by
    central differences: v = ṗ, ω = vee(Ṙ Rᵀ).  Returns arrays (..., 3)."""
    T_plus, T_0, T_minus = pose_at(h), pose_at(0.0), pose_at(-h)
    v = (T_plus[..., :3, 3] - T_minus[..., :3, 3]) / (2 * h)
    R_dot = (T_plus[..., :3, :3] - T_minus[..., :3, :3]) / (2 * h)
    w = vee(R_dot @ np.swapaxes(T_0[..., :3, :3], -1, -2))
    return v, w
