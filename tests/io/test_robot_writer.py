"""robot_writer: TOML files that load back to the same robot, style-preserving edits, and
validated single-value edits (the DH table dock's path)."""
from __future__ import annotations

import dataclasses
import difflib
import math
import os
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, strategies as st

from kin_helpers import ROBOT_NAMES, robot
from robot_sim.model.params import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotParams
from robot_sim.io.robot_file import load_robot
from robot_sim.io.robot_writer import file_number, save_robot, to_toml, with_dh_value
from robot_sim.transforms import HomogeneousTransform

DEG = math.pi / 180.0
ARRAYS = ("dh_a", "dh_alpha", "dh_d", "dh_th", "jtype", "q_home", "q_min", "q_max", "link_com_frac")


def load_text(tmp_path: Path, text: str, name: str = "r.toml") -> RobotParams:
    path = tmp_path / name
    path.write_text(text)
    return load_robot(path)


DRIVE_ARRAYS = ("motor_inertia", "gear_ratio", "viscous", "coulomb", "effort_limit", "velocity_limit")


def assert_same_robot(a: RobotParams, b: RobotParams, tf_atol: float = 0.0) -> None:
    for field in ARRAYS:
        assert np.array_equal(getattr(a, field), getattr(b, field)), field
    assert a.name == b.name and a.description == b.description and a.convention == b.convention
    np.testing.assert_allclose(a.base_tf.mat, b.base_tf.mat, rtol=0, atol=tf_atol)
    np.testing.assert_allclose(a.tool_tf.mat, b.tool_tf.mat, rtol=0, atol=tf_atol)
    for table, fields in (("inertials", ("mass", "com", "inertia")), ("drives", DRIVE_ARRAYS)):
        assert (getattr(a, table) is None) == (getattr(b, table) is None), table
        for field in fields if getattr(a, table) is not None else ():
            assert np.array_equal(getattr(getattr(a, table), field), getattr(getattr(b, table), field)), field


def changed_lines(before: str, after: str) -> list[str]:
    return [
        line
        for line in difflib.unified_diff(before.splitlines(), after.splitlines(), lineterm="", n=0)
        if line[:1] in "+-" and not line.startswith(("+++", "---"))
    ]


# ------------------------------------------------------------------ round trips


@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_every_shipped_robot_round_trips_through_a_new_file(tmp_path, name):
    original = robot(name)
    assert_same_robot(original, load_text(tmp_path, to_toml(original)))


@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_an_unedited_robot_writes_its_template_unchanged(name):
    original = robot(name)
    text = Path(original.source).read_text()
    assert to_toml(original, text) == text


def test_a_programmatic_robot_with_base_tool_limits_and_com_round_trips(tmp_path):
    made = RobotParams.from_arrays(
        "made", [0.3, 0.2, 0.0], [DEG * 90, 0.0, -0.4], [0.1, 0.0, 0.05], [0.0, 0.25, 0.0],
        [JTYPE_REVOLUTE, JTYPE_REVOLUTE, JTYPE_PRISMATIC],
        q_home=[0.1, -0.2, 0.05], q_min=[-1.0, -2.0, 0.0], q_max=[1.0, 2.0, 0.3],
        link_com_frac=[0.5, 0.25, 1.0],
        base_tf=HomogeneousTransform.from_xyz_rpy([0.1, -0.2, 0.5], [0.3, -0.2, 1.1]),
        tool_tf=HomogeneousTransform.from_xyz_rpy([0.0, 0.0, 0.12], [0.0, DEG * 90, 0.0]),
    )
    back = load_text(tmp_path, to_toml(made))
    # rpy goes through atan2 and degrees: the transforms agree to rounding
    assert_same_robot(made, back, tf_atol=1e-15)
    assert back.jtype[2] == JTYPE_PRISMATIC and back.q_max[2] == 0.3


def test_a_modified_dh_robot_keeps_its_convention(tmp_path):
    craig = RobotParams.from_arrays(
        "craig", [0.0, 0.3], [0.0, -DEG * 90], [0.2, 0.0], [0.0, 0.0], [JTYPE_REVOLUTE] * 2,
        convention="modified",
    )
    text = to_toml(craig)
    assert 'convention = "modified"' in text.splitlines()
    assert_same_robot(craig, load_text(tmp_path, text))
    standard = to_toml(robot("puma560"), Path(robot("puma560").source).read_text())
    back = with_dh_value(load_text(tmp_path, text), 1, "a", 0.4)
    assert back.convention == "modified"
    assert "convention" not in standard  # the default is not written into a file without it


def test_numbers_are_written_in_the_shortest_form_that_loads_exactly():
    assert file_number(math.pi / 2, DEG) == 90.0
    assert file_number(-45.0 * DEG, DEG) == -45.0
    assert file_number(0.4318, 1.0) == 0.4318
    assert math.copysign(1.0, file_number(-0.0, DEG)) == 1.0


@given(st.floats(min_value=-10.0, max_value=10.0, allow_nan=False))
def test_angles_in_degrees_load_back_to_the_same_float_or_the_nearest(value):
    written = file_number(value, DEG)
    assert abs(written * DEG - value) <= 2 * math.ulp(value)


def test_one_sided_limits_are_refused_with_the_field_named():
    half = RobotParams.from_arrays("h", [1.0], [0.0], [0.0], [0.0], [JTYPE_REVOLUTE], q_max=[1.0])
    with pytest.raises(ValueError, match=r"^joints\[0\]\.limits: a robot file holds two finite limits or none, got \[-inf, 1\.0\]$"):
        to_toml(half)


# ------------------------------------------------------------------ style preservation


def test_editing_one_value_in_a_template_keeps_comments_and_changes_one_line(tmp_path):
    original = robot("puma560")
    text = Path(original.source).read_text()
    edited = with_dh_value(original, 0, "d", 0.7)
    out = to_toml(edited, text)
    assert changed_lines(text, out) == [
        "-d = 0.67183             # 26.45 in: mounting surface to shoulder axis",
        "+d = 0.7             # 26.45 in: mounting surface to shoulder axis",
    ]
    assert out.startswith("# Unimation PUMA 560, standard DH parameters")
    assert_same_robot(edited, load_text(tmp_path, out))


def test_template_units_are_kept_for_angles_and_limits(tmp_path):
    text = (
        "# cited source\nname = \"r\"\nunits = \"rad\"\n\n[[joints]]\ntype = \"revolute\"\n"
        "a = 0\nalpha = 0\nd = 0\ntheta = 0\nlimits = [-1, 1]  # datasheet\n"
    )
    rob = load_text(tmp_path, text)
    out = to_toml(with_dh_value(with_dh_value(rob, 0, "alpha", 0.5), 0, "limits", (-2.0, 2.0)), text)
    assert changed_lines(text, out) == [
        "-alpha = 0", "+alpha = 0.5", "-limits = [-1, 1]  # datasheet", "+limits = [-2.0, 2.0]  # datasheet",
    ]


def test_a_template_with_more_joints_is_trimmed_and_one_with_fewer_is_extended(tmp_path):
    six = robot("anthropomorphic6")
    three = robot("anthropomorphic")
    assert_same_robot(three, load_text(tmp_path, to_toml(three, Path(six.source).read_text())))
    assert_same_robot(six, load_text(tmp_path, to_toml(six, Path(three.source).read_text())))


# ------------------------------------------------------------------ with_dh_value


@pytest.mark.parametrize(
    "field, value, array, expected",
    [
        ("a", 0.5, "dh_a", 0.5),
        ("d", -0.1, "dh_d", -0.1),
        ("alpha", 30 * DEG, "dh_alpha", 30 * DEG),
        ("theta", -10 * DEG, "dh_th", -10 * DEG),
        ("home", 20 * DEG, "q_home", 20 * DEG),
        ("com", 0.25, "link_com_frac", 0.25),
    ],
)
def test_with_dh_value_changes_exactly_one_entry(field, value, array, expected):
    original = robot("puma560")
    if field == "com":  # the com fraction only places COMs of robots without inertial data
        with pytest.raises(ValueError, match=r"^joints\[1\]\.com: ambiguous: both the com fraction 0\.25 and \[joints\.inertial\]"):
            with_dh_value(original, 1, field, value)
        original = dataclasses.replace(original, inertials=None)
    edited = with_dh_value(original, 1, field, value)
    assert edited is not original and edited.source == original.source
    assert getattr(edited, array)[1] == expected
    for other in ARRAYS:
        want = np.array(getattr(original, other))
        if other == array:
            want[1] = expected
        assert np.array_equal(getattr(edited, other), want), other
    assert getattr(original, array)[1] != expected  # the original is untouched


def test_with_dh_value_limits_and_unlimited():
    original = robot("puma560")
    edited = with_dh_value(original, 2, "limits", (-200 * DEG, 40 * DEG))
    assert (edited.q_min[2], edited.q_max[2]) == (-200 * DEG, 40 * DEG)
    free = with_dh_value(original, 0, "limits", None)
    assert free.q_min[0] == -math.inf and free.q_max[0] == math.inf


def test_changing_the_joint_type_resets_home_and_limits():
    edited = with_dh_value(robot("puma560"), 1, "type", "prismatic")
    assert edited.jtype[1] == JTYPE_PRISMATIC
    assert edited.q_home[1] == 0.0 and edited.q_min[1] == -math.inf and edited.q_max[1] == math.inf


@pytest.mark.parametrize(
    "joint, field, value, message",
    [
        (1, "limits", (10 * DEG, -5 * DEG), r"joints[1].limits: min 10.0 > max -5.0"),
        (1, "home", 300 * DEG, r"joints[1].home: home 300.0 is outside the limits [-45.0, 225.0]"),
        (1, "limits", (50 * DEG, 60 * DEG), r"joints[1].home: home 45.0 is outside the limits [50.0, 60.0]"),
        (0, "com", 1.5, "joints[0].com: com fraction 1.5 is outside [0, 1]"),
        (0, "a", math.nan, "a: expected a finite number, got nan"),
        (0, "d", "abc", "d: expected a number, got 'abc'"),
        (0, "type", "spherical", "type: expected 'revolute' or 'prismatic', got 'spherical'"),
        (6, "a", 0.1, "joint must be an index in 0..5, got 6"),
        (0, "offset", 0.1, "field must be one of type, theta, d, a, alpha, home, limits, com, got 'offset'"),
    ],
)
def test_invalid_edits_are_refused_with_the_reason(joint, field, value, message):
    with pytest.raises(ValueError) as info:
        with_dh_value(robot("puma560"), joint, field, value)
    assert str(info.value) == message


# ------------------------------------------------------------------ save_robot


def test_save_robot_replaces_the_file_atomically_and_keeps_its_comments(tmp_path):
    original = robot("scara")
    text = Path(original.source).read_text()
    path = tmp_path / "scara.toml"
    path.write_text("old contents")
    save_robot(with_dh_value(original, 0, "a", 0.4), path, template=text)
    assert os.listdir(tmp_path) == ["scara.toml"]  # no temporary file left behind
    saved = path.read_text()
    assert [line for line in text.splitlines() if line.startswith("#")] == [
        line for line in saved.splitlines() if line.startswith("#")
    ]
    assert load_robot(path).dh_a[0] == 0.4


def test_save_robot_onto_a_directory_raises_and_leaves_nothing_behind(tmp_path):
    (tmp_path / "p.toml").mkdir()
    with pytest.raises(OSError, match=r"p\.toml': it is a directory, not a regular file$"):
        save_robot(robot("planar3"), tmp_path / "p.toml")
    assert os.listdir(tmp_path) == ["p.toml"] and (tmp_path / "p.toml").is_dir()
