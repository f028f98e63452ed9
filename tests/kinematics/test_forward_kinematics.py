"""Forward kinematics against closed forms derived by hand and against a chain of
elementary matrices (kin_helpers.hand_chain) on random DH tables.

Closed forms (standard DH, A = Rz(θ)·Tz(d)·Tx(a)·Rx(α); c1 = cos θ1, c12 = cos(θ1+θ2) ...):

* planar3 (α = 0, d = 0): p = (a1c1 + a2c12 + a3c123, a1s1 + a2s12 + a3s123, 0),
  R = Rz(θ1+θ2+θ3); origins o1 = a1(c1, s1, 0), o2 = o1 + a2(c12, s12, 0).
* anthropomorphic (α1 = 90°, a1 = 0; α2 = α3 = 0): A1 gives x1 = (c1, s1, 0),
  y1 = z0 = (0, 0, 1), z1 = (s1, −c1, 0); links 2 and 3 then move in the x1-y1 plane, so
  p = (c1(a2c2 + a3c23), s1(a2c2 + a3c23), a2s2 + a3s23) and R = [x1c23 + y1s23,
  −x1s23 + y1c23, z1] = columns (c1c23, s1c23, s23), (−c1s23, −s1s23, c23), (s1, −c1, 0);
  origins o1 = 0, o2 = a2(c1c2, s1c2, s2).
* spherical (α1 = −90°, α2 = 90°, d2 shoulder offset, prismatic d3): A1 gives
  x1 = (c1, s1, 0), y1 = (0, 0, −1), z1 = (−s1, c1, 0); A2 gives o2 = d2 z1,
  x2 = c2x1 + s2y1, y2 = z1, z2 = s2x1 − c2y1; A3 slides d3 along z2 (Siciliano 2.9.2):
  p = (c1s2d3 − s1d2, s1s2d3 + c1d2, c2d3), R columns (c1c2, s1c2, −s2), (−s1, c1, 0),
  (c1s2, s1s2, c2); origins o1 = 0, o2 = d2(−s1, c1, 0).
"""
from __future__ import annotations

import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kin_helpers import (
    CONVENTIONS,
    ROBOT_NAMES,
    expected_coms,
    assert_rotations,
    hand_chain,
    random_dh_robot,
    random_q,
    random_rigid,
    robot,
)
from robot_sim.kinematics import CHUNK, Kinematics, forward_kinematics
from robot_sim.model.params import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotParams
from robot_sim.model.state import RobotState
from robot_sim.transforms import HomogeneousTransform, angle_axis_from_vec_dir, rot_from_angle_axis

HALF_PI = np.pi / 2
seeds = st.integers(0, 2**32 - 1)


# ------------------------------------------------------------------ closed forms (frame 0)


def _pose(R_cols, p):
    """(N, 4, 4) poses from three (N, 3) rotation columns and an (N, 3) position."""
    T = np.zeros(p.shape[:-1] + (4, 4))
    for k, col in enumerate(R_cols):
        T[..., :3, k] = col
    T[..., :3, 3] = p
    T[..., 3, 3] = 1.0
    return T


def planar3_closed(rob, Q):
    np.testing.assert_array_equal(rob.dh_alpha, 0.0)  # the assumptions of the formula
    np.testing.assert_array_equal([rob.dh_d, rob.dh_th], 0.0)
    a1, a2, a3 = rob.dh_a
    t1, t12, t123 = Q[:, 0], Q[:, 0] + Q[:, 1], Q[:, 0] + Q[:, 1] + Q[:, 2]
    zero, one = np.zeros_like(t1), np.ones_like(t1)
    o1 = np.stack([a1 * np.cos(t1), a1 * np.sin(t1), zero], -1)
    o2 = o1 + np.stack([a2 * np.cos(t12), a2 * np.sin(t12), zero], -1)
    p = o2 + np.stack([a3 * np.cos(t123), a3 * np.sin(t123), zero], -1)
    c, s = np.cos(t123), np.sin(t123)
    R = (np.stack([c, s, zero], -1), np.stack([-s, c, zero], -1), np.stack([zero, zero, one], -1))
    return _pose(R, p), [np.zeros_like(p), o1, o2, p]


def anthropomorphic_closed(rob, Q):
    np.testing.assert_allclose(rob.dh_alpha, [HALF_PI, 0, 0], atol=1e-15)
    np.testing.assert_array_equal([rob.dh_a[0], *rob.dh_d, *rob.dh_th], 0.0)
    a2, a3 = rob.dh_a[1:]
    c1, s1 = np.cos(Q[:, 0]), np.sin(Q[:, 0])
    c2, s2 = np.cos(Q[:, 1]), np.sin(Q[:, 1])
    c23, s23 = np.cos(Q[:, 1] + Q[:, 2]), np.sin(Q[:, 1] + Q[:, 2])
    reach = a2 * c2 + a3 * c23
    p = np.stack([c1 * reach, s1 * reach, a2 * s2 + a3 * s23], -1)
    R = (
        np.stack([c1 * c23, s1 * c23, s23], -1),
        np.stack([-c1 * s23, -s1 * s23, c23], -1),
        np.stack([s1, -c1, np.zeros_like(c1)], -1),
    )
    o2 = a2 * np.stack([c1 * c2, s1 * c2, s2], -1)
    return _pose(R, p), [np.zeros_like(p), np.zeros_like(p), o2, p]


def spherical_closed(rob, Q):
    np.testing.assert_allclose(rob.dh_alpha, [-HALF_PI, HALF_PI, 0], atol=1e-15)
    np.testing.assert_array_equal([*rob.dh_a, rob.dh_d[0], rob.dh_d[2], *rob.dh_th], 0.0)
    np.testing.assert_array_equal(rob.jtype, [JTYPE_REVOLUTE, JTYPE_REVOLUTE, JTYPE_PRISMATIC])
    d2, d3 = rob.dh_d[1], Q[:, 2]
    c1, s1 = np.cos(Q[:, 0]), np.sin(Q[:, 0])
    c2, s2 = np.cos(Q[:, 1]), np.sin(Q[:, 1])
    p = np.stack([c1 * s2 * d3 - s1 * d2, s1 * s2 * d3 + c1 * d2, c2 * d3], -1)
    R = (
        np.stack([c1 * c2, s1 * c2, -s2], -1),
        np.stack([-s1, c1, np.zeros_like(c1)], -1),
        np.stack([c1 * s2, s1 * s2, c2], -1),
    )
    o2 = d2 * np.stack([-s1, c1, np.zeros_like(c1)], -1)
    return _pose(R, p), [np.zeros_like(p), np.zeros_like(p), o2, p]


CLOSED_FORMS = {"planar3": planar3_closed, "anthropomorphic": anthropomorphic_closed, "spherical": spherical_closed}


def to_world(rob, T0):
    """Poses or points in frame 0 expressed in the world through the robot's base."""
    B = rob.base_tf.mat
    if T0.shape[-2:] == (4, 4):
        return B @ T0
    return T0 @ B[:3, :3].T + B[:3, 3]


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", CLOSED_FORMS)
def test_forward_kinematics_matches_closed_form(name, conv):
    rob = robot(name, conv)
    Q = random_q(rob, np.random.default_rng(10), 300)
    # the closed forms read the standard table's lengths; the pose is the same in both
    expected = to_world(rob, CLOSED_FORMS[name](robot(name, "standard"), Q)[0])
    np.testing.assert_allclose(forward_kinematics(rob, Q), expected, atol=1e-12)
    for q, T in zip(Q[:30], expected):
        np.testing.assert_allclose(forward_kinematics(rob, q), T, atol=1e-12)
        np.testing.assert_allclose(forward_kinematics(rob, list(q)), T, atol=1e-12)


@pytest.mark.parametrize("name", CLOSED_FORMS)
def test_kinematics_update_matches_closed_form(name):
    rob = robot(name)
    Q = random_q(rob, np.random.default_rng(11), 40)
    T0, origins = CLOSED_FORMS[name](rob, Q)
    expected_ee = to_world(rob, T0)
    origins = [to_world(rob, o) for o in origins]
    kin, state = Kinematics(rob), RobotState(rob)
    f = rob.link_com_frac
    for k, q in enumerate(Q):
        state.set_q(q)
        kin.update(state.joint_state)
        np.testing.assert_allclose(kin.endeff_tf.mat, expected_ee[k], atol=1e-12)
        np.testing.assert_allclose(kin.h_tf[-1].mat, expected_ee[k], atol=1e-12)  # no tool
        np.testing.assert_allclose(kin.h_tf[0].mat, rob.base_tf.mat, atol=0)
        for i in range(rob.n_dofs + 1):
            np.testing.assert_allclose(kin.h_tf[i].t(), origins[i][k], atol=1e-12)
        np.testing.assert_allclose(kin.link_com[0], origins[0][k], atol=1e-12)
        if rob.inertials is not None:  # COMs fixed in the link frames
            np.testing.assert_allclose(kin.link_com, expected_coms(rob, kin.frames), atol=1e-12)
            continue
        for i in range(1, rob.n_links + 1):
            com = origins[i - 1][k] + f[i - 1] * (origins[i][k] - origins[i - 1][k])
            np.testing.assert_allclose(kin.link_com[i], com, atol=1e-12)


def test_closed_form_worked_examples():
    """A few poses checked by eye, so the closed forms above are themselves anchored."""
    planar = robot("planar3")  # a = 0.5, 0.4, 0.3; base 0.05 up
    np.testing.assert_allclose(forward_kinematics(planar, [0, 0, 0])[:3, 3], [1.2, 0, 0.05], atol=1e-15)
    np.testing.assert_allclose(forward_kinematics(planar, [HALF_PI, -HALF_PI, 0])[:3, 3], [0.7, 0.5, 0.05], atol=1e-15)
    arm = robot("anthropomorphic")  # a2 = 0.5, a3 = 0.4; base 0.5 up
    T = forward_kinematics(arm, [HALF_PI, HALF_PI, 0])  # pointing straight up
    np.testing.assert_allclose(T[:3, 3], [0, 0, 1.4], atol=1e-15)
    # x3 up, y3 = −x1 = (0, −1, 0), z3 = z1 = (1, 0, 0)
    np.testing.assert_allclose(T[:3, :3], [[0, 0, 1], [0, -1, 0], [1, 0, 0]], atol=1e-15)
    sph = robot("spherical")  # d2 = 0.2; base 0.6 up
    np.testing.assert_allclose(forward_kinematics(sph, [0, 0, 0.5])[:3, 3], [0, 0.2, 1.1], atol=1e-15)


# ------------------------------------------------------------------ random DH chains


@pytest.mark.parametrize("conv", CONVENTIONS)
@settings(max_examples=40, deadline=None)
@given(seeds, st.integers(1, 8))
def test_random_chains_match_elementary_product(conv, seed, n):
    rng = np.random.default_rng(seed)
    rob = random_dh_robot(rng, n, convention=conv)
    Q = random_q(rob, rng, 12)
    batch = forward_kinematics(rob, Q)
    frames = forward_kinematics(rob, Q, all_frames=True)
    assert batch.shape == (12, 4, 4) and frames.shape == (12, n + 2, 4, 4)
    assert_rotations(frames[..., :3, :3])
    np.testing.assert_array_equal(frames[..., 3, :], np.broadcast_to([0, 0, 0, 1.0], (12, n + 2, 4)))
    for k, q in enumerate(Q):
        reference = np.array(hand_chain(rob, q))
        np.testing.assert_allclose(frames[k], reference, atol=1e-12)
        np.testing.assert_allclose(forward_kinematics(rob, q), batch[k], atol=1e-12, rtol=0)
        np.testing.assert_allclose(forward_kinematics(rob, q, all_frames=True), frames[k], atol=1e-12, rtol=0)
    # frame 0 is the base, the last entry is the endeffector = frame n · tool
    np.testing.assert_allclose(frames[:, 0], np.broadcast_to(rob.base_tf.mat, (12, 4, 4)), atol=1e-15)
    np.testing.assert_allclose(frames[:, -1], batch, atol=1e-12)
    np.testing.assert_allclose(frames[:, -1], frames[:, -2] @ rob.tool_tf.mat, atol=1e-12)


@pytest.mark.parametrize("conv", CONVENTIONS)
@settings(max_examples=25, deadline=None)
@given(seeds, st.integers(1, 7))
def test_base_tool_and_world_compose_as_stated(conv, seed, n):
    rng = np.random.default_rng(seed)
    rob = random_dh_robot(rng, n, convention=conv)
    bare = RobotParams.from_arrays("bare", rob.dh_a, rob.dh_alpha, rob.dh_d, rob.dh_th, rob.jtype, convention=conv)
    Q = random_q(rob, rng, 6)
    B, tool = rob.base_tf.mat, rob.tool_tf.mat
    W = random_rigid(rng, 2.0)
    with_all = forward_kinematics(rob, Q)
    np.testing.assert_allclose(with_all, B @ forward_kinematics(bare, Q) @ tool, atol=1e-12)
    np.testing.assert_allclose(forward_kinematics(rob, Q, world_tf=W), W @ with_all, atol=1e-12)
    np.testing.assert_allclose(
        forward_kinematics(rob, Q[0], world_tf=HomogeneousTransform(W)), W @ with_all[0], atol=1e-12
    )
    framed = forward_kinematics(rob, Q, all_frames=True, world_tf=W)
    np.testing.assert_allclose(framed, W @ forward_kinematics(rob, Q, all_frames=True), atol=1e-12)


@pytest.mark.parametrize("conv", CONVENTIONS)
@settings(max_examples=25, deadline=None)
@given(seeds, st.integers(1, 7))
def test_kinematics_update_equals_forward_kinematics(conv, seed, n):
    rng = np.random.default_rng(seed)
    rob = random_dh_robot(rng, n, convention=conv)
    kin, state = Kinematics(rob), RobotState(rob)
    W = HomogeneousTransform(random_rigid(rng))
    for q in random_q(rob, rng, 4):
        state.set_q(q)
        frames = forward_kinematics(rob, q, all_frames=True)
        kin.update(state.joint_state)
        assert len(kin.h_tf) == n + 1
        np.testing.assert_allclose(np.array([T.mat for T in kin.h_tf]), frames[:-1], atol=1e-12)
        np.testing.assert_allclose(kin.frames, frames[:-1], atol=1e-12)
        np.testing.assert_allclose(kin.endeff_tf.mat, frames[-1], atol=1e-12)
        origins = frames[:-1, :3, 3]
        com = origins[:-1] + rob.link_com_frac[:, None] * (origins[1:] - origins[:-1])
        np.testing.assert_allclose(kin.link_com, np.vstack([origins[:1], com]), atol=1e-12)
        kin.update(state.joint_state, W)
        np.testing.assert_allclose(kin.frames, W.mat @ frames[:-1], atol=1e-12)
        np.testing.assert_allclose(kin.endeff_tf.mat, W.mat @ frames[-1], atol=1e-12)


def test_kinematics_starts_at_home():
    rob = robot("puma560")
    np.testing.assert_allclose(Kinematics(rob).endeff_tf.mat, forward_kinematics(rob, rob.q_home), atol=1e-12)


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_shipped_robots_batch_equals_single_across_chunks(name, conv):
    rob = robot(name, conv)
    Q = random_q(rob, np.random.default_rng(12), CHUNK + 5)
    batch = forward_kinematics(rob, Q, all_frames=True)
    assert_rotations(batch[..., :3, :3])
    for k in (0, 1, CHUNK - 1, CHUNK, CHUNK + 4):
        np.testing.assert_allclose(batch[k], np.array(hand_chain(rob, Q[k])), atol=1e-12)
        np.testing.assert_allclose(forward_kinematics(rob, Q[k], all_frames=True), batch[k], atol=1e-12, rtol=0)


@pytest.mark.parametrize(
    "q",
    [[0.0, 0.0], [0.0] * 4, [0.0, np.nan, 0.0], [np.inf, 0.0, 0.0], [[0.0, 0.0, -np.inf]], np.zeros((2, 2, 3)), 0.0],
)
def test_forward_kinematics_rejects_bad_q(q):
    with pytest.raises(ValueError, match="q"):
        forward_kinematics(robot("planar3"), q)


# ------------------------------------------------------------------ degenerate geometry


@pytest.mark.parametrize("conv", CONVENTIONS)
def test_spherical_arm_degenerate_links_stay_finite(conv):
    rob = robot("spherical", conv)
    # q2 = 180° points the prismatic link along −z; frames 0 and 1 always coincide.
    for q in ([0.0, np.pi, 0.5], [0.3, np.pi, 0.1], [0.0, 0.0, 0.0], [1.0, -np.pi, 0.9]):
        frames = forward_kinematics(rob, q, all_frames=True)
        assert np.all(np.isfinite(frames))
        assert_rotations(frames[:, :3, :3])
        origins = frames[:, :3, 3]
        np.testing.assert_allclose(origins[1], origins[0], atol=1e-15)  # zero-length link 1
        if q[1] == np.pi and q[2] > 0:
            direction = origins[3] - origins[2]
            np.testing.assert_allclose(direction / np.linalg.norm(direction), [0, 0, -1], atol=1e-12)
        for i in range(rob.n_dofs):
            link = origins[i + 1] - origins[i]
            angle, axis = angle_axis_from_vec_dir([0, 0, 1], link)
            assert np.isfinite(angle) and np.all(np.isfinite(axis))
            if np.linalg.norm(link) > 1e-9:
                np.testing.assert_allclose(
                    rot_from_angle_axis(angle, axis) @ [0, 0, 1], link / np.linalg.norm(link), atol=1e-9
                )


# ------------------------------------------------------------------ memory


@pytest.mark.parametrize("conv", CONVENTIONS)
def test_batched_forward_kinematics_memory_is_bounded(conv):
    rob = robot("humanoid7", conv)
    N = 100_000
    Q = random_q(rob, np.random.default_rng(13), N)
    forward_kinematics(rob, Q[:10])  # build the per-robot model outside the measurement
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        base, _ = tracemalloc.get_traced_memory()
        out = forward_kinematics(rob, Q)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    output_bytes = 128 * N
    assert out.nbytes == output_bytes
    assert peak - base <= 2 * output_bytes, f"peak {(peak - base) / 1e6:.1f} MB for a {output_bytes / 1e6:.1f} MB result"
