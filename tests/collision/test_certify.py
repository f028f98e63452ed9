"""The planner's continuous checks (robot_sim.collision.certify through
robot_sim.planning.edges.CheckCounter) against checking every configuration at the
resolution with the checker's own batched ``in_collision``: the same edges and spline
spans collide, and the first collision found is the first one there is.  The group
clearances they certify with are each group's closest pair (recomputed pair by pair from
``contacts``), and the groups' motion bounds bound how fast those distances change.
The spline spans' exact speed and range bounds against dense sampling."""
from __future__ import annotations

import numpy as np
import pytest

from kin_helpers import robot
from robot_sim.collision import Box, CollisionChecker, Cylinder, Sphere, World
from robot_sim.kinematics import random_configurations, sampling_bounds
from robot_sim.planning.carrying import CheckerGroup, held_object
from robot_sim.planning.edges import CheckCounter
from robot_sim.planning.spline import JointSpline


def pose(xyz, yaw=0.0):
    T = np.eye(4)
    c, s = np.cos(yaw), np.sin(yaw)
    T[:2, :2] = [[c, -s], [s, c]]
    T[:3, 3] = xyz
    return T


CLUTTER = World({
    "table": Box([0.6, 1.2, 0.05], pose([0.55, 0.0, 0.175])),
    "post": Cylinder(0.04, 0.3, pose([0.45, 0.1, 0.35])),
    "crate": Box([0.1, 0.15, 0.2], pose([0.4, -0.25, 0.3], 0.4)),
    "ball": Sphere(0.06, [0.3, 0.3, 0.55]),
})


def counter_for(checker):
    return CheckCounter(checker, *sampling_bounds(checker.robot))


def groups_among_clutter(name, count, seed):
    """(arm, its checker among CLUTTER, the checker's pair groups, ``count`` random configurations)."""
    arm = robot(name)
    checker = CollisionChecker(arm, CLUTTER)
    return arm, checker, counter_for(checker).groups, random_configurations(arm, count, np.random.default_rng(seed))


def every_row(counter, qa, qb):
    """Every configuration of the edge qa → qb at the checker's resolution (the rows)."""
    m = int(counter.steps(qb - qa))
    return qa + (np.arange(m + 1) / m)[:, None] * (qb - qa)


def random_edges(arm, rng, count, checker):
    """Edges between free configurations, long and short."""
    Q = random_configurations(arm, 8 * count, rng)
    Q = Q[~checker.in_collision(Q)]
    A, B = Q[:count], Q[count:2 * count]
    scale = rng.choice([0.05, 0.3, 1.0], size=(count, 1))
    return A, A + scale * (B - A)


@pytest.mark.parametrize("name", ["panda", "ur5", "humanoid7"])
@pytest.mark.parametrize("padding", [0.0, 0.01])
def test_edges_collide_exactly_where_some_row_does_and_the_first_hit_is_the_first(name, padding):
    arm = robot(name)
    checker = CollisionChecker(arm, CLUTTER, padding=padding)
    counter = counter_for(checker)
    A, B = random_edges(arm, np.random.default_rng(3), 40, checker)
    free = counter.edges_free(A, B)
    seen_hit = seen_free = 0
    for qa, qb, ok in zip(A, B, free):
        rows = every_row(counter, qa, qb)
        hits = np.flatnonzero(checker.in_collision(rows))
        assert ok == (hits.size == 0)
        fraction = counter.free_fraction(qa, qb)
        m = rows.shape[0] - 1
        assert fraction == (1.0 if not hits.size else max(hits[0] - 1, 0) / m)
        seen_hit += bool(hits.size)
        seen_free += not hits.size
    assert seen_hit >= 5 and seen_free >= 5  # both kinds were exercised
    assert counter.count < sum(every_row(counter, a, b).shape[0] for a, b in zip(A, B)) / 5  # and few were asked


def test_first_free_checks_in_order_and_stops_at_the_first_free_edge():
    arm = robot("ur5")
    checker = CollisionChecker(arm, CLUTTER)
    counter = counter_for(checker)
    A, B = random_edges(arm, np.random.default_rng(5), 30, checker)
    qa = A[0]
    expected = [not checker.in_collision(every_row(counter, qa, qb)).any() for qb in B]
    k = counter.first_free(qa, B)
    assert k == (expected.index(True) if True in expected else -1)
    assert k > 0  # the test's edges start with colliding ones


def test_a_checker_group_is_checked_as_its_members_together():
    arm = robot("panda")
    world = World({"shelf": Box([0.3, 0.3, 0.02], pose([0.5, 0.0, 0.45]))})
    group = CheckerGroup(CollisionChecker(arm, world), held_object(arm, Box([0.05, 0.05, 0.12], pose([0, 0, 0.15])),
                                                                   world))
    counter = counter_for(group)
    A, B = random_edges(arm, np.random.default_rng(8), 30, group)
    free = counter.edges_free(A, B)
    brute = [not group.in_collision(every_row(counter, a, b)).any() for a, b in zip(A, B)]
    assert free.tolist() == brute
    assert 0 < sum(brute) < len(brute)


@pytest.mark.parametrize("name", ["panda", "stanford"])
def test_group_clearances_are_each_groups_closest_pair(name):
    arm, checker, groups, Q = groups_among_clutter(name, 60, 1)
    d = groups.clearance(Q)
    index = {link: k for k, link in enumerate(arm.link_names)}
    for q, row in zip(Q, d):
        contacts = checker.contacts(q, within=np.inf)
        if checker.in_collision(q):
            assert np.all(row < 0.0) and np.any(np.isclose(row[0], [c.distance for c in contacts], atol=1e-12))
            continue
        best: dict = {}
        for c in contacts:
            a, b = c.pair
            key = tuple(sorted((index[a], index[b]))) if b in index else (-1, index[a])
            best[key] = min(best.get(key, np.inf), c.distance)
        got = sorted(zip(map(tuple, np.unique(list(best), axis=0)), row))
        assert len(got) == groups.count
        for key, value in got:
            assert value == pytest.approx(best[key], abs=1e-9)


@pytest.mark.parametrize("name", ["panda", "ur5", "stanford"])
def test_no_group_closes_faster_than_its_bound(name):
    arm = robot(name)
    checker = CollisionChecker(arm, CLUTTER)
    lo, hi = sampling_bounds(arm)
    groups = counter_for(checker).groups
    rng = np.random.default_rng(2)
    Q = random_configurations(arm, 300, rng)
    dQ = rng.normal(size=Q.shape) * rng.choice([0.001, 0.05, 0.3], size=(Q.shape[0], 1))
    Q2 = np.clip(Q + dQ, lo, hi)
    free = ~checker.in_collision(Q) & ~checker.in_collision(Q2)
    change = np.abs(groups.clearance(Q2[free]) - groups.clearance(Q[free]))
    bound = groups.closing(Q2[free] - Q[free])
    assert np.all(change <= bound + 1e-12)
    assert np.max(change / np.maximum(bound, 1e-300)) > 0.2  # and the bound is not vacuous


def test_spline_span_bounds_are_the_extremes_of_dense_samples():
    rng = np.random.default_rng(1)
    for K in (2, 3, 4, 7):
        spline = JointSpline.through(rng.normal(size=(K, 5)))
        s = np.linspace(0.0, spline.length, 200_001)
        q, dq, _ = spline.evaluate(s)
        span = np.clip(np.searchsorted(spline.knots, s, side="right") - 1, 0, K - 2)
        lo, hi = spline.span_range()
        speed = spline.span_speed()
        step = spline.length / 200_000
        for i in range(K - 1):
            rows = span == i
            slack = step * speed[i] + 1e-12  # how far a sample can be from the extreme
            assert np.all(lo[i] <= q[rows].min(axis=0) + 1e-12) and np.all(q[rows].min(axis=0) <= lo[i] + slack)
            assert np.all(hi[i] >= q[rows].max(axis=0) - 1e-12) and np.all(q[rows].max(axis=0) >= hi[i] - slack)
            top = np.abs(dq[rows]).max(axis=0)
            assert np.all(speed[i] >= top - 1e-12) and np.all(top >= speed[i] - 1e-3 * (1 + speed[i]))


@pytest.mark.parametrize("name", ["panda", "ur5"])
def test_spline_spans_collide_exactly_where_their_rows_do(name):
    arm = robot(name)
    checker = CollisionChecker(arm, CLUTTER)
    counter = counter_for(checker)
    rng = np.random.default_rng(4)
    Q = random_configurations(arm, 400, rng)
    Q = Q[~checker.in_collision(Q)][:24]
    seen = 0
    for k in range(0, 24, 6):
        spline = JointSpline.through(Q[k:k + 6] * 0.5)
        got = counter.spans_colliding(spline)
        motion = spline.span_speed() * np.diff(spline.knots)[:, None]
        m = np.maximum(1, np.ceil(motion @ counter.radii / counter.resolution - 1e-12)).astype(int)
        for i, (t0, t1) in enumerate(zip(spline.knots[:-1], spline.knots[1:])):
            rows = spline.positions(t0 + (np.arange(m[i] + 1) / m[i]) * (t1 - t0))
            assert got[i] == checker.in_collision(rows).any()
            seen += got[i]
    assert seen > 0


@pytest.mark.parametrize("name", ["panda", "humanoid7"])
def test_clearances_asked_below_a_limit_are_exact_below_it_and_lower_bounds_above(name):
    arm, checker, groups, Q = groups_among_clutter(name, 300, 6)
    Q = Q[~checker.in_collision(Q)]
    exact = groups.clearance(Q)
    for limit in (0.0, 0.02, 0.2):
        got = groups.clearance(Q, limit)
        below = exact < limit
        np.testing.assert_allclose(got[below], exact[below], rtol=0, atol=1e-12)
        assert np.all(got[~below] >= limit) and np.all(got[~below] <= exact[~below] + 1e-12)
        assert np.isfinite(got).all()  # every group has pairs, each bounded from below
