"""The pick-and-place task: default tasks on every shipped 6- and 7-DOF robot place the
object within 1 mm, the scene at any time, one-line errors, task file validation."""
from __future__ import annotations

import numpy as np
import pytest

from kin_helpers import ROBOT_NAMES, robot, sweep
from plan_helpers import TASK, straight_transport_clearance
from robot_sim.kinematics import forward_kinematics
from robot_sim.planning.cartesian import qdd_limits
from robot_sim.planning.pick_task import GRIPPER_CLEARANCE, PHASES, TaskError, default_plan, plan_pick
from robot_sim.planning.task_file import TaskDefinitionError, load_task, task_toml

ARMS = [name for name in ROBOT_NAMES if robot(name).n_dofs >= 6]


def test_there_are_six_and_seven_dof_robots():
    assert {robot(n).n_dofs for n in ARMS} >= {6, 7}


@pytest.mark.parametrize("name", sweep(ARMS))
def test_default_pick_places_the_object_within_1mm(name):
    arm = robot(name)
    plan = default_plan(arm)
    spec = plan.spec
    end = plan.state_at(plan.duration + 10.0)  # past the end: the final scene
    assert end.phase == "done" and not end.attached
    assert np.linalg.norm(end.object_pose[:3, 3] - spec.place[:3, 3]) < 1e-3
    # the object is where the tool let it go (forward kinematics of the release sample)
    q_release, _, _ = plan.trajectory.evaluate(plan.t_release)
    np.testing.assert_allclose(end.object_pose, forward_kinematics(arm, q_release) @ np.linalg.inv(spec.grasp), atol=1e-12)
    # phases in order, each starting after the previous one
    marks = plan.trajectory.marks
    assert [m for _, m in marks] == list(PHASES)
    assert all(b[0] > a[0] for a, b in zip(marks, marks[1:]))
    # within the joint limits all the way
    assert (plan.trajectory.q >= arm.q_min - 1e-9).all() and (plan.trajectory.q <= arm.q_max + 1e-9).all()
    # the table top is under the object
    bottom = spec.object_pose[2, 3] - spec.object_size[2] / 2
    assert bottom == pytest.approx(spec.table_top[2], abs=1e-9)
    assert spec.table_top[2] > 0.0
    # issue 19: no sample above the acceleration limit, and a wall that a straight transport hits
    assert np.max(np.abs(plan.trajectory.qdd) / qdd_limits(arm)) <= 1.0 + 1e-6
    assert "wall" in dict(spec.obstacles) and straight_transport_clearance(plan) < 0.0


@pytest.mark.parametrize("name", ["ur5", "humanoid7"])
def test_object_rides_with_the_tool_only_while_grasped(name):
    arm = robot(name)
    plan = default_plan(arm)
    spec, times = plan.spec, plan.phase_times()
    before = plan.state_at(times["close"] + 0.5 * spec.dwell)
    np.testing.assert_array_equal(before.object_pose, spec.object_pose)
    assert not before.attached and before.phase == "close"
    mid = plan.state_at(0.5 * (times["transport"] + times["place"]))
    assert mid.attached and mid.phase == "transport"
    np.testing.assert_allclose(mid.object_pose, mid.tool_pose @ np.linalg.inv(spec.grasp), atol=1e-12)
    # the object has left its start: it moves with the arm
    assert np.linalg.norm(mid.object_pose[:3, 3] - spec.object_pose[:3, 3]) > 0.05
    after = plan.state_at(0.5 * (times["retreat"] + plan.trajectory.t[-1]))
    assert not after.attached
    np.testing.assert_array_equal(after.object_pose, plan.placed_pose)
    # the tool rises away from the placed object during the retreat
    assert after.tool_pose[2, 3] > plan.placed_pose[2, 3] + 1e-3


def test_gripper_closes_onto_the_object_and_opens_again():
    plan = default_plan(robot("ur5"))
    spec, times = plan.spec, plan.phase_times()
    width = spec.grip_width()
    assert width == pytest.approx(spec.object_size[1])
    assert plan.gripper_opening(0.0) == pytest.approx(width + 2 * GRIPPER_CLEARANCE)
    half = plan.gripper_opening(times["close"] + spec.dwell / 2)
    assert half == pytest.approx(width + GRIPPER_CLEARANCE)
    assert plan.gripper_opening(times["lift"]) == pytest.approx(width)
    assert plan.gripper_opening(times["retreat"]) == pytest.approx(width + 2 * GRIPPER_CLEARANCE)


def test_approach_is_straight_down():
    arm = robot("puma560")
    plan = default_plan(arm)
    times = plan.phase_times()
    traj = plan.trajectory
    seg = (traj.t >= times["approach"]) & (traj.t <= times["close"])
    p = forward_kinematics(arm, traj.q[seg])[:, :3, 3]
    np.testing.assert_allclose(p[:, :2], p[:1, :2].repeat(len(p), axis=0), atol=1e-6)
    assert p[0, 2] - p[-1, 2] == pytest.approx(plan.spec.approach, abs=1e-6)


def test_task_file_loads_and_round_trips(tmp_path):
    path = tmp_path / "block.toml"
    path.write_text(TASK.format(x=0.4))
    spec = load_task(path)
    assert spec.object_shape == "cylinder"
    np.testing.assert_allclose(spec.object_size, [0.05, 0.05, 0.1])
    assert spec.lift == 0.1 and spec.approach == 0.10
    np.testing.assert_allclose(spec.place[:3, 0], [0.0, 1.0, 0.0], atol=1e-12)
    again = tmp_path / "again.toml"
    again.write_text(task_toml(spec))
    back = load_task(again)
    for key in ("table_top", "table_size", "object_size", "object_pose", "grasp", "place"):
        np.testing.assert_allclose(getattr(back, key), getattr(spec, key), atol=1e-6)


def test_unreachable_task_fails_with_one_line_before_moving(tmp_path):
    path = tmp_path / "far.toml"
    path.write_text(TASK.format(x=5.0))
    spec = load_task(path)
    with pytest.raises(TaskError) as info:
        plan_pick(robot("ur5"), spec)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"task {path}: UR5: pre-grasp: tool at xyz [5.000, -0.200, 0.410] m, rpy [180.0, ")
    arm = robot("ur5")
    reach = f"is out of reach: IK target is 5.02 m from the base, beyond the arm's reach of {arm.reach:.3g} m; "
    assert reach + "did not converge" in message


@pytest.mark.parametrize(
    "edit, message",
    [
        (("[motion]", "[motion]\nspeeed = 1.0"), "motion.speeed: unknown key 'speeed'; accepted keys: approach, dwell, lift, speed"),
        (('shape = "cylinder"', 'shape = "sphere"'), "object.shape: unknown shape 'sphere'; accepted: 'box' or 'cylinder'"),
        (("size = [0.05, 0.1]", "size = [0.05, -0.1]"), r"object.size\[1\]: expected a positive number, got -0.1"),
        (("size = [0.05, 0.1]", "size = [0.05, 0.1, 0.2]"), r"object.size: expected a list of 2 positive numbers"),
        (("[place]\nxyz = [0.4, 0.2, 0.25]\n", "[place]\n"), "place.xyz: missing required field"),
        (("lift = 0.1", "lift = nan"), "motion.lift: expected a finite number, got nan"),
        (('units = "deg"', 'units = "grad"'), "units: unknown units 'grad'; accepted: 'deg' or 'rad'"),
    ],
)
def test_bad_task_file_names_file_field_value_and_accepted(tmp_path, edit, message):
    path = tmp_path / "bad.toml"
    text = TASK.format(x=0.4)
    assert edit[0] in text
    path.write_text(text.replace(edit[0], edit[1], 1))
    with pytest.raises(TaskDefinitionError, match=f"^{path}: {message}"):
        load_task(path)


@pytest.mark.parametrize(
    "edit, message",
    [
        (("lift = 0.1", "lift = 1" + "0" * 400), "motion.lift: expected a finite number, got 1000"),
        (("lift = 0.1", "lift = " + "[" * 3000 + "]" * 3000), r"line \d+: keys, tables or arrays nested more than 32 levels deep"),
        (('units = "deg"', 'units = "deg"  # angles in \xb0'), "not UTF-8 text: byte 0xb0 at line"),
    ],
)
def test_hostile_task_file_is_one_task_error(tmp_path, edit, message):
    """Task files are read like robot files: an integer beyond float range, absurd nesting
    or a Latin-1 byte is a TaskDefinitionError naming the file (they escaped as
    OverflowError, RecursionError and a bare codec message)."""
    path = tmp_path / "hostile.toml"
    text = TASK.format(x=0.4)
    assert edit[0] in text
    path.write_bytes(text.replace(edit[0], edit[1], 1).encode("latin-1"))
    with pytest.raises(TaskDefinitionError, match=f"^{path}: {message}"):
        load_task(path)


def test_task_path_that_is_a_directory_is_one_task_error(tmp_path):
    with pytest.raises(TaskDefinitionError, match=f"^{tmp_path}: cannot read task file: "):
        load_task(tmp_path)
