"""The compiled contact kernels' shortcuts give what the full computation gives: the near
check's bound on the other pairs' distances (which lets the multi-step loop skip the
check while the arm has not moved that far) against every pair's exact distance, and the
remembered distance of a capsule's end sphere (which spares its narrow-phase call)
against a fresh evaluation, on the UR5 resting on the box; and the contact frames held
over a step against the exact distances: the same energy at the start, second-order
differences over the step, none for the UR5 on the box's face; frames held over steps
while the arm has not moved HOLD; the step's start giving the torque its first stage
takes; and the stages' link frames from the forward dynamics' trigonometry."""
from __future__ import annotations

import numpy as np
import pytest

from contact_helpers import panda_in_self_contact, ur5_over_box
from kin_helpers import robot
from robot_sim.collision import CollisionChecker
from robot_sim.collision.batch import pair_results
from robot_sim.dynamics.compiled import geometry
from robot_sim.kernels.chain import frames, frames_cs
from robot_sim.sim import contact_kernels as K
from robot_sim.sim.contact import ContactModel
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


def _begin_and_stage(contact, C, q, qd, threshold, work):
    """contact_begin at q (anchors not moved), then contact_torque at q: the torque (n,)."""
    scene, n = contact.checker.scene, contact.robot.n_dofs
    K.contact_begin(q, qd, scene.dh, contact.robot.is_modified, C, False, False, threshold, work)
    tau = np.empty(n)
    K.contact_torque(q, qd, scene.dh, contact.robot.is_modified, C, tau, work)
    return tau


def test_a_remembered_end_distance_changes_no_contact_torque(resting):
    """Along a motion that presses the arm into the box by its shoulder and back (a capsule
    whose far end was spared its distance call coming to touch with that end), the
    contact frames, the contact torque, every point's distance and every touching
    point's record with the end spheres' distances remembered from the evaluation before
    equal those of a fresh evaluation bit for bit."""
    sim, contact = resting, resting.contact
    scene = contact.checker.scene
    C = contact.compiled()
    out = C[-1]
    work = K.contact_work(scene.dh, C)
    q0, n = sim.q.copy(), sim.robot.n_dofs
    qd = np.linspace(-0.2, 0.3, n)
    threshold = K.margin(C[12], qd, sim.dt)
    spared, spared_then_touching = set(), 0
    for s in np.concatenate([np.linspace(0.0, 0.3, 61), np.linspace(0.3, 0.0, 31)]):
        q = q0 + s * np.eye(n)[1]
        fresh = C[:-2] + (np.full_like(C[-2], -np.inf), np.zeros_like(out))  # frames fixed anew, nothing remembered
        before = out[:, 1:, K.O_GAP].copy()
        C[-2][n] = -np.inf  # the frames fixed anew here too (not held)
        tau = _begin_and_stage(contact, C, q, qd, threshold, work)
        tau_fresh = _begin_and_stage(contact, fresh, q, qd, threshold, K.contact_work(scene.dh, fresh))
        np.testing.assert_array_equal(tau, tau_fresh)
        np.testing.assert_array_equal(out[:, :, K.O_ON], fresh[-1][:, :, K.O_ON])
        np.testing.assert_array_equal(out[:, :, K.O_D], fresh[-1][:, :, K.O_D])
        on = out[:, :, K.O_ON] == 1.0  # the other columns of a point not taking part are not read
        for cols in (slice(0, K.O_GAP), slice(K.O_ON, K.OUT)):
            np.testing.assert_array_equal(out[on, cols], fresh[-1][on, cols])
        # an end of a pair in contact whose remembered distance was kept: its call was spared
        kept = (out[:, 1:, K.O_GAP] == before) & (out[:, :1, K.O_D] < 0.0) & (before > 0.0)
        spared |= set(zip(*np.nonzero(kept)))
        for p, e in list(spared):
            if out[p, 1 + e, K.O_D] < 0.0:
                spared_then_touching += 1
                spared.discard((p, e))
    assert spared_then_touching > 0


def _held_energy(model, q):
    """Σ ½ k δ² + ½ k_T |u|² of the contact points of the step at q, their frames held from
    the step's start (contact_torque's distances and anchor offsets)."""
    model.torque(q, np.zeros(model.robot.n_dofs))
    C = model.compiled(all_q=False)
    gains, out = C[14], C[-1]
    depth = np.where(out[:, :, K.O_ON] == 1.0, np.maximum(-out[:, :, K.O_D], 0.0), 0.0)
    u = out[:, :, K.O_SLIP:K.O_SLIP + 3]
    spring = gains[:, K.K_N, None] * depth**2 + gains[:, K.K_T, None] * np.sum(u * u, axis=2)
    return float(0.5 * np.sum(np.where(depth > 0.0, spring, 0.0)))


def _within_margin(model, q0, rng, count):
    """``count`` directions (n,) about q0 along which the shapes move by the step's margin."""
    arms = model.compiled(all_q=False)[12]
    threshold = model.margin(q0, np.zeros(q0.size), 1e-3)
    out = []
    for _ in range(count):
        step = rng.normal(size=q0.size)
        out.append(step * (threshold / K.moved(arms, q0 + step, q0)))
    return out


def test_held_contact_frames_differ_from_the_exact_energy_by_second_order_terms():
    """Links of the Panda pushed into each other, where the exact normals turn as they
    move: the springs' energy with the contact frames held from the step's start equals
    the exact one at the start, and along any motion the step can make (shapes moved up
    to the margin) differs from it by second-order terms (half the motion, a quarter of
    the difference)."""
    rob, checker, q0 = panda_in_self_contact()
    rng = np.random.default_rng(0)
    model = ContactModel(checker, friction=0.0)
    assert model.begin_step(q0, np.zeros(rob.n_dofs), 1e-3)
    exact = model.stored_energy(q0)
    assert exact > 0.1 and _held_energy(model, q0) == pytest.approx(exact, rel=1e-12)
    largest = 0.0
    for step in _within_margin(model, q0, rng, 10):
        full, half = (_held_energy(model, q0 + s * step) - model.stored_energy(q0 + s * step) for s in (1.0, 0.5))
        assert abs(half) <= 0.3 * abs(full) + 1e-12 * exact
        largest = max(largest, abs(full))
    assert largest > 1e-9


def test_held_contact_frames_on_a_face_are_exact():
    """The UR5 resting on the box's top face: a capsule's end or side on a face of a fixed
    shape keeps its normal and its core point, so the held frames' spring energy is the
    exact one at every configuration the step can reach (the two ends of the capsule
    lying flat trading places included).  Frictionless: the exact model's anchors belong
    to its slots, which the trade swaps."""
    rob, world = ur5_over_box()
    checker = CollisionChecker(rob, world)
    sim = Simulation(rob, checker=checker, friction=0.5)
    sim.step(1500)
    model, q0 = ContactModel(checker, friction=0.0), sim.q.copy()
    assert model.begin_step(q0, np.zeros(rob.n_dofs), sim.dt) and len(model.forces) >= 3
    for step in _within_margin(model, q0, np.random.default_rng(1), 40):
        q = q0 + step
        assert _held_energy(model, q) == pytest.approx(model.stored_energy(q), rel=1e-9, abs=1e-12)


def test_a_resting_arm_holds_its_contact_frames_until_it_has_moved_hold(resting):
    """A step's start within HOLD of where the frames were fixed keeps them (no narrow
    phase), with the torque of frames fixed anew there to 1e-9; once the arm has moved
    farther, they are fixed anew."""
    sim, contact = resting, resting.contact
    dh, modified, n = contact.checker.scene.dh, sim.robot.is_modified, sim.robot.n_dofs
    C = contact.compiled()
    arms, fixed = C[12], C[-2]
    q0, qd = sim.q.copy(), np.zeros(n)
    threshold = K.margin(arms, qd, sim.dt)
    work = K.contact_work(dh, C)
    fixed[n] = -np.inf
    assert K.contact_begin(q0, qd, dh, modified, C, False, False, threshold, work)  # fixed anew
    direction = np.linspace(1.0, -0.5, n)
    for share, held in ((0.5, True), (0.99, True), (1.5, False)):
        q = q0 + direction * (share * K.HOLD / K.moved(arms, q0 + direction, q0))
        fixed[:n] = q0
        assert K.contact_begin(q, qd, dh, modified, C, False, False, threshold, work) != held
        tau = np.empty(n)
        K.contact_torque(q, qd, dh, modified, C, tau, work)
        fresh = C[:-2] + (np.full_like(fixed, -np.inf), np.zeros_like(C[-1]))
        expected = _begin_and_stage(contact, fresh, q, qd, threshold, K.contact_work(dh, fresh))
        np.testing.assert_allclose(tau, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
        assert np.abs(tau).max() > 1.0


def test_a_steps_start_gives_the_contact_torque_its_first_stage_takes(resting):
    """contact_begin's torque at the start (work[6], which the compiled loop's first RK4
    stage takes instead of computing it again) is contact_torque's there, bit for bit,
    with the friction anchors it just moved: when it fixes the frames anew and when it
    holds them."""
    sim, contact = resting, resting.contact
    dh, modified, n = contact.checker.scene.dh, sim.robot.is_modified, sim.robot.n_dofs
    C = tuple(x.copy() if isinstance(x, np.ndarray) else x for x in contact.compiled())  # the fixture's stay
    q, qd = sim.q.copy(), np.random.default_rng(5).uniform(-0.01, 0.01, n)  # slipping: the anchors slide
    threshold = K.margin(C[12], qd, sim.dt)
    work = K.contact_work(dh, C)
    C[-2][n] = -np.inf
    tau = np.empty(n)
    for refixed in (True, False):
        work[6][:] = np.nan
        assert K.contact_begin(q, qd, dh, modified, C, True, False, threshold, work) == refixed
        K.contact_torque(q, qd, dh, modified, C, tau, work)
        np.testing.assert_array_equal(work[6], tau)
        assert np.abs(tau).max() > 1.0 and C[17].any()


@pytest.mark.parametrize("name,convention", [("ur5", None), ("ur5", "modified"), ("stanford", None),
                                             ("stanford", "modified")])
def test_the_stages_frames_from_the_dynamics_trigonometry_are_the_frames(name, convention):
    """frames_cs from geometry's cos θ, sin θ (what a contact stage takes) equals frames
    bit for bit, for standard and modified DH and a prismatic joint (the Stanford arm's)."""
    rob = robot(name, convention)
    scene, n = CollisionChecker(rob).scene, rob.n_dofs
    rng = np.random.default_rng(6)
    for _ in range(5):
        q = rng.uniform(-3.0, 3.0, n)
        expected, F = np.empty((n + 1, 3, 4)), np.full((n + 1, 3, 4), np.nan)
        frames(scene.dh, rob.is_modified, scene.world0, q, expected)
        O, CS = np.empty((n, 3)), np.empty((n, 2))
        geometry(scene.dh, rob.is_modified, q, O, CS)
        frames_cs(scene.dh, rob.is_modified, scene.world0, q, CS, F)
        np.testing.assert_array_equal(F, expected)
