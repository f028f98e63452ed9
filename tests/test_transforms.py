"""transforms.py against hand-written matrices and SE(3)/SO(3) identities."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kin_helpers import dh_by_hand, h_rot_x, h_rot_z, random_rigid, random_rotation, rodrigues
from robot_sim.transforms import (
    HomogeneousTransform,
    angle_axis_from_vec_dir,
    dh_transform,
    is_rigid_transform,
    quaternion_from_rot,
    rot_from_angle_axis,
    rot_from_rpy,
    rot_x,
    rot_y,
    rot_z,
    rotation_log,
    rotations_z_onto,
    rpy_from_rot,
)

angles = st.floats(-2 * math.pi, 2 * math.pi, allow_nan=False)
coords = st.floats(-10.0, 10.0, allow_nan=False)
vec3 = st.tuples(coords, coords, coords).map(np.array)
seeds = st.integers(0, 2**32 - 1)
S2 = math.sqrt(0.5)


# ------------------------------------------------------------------ elementary rotations


@pytest.mark.parametrize(
    "fn, angle, expected",
    [
        (rot_x, math.pi / 2, [[1, 0, 0], [0, 0, -1], [0, 1, 0]]),
        (rot_y, math.pi / 2, [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]),
        (rot_z, math.pi / 2, [[0, -1, 0], [1, 0, 0], [0, 0, 1]]),
        (rot_x, math.pi / 4, [[1, 0, 0], [0, S2, -S2], [0, S2, S2]]),
        (rot_y, -math.pi / 4, [[S2, 0, -S2], [0, 1, 0], [S2, 0, S2]]),
        (rot_z, math.pi, [[-1, 0, 0], [0, -1, 0], [0, 0, 1]]),
        (rot_x, 0.0, np.eye(3)),
    ],
)
def test_elementary_rotations_match_hand_written_matrices(fn, angle, expected):
    np.testing.assert_allclose(fn(angle), expected, atol=1e-15)


@given(angles)
def test_elementary_rotations_turn_the_right_axes(angle):
    c, s = math.cos(angle), math.sin(angle)
    # Each rotation leaves its own axis fixed and turns the next axis (cyclically) by angle.
    np.testing.assert_allclose(rot_x(angle) @ [1, 0, 0], [1, 0, 0])
    np.testing.assert_allclose(rot_x(angle) @ [0, 1, 0], [0, c, s], atol=1e-15)
    np.testing.assert_allclose(rot_y(angle) @ [0, 1, 0], [0, 1, 0])
    np.testing.assert_allclose(rot_y(angle) @ [0, 0, 1], [s, 0, c], atol=1e-15)
    np.testing.assert_allclose(rot_z(angle) @ [0, 0, 1], [0, 0, 1])
    np.testing.assert_allclose(rot_z(angle) @ [1, 0, 0], [c, s, 0], atol=1e-15)


# ------------------------------------------------------------------ roll-pitch-yaw


@given(angles, angles, angles)
def test_rpy_follows_urdf_order(roll, pitch, yaw):
    expected = h_rot_z(yaw)[:3, :3] @ rodrigues(pitch, [0, 1, 0]) @ h_rot_x(roll)[:3, :3]
    np.testing.assert_allclose(rot_from_rpy([roll, pitch, yaw]), expected, atol=1e-12)
    T = HomogeneousTransform.from_xyz_rpy([1.0, -2.0, 3.0], [roll, pitch, yaw])
    np.testing.assert_allclose(T.R(), expected, atol=1e-12)
    np.testing.assert_allclose(T.t(), [1.0, -2.0, 3.0])
    np.testing.assert_allclose(T.mat[3], [0, 0, 0, 1])


def test_rpy_worked_example():
    # roll 90° then yaw 90°: x -> y, y -> z (roll) -> z, z -> -y (roll) -> x.
    R = HomogeneousTransform.from_xyz_rpy([0, 0, 0], [math.pi / 2, 0, math.pi / 2]).R()
    np.testing.assert_allclose(R, [[0, 0, 1], [1, 0, 0], [0, 1, 0]], atol=1e-15)


@given(
    st.floats(-math.pi + 1e-6, math.pi - 1e-6),
    st.floats(-math.pi / 2 + 1e-3, math.pi / 2 - 1e-3),
    st.floats(-math.pi + 1e-6, math.pi - 1e-6),
)
def test_rpy_from_rot_inverts_rot_from_rpy_away_from_gimbal_lock(roll, pitch, yaw):
    got = rpy_from_rot(rot_from_rpy([roll, pitch, yaw]))
    np.testing.assert_allclose(got, [roll, pitch, yaw], atol=1e-9)


@pytest.mark.parametrize("sign", [1.0, -1.0])
@pytest.mark.parametrize("delta", [0.0, 1e-12, 1e-9, 1e-8, 1e-7, 1e-6, 1.3e-6, 1e-5, 1e-4, 1e-2])
@pytest.mark.parametrize("roll, yaw", [(0.7, -0.4), (2.5, 1.9), (-3.0, 0.1)])
def test_rpy_from_rot_recovers_the_rotation_near_gimbal_lock(sign, delta, roll, yaw):
    """At pitch = ±90° only yaw ∓ roll is defined; the angles returned must still
    rebuild the same rotation, also just beside the lock."""
    R = rot_from_rpy([roll, sign * (math.pi / 2 - delta), yaw])
    got = rpy_from_rot(R)
    assert all(math.isfinite(x) for x in got)
    assert abs(got[1] - sign * (math.pi / 2 - delta)) < 1e-7
    np.testing.assert_allclose(rot_from_rpy(got), R, atol=1e-7)


# ------------------------------------------------------------------ HomogeneousTransform


def test_accessors_return_blocks_and_columns():
    rng = np.random.default_rng(1)
    m = random_rigid(rng)
    T = HomogeneousTransform(m)
    np.testing.assert_array_equal(T.R(), m[:3, :3])
    np.testing.assert_array_equal(T.t(), m[:3, 3])
    np.testing.assert_array_equal(T.Rx(), m[:3, 0])
    np.testing.assert_array_equal(T.Ry(), m[:3, 1])
    np.testing.assert_array_equal(T.Rz(), m[:3, 2])
    np.testing.assert_array_equal(HomogeneousTransform().mat, np.eye(4))
    # the constructor copies: changing the source leaves the transform alone
    m[0, 3] += 1.0
    assert T.t()[0] == m[0, 3] - 1.0


@given(seeds)
def test_inverse_is_the_inverse_and_uses_the_transpose(seed):
    rng = np.random.default_rng(seed)
    m = random_rigid(rng, 5.0)
    T = HomogeneousTransform(m)
    Ti = T.inv()
    np.testing.assert_allclose((T @ Ti).mat, np.eye(4), atol=1e-12)
    np.testing.assert_allclose((Ti @ T).mat, np.eye(4), atol=1e-12)
    np.testing.assert_array_equal(Ti.R(), m[:3, :3].T)
    np.testing.assert_allclose(Ti.t(), -m[:3, :3].T @ m[:3, 3], atol=1e-15)
    np.testing.assert_array_equal(Ti.mat[3], [0, 0, 0, 1])


@given(seeds)
def test_composition_and_point_application(seed):
    rng = np.random.default_rng(seed)
    A, B = random_rigid(rng, 3.0), random_rigid(rng, 3.0)
    TA, TB = HomogeneousTransform(A), HomogeneousTransform(B)
    np.testing.assert_allclose((TA @ TB).mat, A @ B, atol=1e-14)
    np.testing.assert_allclose((TA @ B).mat, A @ B, atol=1e-14)  # a raw (4, 4) array composes too
    p = rng.normal(size=3)
    np.testing.assert_allclose(TA @ p, (A @ np.append(p, 1.0))[:3], atol=1e-14)
    P = rng.normal(size=(7, 3))
    expected = (A @ np.hstack([P, np.ones((7, 1))]).T).T[:, :3]
    got = TA @ P
    assert got.shape == (7, 3)
    np.testing.assert_allclose(got, expected, atol=1e-14)
    # composition is associative with point application
    np.testing.assert_allclose((TA @ TB) @ P, TA @ (TB @ P), atol=1e-12)


@pytest.mark.parametrize("shape", [(4,), (2,), (3, 4), (2, 3, 3), (5, 4), ()])
def test_applying_to_a_bad_shape_raises(shape):
    with pytest.raises(ValueError, match="point"):
        HomogeneousTransform() @ np.zeros(shape)


@pytest.mark.parametrize("shape", [(3, 3), (4,), (4, 3), (16,), (1, 4, 4)])
def test_constructor_rejects_bad_shapes(shape):
    with pytest.raises(ValueError, match="4x4"):
        HomogeneousTransform(np.zeros(shape))


# ------------------------------------------------------------------ DH transform


@pytest.mark.parametrize("conv", ["standard", "modified"])
@given(theta=angles, d=coords, a=coords, alpha=angles)
def test_dh_transform_scalar_equals_elementary_product(conv, theta, d, a, alpha):
    got = dh_transform(theta, d, a, alpha, conv)
    assert got.shape == (4, 4)
    np.testing.assert_allclose(got, dh_by_hand(theta, d, a, alpha, conv), atol=1e-12)


def test_dh_transform_modified_worked_example_and_bad_convention():
    # Rx(90°) Tx(2) Rz(90°) Tz(1): x1 = y0 turned by Rx(90°) = z0, z1 = Rx(90°) z0 = −y0,
    # origin (2, 0, 0) + Rx(90°)(0, 0, 1) = (2, −1, 0).
    expected = [[0, -1, 0, 2], [0, 0, -1, -1], [1, 0, 0, 0], [0, 0, 0, 1]]
    np.testing.assert_allclose(dh_transform(math.pi / 2, 1.0, 2.0, math.pi / 2, "modified"), expected, atol=1e-15)
    with pytest.raises(ValueError, match="convention must be 'standard' or 'modified', got 'craig'"):
        dh_transform(0.0, 0.0, 0.0, 0.0, "craig")


def test_dh_transform_worked_example():
    # θ = 90°, d = 1, a = 2, α = 90°: x1 = y0, y1 = z0, z1 = x0, origin (0, 2, 1).
    expected = [[0, 0, 1, 0], [1, 0, 0, 2], [0, 1, 0, 1], [0, 0, 0, 1]]
    np.testing.assert_allclose(dh_transform(math.pi / 2, 1.0, 2.0, math.pi / 2), expected, atol=1e-15)


@pytest.mark.parametrize("conv", ["standard", "modified"])
@given(seed=seeds)
def test_dh_transform_batched_equals_scalar_per_element(conv, seed):
    rng = np.random.default_rng(seed)
    N = 9
    theta, d = rng.uniform(-7, 7, N), rng.uniform(-2, 2, N)
    a, alpha = rng.uniform(-2, 2, N), rng.uniform(-7, 7, N)
    batch = dh_transform(theta, d, a, alpha, conv)
    assert batch.shape == (N, 4, 4)
    for k in range(N):
        np.testing.assert_allclose(batch[k], dh_transform(theta[k], d[k], a[k], alpha[k], conv), atol=1e-15)
    # broadcasting: scalars against arrays, and a (2, 1) against an (N,) array
    mixed = dh_transform(theta, 0.3, a[0], alpha, conv)
    for k in range(N):
        np.testing.assert_allclose(mixed[k], dh_transform(theta[k], 0.3, a[0], alpha[k], conv), atol=1e-15)
    grid = dh_transform(theta[:2, None], d, 0.1, 0.2, conv)
    assert grid.shape == (2, N, 4, 4)
    np.testing.assert_allclose(grid[1, 4], dh_transform(theta[1], d[4], 0.1, 0.2, conv), atol=1e-15)


# ------------------------------------------------------------------ angle-axis helpers


def _assert_maps(vec, dir_):
    angle, axis = angle_axis_from_vec_dir(vec, dir_)
    assert np.all(np.isfinite(axis)) and math.isfinite(angle)
    np.testing.assert_allclose(np.linalg.norm(axis), 1.0, atol=1e-12)
    R = rodrigues(angle, axis)
    v, d = np.asarray(vec, float), np.asarray(dir_, float)
    np.testing.assert_allclose(R @ (v / np.linalg.norm(v)), d / np.linalg.norm(d), atol=1e-9)
    return angle, axis


nonzero_vec = vec3.filter(lambda v: np.linalg.norm(v) > 1e-3)


@given(nonzero_vec, nonzero_vec)
def test_angle_axis_turns_vec_onto_dir(vec, dir_):
    _assert_maps(vec, dir_)


@given(nonzero_vec, st.floats(1e-3, 1e3))
def test_angle_axis_parallel_is_identity(vec, scale):
    angle, axis = _assert_maps(vec, vec * scale)
    assert angle == pytest.approx(0.0, abs=1e-9)


@given(nonzero_vec, st.floats(1e-3, 1e3))
def test_angle_axis_antiparallel_is_half_turn_about_a_perpendicular(vec, scale):
    angle, axis = _assert_maps(vec, -vec * scale)
    assert angle == pytest.approx(math.pi, abs=1e-9)
    assert abs(axis @ vec) < 1e-9 * np.linalg.norm(vec)
    np.testing.assert_allclose(rot_from_angle_axis(angle, axis) @ vec, -vec, atol=1e-9)


@pytest.mark.parametrize(
    "vec, dir_",
    [
        ([0, 0, 1], [0, 0, -1]),
        ([0, 0, -1], [0, 0, 1]),
        ([0, 0, 1], [0, 0, -2.5]),
        ([0, 0, -3], [1, 0, 0]),
        ([0, 0, 1], [1e-10, 0, -1]),  # almost antiparallel
        ([1, 0, 0], [-1, 1e-12, 0]),
        ([0, 0, 1], [1e-10, 1e-10, 1]),  # almost parallel
    ],
)
def test_angle_axis_along_minus_z_and_near_degenerate(vec, dir_):
    _assert_maps(vec, dir_)


@pytest.mark.parametrize(
    "vec, dir_",
    [
        ([0, 0, 1], [0, 0, 0]),
        ([0, 0, 0], [1, 2, 3]),
        ([0, 0, 0], [0, 0, 0]),
        ([0, 0, 1], [1e-14, 0, 0]),
        ([0, 0, 1], [np.nan, 0, 1]),
        ([0, 0, 1], [np.inf, 0, 1]),
    ],
)
def test_angle_axis_of_zero_or_invalid_input_is_identity(vec, dir_):
    angle, axis = angle_axis_from_vec_dir(vec, dir_)
    assert angle == 0.0
    assert np.all(np.isfinite(axis))
    np.testing.assert_allclose(rot_from_angle_axis(angle, axis), np.eye(3), atol=0)


@given(angles, vec3.filter(lambda v: np.linalg.norm(v) > 1e-6))
def test_rot_from_angle_axis_is_rodrigues(angle, axis):
    np.testing.assert_allclose(rot_from_angle_axis(angle, axis), rodrigues(angle, axis), atol=1e-12)


def test_rot_from_angle_axis_worked_example():
    np.testing.assert_allclose(rot_from_angle_axis(math.pi / 2, [0, 0, 2]), rot_z(math.pi / 2), atol=1e-15)


@given(st.floats(0.0, math.pi, allow_nan=False), vec3.filter(lambda v: np.linalg.norm(v) > 1e-3))
def test_quaternion_is_half_angle_cos_and_sin_times_axis(angle, axis):
    quat = quaternion_from_rot(rodrigues(angle, axis))
    axis = axis / np.linalg.norm(axis)
    expected = np.r_[math.cos(angle / 2), math.sin(angle / 2) * axis]
    if abs(expected[0]) < 1e-9 and np.dot(quat[1:], expected[1:]) < 0:
        expected = -expected  # a half turn: q and -q are the same rotation
    np.testing.assert_allclose(quat, expected, atol=1e-9)
    assert quat[0] >= 0.0


def test_quaternion_worked_examples():
    np.testing.assert_allclose(quaternion_from_rot(np.eye(3)), [1, 0, 0, 0])
    np.testing.assert_allclose(quaternion_from_rot(rot_z(math.pi / 2)), [math.sqrt(0.5), 0, 0, math.sqrt(0.5)], atol=1e-15)
    np.testing.assert_allclose(quaternion_from_rot(rot_x(math.pi)), [0, 1, 0, 0], atol=1e-15)


# ------------------------------------------------------------------ rotation log


def _assert_log_inverts(R):
    w = rotation_log(R)
    assert w.shape == (3,) and np.all(np.isfinite(w))
    angle = np.linalg.norm(w)
    assert angle <= math.pi + 1e-12
    rebuilt = np.eye(3) if angle == 0.0 else rodrigues(angle, w)
    np.testing.assert_allclose(rebuilt, R, atol=1e-7)
    return w


@settings(max_examples=200)
@given(seeds)
def test_rotation_log_inverts_exp_for_random_rotations(seed):
    _assert_log_inverts(random_rotation(np.random.default_rng(seed)))


@pytest.mark.parametrize(
    "angle",
    [0.0, 1e-12, 1e-9, 1e-7, 1e-6, 1.1e-6, 1e-5, 1e-3, 1.0, 2.0, 3.0,
     math.pi - 1e-3, math.pi - 2e-4, math.pi - 1.01e-4, math.pi - 0.99e-4, math.pi - 5e-5,
     math.pi - 1e-5, math.pi - 1e-6, math.pi - 1e-8, math.pi - 1e-10, math.pi],
)
@pytest.mark.parametrize("seed", range(4))
def test_rotation_log_near_zero_and_pi(angle, seed):
    rng = np.random.default_rng(seed)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    w = _assert_log_inverts(rodrigues(angle, axis))
    assert np.linalg.norm(w) == pytest.approx(angle, abs=1e-7)
    if 1e-6 < angle < math.pi - 1e-6:  # the axis is unique (up to sign only at π)
        np.testing.assert_allclose(w / np.linalg.norm(w), axis, atol=1e-7)


@pytest.mark.parametrize("axis", np.vstack([np.eye(3), -np.eye(3), [[1, 1, 0], [1, -1, 1]]]))
def test_rotation_log_half_turns_about_special_axes(axis):
    _assert_log_inverts(rodrigues(math.pi, axis))


# ------------------------------------------------------------------ rigid-transform check


def test_is_rigid_transform_accepts_rigid():
    rng = np.random.default_rng(3)
    for _ in range(20):
        assert is_rigid_transform(random_rigid(rng, 10.0))
    assert is_rigid_transform(np.eye(4))


@pytest.mark.parametrize(
    "make_bad",
    [
        lambda m: m * np.diag([1.01, 1, 1, 1]),  # stretched x axis
        lambda m: m @ np.diag([1, 1, -1, 1]),  # reflection: det -1
        lambda m: m @ np.array([[1, 0.01, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]),  # shear
        lambda m: np.where(np.arange(16).reshape(4, 4) == 5, np.nan, m),
        lambda m: np.where(np.arange(16).reshape(4, 4) == 3, np.inf, m),
        lambda m: m + np.array([[0, 0, 0, 0]] * 3 + [[0, 0, 0.1, 0]]),  # bottom row
        lambda m: m[:3, :],
        lambda m: m[:3, :3],
        lambda m: m.reshape(16),
        lambda m: np.zeros((4, 4)),
    ],
)
def test_is_rigid_transform_rejects(make_bad):
    m = random_rigid(np.random.default_rng(4))
    assert is_rigid_transform(m)
    assert not is_rigid_transform(make_bad(m))


# ------------------------------------------------------------------ batched z alignment


def test_rotations_z_onto_points_z_along_each_direction():
    rng = np.random.default_rng(41)
    dirs = np.vstack([rng.normal(size=(50, 3)), [[0, 0, -2.0], [0, 0, 3.0], [1e-3, 0, -1.0], [5.0, 0, 0], [0, 1e-14, 0]]])
    rots = rotations_z_onto(dirs)
    for d, R in zip(dirs, rots):
        assert np.all(np.isfinite(R))
        np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)
        assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
        if np.linalg.norm(d) > 1e-12:
            np.testing.assert_allclose(R[:, 2], d / np.linalg.norm(d), atol=1e-12)
        else:
            np.testing.assert_array_equal(R, np.eye(3))


def test_rotations_z_onto_degenerate_directions_give_identity():
    rots = rotations_z_onto([[0, 0, 0], [np.nan, 0, 1], [np.inf, 0, 0]])
    np.testing.assert_array_equal(rots, np.broadcast_to(np.eye(3), (3, 3, 3)))
