"""URDF geometry in: <visual>/<collision> of the chain's links become shapes in the DH
frames; meshes (STL, OBJ, PLY, DAE) resolve through package://, ROS_PACKAGE_PATH,
relative and file:// paths, with scale and materials; the vertices of every mesh, moved
by our forward kinematics, are where the URDF's own joint chain (computed in the test by
urdf_helpers) puts them; a missing or corrupt mesh is one error, or one warning per file
with --skip-missing-meshes."""
from __future__ import annotations

import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh

from paths import DATA, ROOT
from cli_helpers import run
from geometry_helpers import file_vertices, odd_mesh, shape_world, urdf_visual_world, write_mesh
from kin_helpers import CONVENTIONS
from robot_sim.io.meshes import MeshSkippedWarning
from robot_sim.io.robot_file import load_robot
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.params import RobotDefinitionError
from robot_sim.model.shapes import Box, Cylinder, Mesh, Sphere
from urdf_helpers import parse

PKG = "meshy_description"

URDF = """<?xml version="1.0"?>
<robot name="meshy">
  <material name="steel"><color rgba="0.6 0.6 0.65 1"/></material>
  <link name="base_link">
    <visual>
      <origin xyz="0 0 0.05" rpy="0 0 0.3"/>
      <geometry><mesh filename="package://{pkg}/meshes/base.stl"/></geometry>
      <material name="steel"/>
    </visual>
    <collision><origin xyz="0 0 0.05"/><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base_link"/><child link="shoulder"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="1"/>
  </joint>
  <link name="shoulder">
    <visual>
      <origin xyz="0.01 0.02 0.1" rpy="0.1 0.2 0.3"/>
      <geometry><mesh filename="../meshes/shoulder.obj"/></geometry>
      <material name="blue"><color rgba="0 0 1 1"/></material>
    </visual>
    <collision><origin xyz="0 0 0.1"/><geometry><cylinder radius="0.05" length="0.2"/></geometry></collision>
  </link>
  <joint name="j2" type="revolute">
    <parent link="shoulder"/><child link="upper"/>
    <origin xyz="0 0.05 0.2" rpy="1.2 0.1 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="10" velocity="1"/>
  </joint>
  <link name="upper">
    <visual>
      <origin xyz="0.15 0 0" rpy="0 1.5707963267948966 0"/>
      <geometry><mesh filename="package://{pkg}/meshes/upper.dae"/></geometry>
      <material name="blue"/>
    </visual>
    <collision><origin xyz="0.3 0 0"/><geometry><sphere radius="0.04"/></geometry></collision>
  </link>
  <joint name="adapter_joint" type="fixed">
    <parent link="upper"/><child link="adapter"/>
    <origin xyz="0.3 0 0" rpy="0.3 -0.2 0.5"/>
  </joint>
  <link name="adapter">
    <visual>
      <origin xyz="0 0 0.01" rpy="0 0 0.7"/>
      <geometry><mesh filename="package://{pkg}/meshes/adapter_mm.stl" scale="0.001 0.002 0.001"/></geometry>
    </visual>
  </link>
  <joint name="j3" type="prismatic">
    <parent link="adapter"/><child link="slider"/>
    <origin xyz="0.05 0.02 0.03" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.2" effort="10" velocity="1"/>
  </joint>
  <link name="slider">
    <visual>
      <origin xyz="0 0.1 0" rpy="0.4 0 0"/>
      <geometry><mesh filename="file://{slider}"/></geometry>
    </visual>
  </link>
  <joint name="tool_joint" type="fixed">
    <parent link="slider"/><child link="tool"/><origin xyz="0 0.25 0" rpy="0 0 0"/>
  </joint>
  <link name="tool">
    <visual><geometry><sphere radius="0.02"/></geometry></visual>
  </link>
  <joint name="camera_mount" type="fixed">
    <parent link="shoulder"/><child link="camera"/><origin xyz="0.05 0 0.15" rpy="0 0.5 0"/>
  </joint>
  <link name="camera">
    <visual><origin xyz="0.01 0 0"/><geometry><box size="0.03 0.02 0.02"/></geometry></visual>
  </link>
  <joint name="finger_joint" type="revolute">
    <parent link="upper"/><child link="finger"/><origin xyz="0.1 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <link name="finger">
    <visual><geometry><mesh filename="package://{pkg}/meshes/not_there.stl"/></geometry></visual>
  </link>
</robot>
"""

#: Link of each mesh file in the URDF, and the link whose body (DH link) holds it.
MESH_LINKS = {"base.stl": ("base_link", 0), "shoulder.obj": ("shoulder", 1), "upper.dae": ("upper", 2),
              "adapter_mm.stl": ("adapter", 2), "slider.ply": ("slider", 3)}


def write_arm(tmp_path: Path) -> tuple[Path, dict[str, Path]]:
    """The URDF above in <tmp>/ws/src/meshy_description/urdf/ with its meshes written
    beside it; returns the URDF's path and each mesh file's path."""
    package = tmp_path / "ws" / "src" / PKG
    meshes = {
        "base.stl": write_mesh(package / "meshes" / "base.stl", odd_mesh(1)),
        "shoulder.obj": write_mesh(package / "meshes" / "shoulder.obj", odd_mesh(2)),
        "upper.dae": write_mesh(package / "meshes" / "upper.dae", odd_mesh(3, 0.2)),
        "adapter_mm.stl": write_mesh(package / "meshes" / "adapter_mm.stl", odd_mesh(4, 40.0)),
        "slider.ply": write_mesh(tmp_path / "elsewhere" / "slider.ply", odd_mesh(5)),
    }
    urdf = package / "urdf" / "meshy.urdf"
    urdf.parent.mkdir(parents=True)
    urdf.write_text(URDF.format(pkg=PKG, slider=meshes["slider.ply"]))
    return urdf, meshes


@pytest.fixture
def arm(tmp_path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    return write_arm(tmp_path)


@pytest.mark.parametrize("conv", CONVENTIONS)
def test_every_mesh_is_where_the_urdf_joint_chain_puts_it(arm, conv):
    urdf, files = arm
    robot = load_robot(urdf, tip="tool", convention=conv)
    model = parse(urdf.read_text())
    meshes = {Path(s.path).name: (i, s) for i, shapes in enumerate((robot.base_visuals, *robot.visuals))
              for s in shapes if isinstance(s, Mesh)}
    assert {name: i for name, (i, _) in meshes.items()} == {name: body for name, (_, body) in MESH_LINKS.items()}
    rng = np.random.default_rng(7)
    for q in np.column_stack([rng.uniform(-2, 2, (6, 2)), rng.uniform(0, 0.2, 6)]):
        frames = forward_kinematics(robot, q, all_frames=True)
        for name, (link, _) in MESH_LINKS.items():
            i, shape = meshes[name]
            assert shape.path == str(files[name])
            raw = file_vertices(files[name])  # read by trimesh here, not by the package
            expected = urdf_visual_world(model, link, model.link_map[link].visuals[0], q, raw)
            np.testing.assert_allclose(shape_world(frames[i], shape), expected, atol=1e-9, rtol=0)


def test_mesh_vertices_are_the_files_and_the_scale_is_applied(arm):
    urdf, files = arm
    robot = load_robot(urdf, tip="tool")
    shapes = {Path(s.path).name: s for s in (*robot.base_visuals, *sum(robot.visuals, ())) if isinstance(s, Mesh)}
    for name, path in files.items():
        np.testing.assert_array_equal(shapes[name].faces, trimesh.load(path, force="mesh").faces)
        scale = np.array([0.001, 0.002, 0.001]) if name == "adapter_mm.stl" else np.ones(3)
        np.testing.assert_array_equal(shapes[name].scale, scale)
        np.testing.assert_allclose(shapes[name].vertices, file_vertices(path) * scale, rtol=1e-15, atol=0)
    # the written box is 40 x 24 x 12 (mm), so scaled its x extent is 0.04 m and its y extent 0.048 m
    extent = np.ptp(shapes["adapter_mm.stl"].vertices, axis=0)
    assert 0.04 <= extent[0] < 0.06 and 0.048 <= extent[1] < 0.07


def test_primitives_materials_and_folded_links(arm):
    urdf, _ = arm
    robot = load_robot(urdf, tip="tool")
    model = parse(urdf.read_text())
    frames = forward_kinematics(robot, np.zeros(3), all_frames=True)
    base_box, = robot.base_collisions
    assert isinstance(base_box, Box) and base_box.size.tolist() == [0.2, 0.2, 0.1]
    assert robot.base_visuals[0].color == (0.6, 0.6, 0.65, 1.0)  # top-level material by name
    assert robot.visuals[0][0].color == (0.0, 0.0, 1.0, 1.0)  # inline
    assert robot.visuals[1][0].color == (0.0, 0.0, 1.0, 1.0)  # named inline in an earlier visual
    assert robot.visuals[1][1].color is None
    # link 1: the shoulder's OBJ and the camera box (a fixed joint off the chain); link 3:
    # the slider's PLY and the tool's sphere (fixed after the last joint); no finger
    assert [type(s) for s in robot.visuals[0]] == [Mesh, Box]
    assert [type(s) for s in robot.visuals[2]] == [Mesh, Sphere]
    assert [type(s) for s in robot.collisions[0]] == [Cylinder]
    assert [type(s) for s in robot.collisions[1]] == [Sphere]
    assert robot.collisions[2] == ()
    expected = {  # world pose at q = 0 of each primitive, from the URDF's chain
        (0, "visual", 1): ("camera", model.link_map["camera"].visuals[0]),
        (2, "visual", 1): ("tool", model.link_map["tool"].visuals[0]),
        (0, "collision", 0): ("shoulder", model.link_map["shoulder"].collisions[0]),
        (1, "collision", 0): ("upper", model.link_map["upper"].collisions[0]),
    }
    from urdf_helpers import origin_matrix, urdf_fk
    for (i, kind, k), (link, element) in expected.items():
        shape = (robot.visuals if kind == "visual" else robot.collisions)[i][k]
        want = urdf_fk(model, link, np.zeros(3)) @ origin_matrix(element.origin)
        got = frames[i + 1] @ shape.pose
        if isinstance(shape, Sphere):  # a sphere keeps its centre only
            np.testing.assert_allclose(got[:3, 3], want[:3, 3], atol=1e-12)
        else:
            np.testing.assert_allclose(got, want, atol=1e-12)


def test_ros_package_path_is_searched_first(tmp_path, monkeypatch):
    urdf, files = write_arm(tmp_path)
    other = write_mesh(tmp_path / "overlay" / PKG / "meshes" / "base.stl", odd_mesh(9))
    monkeypatch.setenv("ROS_PACKAGE_PATH", f"{tmp_path / 'nothing'}:{tmp_path / 'overlay'}")
    robot = load_robot(urdf, tip="tool")
    assert robot.base_visuals[0].path == str(other)
    # a package found nowhere but in ROS_PACKAGE_PATH: the URDF outside any package
    lone = tmp_path / "lone.urdf"
    lone.write_text(urdf.read_text().replace("../meshes/shoulder.obj", f"package://{PKG}/meshes/shoulder.obj"))
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "ws" / "src"))
    robot = load_robot(lone, tip="tool")
    assert robot.visuals[0][0].path == str(files["shoulder.obj"])


def test_a_dae_unit_scales_its_vertices(tmp_path):
    dae = write_mesh(tmp_path / "mm.dae", odd_mesh(6, 50.0))
    text = dae.read_text()
    assert "<unit" not in text
    dae.write_text(text.replace("<asset>", '<asset><unit name="millimeter" meter="0.001"/>', 1))
    urdf = tmp_path / "one.urdf"
    urdf.write_text(_one_link_urdf('<mesh filename="mm.dae"/>'))
    shape, = load_robot(urdf).visuals[0]
    np.testing.assert_allclose(shape.vertices, file_vertices(dae) * 0.001, rtol=1e-15)


def _one_link_urdf(geometry: str, link_extra: str = "") -> str:
    return f"""<robot name="one">
  <link name="base"/>
  <joint name="j" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/></joint>
  <link name="arm"><visual><geometry>{geometry}</geometry></visual>{link_extra}</link>
</robot>"""


def _one_line_error(urdf: Path, **kwargs) -> str:
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(urdf, **kwargs)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{urdf}: link 'arm' visual 1 mesh ")
    return message


def test_a_missing_mesh_is_one_error_naming_file_link_and_uri(tmp_path):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(_one_link_urdf('<mesh filename="meshes/gone.stl"/>'))
    message = _one_line_error(urdf)
    assert f"'meshes/gone.stl': {tmp_path / 'meshes' / 'gone.stl'}: mesh file not found" in message
    urdf.write_text(_one_link_urdf('<mesh filename="package://nowhere_pkg/gone.stl"/>'))
    assert "package 'nowhere_pkg' with gone.stl not found in ROS_PACKAGE_PATH" in _one_line_error(urdf)
    urdf.write_text(_one_link_urdf('<mesh filename="https://example.invalid/x.stl"/>'))
    assert "unsupported URI scheme 'https://'" in _one_line_error(urdf)


@pytest.mark.parametrize("name, data, reason", [
    ("bad.stl", b"solid nothing\nendsolid\n", "not a readable .stl mesh: it holds no triangles"),
    ("bad.obj", b"this is not an obj file\n", "not a readable .obj mesh: it holds no triangles"),
    ("bad.ply", b"ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n", "not a readable .ply mesh"),
    ("bad.dae", b"<COLLADA><library_geometries>", "not a readable .dae mesh"),
    ("bad.3ds", b"whatever", "unsupported mesh format '.3ds'; accepted: .stl, .obj, .ply, .dae"),
])
def test_a_corrupt_mesh_is_one_error_naming_the_file(tmp_path, name, data, reason):
    (tmp_path / name).write_bytes(data)
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(_one_link_urdf(f'<mesh filename="{name}"/>'))
    message = _one_line_error(urdf)
    assert f"'{name}': {tmp_path / name}: {reason}" in message


def test_bad_geometry_elements_are_refused(tmp_path):
    urdf = tmp_path / "arm.urdf"
    for geometry, message in [
        ('<box size="1 2"/>', "link 'arm' visual 1 box size: expected 3 finite numbers, got '1 2'"),
        ('<cylinder radius="0.1"/>', "link 'arm' visual 1 cylinder: missing attribute length"),
        ('<sphere radius="-1"/>', "link 'arm' visual 1 sphere: expected lengths > 0 m, got radius='-1'"),
        ('<mesh filename="x.stl" scale="1 0 1"/>', "link 'arm' visual 1 mesh scale: expected scale factors > 0, got '1 0 1'"),
        ("", "link 'arm' visual 1: expected one <geometry> holding one of box, sphere, cylinder, capsule, mesh"),
    ]:
        urdf.write_text(_one_link_urdf(geometry))
        with pytest.raises(RobotDefinitionError) as info:
            load_robot(urdf)
        assert str(info.value) == f"{urdf}: {message}"


def test_skip_missing_meshes_warns_once_per_file_and_keeps_the_rest(tmp_path):
    write_mesh(tmp_path / "ok.stl", odd_mesh(1))
    (tmp_path / "bad.stl").write_bytes(b"")
    collisions = ('<collision><geometry><mesh filename="gone.stl"/></geometry></collision>'
                  '<visual><geometry><mesh filename="gone.stl"/></geometry></visual>'
                  '<visual><geometry><mesh filename="bad.stl"/></geometry></visual>'
                  '<visual><geometry><mesh filename="ok.stl"/></geometry></visual>')
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(_one_link_urdf('<mesh filename="gone.stl"/>', collisions))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = load_robot(urdf, skip_missing_meshes=True)
    messages = [str(w.message) for w in caught if issubclass(w.category, MeshSkippedWarning)]
    assert len(messages) == 2, messages
    assert "gone.stl: mesh file not found; mesh left out" in messages[0]
    assert "bad.stl: not a readable .stl mesh" in messages[1]
    assert [Path(s.path).name for s in robot.visuals[0]] == ["ok.stl"] and robot.collisions[0] == ()


def test_the_command_line_reports_a_missing_mesh_or_skips_it(tmp_path):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(_one_link_urdf('<mesh filename="gone.stl"/>'))
    args = ["--robot", str(urdf), "--print-dh"]
    failed = run(*args, cwd=tmp_path)
    assert failed.returncode == 2 and failed.stdout == ""
    assert failed.stderr.strip().splitlines() == [
        f"robot-sim: error: {urdf}: link 'arm' visual 1 mesh 'gone.stl': {tmp_path / 'gone.stl'}: mesh file not found"
    ]
    skipped = run(*args, "--skip-missing-meshes", cwd=tmp_path)
    assert skipped.returncode == 0, skipped.stderr
    assert skipped.stderr.strip().splitlines() == [
        f"robot-sim: warning: {urdf}: link 'arm' visual 1 mesh 'gone.stl': {tmp_path / 'gone.stl'}: "
        "mesh file not found; mesh left out"
    ]
    assert "one: 1 joints" in skipped.stdout


def test_robots_without_meshes_never_import_trimesh():
    code = ("import sys; from robot_sim.io.robot_file import load_robot; load_robot('puma560'); "
            "load_robot(sys.argv[1]); print('trimesh' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code, str(DATA / "fixed_mid.urdf")],
                         capture_output=True, text=True, cwd=ROOT, timeout=60)
    assert out.stdout.strip() == "False", out.stderr
