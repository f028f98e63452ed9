"""plan_path and plan_to_pose with the CollisionChecker: around a wall, never through a
thin post between checks, reproducible by seed, start/goal in collision or outside the
limits named; the returned polyline and the spline retime follows through it both free
when sampled at 0.5 mm of measured motion (plan_helpers), twice finer than the
planner's resolution and independent of its bound."""
from __future__ import annotations

import numpy as np
import pytest

from kin_helpers import robot
from plan_helpers import free_at
from robot_sim.collision import Box, CollisionChecker, Cylinder, World
from robot_sim.kinematics import forward_kinematics, random_configurations
from robot_sim.planning.pose_goal import ik_branches, plan_to_pose
from robot_sim.planning.rrt import plan_path
from robot_sim.planning.spline import JointSpline

WALL_CENTRE, WALL_SIZE = np.array([0.45, 0.0, 0.25]), np.array([0.3, 0.04, 0.5])
WALL = World({"wall": Box(WALL_SIZE, np.block([[np.eye(3), WALL_CENTRE[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]]))})
SIDES = (np.array([0.45, -0.25, 0.3]), np.array([0.45, 0.25, 0.3]))  # tool positions either side


def fine_free(checker, path):
    return free_at(checker, np.asarray(path, dtype=float)), None


def sides_of_the_wall(arm, checker):
    """Free configurations with the tool pointing down on the -y and +y sides of the wall."""
    out, near = [], np.asarray(arm.q_home, dtype=float)
    for tip in SIDES:
        target = np.diag([1.0, -1.0, -1.0, 1.0])
        target[:3, 3] = tip
        branches = ik_branches(arm, target, near, checker)  # the second on the first's branch
        assert branches, f"{arm.name}: no free IK branch at {tip}"
        out.append(near := branches[0])
    return out


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_start_and_goal_separated_by_a_wall_are_planned_around_it(name):
    arm = robot(name)
    checker = CollisionChecker(arm, WALL)
    qa, qb = sides_of_the_wall(arm, checker)
    assert not checker.path_is_free(np.stack([qa, qb]))  # the wall is in the way
    res = plan_path(arm, qa, qb, checker, time_limit=10.0, seed=0)
    assert res.success, res.message
    np.testing.assert_array_equal(res.path[0], qa)
    np.testing.assert_array_equal(res.path[-1], qb)
    assert (res.path >= arm.q_min).all() and (res.path <= arm.q_max).all()
    assert res.checks > 0 and res.planning_time > 0
    assert fine_free(checker, res.path)[0]
    # the spline retime follows through the waypoints is free too
    spline = JointSpline.through(res.path)
    assert fine_free(checker, spline.evaluate(np.linspace(0, spline.length, 1001))[0])[0]


def test_a_path_that_grazes_a_thin_post_between_coarse_samples_is_rejected():
    arm = robot("ur5")
    q0 = np.array([-0.6, -1.6, 1.6, -1.5, -1.57, 0.0])
    q1 = q0.copy()
    q1[0] = 0.6  # a 0.1 s base turn: sampled at 10 ms the flange moves about 5 cm a sample
    samples = q0 + (np.arange(11) / 10)[:, None] * (q1 - q0)
    between = q0 + (5.5 / 10) * (q1 - q0)
    tip = forward_kinematics(arm, between)[:3, 3]
    post = Cylinder(0.002, 0.04, np.block([[np.eye(3), tip[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]]))
    checker = CollisionChecker(arm, World({"post": post}))
    assert not checker.in_collision(samples).any()  # sampling at 10 ms calls it free
    assert not fine_free(checker, np.stack([q0, q1]))[0]  # but it hits the 4 mm post
    assert not checker.path_is_free(np.stack([q0, q1]))
    res = plan_path(arm, q0, q1, checker, time_limit=10.0, seed=0)
    assert res.success, res.message
    assert res.path.shape[0] > 2  # not the straight line
    assert fine_free(checker, res.path)[0]


def test_same_seed_same_path_other_seed_other_path():
    arm = robot("ur5")
    checker = CollisionChecker(arm, WALL)
    qa, qb = sides_of_the_wall(arm, checker)
    runs = [plan_path(arm, qa, qb, checker, time_limit=10.0, seed=s) for s in (4, 4, 5)]
    assert all(r.success for r in runs)
    np.testing.assert_array_equal(runs[0].path, runs[1].path)
    assert runs[0].checks == runs[1].checks
    assert runs[0].path.shape != runs[2].path.shape or not np.array_equal(runs[0].path, runs[2].path)


def test_start_or_goal_in_collision_or_outside_the_limits_is_named():
    arm = robot("ur5")
    checker = CollisionChecker(arm, WALL)
    A, B = (q[None] for q in sides_of_the_wall(arm, checker))
    hit = A[0].copy()
    hit[1] = -0.2  # the upper arm down through the floor
    assert checker.in_collision(hit)
    res = plan_path(arm, hit, B[0], checker)
    assert not res.success and res.message.startswith("start is in collision")
    assert res.path.shape == (0, 6)
    res = plan_path(arm, A[0], hit, checker)
    assert not res.success and res.message.startswith("goal is in collision")
    res = plan_path(arm, hit, hit, checker)
    assert not res.success and "start and goal are in collision" in res.message
    out = A[0].copy()
    out[2] = arm.q_max[2] + 0.1
    res = plan_path(arm, A[0], out, checker)
    assert not res.success and "goal is outside the joint limits: joint 3" in res.message
    res = plan_path(arm, out, A[0], checker)
    assert not res.success and "start is outside the joint limits: joint 3" in res.message


def test_a_free_straight_line_is_returned_as_it_is():
    arm = robot("ur5")
    checker = CollisionChecker(arm)
    q0 = np.array([-0.6, -1.6, 1.6, -1.5, -1.57, 0.0])
    q1 = q0 + 0.3
    res = plan_path(arm, q0, q1, checker)
    assert res.success
    np.testing.assert_array_equal(res.path, np.stack([q0, q1]))


def test_malformed_arguments_raise():
    arm = robot("ur5")
    checker = CollisionChecker(arm)
    with pytest.raises(ValueError, match="q_start"):
        plan_path(arm, np.zeros(5), np.zeros(6), checker)
    with pytest.raises(ValueError, match="q_goal"):
        plan_path(arm, np.zeros(6), np.full(6, np.nan), checker)
    with pytest.raises(ValueError, match="time_limit"):
        plan_path(arm, np.zeros(6), np.zeros(6), checker, time_limit=0.0)


def test_plan_to_pose_ends_at_the_pose_on_a_collision_free_branch():
    arm = robot("ur5")
    checker = CollisionChecker(arm, WALL)
    qa, qb = sides_of_the_wall(arm, checker)
    target = forward_kinematics(arm, qb)
    res = plan_to_pose(arm, qa, target, checker, time_limit=20.0)
    assert res.success, res.message
    np.testing.assert_allclose(forward_kinematics(arm, res.path[-1]), target, atol=1e-6)
    assert fine_free(checker, res.path)[0]
    # the branches are free, distinct and nearest first
    branches = ik_branches(arm, target, qa, checker)
    assert len(branches) >= 2
    assert not checker.in_collision(np.array(branches)).any()
    d = [np.linalg.norm(q - qa) for q in branches]
    assert d == sorted(d)
    # a pose inside the wall has no free branch
    inside = target.copy()
    inside[:3, 3] = WALL_CENTRE
    res = plan_to_pose(arm, qa, inside, checker)
    assert not res.success and "no collision-free IK solution" in res.message
