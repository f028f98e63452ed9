"""Differential kinematics: Jacobian, frame and COM velocities, manipulability, workspace
sampling and differential IK, checked against central finite differences of forward
kinematics (kin_helpers.fd_pose_rates) and against closed forms derived by hand."""
from __future__ import annotations

from typing import Iterator

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kin_helpers import CONVENTIONS, ROBOT_NAMES, expected_coms, fd_pose_rates, random_dh_robot, random_q, random_rigid, robot
from robot_sim.kinematics import (
    Kinematics,
    diff_ik_velocity,
    forward_kinematics,
    jacobian,
    manipulability,
    workspace_points,
)
from robot_sim.model.params import RobotParams
from robot_sim.model.state import RobotState
from robot_sim.transforms import HomogeneousTransform

FD_TOL = 1e-6  # finite differences against analytic rates (FD error is ~1e-10)


def fd_jacobian(rob: RobotParams, Q: np.ndarray, **fk_kwargs) -> np.ndarray:
    """(N, 6, n) Jacobian by central differences of forward_kinematics, one joint at a time:
    column j = [ṗ; vee(Ṙ Rᵀ)] for q̇ = e_j."""
    N, n = Q.shape
    J = np.empty((N, 6, n))
    for j in range(n):
        e = np.eye(n)[j]
        v, w = fd_pose_rates(lambda t: forward_kinematics(rob, Q + t * e, **fk_kwargs))
        J[:, :3, j], J[:, 3:, j] = v, w
    return J


def moving_states(rob: RobotParams, seed: int, count: int = 3) -> Iterator[tuple[np.ndarray, np.ndarray, Kinematics]]:
    """``count`` random configurations q with joint velocities qd (set through RobotState),
    each with a Kinematics updated from that state."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        q, qd = random_q(rob, rng), rng.uniform(-1.0, 1.0, rob.n_dofs)
        state = RobotState(rob)
        state.set_q(q)
        state.set_qd(qd)
        kin = Kinematics(rob)
        kin.update(state.joint_state)
        yield q, qd, kin


# ------------------------------------------------------------------ Jacobian


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_jacobian_matches_finite_differences(name, conv):
    rob = robot(name, conv)
    rng = np.random.default_rng(20)
    Q = random_q(rob, rng, 10)
    J = jacobian(rob, Q)
    assert J.shape == (10, 6, rob.n_dofs)
    np.testing.assert_allclose(J, fd_jacobian(rob, Q), atol=FD_TOL)
    # a prismatic joint only translates: its angular column is zero
    np.testing.assert_array_equal(J[:, 3:, ~rob.is_revolute], 0.0)
    kin, state = Kinematics(rob), RobotState(rob)
    for k, q in enumerate(Q):
        np.testing.assert_allclose(jacobian(rob, q), J[k], atol=1e-12, rtol=0)
        state.set_q(q)
        kin.update(state.joint_state)
        np.testing.assert_allclose(kin.jacobian, J[k], atol=1e-12, rtol=0)


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ["stanford", "humanoid7"])
def test_jacobian_with_world_transform(name, conv):
    rob = robot(name, conv)
    rng = np.random.default_rng(21)
    Q = random_q(rob, rng, 5)
    W = random_rigid(rng)
    J = jacobian(rob, Q, world_tf=W)
    np.testing.assert_allclose(J, fd_jacobian(rob, Q, world_tf=W), atol=FD_TOL)
    # twists rotate with the world: J_world = blockdiag(R_W, R_W) J
    R = W[:3, :3]
    np.testing.assert_allclose(J[:, :3], R @ jacobian(rob, Q)[:, :3], atol=1e-12)
    np.testing.assert_allclose(J[:, 3:], R @ jacobian(rob, Q)[:, 3:], atol=1e-12)
    np.testing.assert_allclose(jacobian(rob, Q[0], world_tf=HomogeneousTransform(W)), J[0], atol=1e-12)


@pytest.mark.parametrize("conv", CONVENTIONS)
@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 7))
def test_jacobian_of_random_chains_matches_finite_differences(conv, seed, n):
    rng = np.random.default_rng(seed)
    rob = random_dh_robot(rng, n, convention=conv)
    Q = random_q(rob, rng, 4)
    np.testing.assert_allclose(jacobian(rob, Q), fd_jacobian(rob, Q), atol=FD_TOL)


# ------------------------------------------------------------------ velocities


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_link_velocities_match_finite_differences(name, conv):
    rob = robot(name, conv)
    n = rob.n_dofs
    for q, qd, kin in moving_states(rob, seed=22):
        v, w = fd_pose_rates(lambda t: forward_kinematics(rob, q + t * qd, all_frames=True)[: n + 1])
        assert kin.link_vel.shape == (n + 1, 6)
        np.testing.assert_array_equal(kin.link_vel[0], 0.0)  # frame 0 is fixed
        np.testing.assert_allclose(kin.link_vel[:, :3], v, atol=FD_TOL)
        np.testing.assert_allclose(kin.link_vel[:, 3:], w, atol=FD_TOL)


def _coms(rob: RobotParams, q: np.ndarray) -> np.ndarray:
    """COM positions by the documented rule (see kin_helpers.expected_coms)."""
    return expected_coms(rob, forward_kinematics(rob, q, all_frames=True)[: rob.n_dofs + 1])


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_link_com_velocities_match_finite_differences(name, conv):
    rob = robot(name, conv)
    h = 1e-5
    for q, qd, kin in moving_states(rob, seed=23):
        expected = (_coms(rob, q + h * qd) - _coms(rob, q - h * qd)) / (2 * h)
        np.testing.assert_allclose(kin.link_com, _coms(rob, q), atol=1e-12)
        assert kin.link_com_vel.shape == (rob.n_links + 1, 3)
        np.testing.assert_allclose(kin.link_com_vel, expected, atol=FD_TOL)


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_endeffector_twist_is_jacobian_times_qd(name, conv):
    rob = robot(name, conv)
    for q, qd, kin in moving_states(rob, seed=24):
        np.testing.assert_allclose(kin.endeff_twist, jacobian(rob, q) @ qd, atol=1e-12)
        v, w = fd_pose_rates(lambda t: forward_kinematics(rob, q + t * qd))
        np.testing.assert_allclose(kin.endeff_twist, np.concatenate([v, w]), atol=FD_TOL)


@pytest.mark.parametrize("conv", CONVENTIONS)
def test_velocities_follow_each_update(conv):
    rob = robot("stanford", conv)
    q, qd, kin = next(moving_states(rob, seed=25))
    first = kin.link_vel.copy()
    state = RobotState(rob)
    state.set_q(q)
    state.set_qd(2 * qd)
    kin.update(state.joint_state)
    np.testing.assert_allclose(kin.link_vel, 2 * first, atol=1e-12)
    np.testing.assert_allclose(kin.endeff_twist, 2 * (jacobian(rob, q) @ qd), atol=1e-12)


# ------------------------------------------------------------------ manipulability


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_manipulability_is_yoshikawa_measure(name, conv):
    rob = robot(name, conv)
    Q = random_q(rob, np.random.default_rng(26), 6)
    J = fd_jacobian(rob, Q)
    if rob.n_dofs < 6:
        # arms with fewer joints: position rows only, without the planar arm's z row,
        # which is zero everywhere
        J = J[:, :2] if name == "planar3" else J[:, :3]
    expected = np.sqrt(np.abs(np.linalg.det(J @ np.swapaxes(J, 1, 2))))
    got = manipulability(rob, Q)
    assert got.shape == (6,)
    np.testing.assert_allclose(got, expected, rtol=1e-6, atol=1e-9)
    for k, q in enumerate(Q):
        assert manipulability(rob, q) == pytest.approx(got[k], rel=1e-12, abs=1e-15)
        assert manipulability(rob, q, jac=jacobian(rob, q)) == pytest.approx(got[k], rel=1e-12, abs=1e-15)


def test_planar_arm_manipulability_by_cauchy_binet():
    """For the planar arm, column j of the x-y Jacobian is r_j = p_e − o_{j-1} turned by 90°,
    so det(J Jᵀ) = Σ_{j<k} (r_j × r_k)² (Cauchy–Binet over the 2×2 minors)."""
    arm = robot("planar3")
    a = arm.dh_a
    for q in random_q(arm, np.random.default_rng(31), 20):
        angles = np.cumsum(q)
        joints = np.vstack([[0.0, 0.0], np.cumsum(a[:, None] * np.c_[np.cos(angles), np.sin(angles)], axis=0)])
        r = joints[-1] - joints[:-1]
        minors = [r[j, 0] * r[k, 1] - r[j, 1] * r[k, 0] for j in range(3) for k in range(j + 1, 3)]
        assert manipulability(arm, q) == pytest.approx(np.sqrt(np.sum(np.square(minors))), rel=1e-9)
    assert manipulability(arm, np.zeros(3)) < 1e-7  # stretched out: singular


def test_manipulability_with_an_unlimited_prismatic_joint():
    """A Cartesian (PPP) gantry with unlimited strokes: J_v is the identity whatever q, so
    the measure is exactly 1 (the structural-row probe must not need the joint limits)."""
    gantry = RobotParams.from_arrays(
        "gantry", [0.0, 0.0, 0.0], [-np.pi / 2, -np.pi / 2, 0.0], [0.0, 0.0, 0.0],
        [-np.pi / 2, -np.pi / 2, 0.0], [1, 1, 1],
    )
    for q in ([0.0, 0.0, 0.0], [3.0, -250.0, 7.5]):
        assert manipulability(gantry, np.array(q)) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("conv", CONVENTIONS)
def test_manipulability_closed_forms_of_the_3dof_arms(conv):
    """det J_P of the anthropomorphic arm is −a2 a3 s3 (a2 c2 + a3 c23), of the spherical
    arm −d3² s2 (Siciliano 3.3): both follow from the closed-form positions (lengths read
    from the standard table, the measure taken in ``conv``)."""
    rng = np.random.default_rng(27)
    arm = robot("anthropomorphic", conv)
    a2, a3 = robot("anthropomorphic", "standard").dh_a[1:]
    Q = random_q(arm, rng, 50)
    expected = a2 * a3 * np.abs(np.sin(Q[:, 2]) * (a2 * np.cos(Q[:, 1]) + a3 * np.cos(Q[:, 1] + Q[:, 2])))
    np.testing.assert_allclose(manipulability(arm, Q), expected, rtol=1e-9, atol=1e-12)
    sph = robot("spherical", conv)
    Q = random_q(sph, rng, 50)
    np.testing.assert_allclose(manipulability(sph, Q), Q[:, 2] ** 2 * np.abs(np.sin(Q[:, 1])), rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize(
    "name, q",
    [
        ("anthropomorphic", [0.3, 0.7, 0.0]),  # elbow stretched
        ("anthropomorphic", [0.3, 0.7, np.pi]),  # elbow folded back
        ("anthropomorphic", [0.3, np.pi / 2, 0.0]),  # wrist point on the waist axis
        ("spherical", [0.4, 0.0, 0.5]),  # arm along the first axis
        ("puma560", [0.2, 0.5, -0.8, 0.3, 0.0, 0.4]),  # wrist: q5 = 0 aligns axes 4 and 6
        ("ur5", [0.1, -1.0, 0.0, -0.5, 0.7, 0.2]),  # elbow stretched
    ],
)
@pytest.mark.parametrize("conv", CONVENTIONS)
def test_manipulability_vanishes_at_singularities(name, q, conv):
    rob = robot(name, conv)
    assert manipulability(rob, q) < 1e-7  # √(rounding-level det) is ~1e-8; regular values ~0.1
    nearby = np.array(q) + 0.1
    assert manipulability(rob, nearby) > 1e-4


# ------------------------------------------------------------------ workspace


def test_workspace_points_planar3_bounds_and_reproducibility():
    rob = robot("planar3")
    points, manip = workspace_points(rob, 2000, seed=3)
    assert points.shape == (2000, 3) and manip.shape == (2000,)
    assert np.all(np.isfinite(points)) and np.all(manip >= 0)
    base = rob.base_tf.t()
    radius = np.linalg.norm(points[:, :2] - base[:2], axis=1)
    reach = rob.dh_a.sum()
    assert np.all(radius <= reach + 1e-12)
    assert radius.max() > 0.95 * reach  # the sampling covers the whole disc
    np.testing.assert_allclose(points[:, 2], base[2], atol=1e-12)  # the arm stays in its plane
    again, manip_again = workspace_points(rob, 2000, seed=3)
    np.testing.assert_array_equal(again, points)
    np.testing.assert_array_equal(manip_again, manip)
    assert not np.array_equal(workspace_points(rob, 2000, seed=4)[0], points)


def test_workspace_points_lie_in_the_reachable_sets():
    # anthropomorphic: the wrist point is a2 + a3 at most from the shoulder (frame 0)
    arm = robot("anthropomorphic")
    points, manip = workspace_points(arm, 1500, seed=1)
    dist = np.linalg.norm(points - arm.base_tf.t(), axis=1)
    a2, a3 = arm.dh_a[1:]
    assert np.all(dist <= a2 + a3 + 1e-12) and np.all(dist >= abs(a2 - a3) - 1e-12)
    # manipulability is the closed form a2 a3 |s3 (a2 c2 + a3 c23)| ≤ a2 a3 (a2 + a3)
    assert np.all(manip <= a2 * a3 * (a2 + a3) + 1e-12)
    # scara: height = d1 − d3 − tool within the quill range, radius within the link lengths
    scara = robot("scara")
    points, _ = workspace_points(scara, 1500, seed=2)
    d1, tool = scara.dh_d[0], scara.tool_tf.t()[2]
    lo, hi = scara.q_min[2], scara.q_max[2]
    assert np.all(points[:, 2] <= d1 - lo - tool + 1e-12) and np.all(points[:, 2] >= d1 - hi - tool - 1e-12)
    a1, a2 = scara.dh_a[:2]
    c_min = np.cos(scara.q_max[1])  # |q2| ≤ 150°: the elbow never folds completely
    r_min = np.sqrt(a1**2 + a2**2 + 2 * a1 * a2 * c_min)
    radius = np.linalg.norm(points[:, :2], axis=1)
    assert np.all(radius <= a1 + a2 + 1e-12) and np.all(radius >= r_min - 1e-12)
    # spherical: |p − o2|² = d3² with d3 in its limits, o2 on a circle of radius d2
    sph = robot("spherical")
    points, _ = workspace_points(sph, 1500, seed=3)
    local = points - sph.base_tf.t()
    d3_sq = np.sum(local**2, axis=1) - sph.dh_d[1] ** 2
    assert np.all(d3_sq >= sph.q_min[2] ** 2 - 1e-12) and np.all(d3_sq <= sph.q_max[2] ** 2 + 1e-12)


def test_workspace_points_bad_input():
    with pytest.raises(ValueError, match="n_samples"):
        workspace_points(robot("planar3"), 0)
    unlimited = RobotParams.from_arrays("slider", [0.0], [0.0], [0.0], [0.0], [1])
    with pytest.raises(ValueError, match="prismatic joint 1 has no limits"):
        workspace_points(unlimited, 10)


# ------------------------------------------------------------------ differential IK


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_diff_ik_velocity_reproduces_reachable_twists(name, conv):
    rob = robot(name, conv)
    rng = np.random.default_rng(28)
    rows = 6 if rob.n_dofs >= 6 else 3
    # planar3's position Jacobian has a zero z row: use its rank, not its row count
    rank = np.linalg.matrix_rank(jacobian(rob, rob.q_home)[:rows])
    checked = 0
    for q in random_q(rob, rng, 40):
        J = jacobian(rob, q)[:rows]
        sigma_min = np.linalg.svd(J, compute_uv=False)[rank - 1]
        if sigma_min < 0.05:  # stay away from singularities
            continue
        twist = J @ rng.uniform(-1, 1, rob.n_dofs)  # reachable by construction
        exact = diff_ik_velocity(rob, q, twist, damping=1e-7)
        np.testing.assert_allclose(J @ exact, twist, atol=1e-9)
        np.testing.assert_allclose(exact, np.linalg.pinv(J) @ twist, atol=1e-8)  # least norm
        # the default damping λ = 1e-2 leaves an error of at most λ²/σ_min² of the twist
        damped = diff_ik_velocity(rob, q, twist)
        bound = 1e-4 / sigma_min**2 * np.linalg.norm(twist)
        assert np.linalg.norm(J @ damped - twist) <= bound
        checked += 1
    assert checked >= 10


def test_diff_ik_velocity_rejects_bad_twists():
    rob = robot("puma560")
    for bad in ([0.0] * 4, [0.0, np.nan, 0.0], [np.inf] * 6, np.zeros((2, 3))):
        with pytest.raises(ValueError, match="twist_des"):
            diff_ik_velocity(rob, rob.q_home, bad)
    with pytest.raises(ValueError):
        diff_ik_velocity(rob, [0.0] * 5, [0.0] * 6)


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ["anthropomorphic", "puma560"])
def test_closed_loop_circle_tracking(name, conv):
    """Resolved-rate control q += dt · diff_ik(v_des + K (p_des − p)) follows a circle of
    radius 10 cm in a vertical plane, one revolution in 2 s, within a few millimetres."""
    rob = robot(name, conv)
    q = np.array(rob.q_home, dtype=float)
    p0 = forward_kinematics(rob, q)[:3, 3]
    radius, omega, gain, dt = 0.1, np.pi, 20.0, 2e-3
    e1, e2 = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])
    center = p0 - radius * e1
    worst = 0.0
    for step in range(1, int(round(2 * np.pi / omega / dt)) + 1):
        t = step * dt
        p_des = center + radius * (np.cos(omega * t) * e1 + np.sin(omega * t) * e2)
        v_des = radius * omega * (-np.sin(omega * t) * e1 + np.cos(omega * t) * e2)
        p = forward_kinematics(rob, q)[:3, 3]
        q = q + dt * diff_ik_velocity(rob, q, v_des + gain * (p_des - p))
        p_new = forward_kinematics(rob, q)[:3, 3]
        t_new = t + dt
        p_next = center + radius * (np.cos(omega * t_new) * e1 + np.sin(omega * t_new) * e2)
        worst = max(worst, np.linalg.norm(p_new - p_next))
    assert worst < 3e-3, f"{name}: worst tracking error {worst * 1e3:.2f} mm"
    assert np.linalg.norm(forward_kinematics(rob, q)[:3, 3] - p0) < 3e-3  # back where it began
