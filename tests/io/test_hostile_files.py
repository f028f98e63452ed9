"""Issue 31, robot, world and task files: TOML nesting bounded before parsing, task-file
values that size arrays bounded, values of the wrong type and absurd lengths refused in
one line, long values cut."""
from __future__ import annotations

import time

import numpy as np
import pytest

from plan_helpers import TASK as TASK_TEMPLATE
from robot_sim.io.robot_file import load_robot
from robot_sim.io.toml_depth import nesting_too_deep
from robot_sim.io.world_file import WorldDefinitionError, load_world
from robot_sim.model.params import RobotDefinitionError
from robot_sim.planning.retime import retime
from robot_sim.planning.task_file import TaskDefinitionError, load_task
from paths import ROOT

TASK = TASK_TEMPLATE.format(x=0.4)
ROBOT = 'name = "r"\nunits = "rad"\n[[joints]]\ntype = "revolute"\na = 0.5\nalpha = 0.0\nd = 0.0\ntheta = 0.0\n'
WORLD = '[[obstacles]]\nname = "b"\nshape = "box"\nsize = [0.1, 0.1, 0.1]\n'

LOADERS = {
    "robot": (ROBOT, load_robot, RobotDefinitionError),
    "world": (WORLD, load_world, WorldDefinitionError),
    "task": (TASK, load_task, TaskDefinitionError),
}


@pytest.mark.parametrize("kind", LOADERS)
def test_deep_dotted_keys_are_refused_by_a_prescan_in_every_file(tmp_path, kind):
    text, load, error = LOADERS[kind]
    path = tmp_path / f"{kind}.toml"
    path.write_text(text + "units" + ".a" * 15_000 + " = 1\n")
    line = text.count("\n") + 1
    start = time.process_time()
    with pytest.raises(error) as info:
        load(path)
    assert time.process_time() - start < 5.0  # tomllib took gigabytes and minutes here
    assert str(info.value) == f"{path}: line {line}: keys, tables or arrays nested more than 32 levels deep"


@pytest.mark.parametrize("text, line", [
    ("a" + ".a" * 31 + " = 1", None),  # 32 levels: accepted
    ("a" + ".a" * 32 + " = 1", 1),
    ("x = 1\n[" + "t." * 32 + "t]\n", 2),
    ("[" + "t." * 20 + "t]\n" + "b" + ".b" * 11 + " = 1", 2),  # 21 + 12 levels
    ("x = " + "[" * 32 + "]" * 32, None),
    ("x = " + "[" * 33 + "]" * 33, 1),
    ("a" + ".a" * 15 + " = {" + "b" + ".b" * 15 + " = 1}", None),  # 16 + 16
    ("a" + ".a" * 15 + " = {" + "b" + ".b" * 16 + " = 1}", 1),  # 16 + 17
    ('s = "' + "a." * 100 + '"\n# ' + "[" * 100, None),  # strings and comments do not count
    ('s = """\n' + "[" * 100 + '\n"""\nx.y = 2.5', None),
])
def test_nesting_prescan_counts_levels_as_tomllib_builds_them(text, line):
    assert nesting_too_deep(text) == line


@pytest.mark.parametrize("key, value, message", [
    ("speed", "1e-9", "motion.speed: expected more than 0.001 and at most 10 m/s, got 1e-09"),
    ("dwell", "1e9", "motion.dwell: expected more than 0 and at most 60 s, got 1000000000.0"),
    ("lift", "1e6", "motion.lift: expected more than 0 and at most 10 m, got 1000000.0"),
])
def test_task_motion_values_that_size_the_plan_are_bounded(tmp_path, key, value, message):
    path = tmp_path / "task.toml"
    path.write_text(TASK.replace("lift = 0.1", f"{key} = {value}"))
    with pytest.raises(TaskDefinitionError) as info:
        load_task(path)
    assert str(info.value) == f"{path}: {message}"


@pytest.mark.parametrize("old, new, message", [
    ('units = "deg"', 'units = ["deg"]', "units: unknown units ['deg']; accepted: 'deg' or 'rad'"),
    ('units = "deg"', 'units = "' + "d" * 500_000 + '"',
     "units: unknown units '" + "d" * 79 + "... (500002 characters); accepted: 'deg' or 'rad'"),
    ("xyz = [0.4, 0.2, 0.25]", "xyz = [1e300, 0.2, 0.25]", "place.xyz[0]: expected a length within ±1000 m, got 1e+300"),
    ("size = [0.4, 0.6, 0.2]", "size = [0.4, 1e300, 0.2]", "table.size[1]: expected a length within ±1000 m, got 1e+300"),
    ('shape = "cylinder"', "shape = [1]", "object.shape: unknown shape [1]; accepted: 'box' or 'cylinder'"),
])
def test_task_values_of_the_wrong_type_or_size_are_one_line(tmp_path, old, new, message):
    path = tmp_path / "task.toml"
    path.write_text(TASK.replace(old, new, 1))
    with pytest.raises(TaskDefinitionError) as info:
        load_task(path)
    assert str(info.value) == f"{path}: {message}"


def test_retime_sample_count_is_bounded_before_allocation():
    arm = load_robot("puma560")
    path = arm.q_home + np.array([[0.0], [0.5], [-0.5], [0.5], [-0.5], [0.0]])  # a few seconds
    with pytest.raises(ValueError) as info:
        retime(arm, path, dt=1e-9)
    assert str(info.value) == "dt must be a number of seconds >= 1e-06, got 1e-09"
    with pytest.raises(ValueError, match=r"sampled every 1e-06 s needs .* samples; at most 1000000 are accepted"):
        retime(arm, path, dt=1e-6)


# ------------------------------------------------------------------ published inertia tables
PUMA_LINK1 = np.diag([0.0, 0.35, 0.0])  # the Robotics Toolbox's PUMA 560 link 1 (Armstrong et al. 1986)


def _inertials(inertia, **options):
    from robot_sim.model.inertials import LinkInertials

    return LinkInertials.from_arrays([0.0, 17.4], np.zeros((2, 3)), [inertia, np.diag([0.13, 0.524, 0.539])], **options)


def test_a_triangle_violation_is_refused_by_default_naming_the_link():
    with pytest.raises(ValueError) as info:
        _inertials(PUMA_LINK1)
    assert str(info.value) == (
        "inertia of link 1 principal moments [0, 0, 0.35] violate the triangle inequality (0.35 > 0 + 0); "
        "balance_inertia raises the smallest moment just enough (a keyword, or balance_inertia = true in a robot file)")


def test_balance_inertia_raises_the_smallest_moment_just_enough_and_says_so():
    from robot_sim.model.inertials import InertiaBalancedWarning, inertia_problem

    with pytest.warns(InertiaBalancedWarning) as caught:
        inertials = _inertials(PUMA_LINK1, balance_inertia=True)
    assert len(caught) == 1 and str(caught[0].message) == (
        "inertia of link 1: principal moments [0, 0, 0.35] raised to [0, 0.35, 0.35] kg m^2 (balance_inertia: "
        "the smallest moment raised just enough for the triangle inequality)")
    fixed = inertials.inertia[0]
    moments = np.linalg.eigvalsh(fixed)
    np.testing.assert_allclose(moments, [0.0, 0.35, 0.35], atol=1e-15)
    assert moments[2] == pytest.approx(moments[0] + moments[1], abs=1e-15) and inertia_problem(fixed) is None
    assert fixed[1, 1] == 0.35 and np.trace(fixed) == pytest.approx(0.70)  # Iyy kept, one zero moment raised to 0.35
    np.testing.assert_array_equal(inertials.inertia[1], np.diag([0.13, 0.524, 0.539]))  # valid ones untouched
    rot = np.array([[0.0, -0.6, 0.8], [1.0, 0.0, 0.0], [0.0, 0.8, 0.6]])  # same result in any axes
    with pytest.warns(InertiaBalancedWarning):
        turned = _inertials(rot @ np.diag([0.1, 0.2, 0.5]) @ rot.T, balance_inertia=True)
    np.testing.assert_allclose(np.linalg.eigvalsh(turned.inertia[0]), [0.2, 0.3, 0.5], atol=1e-12)
    with pytest.raises(ValueError, match="negative principal moment"):  # balancing makes nothing else physical
        _inertials(np.diag([-0.1, 0.2, 0.2]), balance_inertia=True)


def test_balance_inertia_switch_in_a_robot_file(tmp_path):
    from robot_sim.model.inertials import InertiaBalancedWarning

    table = "[joints.inertial]\nmass = 1.0\ncom = [0.0, 0.0, 0.0]\ninertia = [0.0, 0.35, 0.0, 0.0, 0.0, 0.0]\n"
    path = tmp_path / "puma1.toml"
    path.write_text(ROBOT + table)
    with pytest.raises(RobotDefinitionError, match=r"joints\[0\].inertial.inertia: .* violate the triangle inequality"
                                                   r" .*; or set balance_inertia = true$"):
        load_robot(path)
    path.write_text("balance_inertia = true\n" + ROBOT + table)
    with pytest.warns(InertiaBalancedWarning, match=f"^inertia of {path}: joints\\[0\\].inertial.inertia: "):
        robot = load_robot(path)
    np.testing.assert_allclose(np.linalg.eigvalsh(robot.inertials.inertia[0]), [0.0, 0.35, 0.35], atol=1e-15)


def test_the_pick_tracking_figures_name_the_script_that_measures_them():
    """docs/trajectories.md's computed-torque figures were stale; they now come from a
    script the page names, whose table header the page holds as printed."""
    import re
    from pathlib import Path

    root = ROOT
    page = (root / "docs" / "trajectories.md").read_text(encoding="utf-8")
    (script,) = re.findall(r"Measured with `([^`]+)`", page)
    source = (root / script).read_text(encoding="utf-8")
    header = "| robot | tool error [mm] | placed from target [mm] | task [s] | run [s] (median"
    assert header in page and header in source
    for robot in ("UR5", "Humanoid arm (7-DOF)", "Franka Emika Panda", "PUMA 560"):
        assert f"\n| {robot} | " in page
