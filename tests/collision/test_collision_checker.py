"""CollisionChecker: batched == single, distances against an independent recomputation from
shapes(q), allowed pairs (adjacent, always touching, the robot file's [collision] table),
padding, IK with a checker and continuous path checks."""
from __future__ import annotations

import math

import numpy as np
import pytest

from robot_sim.collision import Box, Capsule, CollisionChecker, Cylinder, Sphere, World
from robot_sim.collision.allowed import adjacent_pairs, sample_configurations
from robot_sim.collision.capsules import dh_capsules
from robot_sim.io.robot_file import load_robot
from robot_sim.kinematics import forward_kinematics, solve_ik
from robot_sim.model.params import RobotDefinitionError
from robot_sim.model.shapes import HalfSpace
from robot_sim.transforms import rot_z

ARMS = ("ur5", "panda", "puma560", "gen3", "stanford", "kr6_r900")


def at(xyz) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = xyz
    return m


def obstacles(rng: np.random.Generator, count: int = 8) -> World:
    items = {}
    for k in range(count):
        xyz = rng.uniform([-0.7, -0.7, 0.05], [0.7, 0.7, 0.9])
        kind = k % 4
        items[f"o{k}"] = (Box(rng.uniform(0.05, 0.25, 3), at(xyz)) if kind == 0 else
                          Sphere(rng.uniform(0.03, 0.12), xyz) if kind == 1 else
                          Cylinder(rng.uniform(0.03, 0.1), rng.uniform(0.05, 0.3), at(xyz)) if kind == 2 else
                          Capsule(rng.uniform(0.03, 0.1), rng.uniform(0.05, 0.3), at(xyz)))
    return World(items)


# ---------------------------------------------------------------- segment distance oracle
def _point_segment(p, a, b):
    u = b - a
    t = np.clip(((p - a) @ u) / max(u @ u, 1e-300), 0.0, 1.0)
    return np.linalg.norm(p - (a + t * u))


def segment_distance(a0, a1, b0, b1) -> float:
    """Distance between two segments by golden-section search over the first segment's
    parameter (the distance to the second segment is convex along it): no shared code."""
    f = lambda s: _point_segment(a0 + s * (a1 - a0), b0, b1)  # noqa: E731
    lo, hi = 0.0, 1.0
    g = (math.sqrt(5) - 1) / 2
    for _ in range(80):
        x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
        if f(x1) < f(x2):
            hi = x2
        else:
            lo = x1
    return min(f(0.5 * (lo + hi)), f(0.0), f(1.0))


def capsule_ends(c: Capsule):
    z, mid = c.pose[:3, 2], c.pose[:3, 3]
    return mid - 0.5 * c.length * z, mid + 0.5 * c.length * z


@pytest.mark.parametrize("name", ARMS)
def test_self_and_floor_distances_match_an_independent_recomputation(name):
    """The capsule arm's smallest distance over its checked pairs, recomputed from
    shapes(q) with the golden-section segment oracle (floor: lowest cap point)."""
    robot = load_robot(name)
    checker = CollisionChecker(robot)
    for q in sample_configurations(robot, 25, seed=3):
        shapes = checker.shapes(q)
        best = math.inf
        for i, (na, a) in enumerate(shapes):
            for nb, b in shapes[i + 1:]:
                if na != nb and (na, nb) not in checker.allowed:
                    best = min(best, segment_distance(*capsule_ends(a), *capsule_ends(b)) - a.radius - b.radius)
            if (na, "floor") not in checker.allowed:
                best = min(best, min(p[2] for p in capsule_ends(a)) - a.radius)
        res = checker.distance(q)
        assert res.distance == pytest.approx(best, abs=1e-9)
        assert checker.in_collision(q) == (best < 0.0)
        assert res.pair not in checker.allowed


@pytest.mark.parametrize("name", ("ur5", "panda"))
def test_batched_results_equal_single_ones(name):
    robot = load_robot(name)
    checker = CollisionChecker(robot, obstacles(np.random.default_rng(2)))
    Q = sample_configurations(robot, 300, seed=5)
    hit, dist = checker.in_collision(Q), checker.distance(Q)
    assert hit.dtype == bool and hit.shape == (300,) and dist.shape == (300,)
    assert 0 < hit.sum() < 300  # both outcomes occur
    for k in range(0, 300, 7):
        assert checker.in_collision(Q[k]) is bool(hit[k])
        assert checker.distance(Q[k]).distance == dist[k]
    assert np.array_equal(hit, dist < 0.0)


def test_distance_result_fields():
    robot = load_robot("ur5")
    tool = forward_kinematics(robot, robot.q_home)[:3, 3]
    world = World({"ball": Sphere(0.05, tool + (0.0, 0.0, 0.15))}, floor=False)
    checker = CollisionChecker(robot, world, self_collision=False)
    res = checker.distance(robot.q_home)
    assert res.pair[1] == "ball"
    assert res.points.shape == (2, 3) and res.normal.shape == (3,)
    assert np.allclose(res.points[1], res.points[0] + res.distance * res.normal)
    assert np.linalg.norm(res.points[1] - world["ball"].center) == pytest.approx(0.05)


def test_adjacent_pairs_are_allowed_and_an_allowed_overlap_is_not_a_collision():
    robot = load_robot("puma560")
    checker = CollisionChecker(robot)
    for a, b in adjacent_pairs(robot):
        assert (a, b) in checker.allowed and (b, a) in checker.allowed
    assert ("link1", "floor") in checker.allowed  # turns on the floor it stands on: always touching
    # links 2 and 3 overlap at their shared joint in every pose; that never counts
    shapes = dict((n, s) for n, s in checker.shapes(robot.q_home))
    assert not checker.in_collision(robot.q_home)
    assert all(pair not in checker.allowed for pair in checker.checked_pairs)


def test_always_touching_pairs_found_by_sampling():
    """iiwa14's links 2, 4, 6 have no length: links 1 and 3 meet at joint 2 in every
    configuration, and so do 3-5 and 5-7; 1 and 5 do not."""
    checker = CollisionChecker(load_robot("iiwa14"), World(floor=False))
    for pair in (("link1", "link3"), ("link3", "link5"), ("link5", "link7")):
        assert pair in checker.allowed
    assert ("link1", "link5") in checker.checked_pairs


def test_self_collision_flag_and_padding():
    robot = load_robot("ur5")
    with_self = CollisionChecker(robot, World(floor=False))
    without = CollisionChecker(robot, World(floor=False), self_collision=False)
    Q = sample_configurations(robot, 400, seed=8)
    hit = with_self.in_collision(Q)
    assert hit.any() and not without.in_collision(Q).any()
    assert without.distance(Q[0]).distance == math.inf and without.distance(Q[0]).pair is None
    assert ("link1", "link3") in without.allowed and not without.checked_pairs
    # padding: in collision exactly when a checked pair is closer than the padding
    padded = CollisionChecker(robot, World(floor=False), padding=0.02)
    near = padded.in_collision(Q)
    assert np.array_equal(near, padded.distance(Q) < 0.02)
    assert (near & ~hit).any()  # some configurations are only within the padding


@pytest.mark.parametrize("bad, match", [
    (dict(padding=-0.1), "padding"), (dict(padding=float("nan")), "padding"),
    (dict(self_collision=1), "self_collision"), (dict(world="floor"), "world"),
])
def test_checker_arguments_are_validated(bad, match):
    with pytest.raises(ValueError, match=match):
        CollisionChecker(load_robot("ur5"), **bad)


def test_bad_configurations_are_rejected():
    checker = CollisionChecker(load_robot("ur5"))
    for q in (np.zeros(5), np.full(6, np.nan), np.zeros((2, 3))):
        with pytest.raises(ValueError, match="q"):
            checker.in_collision(q)


def test_world_names_and_floor():
    w = World({"box": Box((1, 1, 1))})
    assert w.names == ("floor", "box") and isinstance(w["floor"], HalfSpace)
    assert World([("box", Box((1, 1, 1)))], floor=False).names == ("box",)
    with pytest.raises(ValueError, match="twice"):
        World({"floor": Box((1, 1, 1))})
    with pytest.raises(ValueError, match="Box, Sphere"):
        World({"x": "box"})


# ---------------------------------------------------------------- the robot file's [collision] table
def robot_text(extra: str) -> str:
    top, _, tables = extra.rpartition("@")  # text before "@" goes above the joint tables
    return ('name = "two"\nunits = "deg"\n' + top +
            '[[joints]]\ntype = "revolute"\na = 0.5\nalpha = 0\nd = 0.3\ntheta = 0\n'
            '[[joints]]\ntype = "revolute"\na = 0.5\nalpha = 0\nd = 0\ntheta = 0\n' + tables)


def test_collision_allow_table_is_read_and_used(tmp_path):
    path = tmp_path / "two.toml"
    path.write_text(robot_text('[collision]\nallow = [["base", "link2"], ["link2", "link1"]]\n'))
    robot = load_robot(path)
    assert robot.collision_allow == (("base", "link2"), ("link2", "link1"))
    assert ("link2", "base") in CollisionChecker(robot).allowed


@pytest.mark.parametrize("table, fragment", [
    ('[collision]\nallow = [["link2", "link9"]]\n', "collision.allow[0]: unknown link 'link9'; accepted link names: base, link1, link2"),
    ('[collision]\nallow = [["link2"]]\n', "collision.allow[0]: expected a pair of link names"),
    ('[collision]\nallow = [["link1", "link1"]]\n', "collision.allow[0]: a link is never checked against itself"),
    ('[collision]\nallow = "link1 link2"\n', "collision.allow: expected a list of [link, link] pairs"),
    ('[collision]\nalow = []\n', "collision.alow: unknown key 'alow'; accepted keys: allow"),
    ('collision = 3\n@', "collision: expected a table with key allow"),
    ('[collision]\nallow = [[1, "link2"]]\n', "collision.allow[0]: unknown link 1"),
])
def test_collision_table_is_validated(tmp_path, table, fragment):
    path = tmp_path / "two.toml"
    path.write_text(robot_text(table))
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    assert str(info.value).startswith(f"{path}: ") and fragment in str(info.value)


def test_collision_table_is_written_back(tmp_path):
    from robot_sim.io.robot_writer import to_toml
    from robot_sim.io.robot_file import parse_robot
    import tomllib
    path = tmp_path / "two.toml"
    text = robot_text('[collision]\nallow = [["base", "link2"]]\n')
    path.write_text(text)
    robot = load_robot(path)
    assert parse_robot(tomllib.loads(to_toml(robot)), path).collision_allow == (("base", "link2"),)
    assert to_toml(robot, text) == text  # unchanged table kept as written


# ---------------------------------------------------------------- DH capsules
@pytest.mark.parametrize("name", ("ur5", "panda", "stanford", "scara"))
def test_dh_capsules_follow_the_dh_segments(name):
    """Every DH segment of the drawn chain (graphics' dh_segments convention: axis and
    offset segments between consecutive frame origins) is covered by a capsule core."""
    robot = load_robot(name)
    caps = dh_capsules(robot)
    assert len(caps) == robot.n_dofs + 1
    q = sample_configurations(robot, 1, seed=1)[0]
    frames = forward_kinematics(robot, q, all_frames=True)
    cores = [capsule_ends(c.moved(frames[k])) for k, group in enumerate(caps) for c in group]
    # every frame origin from 1 to n lies on some core (revolute robots: the chain passes through them)
    if all(robot.jtype == 0):
        for k in range(1, robot.n_dofs + 1):
            origin = frames[k, :3, 3]
            assert min(_point_segment(origin, a, b) for a, b in cores) < 1e-9
    tool = frames[-1, :3, 3]
    assert min(_point_segment(tool, a, b) for a, b in cores) < 1e-9


# ---------------------------------------------------------------- IK with a checker
def test_ik_with_checker_never_returns_a_colliding_solution():
    robot = load_robot("ur5")
    checker = CollisionChecker(robot)
    rng = np.random.default_rng(11)
    colliding_targets = 0
    for q in sample_configurations(robot, 40, seed=9):
        target = forward_kinematics(robot, q)
        plain = solve_ik(robot, target, seed=int(rng.integers(1000)))
        res = solve_ik(robot, target, checker=checker, seed=0)
        colliding_targets += plain.success and checker.in_collision(plain.q)
        if res.success:
            assert not checker.in_collision(res.q)
            assert res.pos_err <= 1e-6
        else:
            assert "collision" in res.message or "did not converge" in res.message
    assert colliding_targets > 0  # without the checker some solutions did collide


def test_ik_with_checker_reports_colliding_minima():
    """A target inside the floor: every converged solution collides."""
    robot = load_robot("ur5")
    target = forward_kinematics(robot, robot.q_home)
    target[2, 3] = -0.2
    res = solve_ik(robot, target, checker=CollisionChecker(robot), max_restarts=5)
    assert not res.success and "in collision" in res.message


def test_ik_checker_argument_is_checked():
    robot = load_robot("ur5")
    with pytest.raises(ValueError, match="in_collision"):
        solve_ik(robot, forward_kinematics(robot, robot.q_home), checker=object())


# ---------------------------------------------------------------- continuous path checks
def thin_wall_case():
    robot = load_robot("ur5")
    ang = math.radians(-145.0)
    wall = np.eye(4)
    wall[:3, :3] = rot_z(ang)
    wall[:3, 3] = [0.62 * math.cos(ang), 0.62 * math.sin(ang), 0.27]
    checker = CollisionChecker(robot, World({"wall": Box((0.08, 0.002, 0.1), wall)}))
    qa = robot.q_home.copy()
    qb = qa.copy()
    qb[0] += math.pi / 2
    return checker, np.linspace(qa, qb, 10)


def test_path_is_free_catches_a_thin_wall_that_the_samples_miss():
    checker, path = thin_wall_case()
    assert not checker.in_collision(path).any()  # the path's own samples all pass the 2 mm wall
    fine = np.linspace(path[0], path[-1], 20001)
    assert checker.in_collision(fine).any()
    res = checker.path_is_free(path)
    assert not res and res.free is False and res.pair[1] == "wall"
    assert checker.in_collision(res.q)
    first = np.flatnonzero(checker.in_collision(fine))[0] / 20000 * 9  # in waypoints
    assert first - 9 / 20000 <= res.time <= first + 0.01  # within one check step (< 0.1° here)
    timed = checker.path_is_free(path, times=np.linspace(0.0, 4.5, 10))
    assert timed.time == pytest.approx(res.time / 2)


def test_path_is_free_on_a_free_path_and_its_motion_bound():
    checker, path = thin_wall_case()
    res = checker.path_is_free(path[:3])
    assert res and res.time is None and res.pair is None
    # the bound really bounds: consecutive checked configurations move no point more than 1 mm
    steps = np.linspace(path[0], path[2], res.checks)
    pts = np.array([[s.moved(np.eye(4)).pose[:3, 3] for _, s in checker.shapes(q)] for q in steps])
    assert np.max(np.linalg.norm(np.diff(pts, axis=0), axis=-1)) <= 1e-3


def test_path_is_free_takes_a_trajectory():
    from robot_sim.planning.profiles import quintic
    checker, path = thin_wall_case()
    traj = quintic(path[0], path[-1], 2.0)
    res = checker.path_is_free(traj)
    assert not res and 0.0 < res.time < 2.0
