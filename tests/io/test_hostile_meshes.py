"""Issue 31, mesh files: one reader for URDFs, robot files and world files, with an
allow-list of formats, a byte cap, declared counts checked against the file size, a
cache of results and failures, and errors that never quote the file."""
from __future__ import annotations

import struct
import subprocess
import sys
import warnings

import numpy as np
import pytest

import robot_sim.io.meshes as meshes
from robot_sim.model.shapes import Mesh
from robot_sim.model.world import World
from robot_sim.io.robot_file import load_robot
from robot_sim.io.world_file import WorldDefinitionError, load_world
from robot_sim.model.params import RobotDefinitionError

SECRET = "SECRET-" + "x" * 300

URDF = """<robot name="r">
  <link name="base"/>
  <link name="l1">{visuals}</link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def _urdf(tmp_path, *filenames):
    visuals = "".join(f'<visual><geometry><mesh filename="{f}"/></geometry></visual>' for f in filenames)
    path = tmp_path / "r.urdf"
    path.write_text(URDF.format(visuals=visuals))
    return path


def _world(tmp_path, mesh, count=1):
    text = "".join(f'[[obstacles]]\nname = "m{k}"\nshape = "mesh"\nmesh = "{mesh}"\nxyz = [{k}, 0, 0]\n'
                   for k in range(count))
    path = tmp_path / "world.toml"
    path.write_text(text)
    return path


def _tetra_stl(path):
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float32)
    faces = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
    body = b"".join(struct.pack("<12fH", 0, 0, 0, *v[a], *v[b], *v[c], 0) for a, b, c in faces)
    path.write_bytes(b"\0" * 80 + struct.pack("<I", len(faces)) + body)
    return path


@pytest.fixture(autouse=True)
def _fresh_cache():
    meshes._CACHE.clear()
    getattr(meshes, "_FAILED", {}).clear()
    yield
    meshes._CACHE.clear()
    getattr(meshes, "_FAILED", {}).clear()


def test_file_uri_mesh_in_a_urdf_never_quotes_the_file(tmp_path):
    bad = tmp_path / "x.ply"
    bad.write_text(f"ply\nformat ascii 1.0\nelement vertex {SECRET}\nend_header\n")
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(_urdf(tmp_path, f"file://{bad}"))
    message = str(info.value)
    assert "SECRET" not in message and "\n" not in message
    assert f"{bad}: not a readable .ply mesh: a PLY element line is not" in message


def test_parser_message_is_never_quoted_only_its_kind(tmp_path):
    bad = tmp_path / "x.obj"
    bad.write_text(f"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 {SECRET}\n")
    with pytest.raises(WorldDefinitionError) as info:
        load_world(_world(tmp_path, bad))
    assert "SECRET" not in str(info.value)
    assert str(info.value).endswith(f"obstacles[0].mesh: {bad}: not a readable .obj mesh: the parser failed (ValueError)")


@pytest.mark.parametrize("suffix", [".off", ".zip", ".tar.gz", ".xyz", ".glb", ".dxf"])
def test_world_mesh_formats_are_allow_listed(tmp_path, suffix):
    other = tmp_path / f"x{suffix}"
    other.write_text(SECRET)
    with pytest.raises(WorldDefinitionError) as info:
        load_world(_world(tmp_path, other))
    assert str(info.value).endswith(
        f"unsupported mesh format '{other.suffix}'; accepted: .stl, .obj, .ply, .dae")


def test_world_mesh_over_the_byte_cap_is_refused_before_reading(tmp_path):
    big = tmp_path / "big.stl"
    with open(big, "wb") as f:  # sparse: no disk used
        f.truncate(meshes.MAX_MESH_BYTES + 1)
    with pytest.raises(WorldDefinitionError, match=f"big.stl: it is larger than {meshes.MAX_MESH_BYTES} bytes"):
        load_world(_world(tmp_path, big))


def test_binary_stl_count_is_checked_against_the_file_size(tmp_path, monkeypatch):
    monkeypatch.setattr("trimesh.load", lambda *a, **k: pytest.fail("parsed a file whose count cannot fit"))
    stl = tmp_path / "x.stl"
    stl.write_bytes(b"\0" * 80 + struct.pack("<I", 10 ** 9) + b"\0" * 100)
    with pytest.raises(WorldDefinitionError, match="do not match the header's count of 1000000000 triangles"):
        load_world(_world(tmp_path, stl))


def test_ply_counts_are_checked_against_the_file_size(tmp_path, monkeypatch):
    monkeypatch.setattr("trimesh.load", lambda *a, **k: pytest.fail("parsed a file whose count cannot fit"))
    ply = tmp_path / "x.ply"
    ply.write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 100000000\nproperty float x\n"
                    b"property float y\nproperty float z\nend_header\n" + b"\0" * 120)
    with pytest.raises(WorldDefinitionError, match="declares elements of at least 1200000000 bytes"):
        load_world(_world(tmp_path, ply))


def test_thousand_obstacles_of_one_mesh_parse_it_once_and_share_it(tmp_path, monkeypatch):
    calls = []
    parse = meshes.parse_mesh
    monkeypatch.setattr(meshes, "parse_mesh", lambda raw, suffix: calls.append(suffix) or parse(raw, suffix))
    stl = _tetra_stl(tmp_path / "part.stl")
    world = load_world(_world(tmp_path, stl, count=1000))
    shapes = [world[f"m{k}"] for k in range(1000)]
    assert len(shapes) == 1000 and calls == [".stl"]
    assert all(np.shares_memory(s.data[0], shapes[0].data[0]) for s in shapes)
    from robot_sim.collision.checker import CollisionChecker

    robot = load_robot("planar3")
    checker = CollisionChecker(robot, world)  # the collision scene packs them once too
    assert checker.scene.verts.shape == (4, 3)
    v, f = shapes[0].data  # the oracle: a world of the same obstacles, each with its own copy
    copies = World([(f"m{k}", Mesh((v.copy(), f.copy()), pose=s.pose)) for k, s in enumerate(shapes)])
    oracle = CollisionChecker(robot, copies)
    for q in (np.zeros(3), np.array([0.4, -0.3, 0.2]), np.array([2.0, 1.0, -1.0])):
        assert checker.distance(q).distance == pytest.approx(oracle.distance(q).distance, abs=1e-12)


def test_an_unreadable_mesh_named_by_many_visuals_is_read_once(tmp_path, monkeypatch):
    calls = []
    monkeypatch.setattr(meshes, "read_regular_file", lambda p, n: calls.append(p) or b"\0" * 200)
    urdf = _urdf(tmp_path, *["broken.stl"] * 30)
    (tmp_path / "broken.stl").write_bytes(b"\0" * 200)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = load_robot(urdf, skip_missing_meshes=True)
    assert len(calls) == 1 and len(caught) == 1 and robot.visuals == ((),)


OBJ_WITH_UV = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n" \
              "f 1/1 3/3 2/2\nf 1/1 2/2 4/4\nf 1/1 4/4 3/3\nf 2/2 3/3 4/4\n"


OBJ_PROBE = """
import sys
sys.modules["PIL"] = None  # Pillow missing: importing it raises ImportError
import numpy as np
from robot_sim.io.robot_file import load_robot
from robot_sim.io.world_file import load_world
(mesh,) = load_robot(sys.argv[1]).visuals[0]
for shape in (mesh, load_world(sys.argv[2])["m0"]):
    tri = shape.vertices[shape.faces]
    print(abs(np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum()) / 6)
"""


def test_obj_with_texture_coordinates_loads_without_pillow(tmp_path):
    """Pillow is not a dependency: an OBJ's texture coordinates must not need it."""
    obj = tmp_path / "part.obj"
    obj.write_text(OBJ_WITH_UV)
    urdf, world = _urdf(tmp_path, "part.obj"), _world(tmp_path, obj)
    out = subprocess.run([sys.executable, "-c", OBJ_PROBE, str(urdf), str(world)],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-500:]
    assert [float(v) for v in out.stdout.split()] == pytest.approx([1 / 6, 1 / 6])  # the tetrahedron's volume


def test_long_mesh_path_is_cut_in_the_middle(tmp_path):
    deep = tmp_path / ("d" * 200) / ("e" * 200) / ("f" * 200)
    path = f"{deep}/missing.stl"
    with pytest.raises(WorldDefinitionError) as info:
        load_world(_world(tmp_path, path))
    tail = str(info.value).split("obstacles[0].mesh: ", 1)[1]
    assert tail.endswith("f/missing.stl: mesh file not found") and len(tail) < 200
