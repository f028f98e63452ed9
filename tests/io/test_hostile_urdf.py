"""Issue 31, URDFs: the reader runs in O(links) and bounds the joint count before the
expensive work; URDFs load the way users name them (a bare file name, any suffix, xacro)."""
from __future__ import annotations

import struct
import time

import numpy as np
import pytest

import robot_sim.io.urdf_in as urdf_in
from robot_sim.app.main import main
from robot_sim.io.robot_file import load_robot
from robot_sim.model.params import RobotDefinitionError

JOINT = ('<joint name="j{k}" type="{kind}"><parent link="l{k}"/><child link="l{k1}"/>'
         '<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>')


def chain_urdf(n: int, kind: str = "revolute", extra: str = "") -> str:
    links = "".join(f'<link name="l{k}"/>' for k in range(n + 1))
    joints = "".join(JOINT.format(k=k, k1=k + 1, kind=kind) for k in range(n))
    return f'<robot name="chain">{links}{joints}{extra}</robot>'


def test_a_long_chain_with_a_loop_off_the_root_is_found_in_linear_time(tmp_path):
    """50 000 links on a chain and a two-link loop beside it: the old check walked up from
    every link (quadratic; 100 000 links took more than 120 s)."""
    loop = ('<link name="a"/><link name="b"/>'
            '<joint name="x" type="fixed"><parent link="a"/><child link="b"/></joint>'
            '<joint name="y" type="fixed"><parent link="b"/><child link="a"/></joint>')
    path = tmp_path / "long.urdf"
    path.write_text(chain_urdf(50_000, "fixed", loop))
    start = time.process_time()
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    assert time.process_time() - start < 30.0  # a hang guard, not a benchmark
    assert str(info.value) in (f"{path}: the joints form a loop through link 'a'",
                               f"{path}: the joints form a loop through link 'b'")


def test_the_joint_count_is_refused_before_the_chain_is_built(tmp_path, monkeypatch):
    monkeypatch.setattr(urdf_in, "_build", lambda *a: pytest.fail("built a chain of too many joints"))
    path = tmp_path / "many.urdf"
    path.write_text(chain_urdf(101))
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    assert str(info.value) == f"{path}: 101 joints; at most 100 are accepted"


def _binary_stl(path):
    v = np.array([[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]], dtype=np.float32)
    faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(b"\0" * 80 + struct.pack("<I", 4)
                     + b"".join(struct.pack("<12fH", 0, 0, 0, *v[a], *v[b], *v[c], 0) for a, b, c in faces))


PACKAGE_URDF = ('<robot name="arm"><link name="base"/><link name="l1"><visual><geometry>'
                '<mesh filename="package://arm_description/meshes/l1.stl"/></geometry></visual></link>'
                '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>'
                '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>')


def _package(tmp_path):
    _binary_stl(tmp_path / "arm_description" / "meshes" / "l1.stl")
    folder = tmp_path / "arm_description" / "urdf"
    folder.mkdir()
    return folder


def test_a_urdf_named_by_its_bare_file_name_finds_its_package_meshes(tmp_path, monkeypatch):
    folder = _package(tmp_path)
    (folder / "arm.urdf").write_text(PACKAGE_URDF)
    monkeypatch.chdir(folder)
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    robot = load_robot("arm.urdf")
    (mesh,) = robot.visuals[0]
    assert mesh.path == str(tmp_path / "arm_description" / "meshes" / "l1.stl")


@pytest.mark.parametrize("name", ["arm.xml", "arm", "arm.description"])
def test_a_urdf_under_any_name_is_read_by_its_content(tmp_path, name):
    folder = _package(tmp_path)
    (folder / name).write_text('<?xml version="1.0"?>\n<!-- exported -->\n' + PACKAGE_URDF)
    assert load_robot(folder / name).n_dofs == 1


def test_an_unknown_name_says_what_is_accepted(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(RobotDefinitionError) as info:
        load_robot("pumaa560")
    message = str(info.value)
    assert message.startswith("unknown robot 'pumaa560': no such file and no shipped robot of that name; accepted: "
                              "a shipped robot's name, a robot file (.toml), a URDF (.urdf, or XML with a <robot> "
                              "root under any name) or a xacro file (.urdf.xacro, .xacro; needs pip install xacro); "
                              "available robots: ")
    assert "puma560" in message.rsplit(": ", 1)[1].split(", ")


XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="xarm">
  <xacro:arg name="reach" default="0.1"/>
  <xacro:include filename="$(find arm_description)/urdf/parts.xacro"/>
  <link name="base"/>
  <xacro:link_with_mesh name="l1"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="$(arg reach) 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="l2"/>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.2"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""
PARTS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="link_with_mesh" params="name">
    <link name="${name}"><visual><geometry>
      <mesh filename="package://arm_description/meshes/l1.stl"/></geometry></visual></link>
  </xacro:macro>
</robot>
"""


def _xacro_package(tmp_path):
    pytest.importorskip("xacro")  # the optional extra, in the test extra
    folder = _package(tmp_path)
    (folder / "parts.xacro").write_text(PARTS)
    (folder / "arm.urdf.xacro").write_text(XACRO)
    return folder / "arm.urdf.xacro"


def test_a_xacro_file_is_expanded_with_its_arguments_and_find(tmp_path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    path = _xacro_package(tmp_path)
    near, far = load_robot(path), load_robot(path, xacro_args={"reach": "0.7"})
    assert near.n_dofs == far.n_dofs == 2 and len(near.visuals[0]) == 1
    from robot_sim.kinematics import forward_kinematics

    q = np.zeros(2)  # the first joint's origin moves with the argument: so does the tool
    gap = forward_kinematics(far, q)[:3, 3] - forward_kinematics(near, q)[:3, 3]
    assert np.allclose(gap, [0.6, 0.0, 0.0], atol=1e-12)


def test_xacro_args_on_the_command_line(tmp_path, monkeypatch, capsys):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    path = _xacro_package(tmp_path)
    assert main(["--robot", str(path), "--xacro-arg", "reach:=0.5", "--print-dh"]) == 0
    assert "base: xyz [0.5, 0, 0.2] m" in capsys.readouterr().out  # frame 1 at q = 0: x from reach
    assert main(["--robot", "puma560", "--xacro-arg", "reach:=0.5", "--print-dh"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--xacro-arg: xacro_args apply to xacro files only" in err
    assert main(["--robot", str(path), "--xacro-arg", "reach=0.5", "--print-dh"]) == 2
    assert "--xacro-arg: xacro argument 'reach=0.5': expected NAME:=VALUE" in capsys.readouterr().err


def test_a_broken_xacro_file_is_one_line_without_its_text(tmp_path):
    pytest.importorskip("xacro")
    path = tmp_path / "bad.urdf.xacro"
    path.write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r"><xacro:SECRET_macro/></robot>')
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    assert "SECRET" not in str(info.value)
    assert str(info.value).startswith(f"{path}: xacro could not expand the file (")
