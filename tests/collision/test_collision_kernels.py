"""Signed distances between shapes (robot_sim.collision.distance.shape_distance): hand-computed
closed forms, witness points on the surfaces, b = a + d n, minimality certificates against
independent NumPy signed-distance functions, and GJK/EPA (meshes) against the closed forms."""
from __future__ import annotations

import math

import numpy as np
import pytest

from robot_sim.collision.distance import shape_distance
from robot_sim.model.shapes import Box, Capsule, Cylinder, HalfSpace, Mesh, Sphere
from robot_sim.transforms import rot_from_rpy, rot_x, rot_y, rot_z

SQ2 = math.sqrt(2.0)


def pose(xyz=(0.0, 0.0, 0.0), R=np.eye(3)) -> np.ndarray:
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = R, xyz
    return m


def check(a, b, expected: float, tol: float = 1e-12):
    res = shape_distance(a, b)
    assert res.distance == pytest.approx(expected, abs=tol)
    assert np.linalg.norm(res.normal) == pytest.approx(1.0, abs=1e-12)
    assert np.allclose(res.points[1], res.points[0] + res.distance * res.normal, atol=1e-12)
    return res


# ---------------------------------------------------------------- independent signed distances
def sdf(shape, p: np.ndarray) -> np.ndarray:
    """Signed distance of points p (M, 3) to ``shape`` (negative inside), plain NumPy."""
    p = np.atleast_2d(p)
    if isinstance(shape, Sphere):
        return np.linalg.norm(p - shape.center, axis=1) - shape.radius
    local = (p - shape.pose[:3, 3]) @ shape.pose[:3, :3]
    if isinstance(shape, Capsule):
        z = np.clip(local[:, 2], -shape.length / 2, shape.length / 2)
        return np.linalg.norm(local - np.c_[0 * z, 0 * z, z], axis=1) - shape.radius
    if isinstance(shape, Box):
        q = np.abs(local) - shape.half_extents
        return np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0)
    if isinstance(shape, Cylinder):
        q = np.c_[np.hypot(local[:, 0], local[:, 1]) - shape.radius, np.abs(local[:, 2]) - shape.length / 2]
        return np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0)
    raise TypeError(shape)


def inside_points(shape, rng: np.random.Generator, count: int) -> np.ndarray:
    """Points inside ``shape`` (rejection sampling in its bounding box)."""
    size = {Sphere: lambda s: np.full(3, s.radius), Capsule: lambda s: np.array([s.radius, s.radius, s.radius + s.length / 2]),
            Box: lambda s: s.half_extents, Cylinder: lambda s: np.array([s.radius, s.radius, s.length / 2])}[type(shape)](shape)
    centre, R = (shape.center, np.eye(3)) if isinstance(shape, Sphere) else (shape.pose[:3, 3], shape.pose[:3, :3])
    pts = centre + (rng.uniform(-1, 1, (20 * count, 3)) * size) @ R.T
    return pts[sdf(shape, pts) <= 0.0][:count]


# ---------------------------------------------------------------- closed forms
def test_sphere_sphere():
    res = check(Sphere(0.1), Sphere(0.2, (1.0, 2.0, 2.0)), 2.7)
    assert np.allclose(res.points[0], np.array([1, 2, 2]) / 3 * 0.1)
    assert np.allclose(res.points[1], np.array([1, 2, 2]) / 3 * 2.8)
    check(Sphere(0.5), Sphere(0.5, (0.6, 0.0, 0.0)), -0.4)


ALONG_X = rot_y(math.pi / 2)  # a capsule's z axis turned onto x
ALONG_Y = rot_x(-math.pi / 2)  # ... onto y


@pytest.mark.parametrize("a, b, expected", [
    (Capsule(0.1, 1.0), Capsule(0.1, 1.0, pose((0.5, 0.0, 0.3))), 0.3),  # parallel, overlapping spans
    (Capsule(0.1, 1.0), Capsule(0.1, 1.0, pose((0.3, 0.0, 1.5))), math.hypot(0.3, 0.5) - 0.2),  # parallel, end to end
    (Capsule(0.1, 1.0, pose(R=ALONG_X)), Capsule(0.1, 1.0, pose(R=ALONG_Y)), -0.2),  # axes cross: depth r1 + r2
    (Capsule(0.1, 1.0, pose(R=ALONG_X)), Capsule(0.2, 1.0, pose((0.0, 0.0, 0.7), ALONG_Y)), 0.4),  # skew, interiors
    (Capsule(0.1, 1.0, pose(R=ALONG_X)), Capsule(0.1, 1.0, pose((2.0, 0.0, 1.0), ALONG_Y)),
     math.hypot(1.5, 1.0) - 0.2),  # skew, clamped at an end
])
def test_capsule_capsule(a, b, expected):
    res = check(a, b, expected)
    if expected < 0:  # crossing axes separate fastest perpendicular to both
        assert abs(res.normal @ a.pose[:3, 2]) < 1e-12 and abs(res.normal @ b.pose[:3, 2]) < 1e-12
    else:
        assert abs(sdf(a, res.points[0])[0]) < 1e-12 and abs(sdf(b, res.points[1])[0]) < 1e-12


@pytest.mark.parametrize("capsule, expected", [
    (Capsule(0.1, 0.6, pose((0.0, 0.0, 1.0), ALONG_X)), 0.4),  # face region
    (Capsule(0.1, 0.6, pose((1.0, 0.0, 1.0), ALONG_Y)), math.sqrt(0.5) - 0.1),  # edge region
    (Capsule(0.1, 0.6, pose((0.0, 0.8, 0.8), ALONG_X)), 0.3 * SQ2 - 0.1),  # over an edge, parallel
    (Capsule(0.1, SQ2, pose((1.5, 1.5, 1.0))), SQ2 - 0.1),  # beside a vertical edge, spans overlapping
    (Capsule(0.1, 0.6, pose((0.0, 0.0, 0.6))), -0.3),  # enters through the top face: push 0.2 up, + r
    (Capsule(0.1, 0.2, pose((0.4, 0.0, 0.0), ALONG_X)), -0.3),  # half inside: push 0.2 out along x
])
def test_capsule_box(capsule, expected):
    res = check(capsule, Box((1.0, 1.0, 1.0)), expected)
    assert abs(sdf(Box((1.0, 1.0, 1.0)), res.points[1])[0]) < 1e-12  # the box's witness is on its surface
    if expected > 0:
        assert abs(sdf(capsule, res.points[0])[0]) < 1e-12


def test_capsule_box_vertex_region_hand_computed():
    """Core from (1, 1, 1) outward along (1, 1, 1): closest to the corner (0.5, 0.5, 0.5)."""
    u = np.ones(3) / math.sqrt(3)
    R = np.column_stack([np.cross([0, 0, 1.0], u) / np.linalg.norm(np.cross([0, 0, 1.0], u)), np.zeros(3), u])
    R[:, 1] = np.cross(R[:, 2], R[:, 0])
    capsule = Capsule(0.1, 1.0, pose(np.ones(3) + 0.5 * u, R))
    res = check(capsule, Box((1.0, 1.0, 1.0)), 0.5 * math.sqrt(3) - 0.1)
    assert np.allclose(res.points[1], [0.5, 0.5, 0.5])


@pytest.mark.parametrize("b, expected", [
    (Box((1.0, 1.0, 1.0), pose((2.0, 0.0, 0.0))), 1.0),  # face to face
    (Box((1.0, 1.0, 1.0), pose((2.0, 0.0, 0.0), rot_z(math.pi / 4))), 1.5 - SQ2 / 2),  # vertex edge to face
    (Box((1.0, 1.0, 1.0), pose((0.8, 0.1, 0.0))), -0.2),  # overlap along x
])
def test_box_box(b, expected):
    check(Box((1.0, 1.0, 1.0)), b, expected, tol=1e-10)


def test_box_box_crossed_edges():
    """A's top is an edge along y (turned 45° about y), B's bottom an edge along x (45°
    about x): the edges cross above the origin, √2/2 from each centre."""
    a = Box((1.0, 1.0, 1.0), pose(R=rot_y(math.pi / 4)))
    b = Box((1.0, 1.0, 1.0), pose((0.0, 0.0, 2.0), rot_x(math.pi / 4)))
    res = check(a, b, 2.0 - SQ2, tol=1e-10)
    assert np.allclose(res.points, [[0, 0, SQ2 / 2], [0, 0, 2 - SQ2 / 2]], atol=1e-9)
    lowered = Box((1.0, 1.0, 1.0), pose((0.0, 0.0, 1.3), rot_x(math.pi / 4)))
    check(a, lowered, 1.3 - SQ2, tol=1e-10)  # the same edges overlap by √2 - 1.3


@pytest.mark.parametrize("sphere, expected", [
    (Sphere(0.1, (0.5, 0.0, 0.0)), 0.2),  # beside the wall
    (Sphere(0.1, (0.5, 0.0, 0.8)), math.hypot(0.3, 0.3) - 0.1),  # beyond the rim
    (Sphere(0.1, (0.0, 0.1, 0.9)), 0.3),  # above the cap
    (Sphere(0.1, (0.1, 0.0, 0.0)), -0.2),  # centre inside, nearer the wall (0.1) than the caps
    (Sphere(0.1, (0.0, 0.0, 0.45)), -0.15),  # centre inside, nearer the cap
])
def test_sphere_cylinder(sphere, expected):
    check(sphere, Cylinder(0.2, 1.0), expected)


@pytest.mark.parametrize("shape, expected", [
    (Capsule(0.1, 1.0, pose((0.0, 0.0, 1.0), rot_x(math.pi / 2))), 0.9),
    (Capsule(0.1, 1.0, pose((0.0, 0.0, 0.3))), -0.3),
    (Box((1.0, 1.0, 1.0), pose((0.0, 0.0, 1.0), rot_x(math.pi / 4))), 1.0 - SQ2 / 2),
    (Cylinder(0.2, 1.0, pose((0.0, 0.0, 1.0))), 0.5),
    (Cylinder(0.2, 1.0, pose((0.0, 0.0, 1.0), rot_x(math.pi / 2))), 0.8),
    (Sphere(0.3, (1.0, 2.0, 0.1)), -0.2),
])
def test_half_space(shape, expected):
    res = check(shape, HalfSpace(), expected, tol=1e-10)
    assert res.points[1][2] == pytest.approx(0.0, abs=1e-12)  # the floor's witness is on z = 0
    assert np.allclose(res.normal, [0, 0, -1])
    swapped = check(HalfSpace(), shape, expected, tol=1e-10)
    assert np.allclose(swapped.points, res.points[::-1])


def test_tilted_half_space():
    h = HalfSpace((1.0, 0.0, 1.0), 0.0)  # {x + z <= 0}
    check(Sphere(0.1, (1.0, 0.0, 1.0)), h, SQ2 - 0.1)


# ---------------------------------------------------------------- certificates on random pairs
KINDS = ("sphere", "capsule", "box", "cylinder")


def random_shape(kind: str, rng: np.random.Generator):
    R = rot_from_rpy(rng.uniform(-math.pi, math.pi, 3))
    xyz = rng.uniform(-0.3, 0.3, 3)
    if kind == "sphere":
        return Sphere(rng.uniform(0.05, 0.3), xyz)
    if kind == "capsule":
        return Capsule(rng.uniform(0.05, 0.2), rng.uniform(0.0, 0.6), pose(xyz, R))
    if kind == "box":
        return Box(rng.uniform(0.05, 0.6, 3), pose(xyz, R))
    return Cylinder(rng.uniform(0.05, 0.3), rng.uniform(0.05, 0.6), pose(xyz, R))


@pytest.mark.parametrize("ka", KINDS)
@pytest.mark.parametrize("kb", KINDS)
def test_random_pairs_witnesses_and_minimality(ka, kb):
    """Apart: both witness points lie on their surfaces, the distance is the other
    shape's signed distance at the witness, and no point inside the first shape is
    nearer the second.  Overlapping: moving the first shape back along the normal by the
    depth separates them, by less does not."""
    rng = np.random.default_rng(4 * KINDS.index(ka) + KINDS.index(kb))
    seen = {True: 0, False: 0}
    for _ in range(40):
        a, b = random_shape(ka, rng), random_shape(kb, rng)
        res = shape_distance(a, b)
        d, (pa, pb), n = res.distance, res.points, res.normal
        assert np.allclose(pb, pa + d * n, atol=1e-12) and abs(np.linalg.norm(n) - 1.0) < 1e-12
        if d > 1e-9:
            seen[True] += 1
            assert abs(sdf(a, pa)[0]) < 1e-8 and abs(sdf(b, pb)[0]) < 1e-8
            assert sdf(b, pa)[0] == pytest.approx(d, abs=1e-8)
            assert sdf(b, inside_points(a, rng, 300)).min() >= d - 1e-9
        elif d < -1e-9:
            seen[False] += 1
            for shift, apart in ((-d + 1e-7, True), (-d - 1e-7, False)):
                moved = a.moved(pose(-shift * n))
                assert (shape_distance(moved, b).distance > 0.0) == apart, (a, b, d)
    assert seen[True] and seen[False]  # both regimes were exercised


# ---------------------------------------------------------------- GJK / EPA against closed forms
def cube_mesh(size) -> Mesh:
    h = np.asarray(size, dtype=float) / 2
    v = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * h
    faces = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return Mesh((v, faces))


def test_mesh_is_its_hull_gjk_epa_match_closed_forms():
    """A box given as a mesh goes through GJK (apart) and EPA (overlapping); a Box through
    the closed forms: the same distances, apart and in penetration."""
    rng = np.random.default_rng(7)
    for k in range(200):
        size = rng.uniform(0.1, 0.6, 3)
        P = pose(rng.uniform(-0.2, 0.2, 3), rot_from_rpy(rng.uniform(-3, 3, 3)))
        other = random_shape(("sphere", "capsule", "box")[k % 3], rng)
        exact = shape_distance(Box(size, P), other).distance
        hull = shape_distance(cube_mesh(size).moved(P), other).distance
        assert hull == pytest.approx(exact, abs=1e-9), (k, exact, hull)


def test_two_half_spaces_are_not_a_pair():
    assert shape_distance(HalfSpace(), HalfSpace((0, 0, -1))).distance == math.inf
