"""Geometry in robot files: [[joints.visual]] / [[joints.collision]] (and under [base])
load as shapes in the joint's frame, are validated field by field with one line naming
file, joint and field, and are written back by the style-preserving writer."""
from __future__ import annotations

import math

import numpy as np
import pytest

from geometry_helpers import odd_mesh, write_mesh
from robot_sim.io.robot_file import load_robot
from robot_sim.io.robot_writer import save_robot, to_toml, with_dh_value
from robot_sim.model.params import RobotDefinitionError
from robot_sim.model.shapes import Box, Capsule, Cylinder, Mesh, Sphere
from robot_sim.transforms import HomogeneousTransform

ROBOT = """# a two-link arm with geometry
name = "geo"
units = "deg"

[base]
xyz = [0.0, 0.0, 0.5]

[[base.visual]]
mesh = "meshes/base.stl"   # the pedestal
color = [0.5, 0.5, 0.5]

[[base.collision]]
box = [0.3, 0.3, 0.5]
xyz = [0.0, 0.0, -0.25]

[[joints]]
type = "revolute"
a = 0.4
alpha = 90
d = 0.2
theta = 0

[[joints.visual]]
mesh = "meshes/link1.obj"
xyz = [-0.2, 0.0, 0.0]
rpy = [0, 90, 0]
scale = 0.001
color = [0.9, 0.4, 0.1, 0.5]

[[joints.collision]]
capsule = [0.05, 0.4]
xyz = [-0.2, 0.0, 0.0]
rpy = [0, 90, 0]

[[joints]]
type = "prismatic"
a = 0.0
alpha = 0
d = 0.1
theta = 30
limits = [0, 0.5]

[[joints.visual]]
mesh = "meshes/link2.ply"
scale = [1, 2, 0.5]

[[joints.visual]]
sphere = 0.03
xyz = [0.0, 0.0, 0.1]

[[joints.collision]]
cylinder = [0.04, 0.3]
"""


@pytest.fixture
def robot_file(tmp_path):
    write_mesh(tmp_path / "meshes" / "base.stl", odd_mesh(1))
    write_mesh(tmp_path / "meshes" / "link1.obj", odd_mesh(2, 300.0))
    write_mesh(tmp_path / "meshes" / "link2.ply", odd_mesh(3))
    path = tmp_path / "geo.toml"
    path.write_text(ROBOT)
    return path


def pose(xyz, rpy_deg) -> np.ndarray:
    return HomogeneousTransform.from_xyz_rpy(xyz, np.radians(rpy_deg)).mat


def test_shapes_load_in_their_joints_frames(robot_file):
    robot = load_robot(robot_file)
    meshes = robot_file.parent / "meshes"
    pedestal, = robot.base_visuals
    assert isinstance(pedestal, Mesh) and pedestal.path == str(meshes / "base.stl")
    assert pedestal.color == (0.5, 0.5, 0.5, 1.0)
    box, = robot.base_collisions
    assert isinstance(box, Box) and box.size.tolist() == [0.3, 0.3, 0.5]
    np.testing.assert_array_equal(box.pose, pose([0, 0, -0.25], [0, 0, 0]))
    link1, = robot.visuals[0]
    assert link1.path == str(meshes / "link1.obj") and link1.scale.tolist() == [0.001] * 3
    assert link1.color == (0.9, 0.4, 0.1, 0.5)
    np.testing.assert_array_equal(link1.pose, pose([-0.2, 0, 0], [0, 90, 0]))
    capsule, = robot.collisions[0]
    assert isinstance(capsule, Capsule) and (capsule.radius, capsule.length) == (0.05, 0.4)
    mesh2, ball = robot.visuals[1]
    assert mesh2.scale.tolist() == [1.0, 2.0, 0.5]
    assert isinstance(ball, Sphere) and ball.radius == 0.03 and ball.center.tolist() == [0, 0, 0.1]
    cylinder, = robot.collisions[1]
    assert isinstance(cylinder, Cylinder) and (cylinder.radius, cylinder.length) == (0.04, 0.3)
    # the meshes hold the files' triangles, scaled (link1 is 300 units long: 0.3 m)
    assert 0.3 <= np.ptp(link1.vertices[:, 0]) < 0.45 and link1.faces.shape[1] == 3


def test_a_robot_without_geometry_has_empty_tuples():
    robot = load_robot("puma560")
    assert robot.visuals == robot.collisions == ((),) * 6
    assert robot.base_visuals == robot.base_collisions == ()


@pytest.mark.parametrize("old, new, where, message", [
    ('sphere = 0.03', 'sphere = 0.03\nsize = 2', "joints[1].visual[1].size",
     "unknown key 'size'; accepted keys: box, capsule, color, cylinder, mesh, rpy, scale, sphere, xyz"),
    ('cylinder = [0.04, 0.3]', 'cylinder = [0.04, 0.3]\ncolor = [1, 0, 0]', "joints[1].collision[0].color",
     "unknown key 'color'; accepted keys: box, capsule, cylinder, mesh, rpy, scale, sphere, xyz"),
    ('"meshes/link2.ply"', '"meshes/link3.ply"', "joints[1].visual[0].mesh", "{dir}/meshes/link3.ply: mesh file not found"),
    ('scale = [1, 2, 0.5]', 'scale = [1, 0, 0.5]', "joints[1].visual[0].scale",
     "expected a scale factor or three, each > 0 and <= 1000, got [1, 0, 0.5]"),
    ('scale = [1, 2, 0.5]', 'scale = [1, 2]', "joints[1].visual[0].scale", "expected a list of 3 numbers, got [1, 2]"),
    ('sphere = 0.03', 'sphere = 0.03\nscale = 2', "joints[1].visual[1].scale", "scale applies to meshes only, not to a sphere"),
    ('sphere = 0.03', 'sphere = 0.03\nbox = [1, 1, 1]', "joints[1].visual[1]", "expected exactly one of mesh, box, sphere, cylinder, capsule, got 2"),
    ('sphere = 0.03', 'sphere = -0.03', "joints[1].visual[1].sphere", "expected a radius > 0 m, got -0.03"),
    ('capsule = [0.05, 0.4]', 'capsule = [0.05]', "joints[0].collision[0].capsule", "expected [radius, length] in metres, got [0.05]"),
    ('box = [0.3, 0.3, 0.5]', 'box = [0.3, 0.0, 0.5]', "base.collision[0].box", "expected [x, y, z] edge lengths > 0 m, got [0.3, 0.0, 0.5]"),
    ('color = [0.5, 0.5, 0.5]', 'color = [0.5, 1.5, 0.5]', "base.visual[0].color", "expected [r, g, b] or [r, g, b, a] in 0..1, got [0.5, 1.5, 0.5]"),
    ('rpy = [0, 90, 0]\nscale', 'rpy = [0, 9000, 0]\nscale', "joints[0].visual[0].rpy[1]", "expected an angle within ±1800 deg, got 9000"),
    ('xyz = [-0.2, 0.0, 0.0]\nrpy = [0, 90, 0]\nscale', 'xyz = [-0.2, 0.0]\nrpy = [0, 90, 0]\nscale', "joints[0].visual[0].xyz",
     "expected a list of 3 numbers, got [-0.2, 0.0]"),
    ('[[joints.collision]]\ncylinder', '[joints.collision]\ncylinder', "joints[1].collision",
     "expected an array of tables ([[...collision]]), got {{'cylinder': [0.04, 0.3]}}"),
])
def test_bad_shape_fields_are_one_line_naming_file_joint_and_field(robot_file, old, new, where, message):
    assert old in ROBOT
    robot_file.write_text(ROBOT.replace(old, new, 1))
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(robot_file)
    assert str(info.value) == f"{robot_file}: {where}: {message.format(dir=robot_file.parent)}"


def test_a_corrupt_mesh_in_a_robot_file_names_the_field(robot_file):
    (robot_file.parent / "meshes" / "link2.ply").write_bytes(b"ply\nnonsense\n")
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(robot_file)
    assert str(info.value).startswith(
        f"{robot_file}: joints[1].visual[0].mesh: {robot_file.parent}/meshes/link2.ply: not a readable .ply mesh")


def test_an_unchanged_robot_writes_its_template_unchanged(robot_file):
    robot = load_robot(robot_file)
    assert to_toml(robot, ROBOT, directory=robot_file.parent) == ROBOT


def test_the_writer_round_trips_shapes_into_another_folder(robot_file, tmp_path):
    robot = load_robot(robot_file, convention="modified")  # every pose moves with the frames
    target = tmp_path / "out" / "deeper" / "geo_mod.toml"
    target.parent.mkdir(parents=True)
    save_robot(robot, target, template=ROBOT)
    text = target.read_text()
    assert 'mesh = "../../meshes/link1.obj"' in text and text.startswith("# a two-link arm with geometry\n")
    again = load_robot(target)
    assert again.convention == "modified"
    for a, b in zip((robot.base_visuals, robot.base_collisions, *robot.visuals, *robot.collisions),
                    (again.base_visuals, again.base_collisions, *again.visuals, *again.collisions)):
        assert len(a) == len(b)
        for s, t in zip(a, b):
            assert type(s) is type(t) and s.color == t.color
            np.testing.assert_allclose(t.pose, s.pose, atol=1e-12, rtol=0)
            if isinstance(s, Mesh):
                assert (s.path, s.scale.tolist()) == (t.path, t.scale.tolist())


def test_a_new_file_holds_the_shapes(robot_file, tmp_path):
    robot = load_robot(robot_file)
    target = tmp_path / "fresh.toml"
    save_robot(robot, target)
    again = load_robot(target)
    assert [len(v) for v in again.visuals] == [1, 2] and len(again.base_collisions) == 1
    assert again.visuals[1][1] == robot.visuals[1][1] and again.base_visuals[0].path == robot.base_visuals[0].path


def test_a_dh_edit_keeps_the_geometry(robot_file):
    robot = load_robot(robot_file)
    edited = with_dh_value(robot, 0, "a", 0.5)
    assert edited.dh_a[0] == 0.5
    assert edited.visuals == robot.visuals and edited.base_collisions == robot.base_collisions
    assert math.isclose(edited.visuals[0][0].vertices[0, 0], robot.visuals[0][0].vertices[0, 0])
