"""The compiled contact kernels' shortcuts give what the full computation gives: the near
check's bound on the other pairs' distances (which lets the multi-step loop skip the
check while the arm has not moved that far) against every pair's exact distance, and the
remembered distance of a capsule's end sphere (which spares its narrow-phase call)
against a fresh evaluation, on the UR5 resting on the box."""
from __future__ import annotations

import numpy as np
import pytest

from contact_helpers import ur5_over_box
from robot_sim.collision import CollisionChecker
from robot_sim.collision.batch import pair_results
from robot_sim.sim import contact_kernels as K
from robot_sim.sim.simulation import Simulation


@pytest.fixture(scope="module")
def resting():
    """The passive UR5 after 1.5 s on the box (three capsules touching it, one flat)."""
    rob, world = ur5_over_box()
    sim = Simulation(rob, checker=CollisionChecker(rob, world), friction=0.5)
    sim.step(1500)
    assert sim.contact.active
    return sim


def _distances(checker, q):
    """The exact signed distance of every checked pair at q (P,)."""
    scene, P = checker.scene, checker.pairs.shape[0]
    d = np.empty(P)
    pair_results(q, *scene.args(), checker.pairs, scene.verts, np.inf, d, np.zeros((P, 2, 3)), np.zeros((P, 3)),
                 np.empty_like(scene.recs0))
    return d


def test_the_near_check_bounds_every_other_pair_until_the_arm_has_moved_that_far(resting):
    """near_slack at q: the active pairs are those closer than the margin, and its bound is
    at most the exact distance of every other pair, then and (less ``moved``) at any
    configuration near q; with a pair missing from or added to the active ones, -inf."""
    sim, contact = resting, resting.contact
    checker, scene = contact.checker, contact.checker.scene
    C = contact.compiled()
    arms, rows = C[12], C[13]
    q, threshold = sim.q.copy(), K.margin(C[12], sim.qd, sim.dt)
    work = K.contact_work(scene.dh, C)
    slack = K.near_slack(q, scene.dh, sim.robot.is_modified, C, threshold, work)
    d = _distances(checker, q)
    near = d < threshold
    np.testing.assert_array_equal(checker.pairs[near], rows)
    assert threshold <= slack <= d[~near].min()
    rng = np.random.default_rng(4)
    for _ in range(20):
        q1 = q + rng.uniform(-0.02, 0.02, q.size)
        assert (_distances(checker, q1)[~near] >= slack - K.moved(arms, q1, q) - 1e-12).all()
    for changed in (rows[:-1], np.concatenate([rows, checker.pairs[~near][:1]])):
        C2 = C[:13] + (np.ascontiguousarray(changed),) + C[14:]
        assert K.near_slack(q, scene.dh, sim.robot.is_modified, C2, threshold, work) == -np.inf


def test_a_remembered_end_distance_changes_no_contact_torque(resting):
    """Along a motion that presses the arm into the box by its shoulder and back (a capsule
    whose far end was spared its distance call coming to touch with that end), the
    contact torque, every point's distance and every touching point's record with the end
    spheres' distances remembered from the evaluation before equal those of a fresh
    evaluation bit for bit."""
    sim, contact = resting, resting.contact
    scene = contact.checker.scene
    C = contact.compiled()
    out = C[-1]
    work = K.contact_work(scene.dh, C)
    q0, n = sim.q.copy(), sim.robot.n_dofs
    qd = np.linspace(-0.2, 0.3, n)
    spared, spared_then_touching = set(), 0
    for s in np.concatenate([np.linspace(0.0, 0.3, 61), np.linspace(0.3, 0.0, 31)]):
        q = q0 + s * np.eye(n)[1]
        fresh = C[:-1] + (np.zeros_like(out),)
        tau, tau_fresh = np.empty(n), np.empty(n)
        before = out[:, 1:, K.O_GAP].copy()
        K.contact_torque(q, qd, scene.dh, sim.robot.is_modified, C, False, False, tau, work)
        K.contact_torque(q, qd, scene.dh, sim.robot.is_modified, fresh, False, False, tau_fresh,
                         K.contact_work(scene.dh, fresh))
        np.testing.assert_array_equal(tau, tau_fresh)
        np.testing.assert_array_equal(out[:, :, K.O_D], fresh[-1][:, :, K.O_D])
        touching = out[:, :, K.O_D] < 0.0  # the other columns of a point not touching are not read
        np.testing.assert_array_equal(out[touching, :K.O_GAP], fresh[-1][touching, :K.O_GAP])
        # an end of a pair in contact whose remembered distance was kept: its call was spared
        kept = (out[:, 1:, K.O_GAP] == before) & (out[:, :1, K.O_D] < 0.0) & (before > 0.0)
        spared |= set(zip(*np.nonzero(kept)))
        for p, e in list(spared):
            if touching[p, 1 + e]:
                spared_then_touching += 1
                spared.discard((p, e))
    assert spared_then_touching > 0
