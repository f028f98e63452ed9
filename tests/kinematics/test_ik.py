"""Inverse kinematics: success rate on reachable targets, limits, accuracy, bad input."""
from __future__ import annotations

import numpy as np
import pytest

from kin_helpers import CONVENTIONS, robot as shipped
from robot_sim.kinematics import forward_kinematics, random_configurations, solve_ik
from robot_sim.model.params import RobotParams
from robot_sim.io.robot_file import available_robots, load_robot
from robot_sim.transforms import HomogeneousTransform, rot_z

N_TARGETS = 200
FULL_POSE_ROBOTS = ["anthropomorphic6", "humanoid7", "stanford", "puma560", "ur5"]
POSITION_ROBOTS = ["planar3", "spherical", "anthropomorphic", "scara"]


def limited_humanoid() -> RobotParams:
    """humanoid7 with every joint limited to ±90°, the 7-DOF case of the IK bar."""
    h = load_robot("humanoid7")
    return RobotParams.from_arrays(
        "humanoid7 ±90°", h.dh_a, h.dh_alpha, h.dh_d, h.dh_th, h.jtype,
        q_min=np.full(7, -np.pi / 2), q_max=np.full(7, np.pi / 2),
        base_tf=h.base_tf, tool_tf=h.tool_tf,
    )


def rotation_angle(Ra: np.ndarray, Rb: np.ndarray) -> float:
    """Angle (rad) of the rotation between two rotation matrices, from the trace."""
    c = (np.trace(Ra.T @ Rb) - 1.0) / 2.0
    return float(np.arccos(np.clip(c, -1.0, 1.0)))


def targets_for(robot: RobotParams, seed: int) -> np.ndarray:
    return forward_kinematics(robot, random_configurations(robot, N_TARGETS, np.random.default_rng(seed)))


def check_solutions(robot: RobotParams, targets: np.ndarray, position_only: bool) -> None:
    results = [solve_ik(robot, t, position_only=position_only) for t in targets]
    solved = [r for r in results if r.success]
    assert len(solved) >= 0.99 * len(targets), f"{robot.name}: {len(solved)}/{len(targets)} solved"
    for target, res in zip(targets, results):
        assert np.all(np.isfinite(res.q))
        assert np.all(res.q >= robot.q_min) and np.all(res.q <= robot.q_max), res.q
        if res.success:
            reached = forward_kinematics(robot, res.q)
            assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) <= 1e-6
            if not position_only:
                assert rotation_angle(reached[:3, :3], target[:3, :3]) <= 1e-6


def each_robot_in_one_convention_by_default(names: list[str]) -> list:
    """(name, convention) pairs: by default each robot in one convention, alternating
    (converted tables have the same forward kinematics, tested elsewhere to 1e-12), the
    other one in the slow sweep."""
    return [
        (name, conv) if k % 2 == j else pytest.param(name, conv, marks=pytest.mark.slow)
        for k, name in enumerate(names)
        for j, conv in enumerate(CONVENTIONS)
    ]


@pytest.mark.parametrize(("name", "conv"), each_robot_in_one_convention_by_default(FULL_POSE_ROBOTS))
def test_full_pose_targets_are_solved(name: str, conv: str) -> None:
    robot = shipped(name, conv)
    check_solutions(robot, targets_for(robot, seed=11), position_only=False)


def test_seven_dof_arm_with_90_degree_limits() -> None:
    robot = limited_humanoid()
    check_solutions(robot, targets_for(robot, seed=12), position_only=False)


@pytest.mark.parametrize(("name", "conv"), each_robot_in_one_convention_by_default(POSITION_ROBOTS))
def test_position_only_targets_are_solved(name: str, conv: str) -> None:
    robot = shipped(name, conv)
    check_solutions(robot, targets_for(robot, seed=13), position_only=True)


def test_short_arm_asked_for_full_pose_solves_position_and_says_so() -> None:
    robot = load_robot("anthropomorphic")
    target = forward_kinematics(robot, np.radians([20.0, 30.0, -40.0]))
    res = solve_ik(robot, target)
    assert res.success and res.position_only
    assert "has 3 joints (< 6): solved for position only" in res.message


def test_unreachable_target_is_a_failed_result_not_an_exception() -> None:
    robot = load_robot("puma560")
    far = HomogeneousTransform.from_rt(np.eye(3), [5.0, 0.0, 1.0])
    res = solve_ik(robot, far, max_iter=200)
    assert not res.success
    assert np.all(np.isfinite(res.q))
    assert np.all(res.q >= robot.q_min) and np.all(res.q <= robot.q_max)
    assert res.pos_err > 3.0
    assert "did not converge" in res.message


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_reach_bounds_every_configuration_and_is_tight_for_a_planar_arm(convention: str) -> None:
    for name in available_robots():
        robot = shipped(name, convention)
        Q = random_configurations(robot, 4000, np.random.default_rng(1))
        tool = forward_kinematics(robot, Q)[:, :3, 3]
        farthest = np.linalg.norm(tool - robot.base_tf.mat[:3, 3], axis=1).max()
        assert farthest <= robot.reach + 1e-12, name
    planar = shipped("planar3", convention)  # stretched out, the bound is reached
    stretched = np.linalg.norm(forward_kinematics(planar, np.zeros(3))[:3, 3] - planar.base_tf.mat[:3, 3])
    assert stretched == pytest.approx(planar.reach, abs=1e-12)


def test_a_target_beyond_reach_is_answered_by_one_descent_and_says_why() -> None:
    # Restarts cannot help: the window answered each key press out of reach after
    # 1000 iterations and 15-35 restarts (0.6-0.9 s).
    robot = load_robot("ur5")
    tool = forward_kinematics(robot, robot.q_home)
    far = tool.copy()
    far[2, 3] += robot.reach
    res = solve_ik(robot, far)
    assert not res.success and res.restarts == 0 and res.iterations <= 40
    distance = np.linalg.norm(far[:3, 3] - robot.base_tf.mat[:3, 3])
    assert res.message.startswith(
        f"target is {distance:.3g} m from the base, beyond the arm's reach of {robot.reach:.3g} m; did not converge"
    ), res.message
    near = tool.copy()  # inside the bound the full search runs as before
    near[2, 3] += 0.01
    assert solve_ik(robot, near).success


def test_a_position_only_failure_quotes_no_rotation_error() -> None:
    robot = load_robot("planar3")
    res = solve_ik(robot, HomogeneousTransform.from_rt(np.eye(3), [5.0, 0.0, 0.0]))
    assert not res.success and res.position_only
    assert res.message.endswith(f"position error {res.pos_err:.3g} m"), res.message


def test_respect_limits_false_may_leave_the_limits() -> None:
    # The planar arm's first joint is limited to ±180°: with limits off the solver
    # still converges, and the result must reach the target.
    robot = load_robot("planar3")
    target = forward_kinematics(robot, np.radians([10.0, 20.0, 30.0]))
    res = solve_ik(robot, target, respect_limits=False)
    assert res.success
    assert np.linalg.norm(forward_kinematics(robot, res.q)[:3, 3] - target[:3, 3]) <= 1e-6


def test_redundant_arm_stays_near_home_for_nearby_targets() -> None:
    # The null-space pull toward home picks, among the many solutions of a 7-DOF arm,
    # one close to home when the target is close to the home pose.
    robot = load_robot("humanoid7")
    q_near = robot.q_home + np.radians([3.0, -2.0, 4.0, 3.0, -3.0, 2.0, 1.0])
    res = solve_ik(robot, forward_kinematics(robot, q_near))
    assert res.success
    assert np.max(np.abs(res.q - robot.q_home)) < np.radians(10.0)


@pytest.mark.parametrize(
    "target, fragment",
    [
        (np.eye(3), "IK target must be a 4x4 transform, got shape (3, 3)"),
        (np.full((4, 4), np.nan), "IK target is not a rigid transform"),
        (np.diag([2.0, 1.0, 1.0, 1.0]), "IK target is not a rigid transform"),
        (np.diag([-1.0, 1.0, 1.0, 1.0]), "IK target is not a rigid transform"),
    ],
)
def test_invalid_targets_raise(target: np.ndarray, fragment: str) -> None:
    with pytest.raises(ValueError) as info:
        solve_ik(load_robot("puma560"), target)
    assert fragment in str(info.value)


def test_sheared_rotation_is_rejected() -> None:
    mat = np.eye(4)
    mat[:3, :3] = rot_z(0.3)
    mat[0, 1] += 0.01
    with pytest.raises(ValueError, match="not a rigid transform"):
        solve_ik(load_robot("puma560"), mat)


@pytest.mark.parametrize(
    "kwargs, fragment",
    [
        ({"q0": np.zeros(5)}, "q0 must have 6 joint values per configuration, got shape (5,)"),
        ({"q0": [0, 0, np.nan, 0, 0, 0]}, "q0 contains NaN or infinite values"),
        ({"q0": np.zeros((2, 6))}, "q0 must be one configuration of shape (6,)"),
        ({"tol_pos": 0.0}, "tol_pos must be a positive finite number, got 0.0"),
        ({"tol_rot": -1e-3}, "tol_rot must be a positive finite number, got -0.001"),
        ({"tol_pos": float("nan")}, "tol_pos must be a positive finite number, got nan"),
    ],
)
def test_bad_arguments_raise(kwargs: dict, fragment: str) -> None:
    robot = load_robot("puma560")
    with pytest.raises(ValueError) as info:
        solve_ik(robot, forward_kinematics(robot, robot.q_home), **kwargs)
    assert fragment in str(info.value)
