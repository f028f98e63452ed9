"""Hostile robot files and paths: every failure is one RobotDefinitionError that starts
with the file's path; sizes are bounded so every robot that loads has finite kinematics."""
from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path

import numpy as np
import pytest

from unprivileged import call_unprivileged
from robot_sim.model.params import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotDefinitionError, RobotParams
from robot_sim.io.robot_file import (
    MAX_ANGLE_DEG,
    MAX_FILE_BYTES,
    MAX_JOINTS,
    MAX_LENGTH,
    ROBOTS_DIR,
    load_robot,
)

HEAD = 'name = "test arm"\nunits = "deg"\n'
JOINT = 'type = "revolute"\na = 0.5\nalpha = 90.0\nd = 0.1\ntheta = 0.0\n'
PRISMATIC = 'type = "prismatic"\na = 0.0\nalpha = 0.0\nd = 0.0\ntheta = 0.0\n'


def write(tmp_path: Path, content: str | bytes, name: str = "robot.toml") -> Path:
    path = tmp_path / name
    path.write_bytes(content.encode("utf-8") if isinstance(content, str) else content)
    return path


def one_joint(joint: str = JOINT, head: str = HEAD) -> str:
    return head + "\n[[joints]]\n" + joint


def error_of(path: Path | str) -> str:
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    return str(info.value)


# ------------------------------------------------------------------ encoding


def test_latin1_byte_in_a_comment_is_a_clear_error(tmp_path):
    path = write(tmp_path, b"# alpha in \xb0\n" + one_joint().encode())
    assert error_of(path) == (
        f"{path}: not UTF-8 text: byte 0xb0 at line 1, column 12; save the file as UTF-8"
    )


def test_utf8_byte_order_mark_is_accepted(tmp_path):
    plain = load_robot(write(tmp_path, one_joint(), "plain.toml"))
    with_bom = load_robot(write(tmp_path, b"\xef\xbb\xbf" + one_joint().encode(), "bom.toml"))
    np.testing.assert_array_equal(plain.dh_alpha, with_bom.dh_alpha)
    assert with_bom.name == "test arm"


# ------------------------------------------------------------------ values of the wrong kind


@pytest.mark.parametrize(
    "content, message",
    [
        (one_joint(head='name = "x"\nunits = ["deg"]\n'), "units: unknown units ['deg']; accepted: 'deg' or 'rad'"),
        (one_joint(head='name = "x"\nunits = {a = 1}\n'), "units: unknown units {'a': 1}; accepted: 'deg' or 'rad'"),
        (
            one_joint(JOINT.replace('type = "revolute"', "type = [1, 2]")),
            "joints[0].type: unknown joint type [1, 2]; accepted: 'revolute' or 'prismatic'",
        ),
        (
            one_joint(JOINT.replace('type = "revolute"', "type = {x = 1}")),
            "joints[0].type: unknown joint type {'x': 1}; accepted: 'revolute' or 'prismatic'",
        ),
    ],
)
def test_unhashable_units_and_type(tmp_path, content, message):
    path = write(tmp_path, content)
    assert error_of(path) == f"{path}: {message}"


def test_integer_beyond_float_range(tmp_path):
    path = write(tmp_path, one_joint(JOINT.replace("a = 0.5", "a = 1" + "0" * 400)))
    message = error_of(path)
    assert message.startswith(f"{path}: joints[0].a: expected a length within ±1000 m, got 1000000")
    assert message.endswith("... (401 characters)")
    assert len(message) < len(str(path)) + 200


def test_deeply_nested_array(tmp_path):
    path = write(tmp_path, one_joint(JOINT.replace("a = 0.5", "a = " + "[" * 50_000 + "]" * 50_000)))
    line = path.read_text().splitlines().index(next(t for t in path.read_text().splitlines() if "[[[" in t)) + 1
    assert error_of(path) == f"{path}: line {line}: keys, tables or arrays nested more than 32 levels deep"


# ------------------------------------------------------------------ bounds


@pytest.mark.parametrize(
    "joint, message",
    [
        (JOINT.replace("a = 0.5", "a = 1e308"), "joints[0].a: expected a length within ±1000 m, got 1e+308"),
        (JOINT.replace("d = 0.1", "d = -1000.5"), "joints[0].d: expected a length within ±1000 m, got -1000.5"),
        (
            JOINT.replace("alpha = 90.0", "alpha = 1e9"),
            "joints[0].alpha: expected an angle within ±1800 deg, got 1000000000.0",
        ),
        (
            JOINT + "limits = [-1e9, 1e9]\n",
            "joints[0].limits[0]: expected an angle within ±1800 deg, got -1000000000.0",
        ),
        (PRISMATIC + "home = 1e7\n", "joints[0].home: expected a length within ±1000 m, got 10000000.0"),
        (PRISMATIC + "limits = [0.0, 1001.0]\n", "joints[0].limits[1]: expected a length within ±1000 m, got 1001.0"),
    ],
)
def test_sizes_beyond_the_bounds_are_refused(tmp_path, joint, message):
    path = write(tmp_path, one_joint(joint))
    assert error_of(path) == f"{path}: {message}"


def test_bounds_in_radians_are_said_in_radians(tmp_path):
    path = write(tmp_path, one_joint(JOINT.replace("alpha = 90.0", "alpha = 100.0"), 'name = "x"\nunits = "rad"\n'))
    assert error_of(path) == f"{path}: joints[0].alpha: expected an angle within ±31.4159 rad, got 100.0"


def test_base_and_tool_are_bounded(tmp_path):
    path = write(tmp_path, HEAD + "[base]\nxyz = [0.0, 2e3, 0.0]\n\n[[joints]]\n" + JOINT)
    assert error_of(path) == f"{path}: base.xyz[1]: expected a length within ±1000 m, got 2000.0"
    path = write(tmp_path, HEAD + "[tool]\nrpy = [0.0, 0.0, 1e6]\n\n[[joints]]\n" + JOINT)
    assert error_of(path) == f"{path}: tool.rpy[2]: expected an angle within ±1800 deg, got 1000000.0"


def test_values_at_the_bounds_load_with_finite_kinematics(tmp_path):
    from robot_sim.kinematics import forward_kinematics

    big = (
        f"type = \"revolute\"\na = {MAX_LENGTH}\nalpha = {MAX_ANGLE_DEG}\nd = {-MAX_LENGTH}\n"
        f"theta = {MAX_ANGLE_DEG}\nlimits = [{-MAX_ANGLE_DEG}, {MAX_ANGLE_DEG}]\n"
    )
    slide = f"type = \"prismatic\"\na = {MAX_LENGTH}\nalpha = 0.0\nd = {MAX_LENGTH}\ntheta = 0.0\nlimits = [{-MAX_LENGTH}, {MAX_LENGTH}]\n"
    text = HEAD + "".join(f"\n[[joints]]\n{j}" for j in [big, slide] * (MAX_JOINTS // 2))
    robot = load_robot(write(tmp_path, text))
    assert robot.n_dofs == MAX_JOINTS
    corners = np.stack([robot.q_min, robot.q_max, robot.q_home])
    assert np.isfinite(forward_kinematics(robot, corners, all_frames=True)).all()


def test_too_many_joints(tmp_path):
    path = write(tmp_path, HEAD + "".join(f"\n[[joints]]\n{JOINT}" for _ in range(MAX_JOINTS + 1)))
    assert error_of(path) == f"{path}: joints: {MAX_JOINTS + 1} joints; at most {MAX_JOINTS} are accepted"


def test_huge_values_are_cut_in_messages(tmp_path):
    path = write(tmp_path, one_joint(head=f'name = "{"x" * 5000}"\nunits = "deg"\ndescription = 5\n'))
    assert error_of(path) == f"{path}: name: expected at most 200 characters on one line, got {repr('x' * 5000)[:80]}... (5002 characters)"
    path = write(tmp_path, one_joint(JOINT.replace("d = 0.1", f"d = {list(range(2000))}")))
    message = error_of(path)
    assert message.startswith(f"{path}: joints[0].d: expected a number, got [0, 1, 2")
    assert len(message) < len(str(path)) + 200
    path = write(tmp_path, one_joint(head=HEAD + f'{"k" * 3000} = 1\n'))
    message = error_of(path)
    assert message.startswith(f"{path}: kkkk") and "unknown key 'kkkk" in message
    assert len(message) < len(str(path)) + 400


def test_name_must_be_one_line(tmp_path):
    path = write(tmp_path, one_joint(head='name = "a\\nb"\nunits = "deg"\n'))
    assert error_of(path) == f"{path}: name: expected at most 200 characters on one line, got 'a\\nb'"


def test_file_too_large(tmp_path):
    path = write(tmp_path, one_joint() + "#" * MAX_FILE_BYTES + "\n")
    assert error_of(path) == f"{path}: cannot read robot file: it is larger than {MAX_FILE_BYTES} bytes"


# ------------------------------------------------------------------ paths


def test_path_too_long(tmp_path):
    path = tmp_path / ("x" * 300 + ".toml")
    assert error_of(path) == f"{path}: cannot read robot file: File name too long"
    deep = tmp_path / "/".join(["d" * 200] * 25) / "r.toml"
    assert error_of(deep) == f"{deep}: cannot read robot file: File name too long"


def test_directory_and_symlink_loop_are_not_reported_as_missing(tmp_path):
    folder = tmp_path / "arm.toml"
    folder.mkdir()
    assert error_of(folder) == f"{folder}: cannot read robot file: it is a directory, not a regular file"
    loop = tmp_path / "loop.toml"
    loop.symlink_to(loop)
    assert error_of(loop) == f"{loop}: cannot read robot file: Too many levels of symbolic links"


def test_fifo_is_refused_without_waiting_for_a_writer(tmp_path):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    assert error_of(fifo) == f"{fifo}: cannot read robot file: it is a FIFO (named pipe), not a regular file"


def test_device_is_refused():
    assert error_of("/dev/zero") == "/dev/zero: cannot read robot file: it is a character device, not a regular file"


def test_missing_file_still_says_not_found(tmp_path):
    path = tmp_path / "none.toml"
    assert error_of(path) == f"{path}: robot file not found"


def test_unreadable_file():
    with tempfile.TemporaryDirectory() as folder:
        os.chmod(folder, 0o755)
        path = Path(folder) / "secret.toml"
        path.write_text((ROBOTS_DIR / "planar3.toml").read_text())
        path.chmod(0o000)
        assert call_unprivileged(lambda: error_of(path)) == f"{path}: cannot read robot file: Permission denied"


# ------------------------------------------------------------------ programmatic robots


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(dh_a=[float("nan")]), "dh_a must hold finite numbers, got [nan]"),
        (dict(dh_d=[math.inf]), "dh_d must hold finite numbers, got [inf]"),
        (dict(dh_alpha=[1j]), "dh_alpha must hold real numbers, got [1j]"),
        (dict(jtype=[7]), "jtype[0] must be 0 (revolute) or 1 (prismatic), got 7"),
        (dict(jtype=[0.5]), "jtype[0] must be 0 (revolute) or 1 (prismatic), got 0.5"),
        (dict(jtype=["revolute"]), "jtype must hold 0 (revolute) or 1 (prismatic), got ['revolute']"),
        (dict(dh_a=[]), "dh_a must hold at least one joint, got []"),
        (dict(dh_a=[[1.0]]), "dh_a must be a 1-D sequence of numbers, got shape (1, 1)"),
        (dict(q_min=[1.0], q_max=[0.0]), "q_min[0] = 1.0 > q_max[0] = 0.0"),
        (dict(q_min=[math.nan]), "q_min must not hold NaN, got [nan]"),
        (dict(q_home=[2.0], q_max=[1.0]), "q_home[0] = 2.0 is outside [q_min, q_max] = [-inf, 1.0]"),
        (dict(link_com_frac=[1.5]), "link_com_frac must lie in [0, 1], got [1.5]"),
        (dict(name=5), "name must be a string, got 5"),
    ],
)
def test_from_arrays_rejects_bad_values(kwargs, message):
    args = dict(name="p", dh_a=[1.0], dh_alpha=[0.0], dh_d=[0.0], dh_th=[0.0], jtype=[JTYPE_REVOLUTE])
    args.update(kwargs)
    with pytest.raises(ValueError) as info:
        RobotParams.from_arrays(**args)
    assert str(info.value) == message


def test_from_arrays_still_builds_programmatic_robots():
    robot = RobotParams.from_arrays("p", [1e4, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [JTYPE_REVOLUTE, JTYPE_PRISMATIC])
    assert robot.n_dofs == 2 and robot.jtype.tolist() == [JTYPE_REVOLUTE, JTYPE_PRISMATIC]


# ------------------------------------------------------------------ URDF robots keep the same bounds

URDF = """<?xml version="1.0"?>
<robot name="u">
  <link name="l0"/><link name="l1"/><link name="l2"/>
  <joint name="j1" type="revolute">
    <parent link="l0"/><child link="l1"/>
    <origin xyz="{base}" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="prismatic">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0.3 0 0.2" rpy="0 0 0"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="{upper}" effort="1" velocity="1"/>
  </joint>
</robot>
"""


def test_urdf_robots_keep_the_bounds(tmp_path):
    good = write(tmp_path, URDF.format(base="0 0 0.1", upper="0.5"), "good.urdf")
    assert load_robot(good).n_dofs == 2
    path = write(tmp_path, URDF.format(base="0 0 0.1", upper="1e300"), "slide.urdf")
    assert error_of(path) == f"{path}: joint 2: upper limit beyond the accepted ±1000 m (lengths) or ±1800 deg (angles)"
    path = write(tmp_path, URDF.format(base="0 0 5000", upper="0.5"), "base.urdf")
    assert error_of(path) == f"{path}: base offset 5000.2 m beyond the accepted ±1000 m"
