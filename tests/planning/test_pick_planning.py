"""The pick task around obstacles: no |q̈| above the limit (humanoid7's lift spike is
gone), the carried object never enters an obstacle (distances recomputed shape by shape),
the arm never enters the world, the default wall blocks a straight transport, Cartesian
segments name the sample, time and joint where they fail, task files with obstacles."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from kin_helpers import robot
from plan_helpers import free_at, straight_transport_clearance
from robot_sim.collision import CollisionChecker
from robot_sim.collision.distance import shape_distance
from robot_sim.kinematics import forward_kinematics
from robot_sim.planning.carrying import CheckerGroup, held_object
from robot_sim.planning.cartesian import CartesianPathError, cartesian_line, qdd_limits
from robot_sim.planning.pick_task import default_plan, plan_pick
from robot_sim.planning.task_file import TaskDefinitionError, load_task, task_toml

NAMES = ["ur5", "humanoid7"]


def test_humanoid7_pick_has_no_acceleration_spike():
    arm = robot("humanoid7")
    traj = default_plan(arm).trajectory
    ratio = np.abs(traj.qdd) / qdd_limits(arm)
    assert ratio.max() <= 1.0 + 1e-6
    # and q̇ follows q (no stop within a few samples hidden in the samples)
    dt = np.diff(traj.t)[:, None]
    assert np.abs(np.diff(traj.q, axis=0) - 0.5 * (traj.qd[1:] + traj.qd[:-1]) * dt).max() < 1e-4


@pytest.mark.parametrize("name", NAMES)
def test_the_object_never_enters_an_obstacle_while_carried(name):
    arm = robot(name)
    plan = default_plan(arm)
    spec = plan.spec
    world = spec.world()
    assert "wall" in world.names and "table" in world.names
    times = plan.trajectory.t[(plan.trajectory.t >= plan.t_attach) & (plan.trajectory.t <= plan.t_release)]
    worst = np.inf
    for t in times[::5]:
        state = plan.state_at(t)
        assert state.attached or t == plan.t_release
        shape = spec.object_shape_at(state.object_pose)
        for obstacle, other in world.obstacles:
            d = shape_distance(shape, other).distance
            worst = min(worst, d)
            assert d >= -1e-6, (t, obstacle, d)
    assert worst < 0.01  # it rests on the table at both ends


@pytest.mark.parametrize("name", NAMES)
def test_the_arm_never_enters_the_world_and_a_straight_transport_would(name):
    arm = robot(name)
    plan = default_plan(arm)
    checker = CollisionChecker(arm, plan.spec.world())
    assert checker.path_is_free(plan.trajectory.q)
    marks = plan.phase_times()
    held = arm.tool_tf.mat @ np.linalg.inv(plan.spec.grasp)
    carrying = CheckerGroup(checker, held_object(arm, plan.spec.object_shape_at(held), plan.spec.world()))
    carried = (plan.trajectory.t >= marks["transport"]) & (plan.trajectory.t <= marks["place"])
    assert free_at(carrying, plan.trajectory.q[carried][::20], step=2e-3)
    # the object carried straight from above the pick to above the place goes through the wall
    assert straight_transport_clearance(plan) < 0.0


def test_a_cartesian_segment_reaching_a_joint_limit_names_sample_time_and_joint():
    arm = robot("humanoid7")
    q0 = np.radians([0.0, 45.0, 0.0, 90.0, 0.0, 45.0, 0.0])
    T0 = forward_kinematics(arm, q0)
    T1 = T0.copy()
    T1[2, 3] += 0.15
    free = cartesian_line(arm, T0, T1, 1.0, q0)  # a redundant arm: joint 6 moves along the way
    j = int(np.argmax(np.abs(free.q[-1] - q0)))
    hi = arm.q_max.copy()
    lo = arm.q_min.copy()
    mid = (q0[j] + free.q[-1, j]) / 2
    if free.q[-1, j] > q0[j]:
        hi[j] = mid
    else:
        lo[j] = mid
    narrow = replace(arm, q_min=lo, q_max=hi)
    with pytest.raises(CartesianPathError) as info:
        cartesian_line(narrow, T0, T1, 1.0, q0)
    err = info.value
    assert err.joint == j and f"joint {j + 1}" in str(err) and "limit" in err.reason
    assert f"sample {err.sample}" in str(err) and f"t = {err.time:.4f} s" in str(err)
    assert 0 < err.sample < 1000 and err.trajectory is not None


def test_a_cartesian_segment_too_fast_for_the_acceleration_limit_names_the_joint():
    arm = robot("ur5")
    q0 = np.array([0.2, -1.4, 1.6, -1.8, -1.57, 0.0])
    T0 = forward_kinematics(arm, q0)
    T1 = T0.copy()
    T1[:3, 3] += [0.05, -0.04, 0.03]
    cartesian_line(arm, T0, T1, 2.0, q0)  # slowly: fine
    with pytest.raises(CartesianPathError, match="would accelerate at .* above its limit") as info:
        cartesian_line(arm, T0, T1, 0.12, q0)
    assert info.value.joint is not None and f"joint {info.value.joint + 1}" in str(info.value)


def test_task_files_hold_obstacles(tmp_path):
    plan = default_plan(robot("ur5"))
    path = tmp_path / "task.toml"
    path.write_text(task_toml(plan.spec))
    spec = load_task(path)
    assert [n for n, _ in spec.obstacles] == ["wall"]
    np.testing.assert_allclose(spec.obstacles[0][1].size, plan.spec.obstacles[0][1].size, atol=1e-6)
    np.testing.assert_allclose(spec.obstacles[0][1].pose, plan.spec.obstacles[0][1].pose, atol=1e-6)
    text = path.read_text()
    path.write_text(text.replace('name = "wall"', 'name = "table"'))
    with pytest.raises(TaskDefinitionError, match=r"obstacles\[0\]\.name.*table"):
        load_task(path)
    head, tail = text.split("[[obstacles]]")
    path.write_text(head + "[[obstacles]]" + tail.replace('shape = "box"', 'shape = "pyramid"'))
    with pytest.raises(TaskDefinitionError, match=r"task\.toml: obstacles\[0\]\.shape: unknown shape 'pyramid'"):
        load_task(path)


def test_a_start_in_collision_is_named():
    arm = robot("ur5")
    spec = default_plan(arm).spec
    q = np.array(arm.q_home, dtype=float)
    q[1] = 0.3  # the upper arm down through the floor
    with pytest.raises(ValueError, match="start configuration is in collision"):
        plan_pick(arm, spec, q)
