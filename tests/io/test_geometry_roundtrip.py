"""Geometry through conversions and files: to_standard/to_modified move every shape with
its frame exactly (world poses unchanged at any q, and back again); robot file with
meshes -> to_urdf -> load_robot keeps every shape's world pose (at any q) to 1e-12 in
both conventions,
with mesh filenames written relative to the URDF; a robot without geometry comes back
without any."""
from __future__ import annotations

import dataclasses
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from geometry_helpers import odd_mesh, write_mesh
from kin_helpers import CONVENTIONS, random_dh_robot, random_q, random_rigid
from robot_sim.io.robot_file import load_robot
from robot_sim.io.urdf_out import to_urdf
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.convert import to_modified, to_standard
from robot_sim.model.params import RobotParams
from robot_sim.model.shapes import Box, Capsule, Cylinder, Mesh, Sphere

ROBOT = """name = "trip"
units = "rad"
convention = "{convention}"

[[base.visual]]
mesh = "meshes/base.dae"
xyz = [0.01, 0.02, 0.03]
rpy = [0.1, 0.2, 0.3]

[[base.collision]]
cylinder = [0.1, 0.2]
rpy = [0.0, 1.0, 0.0]
"""
JOINT = """
[[joints]]
type = "{type}"
a = {a}
alpha = {alpha}
d = {d}
theta = {theta}

[[joints.visual]]
mesh = "meshes/link{i}.{ext}"
xyz = [{x}, 0.01, -0.02]
rpy = [0.3, -0.4, {i}]
scale = [0.5, 1.0, 2.0]
color = [0.1, 0.2, 0.3, 1.0]

[[joints.visual]]
box = [0.1, 0.05, 0.02]
xyz = [0.0, {x}, 0.0]
rpy = [1.0, 0.5, -0.5]

[[joints.collision]]
capsule = [0.03, {x}]
rpy = [0.0, 1.5707963267948966, 0.0]

[[joints.collision]]
sphere = 0.04
xyz = [{x}, 0.0, 0.1]
"""
ROWS = [("revolute", 0.3, 1.5707963267948966, 0.2, 0.0), ("revolute", 0.0, -0.7, 0.1, 0.4),
        ("prismatic", 0.2, 0.3, 0.05, -0.2), ("revolute", 0.1, 1.1, -0.1, 0.9)]
EXTS = ("stl", "obj", "ply", "dae")


def write_robot(folder: Path, convention: str) -> Path:
    write_mesh(folder / "meshes" / "base.dae", odd_mesh(0))
    text = ROBOT.format(convention=convention)
    for i, ((kind, a, alpha, d, theta), ext) in enumerate(zip(ROWS, EXTS), start=1):
        write_mesh(folder / "meshes" / f"link{i}.{ext}", odd_mesh(i))
        text += JOINT.format(type=kind, a=a, alpha=alpha, d=d, theta=theta, i=i, ext=ext, x=0.1 * i)
    path = folder / "trip.toml"
    path.write_text(text)
    return path


def all_shapes(robot: RobotParams) -> list[tuple[int, object]]:
    """(frame index, shape) of every shape: frame 0 for the base, i for link i."""
    groups = [(0, robot.base_visuals), (0, robot.base_collisions)]
    groups += [(i + 1, s) for i, s in enumerate(robot.visuals)] + [(i + 1, s) for i, s in enumerate(robot.collisions)]
    return [(i, shape) for i, shapes in groups for shape in shapes]


def world_poses(robot: RobotParams, q: np.ndarray) -> list[np.ndarray]:
    """World pose of every shape at q (a sphere's centre only: it has no orientation)."""
    frames = forward_kinematics(robot, q, all_frames=True)
    poses = [frames[i] @ shape.pose for i, shape in all_shapes(robot)]
    return [p[:3, 3] if isinstance(s, Sphere) else p for p, (_, s) in zip(poses, all_shapes(robot))]


def assert_same_shapes(a: RobotParams, b: RobotParams, q_samples: np.ndarray, atol: float) -> None:
    """Same shapes (type, size, mesh file, scale, colour) at the same world poses."""
    sa, sb = all_shapes(a), all_shapes(b)
    assert [type(s) for _, s in sa] == [type(s) for _, s in sb]
    for (_, s), (_, t) in zip(sa, sb):
        assert s.color == t.color
        if isinstance(s, Mesh):
            assert s.path == t.path and s.scale.tolist() == t.scale.tolist()
        elif isinstance(s, Box):
            assert s.size.tolist() == t.size.tolist()
        elif isinstance(s, (Sphere, Cylinder, Capsule)):
            assert s.radius == t.radius and getattr(s, "length", 0) == getattr(t, "length", 0)
    for q in q_samples:
        for pa, pb in zip(world_poses(a, q), world_poses(b, q)):
            np.testing.assert_allclose(pb, pa, atol=atol, rtol=0)


@pytest.mark.parametrize("conv", CONVENTIONS)
def test_conversion_moves_every_shape_with_its_frame(tmp_path, conv):
    robot = load_robot(write_robot(tmp_path, conv))
    other = to_modified(robot) if conv == "standard" else to_standard(robot)
    back = to_standard(other) if conv == "standard" else to_modified(other)
    Q = random_q(robot, np.random.default_rng(3), 8)
    assert_same_shapes(robot, other, Q, 1e-12)
    assert_same_shapes(robot, back, Q, 1e-12)
    # frames 1..n-1 are the same after the round trip (frame 0 or n may take up a_0, α_0
    # or a_n, α_n), so there the shapes keep their poses in the link frame
    for (i, s), (_, t) in zip(all_shapes(robot), all_shapes(back)):
        if 1 <= i < robot.n_dofs:
            np.testing.assert_allclose(t.pose, s.pose, atol=1e-12, rtol=0)
    # the frames really differ (else this test would prove nothing) for the standard side
    changed = [not np.allclose(s.pose, t.pose) for (_, s), (_, t) in zip(all_shapes(robot), all_shapes(other))]
    assert sum(changed) >= 8


@pytest.mark.parametrize("source_conv", CONVENTIONS)
@pytest.mark.parametrize("conv", CONVENTIONS)
def test_robot_file_to_urdf_to_robot_keeps_every_shape(tmp_path, source_conv, conv):
    robot = load_robot(write_robot(tmp_path / "src", source_conv), convention=conv)
    urdf = tmp_path / "export" / "urdf" / "trip.urdf"
    urdf.parent.mkdir(parents=True)
    urdf.write_text(to_urdf(robot, path=urdf))
    filenames = [m.get("filename") for m in ET.parse(urdf).getroot().iter("mesh")]
    assert filenames == ["../../src/meshes/base.dae", *(f"../../src/meshes/link{i}.{e}" for i, e in enumerate(EXTS, 1))]
    again = load_robot(urdf, convention=conv)
    assert len(all_shapes(robot)) == len(all_shapes(again)) == 2 + 4 * 4
    # every shape on the same body, at the same world pose for any q: the importer builds
    # its own DH frames (here d_4 moves into the tool), so link-frame poses may differ
    assert [i for i, _ in all_shapes(robot)] == [i for i, _ in all_shapes(again)]
    Q = np.vstack([np.zeros(robot.n_dofs), random_q(robot, np.random.default_rng(4), 5)])
    assert_same_shapes(robot, again, Q, 1e-12)


@pytest.mark.parametrize("conv", CONVENTIONS)
def test_random_chains_with_random_shapes_round_trip_through_urdf(tmp_path, conv):
    rng = np.random.default_rng(11)
    mesh = write_mesh(tmp_path / "m.stl", odd_mesh(8))
    for n in (1, 3, 6):
        base = random_dh_robot(rng, n, convention=conv)
        shapes = [(Box((0.1, 0.2, 0.3), pose=random_rigid(rng, 0.3)),
                   Cylinder(0.05, 0.2, pose=random_rigid(rng, 0.3), color=(1.0, 0.0, 0.0, 1.0)),
                   Mesh(str(mesh), pose=random_rigid(rng, 0.3), scale=(1.0, 2.0, 3.0)))
                  for _ in range(n)]
        robot = dataclasses.replace(base, visuals=tuple(shapes), collisions=tuple((s[0],) for s in shapes),
                                    base_visuals=(Sphere(0.1, center=(0.1, 0.2, 0.3)),))
        urdf = tmp_path / f"r{n}.urdf"
        urdf.write_text(to_urdf(robot, path=urdf))
        assert_same_shapes(robot, load_robot(urdf, convention=conv), random_q(robot, rng, 4), 1e-11)


def test_a_robot_without_geometry_comes_back_without_any(tmp_path):
    robot = load_robot("stanford")
    text = to_urdf(robot)
    assert 'name="dh_drawing"' in text  # other viewers still see the DH segments
    urdf = tmp_path / "stanford.urdf"
    urdf.write_text(text)
    again = load_robot(urdf)
    assert again.visuals == again.collisions == ((),) * 6 and again.base_visuals == ()


def test_a_mesh_without_a_file_cannot_be_written_to_urdf():
    robot = load_robot("planar3")
    triangle = Mesh((np.eye(3), np.array([[0, 1, 2]])))
    robot = dataclasses.replace(robot, visuals=((triangle,), (), ()))
    with pytest.raises(ValueError, match="link 'link1' visual 1: a mesh given as arrays has no file to name in a URDF"):
        to_urdf(robot)


def test_robot_params_refuses_geometry_of_the_wrong_shape():
    robot = load_robot("planar3")
    with pytest.raises(ValueError, match="visuals: expected 3 tuples of shapes .one per link., got 2"):
        dataclasses.replace(robot, visuals=((), ()))
    with pytest.raises(ValueError, match=r"collisions\[1\]\[0\]: expected a Box, Sphere, Cylinder, Capsule or Mesh, got 'box'"):
        dataclasses.replace(robot, collisions=((), ("box",), ()))
