"""plan_path: around a wall, never through a thin post between checks, reproducible by
seed, start/goal in collision or outside the limits named, the returned polyline and the
spline retime follows both free when checked far finer than the planner's resolution."""
from __future__ import annotations

import numpy as np
import pytest

from kin_helpers import robot
from plan_helpers import BallArmChecker
from robot_sim.kinematics import forward_kinematics, random_configurations
from robot_sim.planning.pose_goal import ik_branches, plan_to_pose
from robot_sim.planning.rrt import plan_path
from robot_sim.planning.spline import JointSpline

WALL = (np.array([0.35, -0.04, 0.0]), np.array([0.50, 0.04, 0.9]))


def fine_free(checker, path, step=2.5e-4):
    """Independent check: sample the polyline so that no ball centre moves more than
    ``step`` (measured by forward kinematics) and require clearance at every sample."""
    out = [path[:1]]
    for a, b in zip(path[:-1], path[1:]):
        m = 8
        while True:
            Q = a + (np.arange(m + 1) / m)[:, None] * (b - a)
            C = checker.centres(Q)
            if np.linalg.norm(np.diff(C, axis=0), axis=2).max() <= step:
                break
            m *= 2
        out.append(Q[1:])
    Q = np.concatenate(out)
    return bool(np.all(checker.clearance(Q) >= 0.0)), Q


def sides_of_the_wall(arm, checker, rng, count=3):
    """Free configurations with the tool in front of the wall on its -y and +y sides."""
    Q = random_configurations(arm, 4000, rng)
    tips = forward_kinematics(arm, Q)[:, :3, 3]
    free = ~checker.in_collision(Q)
    near = (tips[:, 0] > 0.3) & (tips[:, 0] < 0.6) & (tips[:, 2] > 0.1) & (tips[:, 2] < 0.7)
    a = Q[free & near & (tips[:, 1] < -0.2)][:count]
    b = Q[free & near & (tips[:, 1] > 0.2)][:count]
    return a, b


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_start_and_goal_separated_by_a_wall_are_planned_around_it(name):
    arm = robot(name)
    checker = BallArmChecker(arm, boxes=[WALL])
    A, B = sides_of_the_wall(arm, checker, np.random.default_rng(1))
    blocked = 0
    for qa, qb in zip(A, B):
        straight_free, _ = fine_free(checker, np.stack([qa, qb]))
        blocked += not straight_free
        res = plan_path(arm, qa, qb, checker, time_limit=10.0, seed=0)
        assert res.success, res.message
        np.testing.assert_array_equal(res.path[0], qa)
        np.testing.assert_array_equal(res.path[-1], qb)
        assert (res.path >= arm.q_min).all() and (res.path <= arm.q_max).all()
        ok, _ = fine_free(checker, res.path)
        assert ok
        assert res.checks > 0 and res.planning_time > 0
        # the spline retime follows through the waypoints is free too
        spline = JointSpline.through(res.path) if len(np.unique(res.path, axis=0)) == len(res.path) else None
        if spline is not None:
            S, _, _ = spline.evaluate(np.linspace(0, spline.length, 4000))
            assert np.all(checker.clearance(S) >= 0.0)
    assert blocked >= 1  # the scene really separates them


def test_a_path_that_grazes_a_thin_post_between_coarse_samples_is_rejected():
    arm = robot("ur5")
    q0 = np.array([-0.6, -1.6, 1.6, -1.5, -1.57, 0.0])
    q1 = q0.copy()
    q1[0] = 0.6  # base turn: the flange sweeps an arc, about 5 mm per 10 ms of a 1.2 s move
    samples = q0 + (np.arange(121) / 120)[:, None] * (q1 - q0)
    between = q0 + (60.5 / 120) * (q1 - q0)
    post = (forward_kinematics(arm, between)[:3, 3], 0.001)  # a 1 mm post between two samples
    checker = BallArmChecker(arm, balls=[post], radius=0.001, skip_links=arm.n_dofs)  # the flange only
    assert not checker.in_collision(samples).any()  # sampling at 10 ms calls it free
    assert not fine_free(checker, np.stack([q0, q1]))[0]  # but it hits the post
    res = plan_path(arm, q0, q1, checker, time_limit=10.0, seed=0)
    assert res.success, res.message
    assert res.path.shape[0] > 2  # not the straight line
    assert fine_free(checker, res.path)[0]


def test_same_seed_same_path_other_seed_other_path():
    arm = robot("ur5")
    checker = BallArmChecker(arm, boxes=[WALL])
    A, B = sides_of_the_wall(arm, checker, np.random.default_rng(1))
    qa, qb = next((a, b) for a, b in zip(A, B) if not fine_free(checker, np.stack([a, b]))[0])
    runs = [plan_path(arm, qa, qb, checker, time_limit=10.0, seed=s) for s in (4, 4, 5)]
    assert all(r.success for r in runs)
    np.testing.assert_array_equal(runs[0].path, runs[1].path)
    assert runs[0].checks == runs[1].checks
    assert runs[0].path.shape != runs[2].path.shape or not np.array_equal(runs[0].path, runs[2].path)


def test_start_or_goal_in_collision_or_outside_the_limits_is_named():
    arm = robot("ur5")
    checker = BallArmChecker(arm, boxes=[WALL])
    A, B = sides_of_the_wall(arm, checker, np.random.default_rng(1), count=1)
    Q = random_configurations(arm, 3000, np.random.default_rng(2))
    hit = Q[checker.in_collision(Q)][0]
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
    checker = BallArmChecker(arm)
    q0 = np.array([-0.6, -1.6, 1.6, -1.5, -1.57, 0.0])
    q1 = q0 + 0.3
    res = plan_path(arm, q0, q1, checker)
    assert res.success
    np.testing.assert_array_equal(res.path, np.stack([q0, q1]))


def test_malformed_arguments_raise():
    arm = robot("ur5")
    checker = BallArmChecker(arm)
    with pytest.raises(ValueError, match="q_start"):
        plan_path(arm, np.zeros(5), np.zeros(6), checker)
    with pytest.raises(ValueError, match="q_goal"):
        plan_path(arm, np.zeros(6), np.full(6, np.nan), checker)
    with pytest.raises(ValueError, match="time_limit"):
        plan_path(arm, np.zeros(6), np.zeros(6), checker, time_limit=0.0)


def test_plan_to_pose_ends_at_the_pose_on_a_collision_free_branch():
    arm = robot("ur5")
    checker = BallArmChecker(arm, boxes=[WALL])
    A, B = sides_of_the_wall(arm, checker, np.random.default_rng(1))
    qa, qb = next((a, b) for a, b in zip(A, B) if not fine_free(checker, np.stack([a, b]))[0])
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
    inside[:3, 3] = (WALL[0] + WALL[1]) / 2
    res = plan_to_pose(arm, qa, inside, checker)
    assert not res.success and "no collision-free IK solution" in res.message
