"""Shape data (robot_sim.model.shapes): validation, immutability, poses and ``moved``."""
from __future__ import annotations

import math

import numpy as np
import pytest

import robot_sim.io.meshes  # noqa: F401  installs the one mesh-file reader Mesh(path) uses
from robot_sim.model.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Sphere


def _tf(rpy=(0.3, -0.2, 1.1), xyz=(0.1, -0.4, 0.7)) -> np.ndarray:
    r, p, y = rpy
    rx = np.array([[1, 0, 0], [0, math.cos(r), -math.sin(r)], [0, math.sin(r), math.cos(r)]])
    ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    rz = np.array([[math.cos(y), -math.sin(y), 0], [math.sin(y), math.cos(y), 0], [0, 0, 1]])
    m = np.eye(4)
    m[:3, :3] = rz @ ry @ rx
    m[:3, 3] = xyz
    return m


TETRA = (np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float),
         np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]))


def test_defaults_and_fields():
    b = Box((0.1, 0.2, 0.3))
    assert np.array_equal(b.pose, np.eye(4)) and np.allclose(b.half_extents, (0.05, 0.1, 0.15))
    s = Sphere(0.2, (1, 2, 3))
    assert np.array_equal(s.pose[:3, 3], (1, 2, 3)) and np.array_equal(s.pose[:3, :3], np.eye(3))
    assert Sphere(0.1).center.tolist() == [0, 0, 0]
    h = HalfSpace()
    assert h.normal.tolist() == [0, 0, 1] and h.offset == 0.0
    assert Capsule(0.1, 0.0).length == 0.0  # a zero-length capsule is a sphere
    assert Box((1, 1, 1), color=(1, 0, 0)).color == (1.0, 0.0, 0.0, 1.0)


def test_arrays_are_read_only_and_fields_frozen():
    b = Box((0.1, 0.2, 0.3), pose=_tf())
    for arr in (b.size, b.pose, Sphere(0.1, (1, 2, 3)).center, HalfSpace().normal, Mesh(TETRA).vertices):
        with pytest.raises(ValueError):
            arr[0] = 5.0
    with pytest.raises(AttributeError):
        b.size = np.ones(3)  # type: ignore[misc]


def test_inputs_are_copied():
    size = np.array([0.1, 0.2, 0.3])
    b = Box(size)
    size[0] = 9.0
    assert b.size[0] == 0.1


@pytest.mark.parametrize("make, field", [
    (lambda: Box((0.1, -0.2, 0.3)), "Box.size"),
    (lambda: Box((0.1, 0.2)), "Box.size"),
    (lambda: Box((0.1, 0.2, 0.3), pose=np.diag([2.0, 1, 1, 1])), "Box.pose"),
    (lambda: Box((0.1, 0.2, 0.3), pose=np.eye(3)), "Box.pose"),
    (lambda: Sphere(0.0), "Sphere.radius"),
    (lambda: Sphere(float("nan")), "Sphere.radius"),
    (lambda: Sphere(0.1, (0, 0)), "Sphere.center"),
    (lambda: Cylinder(0.1, 0.0), "Cylinder.length"),
    (lambda: Capsule(-0.1, 0.2), "Capsule.radius"),
    (lambda: Capsule(0.1, "long"), "Capsule.length"),
    (lambda: HalfSpace((0, 0, 0)), "HalfSpace.normal"),
    (lambda: HalfSpace(offset=float("inf")), "HalfSpace.offset"),
    (lambda: Box((1, 1, 1), color=(1, 0, 2)), "Box.color"),
    (lambda: Mesh(42), "Mesh.source"),
    (lambda: Mesh((TETRA[0], TETRA[1] + 2)), "Mesh.source"),
    (lambda: Mesh((TETRA[0][:, :2], TETRA[1])), "Mesh.source"),
    (lambda: Mesh(TETRA, scale=(1, 0, 1)), "Mesh.scale"),
])
def test_bad_input_names_the_field(make, field):
    with pytest.raises(ValueError, match=field.replace(".", r"\.")):
        make()


def test_moved_composes_poses():
    tf, base = _tf(), _tf((0.5, 0.1, -0.3), (0.0, 0.2, 0.0))
    for shape in (Box((0.1, 0.2, 0.3), base), Cylinder(0.1, 0.3, base), Capsule(0.1, 0.3, base), Mesh(TETRA, base)):
        moved = shape.moved(tf)
        assert type(moved) is type(shape)
        assert np.allclose(moved.pose, tf @ base)
        assert np.array_equal(shape.pose, base)  # the original is untouched
    s = Sphere(0.2, (0.1, 0.2, 0.3)).moved(tf)
    assert np.allclose(s.center, (tf @ [0.1, 0.2, 0.3, 1.0])[:3]) and s.radius == 0.2
    with pytest.raises(ValueError, match="moved"):
        Box((1, 1, 1)).moved(np.diag([1.0, 1, 2, 1]))


def test_half_space_moved_maps_points():
    """A point inside (normal·x <= offset) stays inside after both move by tf, and a
    point on the boundary stays on it."""
    h = HalfSpace((0, 1, 1), 0.3)
    assert np.isclose(np.linalg.norm(h.normal), 1.0) and np.isclose(h.offset, 0.3 / math.sqrt(2))
    tf = _tf()
    hm = h.moved(tf)
    rng = np.random.default_rng(0)
    for x in rng.normal(size=(20, 3)):
        xm = (tf @ np.append(x, 1.0))[:3]
        assert np.isclose(h.normal @ x - h.offset, hm.normal @ xm - hm.offset)
    # pose: origin on the plane, z along the normal, rigid
    p = hm.pose
    assert np.isclose(hm.normal @ p[:3, 3], hm.offset) and np.allclose(p[:3, 2], hm.normal)
    assert np.allclose(p[:3, :3].T @ p[:3, :3], np.eye(3)) and np.isclose(np.linalg.det(p[:3, :3]), 1.0)


def test_capsule_endpoints_along_pose_z():
    tf = _tf()
    ends = Capsule(0.05, 0.4, tf).endpoints
    assert np.allclose(ends[1] - ends[0], 0.4 * tf[:3, 2]) and np.allclose(ends.mean(axis=0), tf[:3, 3])


def test_mesh_from_arrays_scaled_and_path_none():
    m = Mesh(TETRA, scale=(2, 3, 4))
    assert m.path is None
    assert np.allclose(m.vertices, TETRA[0] * (2, 3, 4)) and np.array_equal(m.faces, TETRA[1])


def test_mesh_file_read_once_and_kept_by_moved(tmp_path):
    trimesh = pytest.importorskip("trimesh")  # mesh files are read through trimesh (issue 15)
    path = tmp_path / "t.stl"
    trimesh.Trimesh(*TETRA).export(path)
    m = Mesh(path, scale=(2, 2, 2))
    assert m.path == str(path)
    assert np.allclose(np.sort(m.vertices, axis=0), np.sort(TETRA[0] * 2, axis=0))
    path.unlink()  # already read: moving the shape does not read the file again
    assert np.allclose(m.moved(_tf()).vertices, m.vertices)


def test_mesh_missing_file_error():
    pytest.importorskip("trimesh")
    with pytest.raises(ValueError, match="mesh file not found"):
        Mesh("/nonexistent/part.stl").vertices


def test_equality_and_hash_by_value():
    assert Box((1, 2, 3), _tf()) == Box(np.array([1.0, 2, 3]), _tf())
    assert Box((1, 2, 3)) != Box((1, 2, 4))
    assert Box((1, 2, 3)) != Cylinder(1, 2)
    assert len({Sphere(0.1), Sphere(0.1), Sphere(0.2)}) == 2
    assert Mesh(TETRA) == Mesh(TETRA)
