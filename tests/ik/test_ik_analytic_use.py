"""The analytic IK where the package asks for IK (issue 29): solve_ik returns the nearest
exact solution, Cartesian lines follow one branch from a single batched solve, and
plan_to_pose plans every goal that plan_path plans on seeded table scenes."""
from __future__ import annotations

import sys
from paths import ROOT

import numpy as np
import pytest

import robot_sim as rs

from ik_helpers import REACH_TOL, pose_errors
from kin_helpers import robot
from plan_helpers import free_at
from robot_sim.ik.solutions import ik_solutions
from robot_sim.kinematics import forward_kinematics, random_configurations, solve_ik
from robot_sim.planning.cartesian import cartesian_line
from robot_sim.planning.pose_goal import ik_branches, plan_to_pose
from robot_sim.planning.rrt import plan_path

sys.path.insert(0, str(ROOT / "benchmarks"))
from planning_scenes import make_scene  # noqa: E402


@pytest.mark.parametrize("name", ["ur5", "puma560", "kr6_r900", "stanford"])
def test_solve_ik_returns_the_nearest_exact_solution(name: str) -> None:
    arm = robot(name)
    q = arm.q_home + 0.3
    q0 = arm.q_home + 0.2
    T = forward_kinematics(arm, q)
    res = solve_ik(arm, T, q0)
    assert res.success and res.iterations == 0 and res.message == "analytic: the exact solution nearest to q0"
    np.testing.assert_array_equal(res.q, ik_solutions(arm, T, q0).q[0])
    assert res.pos_err < REACH_TOL and res.rot_err < REACH_TOL


@pytest.mark.parametrize("name", ["ur5", "kr6_r900"])  # joints whose range exceeds 2π: many turns
def test_solve_ik_takes_the_first_of_every_turn(name: str) -> None:
    arm = robot(name)
    rng = np.random.default_rng(7)
    Q = random_configurations(arm, 40, rng)
    for q, q0 in zip(Q, random_configurations(arm, 40, rng)):
        T = forward_kinematics(arm, q)
        res = solve_ik(arm, T, q0)
        assert res.success and res.iterations == 0
        np.testing.assert_array_equal(res.q, ik_solutions(arm, T, q0).q[0])


def test_solve_ik_answers_a_target_only_its_own_check_accepts() -> None:
    arm = robot("puma560")
    T = forward_kinematics(arm, arm.q_home + 0.3)
    T[:3, 0] *= 1.0 + 3e-6  # columns off unit length by 6e-6, det 1: within solve_ik's tolerance
    T[:3, 1] /= 1.0 + 3e-6  # (1e-6 + 1e-5 on the diagonal), not the analytic solver's (1e-6)
    with pytest.raises(ValueError, match=r"T is not a rigid transform"):
        ik_solutions(arm, T)
    res = solve_ik(arm, T)  # the numerical path answers it
    assert res.iterations > 0 and res.pos_err < 1e-5


def test_solve_ik_skips_solutions_the_checker_rejects() -> None:
    arm = robot("puma560")
    T = forward_kinematics(arm, arm.q_home + 0.3)
    every = ik_solutions(arm, T).q

    class RejectsTheNearest:
        def in_collision(self, q: np.ndarray) -> bool:
            return bool(np.array_equal(q, every[0]))

    res = solve_ik(arm, T, checker=RejectsTheNearest())
    assert res.success and res.iterations == 0
    np.testing.assert_array_equal(res.q, every[1])


def test_solve_ik_keeps_its_numerical_path_where_no_closed_form_answers() -> None:
    arm = robot("iiwa14")  # a free joint: the descent chooses it
    res = solve_ik(arm, forward_kinematics(arm, arm.q_home + 0.2))
    assert res.success and res.iterations > 0
    puma = robot("puma560")  # a 6-joint arm asked for a position only: redundant, numerical
    position = solve_ik(puma, forward_kinematics(puma, puma.q_home), puma.q_home + 0.1, position_only=True)
    assert position.success and position.iterations > 0 and "analytic" not in position.message


def test_a_cartesian_line_follows_one_branch_without_a_jump() -> None:
    arm = robot("ur5")
    q0 = np.array([0.2, -1.3, 1.4, -1.7, -1.5, 0.3])
    pose0 = forward_kinematics(arm, q0)
    pose1 = pose0.copy()
    pose1[:3, 3] += [0.1, -0.15, 0.12]
    traj = cartesian_line(arm, pose0, pose1, 2.0, q0)
    for k in (0, len(traj.t) // 2, len(traj.t) - 1):
        pos, rot = pose_errors(arm, traj.q[k:k + 1], traj.poses[k])
        assert pos[0] < REACH_TOL and rot[0] < REACH_TOL
    steps = np.abs(np.diff(np.vstack([q0, traj.q]), axis=0)).max()
    assert steps < 0.02  # rad per sample: one branch all along
    # each sample is the analytic solution nearest the previous one
    k = len(traj.t) // 2
    raw = ik_solutions(arm, traj.poses[k], traj.q[k - 1])
    np.testing.assert_allclose(traj.q[k], raw.q[0], atol=1e-12)


@pytest.mark.parametrize("name", ["panda", "iiwa14"])
def test_a_seven_joint_line_holds_the_free_joint_on_one_closed_form_branch(name: str) -> None:
    arm = robot(name)
    free = rs.ik_family(arm).free_joint
    q0 = arm.q_home + np.linspace(0.25, -0.2, arm.n_dofs)
    pose0 = forward_kinematics(arm, q0)
    pose1 = pose0.copy()
    pose1[:3, 3] += [0.05, -0.04, 0.06]
    traj = cartesian_line(arm, pose0, pose1, 1.0, q0)
    assert (traj.q[:, free] == q0[free]).all()  # the closed form with the free joint held, at every sample
    for k in (0, len(traj.t) // 2, len(traj.t) - 1):
        pos, rot = pose_errors(arm, traj.q[k:k + 1], traj.poses[k])
        assert pos[0] < REACH_TOL and rot[0] < REACH_TOL
    assert np.abs(np.diff(np.vstack([q0, traj.q]), axis=0)).max() < 0.02  # one branch, no jump
    k = len(traj.t) // 2
    nearest = ik_solutions(arm, traj.poses[k], traj.q[k - 1], within_limits=False)
    np.testing.assert_allclose(traj.q[k], nearest.q[0], atol=1e-12)


@pytest.mark.parametrize("seed", [0, 1, pytest.param(2, marks=pytest.mark.slow), pytest.param(3, marks=pytest.mark.slow)])
def test_plan_to_pose_plans_every_goal_plan_path_plans(seed: int) -> None:
    arm = robot("ur5")
    scene = make_scene(arm, np.random.default_rng(seed))
    goal = forward_kinematics(arm, scene.q_goal)
    direct = plan_path(arm, scene.q_start, scene.q_goal, scene.checker, time_limit=10.0, seed=0)
    assert direct.success, direct.message  # the seeds are scenes plan_path solves
    branches = ik_branches(arm, goal, scene.q_start, scene.checker)
    assert any(np.allclose(b, scene.q_goal, atol=1e-9) for b in branches)  # the goal's own branch is offered
    res = plan_to_pose(arm, scene.q_start, goal, scene.checker, time_limit=10.0, seed=0)
    assert res.success, res.message
    pos, rot = pose_errors(arm, res.path[-1:], goal)
    assert pos[0] < 1e-9 and rot[0] < 1e-9
    assert free_at(scene.checker, res.path)
