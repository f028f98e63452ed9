"""Modified (Craig) DH against a published table computed by hand, against the standard
equivalent of random modified chains (built here row by row, not by dh_convert), and the
exact conversions of dh_convert in both directions."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from robot_sim.model.convert import to_convention, to_modified, to_standard
from robot_sim.dynamics import gravity_torque, mass_matrix
from kin_helpers import CONVENTIONS, ROBOT_NAMES, h_rot_x, h_rot_z, h_trans, random_dh_robot, random_q, robot
from robot_sim.kinematics import forward_kinematics, jacobian, solve_ik, workspace_points
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.transforms import HomogeneousTransform

HALF_PI = np.pi / 2
seeds = st.integers(0, 2**32 - 1)

#: Franka Emika Panda, Franka's published table (Craig's convention): per joint
#: a_{i-1} [m], d_i [m], α_{i-1} [rad]; the flange is d = 0.107 m beyond joint 7.
PANDA_TABLE = [
    (0.0, 0.333, 0.0),
    (0.0, 0.0, -HALF_PI),
    (0.0, 0.316, HALF_PI),
    (0.0825, 0.0, HALF_PI),
    (-0.0825, 0.384, -HALF_PI),
    (0.0, 0.0, HALF_PI),
    (0.088, 0.0, HALF_PI),
]
PANDA_FLANGE_D = 0.107


def panda() -> RobotParams:
    a, d, alpha = (np.array(col) for col in zip(*PANDA_TABLE))
    return RobotParams.from_arrays(
        "panda", a, alpha, d, np.zeros(7), [JTYPE_REVOLUTE] * 7,
        tool_tf=HomogeneousTransform(h_trans(z=PANDA_FLANGE_D)), convention="modified",
    )


def panda_by_hand(q: np.ndarray) -> np.ndarray:
    """Flange pose from Franka's table: Π Rx(α_{i-1}) Tx(a_{i-1}) Rz(q_i) Tz(d_i) · Tz(0.107)."""
    T = np.eye(4)
    for (a, d, alpha), qi in zip(PANDA_TABLE, q):
        T = T @ h_rot_x(alpha) @ h_trans(x=a) @ h_rot_z(qi) @ h_trans(z=d)
    return T @ h_trans(z=PANDA_FLANGE_D)


def test_panda_zero_pose_by_hand():
    """At q = 0 the Panda stands straight: the flange is 0.088 m forward (a7), at height
    0.333 + 0.316 + 0.384 − 0.107 (it points down: x along x0, z along −z0); a4 and a5
    (+0.0825, −0.0825) cancel."""
    T = forward_kinematics(panda(), np.zeros(7))
    np.testing.assert_allclose(T[:3, 3], [0.088, 0.0, 0.333 + 0.316 + 0.384 - 0.107], atol=1e-15)
    np.testing.assert_allclose(T[:3, :3], np.diag([1.0, -1.0, -1.0]), atol=1e-15)


def test_panda_joint1_and_joint7_turn_about_their_own_z():
    """Modified DH: joint 1 turns about z_1 = z_0 (vertical through the base), joint 7 about
    z_7 = the flange axis: turning q7 only spins the flange; turning q1 rotates the zero
    pose about the world z axis."""
    rob = panda()
    T0 = forward_kinematics(rob, np.zeros(7))
    T7 = forward_kinematics(rob, [0, 0, 0, 0, 0, 0, 0.7])
    np.testing.assert_allclose(T7[:3, 3], T0[:3, 3], atol=1e-15)
    np.testing.assert_allclose(T7[:3, 2], T0[:3, 2], atol=1e-15)
    T1 = forward_kinematics(rob, [0.7, 0, 0, 0, 0, 0, 0])
    np.testing.assert_allclose(T1, h_rot_z(0.7) @ T0, atol=1e-15)
    J = jacobian(rob, np.zeros(7))
    np.testing.assert_allclose(J[3:, 0], [0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(J[3:, 6], T0[:3, 2], atol=1e-15)


def test_panda_random_poses_by_hand():
    rob = panda()
    Q = np.random.default_rng(40).uniform(-2.8, 2.8, (50, 7))
    batch = forward_kinematics(rob, Q)
    for q, T in zip(Q, batch):
        np.testing.assert_allclose(T, panda_by_hand(q), atol=1e-12)
        np.testing.assert_allclose(forward_kinematics(rob, q), T, atol=1e-12)


def standard_equivalent_by_hand(rob: RobotParams) -> RobotParams:
    """Standard table of a modified chain: row i takes a, α of modified row i+1 (0 for the
    last row), θ and d stay; the base takes modified row 1's Rx(α_0)·Tx(a_0)."""
    a = np.append(rob.dh_a[1:], 0.0)
    alpha = np.append(rob.dh_alpha[1:], 0.0)
    base = rob.base_tf.mat @ h_rot_x(rob.dh_alpha[0]) @ h_trans(x=rob.dh_a[0])
    return RobotParams.from_arrays(
        "std", a, alpha, rob.dh_d, rob.dh_th, rob.jtype,
        base_tf=HomogeneousTransform(base), tool_tf=rob.tool_tf,
    )


@settings(max_examples=30, deadline=None)
@given(seed=seeds, n=st.integers(1, 8))
def test_random_modified_chains_equal_their_standard_equivalent(seed, n):
    rng = np.random.default_rng(seed)
    mod = random_dh_robot(rng, n, convention="modified")
    std = standard_equivalent_by_hand(mod)
    Q = random_q(mod, rng, 20)
    np.testing.assert_allclose(forward_kinematics(mod, Q), forward_kinematics(std, Q), atol=1e-12)
    np.testing.assert_allclose(jacobian(mod, Q), jacobian(std, Q), atol=1e-12)
    # standard frame i = modified frame i · Tx(a_i) Rx(α_i), a_i, α_i of standard row i
    fm, fs = forward_kinematics(mod, Q, all_frames=True), forward_kinematics(std, Q, all_frames=True)
    for i in range(1, n + 1):
        shift = h_trans(x=std.dh_a[i - 1]) @ h_rot_x(std.dh_alpha[i - 1])
        np.testing.assert_allclose(fm[:, i] @ shift, fs[:, i], atol=1e-12)
    converted = to_standard(mod)
    for field in ("dh_a", "dh_alpha", "dh_d", "dh_th"):
        np.testing.assert_array_equal(getattr(converted, field), getattr(std, field))
    np.testing.assert_allclose(converted.base_tf.mat, std.base_tf.mat, atol=1e-15)


@settings(max_examples=30, deadline=None)
@pytest.mark.parametrize("conv", CONVENTIONS)
@given(seed=seeds, n=st.integers(1, 8))
def test_conversions_keep_every_endeffector_pose(conv, seed, n):
    rng = np.random.default_rng(seed)
    rob = random_dh_robot(rng, n, convention=conv)
    Q = random_q(rob, rng, 50)
    expected = forward_kinematics(rob, Q)
    for target in CONVENTIONS:
        other = to_convention(rob, target)
        assert other.convention == target
        np.testing.assert_allclose(forward_kinematics(other, Q), expected, atol=1e-12, rtol=0)
        back = to_convention(other, conv)
        np.testing.assert_allclose(forward_kinematics(back, Q), expected, atol=1e-12, rtol=0)
        for field in ("jtype", "dh_d", "dh_th", "q_min", "q_max", "q_home"):
            np.testing.assert_array_equal(getattr(other, field), getattr(rob, field))


def test_conversion_maps_the_columns_and_absorbs_into_base_and_tool():
    rob = RobotParams.from_arrays(
        "two", [0.3, 0.4], [0.5, -0.6], [0.1, 0.2], [0.7, 0.8], [0, 1], q_min=[-1, 0], q_max=[1, 0.5]
    )
    mod = to_modified(rob)
    np.testing.assert_array_equal(mod.dh_a, [0.0, 0.3])
    np.testing.assert_array_equal(mod.dh_alpha, [0.0, 0.5])
    np.testing.assert_allclose(mod.tool_tf.mat, h_trans(x=0.4) @ h_rot_x(-0.6), atol=1e-15)
    np.testing.assert_array_equal(mod.base_tf.mat, np.eye(4))
    assert to_modified(mod) is mod and to_standard(rob) is rob
    std = to_standard(mod)
    np.testing.assert_array_equal(std.dh_a, [0.3, 0.0])  # the tool keeps the last a, α
    np.testing.assert_allclose(std.tool_tf.mat, mod.tool_tf.mat, atol=0)
    with pytest.raises(ValueError, match="convention must be 'standard' or 'modified', got 'dh'"):
        to_convention(rob, "dh")


@pytest.mark.parametrize("name", [n for n in ROBOT_NAMES if robot(n).inertials is not None])
def test_conversion_moves_the_inertials_with_the_frames(name):
    """Link i's COM stays at the same point of the world and its inertia tensor the same
    world tensor, so the mass matrix and gravity torques agree in both conventions."""
    rob = robot(name)
    Q = random_q(rob, np.random.default_rng(42), 20)
    for conv in CONVENTIONS:
        other = to_convention(rob, conv)
        np.testing.assert_array_equal(other.inertials.mass, rob.inertials.mass)
        fa, fb = forward_kinematics(rob, Q[0], all_frames=True), forward_kinematics(other, Q[0], all_frames=True)
        for i in range(rob.n_dofs):
            Ra, Rb = fa[i + 1][:3, :3], fb[i + 1][:3, :3]
            np.testing.assert_allclose(Ra @ rob.inertials.com[i] + fa[i + 1][:3, 3],
                                       Rb @ other.inertials.com[i] + fb[i + 1][:3, 3], atol=1e-12)
            np.testing.assert_allclose(Ra @ rob.inertials.inertia[i] @ Ra.T, Rb @ other.inertials.inertia[i] @ Rb.T,
                                       atol=1e-12)
        np.testing.assert_allclose(mass_matrix(other, Q), mass_matrix(rob, Q), atol=1e-12, rtol=1e-12)
        np.testing.assert_allclose(gravity_torque(other, Q), gravity_torque(rob, Q), atol=1e-11, rtol=1e-12)


@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_shipped_robots_convert_exactly(name):
    rob = robot(name)
    Q = random_q(rob, np.random.default_rng(41), 200)
    expected = forward_kinematics(rob, Q)
    for conv in CONVENTIONS:
        np.testing.assert_allclose(forward_kinematics(robot(name, conv), Q), expected, atol=1e-12, rtol=0)


@pytest.mark.parametrize("name", ["stanford", "panda", "scara"])
def test_workspace_and_ik_agree_across_conventions(name):
    """Same seed, same samples: the workspace cloud and its manipulability are the same
    for both tables of one arm; IK from home reaches the same target in both."""
    tables = [robot(name, conv) for conv in CONVENTIONS]
    (p_std, m_std), (p_mod, m_mod) = (workspace_points(t, 3000, seed=7) for t in tables)
    np.testing.assert_allclose(p_mod, p_std, atol=1e-12)
    np.testing.assert_allclose(m_mod, m_std, rtol=1e-9, atol=1e-12)
    target = forward_kinematics(tables[0], random_q(tables[0], np.random.default_rng(43)))
    for table in tables:
        result = solve_ik(table, target)
        assert result.success, result.message
        reached = forward_kinematics(table, result.q)
        assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) <= 1e-6
