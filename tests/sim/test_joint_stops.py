"""Joint stops (robot_sim/sim/joint_stops.py and the simulation loop's use of them):
impacts consistent with the mass matrix, joints held on their stops, no energy created."""
from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
import pytest

from robot_sim import dynamics
from robot_sim.sim import joint_stops
from robot_sim.control.controllers import PD, control_gains
from robot_sim.sim.simulation import Simulation
from robot_sim.model.inertials import LinkInertials
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.model.state import RobotState
from robot_sim.transforms import HomogeneousTransform
from sim_helpers import frictionless, pendulum

LINKS = (0.6, 0.4)  # m
MASSES = (2.0, 1.5)  # kg, at each link's tip
TIP_INERTIA = 1e-3  # kg·m², each tip mass about its centre
ENERGY_ROBOTS = ("ur5", "panda", "humanoid7")
ENERGY_STARTS = 20
DEFAULT_STARTS = 3  # per robot in `make test`; the other 17 are marked slow


def _two_link(vertical: bool, q_min=(-math.inf, -math.inf), q_max=(math.inf, math.inf)) -> RobotParams:
    """Planar two-link arm, a tip mass on each link; joint axes vertical (gravity does no
    work) or horizontal (the arm swings in a vertical plane, q = 0 level, gravity pulls
    q1 toward −π/2 as in ``sim_helpers.pendulum``)."""
    inertials = LinkInertials.from_arrays(
        mass=list(MASSES), com=[[0.0, 0.0, 0.0]] * 2, inertia=[np.eye(3) * TIP_INERTIA] * 2
    )
    base = HomogeneousTransform.from_xyz_rpy([0.0, 0.0, 0.0], [math.pi / 2 if vertical else 0.0, 0.0, 0.0])
    return RobotParams.from_arrays(
        "two-link", list(LINKS), [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [JTYPE_REVOLUTE] * 2,
        q_min=list(q_min), q_max=list(q_max), base_tf=base, inertials=inertials,
    )


def _two_link_mass_matrix(q2: float) -> np.ndarray:
    """Closed form M(q2) of :func:`_two_link` (tip masses m1, m2 on links l1, l2)."""
    (l1, l2), (m1, m2), i = LINKS, MASSES, TIP_INERTIA
    c2 = math.cos(q2)
    m12 = i + m2 * (l2**2 + l1 * l2 * c2)
    return np.array([[2 * i + m1 * l1**2 + m2 * (l1**2 + l2**2 + 2 * l1 * l2 * c2), m12], [m12, i + m2 * l2**2]])


def _random_spd(rng: np.random.Generator, n: int) -> np.ndarray:
    A = rng.normal(size=(n, n))
    return A @ A.T + 0.05 * np.eye(n)


def _kinetic(M: np.ndarray, v: np.ndarray) -> float:
    return 0.5 * float(v @ M @ v)


def _random_stops(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    candidates = rng.random(n) < 0.6
    candidates[rng.integers(n)] = True
    push = np.where(rng.random(n) < 0.5, 1.0, -1.0) * candidates
    return push, candidates


def _random_problems(seed: int, count: int, max_n: int):
    """``count`` random problems (trial, M, vector, push, candidates) of 1 … max_n joints."""
    rng = np.random.default_rng(seed)
    for trial in range(count):
        n = 1 + trial % max_n
        yield (trial, _random_spd(rng, n), rng.normal(size=n), *_random_stops(rng, n))


def _complementary_sets(M, rhs, base, push, candidates):
    """Brute force: every subset A of the candidates whose solution holds A (push·μ ≥ 0)
    and keeps the others off their stops (push·(base + x) ≥ 0), with x solved directly."""
    n = len(rhs)
    found = []
    idx = np.flatnonzero(candidates)
    for k in range(len(idx) + 1):
        for subset in itertools.combinations(idx, k):
            A = np.zeros(n, dtype=bool)
            A[list(subset)] = True
            # unknowns: x on the free joints, μ on A; x_A = −base_A
            x = np.where(A, -base, 0.0)
            F = ~A
            x[F] = np.linalg.solve(M[np.ix_(F, F)], rhs[F] - M[np.ix_(F, A)] @ x[A])
            mu = np.where(A, M @ x - rhs, 0.0)
            rate = base + x
            if (push[A] * mu[A] >= -1e-9).all() and (push[candidates & F] * rate[candidates & F] >= -1e-9).all():
                found.append(A)
    return found


# ------------------------------------------------------------------ the functions


@pytest.mark.parametrize("restitution", [0.0, 0.5, 1.0])
def test_impact_never_increases_kinetic_energy_and_loses_what_the_proof_says(restitution):
    """Random SPD M (1-7 joints), velocities and stops: T⁺⁺ ≤ T to 1e-12 relative, and
    T⁺⁺ = T − ½(1 − e²) dᵀ M d with d the compression jump (the docstring's identity)."""
    for trial, M, qd, push, candidates in _random_problems(7, 300, 7):
        after, impulse, held = joint_stops.impact(M, qd, push, candidates, restitution, hold_speed=0.05 * (trial % 2))
        before = _kinetic(M, qd)
        assert _kinetic(M, after) <= before * (1 + 1e-12)
        d = (after - qd) / (1 + restitution)
        assert _kinetic(M, after) == pytest.approx(before - 0.5 * (1 - restitution**2) * d @ M @ d, rel=1e-9, abs=1e-12)
        np.testing.assert_allclose(M @ (after - qd), impulse, atol=1e-9 * (1 + np.abs(M @ qd).max()))
        assert not impulse[~held].any() and not held[~candidates].any()
        if restitution == 0.0:
            assert not after[held].any()


def test_impact_is_the_complementary_solution_and_the_issues_formula():
    """e = 0, no hold speed: the held set is the unique complementary one (brute force over
    every subset), held joints' impulses push and the other candidates leave their stops;
    for one joint the velocity change is −M⁻¹ e_i (e_iᵀ M⁻¹ e_i)⁻¹ q̇_i."""
    for _, M, qd, push, candidates in _random_problems(11, 200, 6):
        after, impulse, held = joint_stops.impact(M, qd, push, candidates)
        sets = _complementary_sets(M, np.zeros_like(qd), qd, push, candidates)
        assert len(sets) == 1 and (sets[0] == held).all()
        assert (push[held] * impulse[held] >= -1e-12).all()
        assert (push[candidates & ~held] * after[candidates & ~held] >= -1e-12).all()
    M = _random_spd(np.random.default_rng(12), 4)
    qd = np.array([0.3, -1.2, 0.5, 0.8])
    push = np.array([0.0, 1.0, 0.0, 0.0])  # joint 1 on its min stop, arriving at −1.2
    after, impulse, held = joint_stops.impact(M, qd, push, push != 0)
    Minv = np.linalg.inv(M)
    np.testing.assert_allclose(after - qd, -Minv[:, 1] / Minv[1, 1] * qd[1], atol=1e-12)
    assert held.tolist() == [False, True, False, False] and impulse[1] == pytest.approx(-qd[1] / Minv[1, 1])


def test_impact_holds_coupled_joints_that_would_leave_slowly():
    """Two coupled joints on their stops: the arrival of one knocks the other off at a
    speed below hold_speed; with hold_speed both are held (no Zeno sequence of ever smaller
    knocks), without it the other leaves; energy drops either way."""
    M = np.array([[1.0, 0.45], [0.45, 0.3]])
    qd = np.array([-0.02, 0.0])  # joint 0 arrives at its min stop, joint 1 rests on its max
    push = np.array([1.0, -1.0])
    free_after, _, held = joint_stops.impact(M, qd, push, push != 0)
    assert held.tolist() == [True, False] and 0 < -free_after[1] < 0.05
    after, impulse, held = joint_stops.impact(M, qd, push, push != 0, hold_speed=0.05)
    assert held.tolist() == [True, True] and not after.any()
    assert _kinetic(M, after) <= _kinetic(M, free_after) <= _kinetic(M, qd)


def test_hold_is_the_complementary_solution():
    """Resting joints: M q̈ = rhs + λ, q̈ = 0 and push·λ ≥ 0 on the held joints, push·q̈ ≥ 0
    on released candidates; the held set is the unique complementary one."""
    for _, M, rhs, push, candidates in _random_problems(5, 200, 6):
        qdd, reaction, held = joint_stops.hold(M, rhs, push, candidates)
        np.testing.assert_allclose(M @ qdd, rhs + reaction, atol=1e-9 * (1 + np.abs(rhs).max()))
        assert not qdd[held].any() and not reaction[~held].any()
        assert (push[held] * reaction[held] >= 0).all()
        assert (push[candidates & ~held] * qdd[candidates & ~held] >= 0).all()
        sets = _complementary_sets(M, rhs, np.zeros_like(rhs), push, candidates)
        assert len(sets) == 1 and (sets[0] == held).all()


def test_constrained_forward_dynamics_solves_the_free_rows_and_reports_the_reaction():
    """Against mass_matrix/bias_torque (reduced solve) and inverse_dynamics (the reaction is
    ID(q, q̇, q̈) − τ on the held rows, zero on the free ones); batched equals single."""
    rob = frictionless("humanoid7")
    rng = np.random.default_rng(3)
    Q, QD, TAU = rng.normal(size=(3, 4, 7))
    HELD = rng.random((4, 7)) < 0.4
    QD[HELD] = 0.0
    QDD, REACT = dynamics.constrained_forward_dynamics(rob, Q, QD, TAU, HELD)
    for q, qd, tau, held, qdd_b, react_b in zip(Q, QD, TAU, HELD, QDD, REACT):
        qdd, react = dynamics.constrained_forward_dynamics(rob, q, qd, tau, held)
        free = ~held
        M = dynamics.mass_matrix(rob, q)
        rhs = tau - dynamics.bias_torque(rob, q, qd)
        np.testing.assert_allclose(qdd[free], np.linalg.solve(M[np.ix_(free, free)], rhs[free]), atol=1e-9)
        assert not qdd[held].any() and not react[free].any()
        np.testing.assert_allclose(react, np.where(held, dynamics.inverse_dynamics(rob, q, qd, qdd) - tau, 0.0), atol=1e-9)
        np.testing.assert_allclose(qdd_b, qdd, atol=1e-9)
        np.testing.assert_allclose(react_b, react, atol=1e-9)
    for bad in (np.zeros(6, dtype=bool), np.zeros(7), None):
        with pytest.raises(ValueError, match="held"):
            dynamics.constrained_forward_dynamics(rob, Q[0], QD[0], TAU[0], bad)


# ------------------------------------------------------------------ the simulation


def test_two_link_arm_stopping_on_one_joint_gets_the_closed_form_impulse():
    """Horizontal two-link arm set on joint 1's min stop moving into it: the stop's impulse
    is −q̇1 (M11 − M12²/M22), joint 1 stops and joint 2 keeps its generalized momentum,
    q̇2⁺ = q̇2 + (M12/M22) q̇1 (then turns freely at that rate: joint 1 held, no gravity
    torque about vertical axes)."""
    lo = -0.3
    rob = _two_link(vertical=False, q_min=(lo, -math.inf))
    q0, v = np.array([lo, -0.8]), np.array([-1.5, 0.7])
    state = RobotState(rob)
    state.set_q(q0)
    state.set_qd(v)
    sim = Simulation(rob, state)
    M = _two_link_mass_matrix(q0[1])
    np.testing.assert_allclose(dynamics.mass_matrix(rob, q0), M, rtol=1e-12)
    sim.step(1)
    (event,) = sim.take_events()
    assert (event.time, event.joint, event.side, event.q) == (0.0, 0, "min", lo)
    assert event.impulse == pytest.approx(-v[0] * (M[0, 0] - M[0, 1] ** 2 / M[1, 1]), rel=1e-12)
    assert sim.q[0] == lo and sim.qd[0] == 0.0
    assert sim.qd[1] == pytest.approx(v[1] + M[0, 1] / M[1, 1] * v[0], rel=1e-12)
    # the stop pushes against link 2's centrifugal pull, −m2 l1 l2 sin(q2) q̇2² > 0
    (l1, l2), (_, m2) = LINKS, MASSES
    assert sim.limit_torque[0] == pytest.approx(-m2 * l1 * l2 * math.sin(q0[1]) * sim.qd[1] ** 2, rel=1e-9)


def test_pendulum_lands_with_the_energy_impulse_then_rests_on_its_stop():
    """Released level, the rod falls onto its stop: the arrival is located on the limit and
    the impulse is I ω with ½ I ω² the potential energy released; then it rests for 5 s
    without chatter (one event in all), held by a reaction equal to the gravity torque."""
    lo = -0.4
    rob = pendulum(limits=(lo, 0.6))
    sim = Simulation(rob)
    sim.step(5000)
    events = sim.take_events()
    assert len(events) == 1 and (events[0].joint, events[0].side, events[0].q) == (0, "min", lo)
    inertia = dynamics.mass_matrix(rob, [lo])[0, 0]
    released = dynamics.energy(rob, [0.0], [0.0])[1] - dynamics.energy(rob, [lo], [0.0])[1]
    assert events[0].impulse == pytest.approx(math.sqrt(2 * inertia * released), rel=1e-8)
    assert sim.q[0] == lo and sim.qd[0] == 0.0 and sim.at_limit.tolist() == [True]
    assert sim.limit_torque[0] == pytest.approx(dynamics.gravity_torque(rob, [lo])[0], abs=1e-9)
    assert sim.limit_torque[0] > 0  # the min stop pushes up


def test_restitution_bounces_at_the_coefficient_times_the_approach_speed():
    """The same fall with e = 0.5: the first impulse is 1.5 times the inelastic one, the rod
    bounces (several events) and settles on the stop; e outside [0, 1] is refused."""
    lo = -0.4
    rob = pendulum(limits=(lo, 0.6))
    inelastic, bouncy = Simulation(rob), Simulation(rob, restitution=0.5)
    inelastic.step(3000)
    bouncy.step(3000)
    first, events = inelastic.take_events()[0], bouncy.take_events()
    assert events[0].time == first.time and events[0].impulse == pytest.approx(1.5 * first.impulse, rel=1e-12)
    assert len(events) > 2 and [e.impulse for e in events] == sorted((e.impulse for e in events), reverse=True)
    assert bouncy.q[0] == lo and bouncy.qd[0] == 0.0
    for bad in (-0.1, 1.5, math.nan, "0.5"):
        with pytest.raises(ValueError, match="restitution"):
            Simulation(rob, restitution=bad)


def test_joint_held_by_gravity_with_the_next_link_hanging_stays_with_the_gravity_reaction():
    """Vertical two-link arm: joint 1 on its min stop, link 2 hanging straight down (its
    equilibrium): 2 s without an event, joint 1 exactly on the stop, its reaction the
    gravity torque it holds (to 1e-9 N·m), joint 2 free (zero reaction)."""
    lo = -0.3
    rob = _two_link(vertical=True, q_min=(lo, -math.inf))
    state = RobotState(rob)
    q0 = np.array([lo, -math.pi / 2 - lo])
    state.set_q(q0)
    sim = Simulation(rob, state)
    g = dynamics.gravity_torque(rob, q0)
    assert g[0] > 1.0 and abs(g[1]) < 1e-12  # the stop holds the arm; link 2 balanced
    for _ in range(200):
        sim.step(10)
        assert sim.q[0] == lo and sim.limit_torque[1] == 0.0
        assert sim.limit_torque[0] == pytest.approx(dynamics.gravity_torque(rob, sim.q)[0], abs=1e-9)
    assert sim.take_events() == [] and sim.stopped is None


def _ur5_shoulder_on_its_stop() -> tuple[RobotParams, np.ndarray]:
    """Frictionless UR5 whose shoulder (joint 2) starts on the stop gravity presses it onto,
    the other joints free to swing."""
    free = frictionless("ur5")
    q0 = np.array([0.3, -0.5, 1.0, -0.4, 0.8, 0.0])
    a = dynamics.forward_dynamics(free, q0, np.zeros(6), np.zeros(6))
    q_min, q_max = free.q_min.copy(), free.q_max.copy()
    (q_min if a[1] < 0 else q_max)[1] = q0[1]
    return dataclasses.replace(free, q_min=q_min, q_max=q_max), q0


def test_a_held_joint_reaction_is_the_inverse_dynamics_of_the_constrained_motion():
    """UR5 (frictionless) with its shoulder on a stop that gravity presses it onto while the
    other joints swing: every step that starts with the shoulder held, its reaction equals
    inverse dynamics of the step's start state and acceleration minus the applied torque."""
    rob, q0 = _ur5_shoulder_on_its_stop()
    state = RobotState(rob)
    state.set_q(q0)
    sim = Simulation(rob, state)
    held_steps = 0
    for _ in range(300):
        q, qd = sim.q.copy(), sim.qd.copy()
        sim.step(1)
        if sim.limit_torque.any():
            held_steps += 1
            expected = dynamics.inverse_dynamics(rob, q, qd, sim.qdd) - sim.effort
            np.testing.assert_allclose(sim.limit_torque[1], expected[1], rtol=1e-9, atol=1e-9)
            np.testing.assert_allclose(expected[[0, 2, 3, 4, 5]], 0.0, atol=1e-9)
            assert sim.qdd[1] == 0.0 and q[1] == q0[1]
    assert held_steps > 100


def _resting_run(case: str, backend: str) -> tuple[np.ndarray, int, int]:
    """Per step (q, qd, q̈, limit_torque, at_limit) of a run that rests on a stop, under
    ``backend``; the arrivals; the steps the stops resolved outside the stepper."""
    if case == "ur5":
        rob, q0 = _ur5_shoulder_on_its_stop()
        controller, reference, steps = None, None, 300
    else:  # the pendulum rests on its min stop until a PD set point 0.1 s in lifts it off
        rob, q0 = pendulum(limits=(-0.4, 0.6)), np.array([-0.4])
        controller = PD(rob, control_gains(rob, bandwidth=5.0))
        reference, steps = (lambda t: (np.array([0.3 if t >= 0.1 else -0.4]), np.zeros(1), np.zeros(1))), 400
    state = RobotState(rob)
    state.set_q(q0)
    sim = Simulation(rob, state, controller, reference=reference)
    general = 0
    through_stops = sim._through_stops

    def counted(*args):
        nonlocal general
        general += 1
        return through_stops(*args)

    sim._through_stops = counted
    dynamics.set_backend(backend)
    try:
        rows = [np.concatenate([sim.q, sim.qd, sim.qdd, sim.limit_torque, sim.at_limit]) for _ in range(steps) if sim.step(1)]
    finally:
        dynamics.set_backend("compiled")
    return np.array(rows), len(sim.take_events()), general


@pytest.mark.parametrize("case", ["ur5", "pendulum"])
def test_resting_in_the_compiled_step_equals_the_reference_backend(case):
    """A joint resting on its stop is held inside the compiled step (no step of the UR5's
    rest leaves it); the run equals the reference backend's, whose steps all go through
    the stops' general path, to round-off: the same held steps, reactions and release."""
    compiled, events_c, general_c = _resting_run(case, "compiled")
    reference, events_r, general_r = _resting_run(case, "reference")
    assert compiled.shape == reference.shape and events_c == events_r
    np.testing.assert_allclose(compiled, reference, rtol=1e-9, atol=1e-9)
    n = compiled.shape[1] // 5
    held_steps = int(compiled[:, 4 * n + (1 if case == "ur5" else 0)].sum())
    if case == "ur5":
        assert held_steps == len(compiled) and general_c == 0 and general_r == len(compiled)
    else:  # rests 100 steps, released once (by the general path), then swings free
        assert held_steps == 100 and general_c == 1 and compiled[-1, 0] > -0.3


def test_limits_never_reached_change_nothing_bit_for_bit():
    """The same swing with limits far from the motion and with no limits: identical states."""
    rob = frictionless("humanoid7")
    bounded = dataclasses.replace(rob, q_min=np.full(7, -10.0), q_max=np.full(7, 10.0))
    runs = []
    for r in (rob, bounded):
        state = RobotState(r)
        state.set_q(np.radians([0.0, 165.0, 0.0, -20.0, 0.0, 15.0, 0.0]))
        state.set_qd([0.3, 0.0, -0.3, 0.0, 0.3, 0.0, 0.3])
        sim = Simulation(r, state)
        runs.append(np.array([np.concatenate([sim.q, sim.qd, sim.qdd]) for _ in range(500) if sim.step(1)]))
    np.testing.assert_array_equal(runs[0], runs[1])


def _energy_cases():
    return [
        pytest.param(name, start, marks=() if start < DEFAULT_STARTS else pytest.mark.slow, id=f"{name}-{start}")
        for name in ENERGY_ROBOTS
        for start in range(ENERGY_STARTS)
    ]


def _energy_run(rob: RobotParams, q0: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """5 s passive from rest at q0, RK4 at 1 kHz: total energy per step, q, qd, events."""
    state = RobotState(rob)
    state.set_q(q0)
    sim = Simulation(rob, state, dt=1e-3, integrator="rk4")
    Q, QD = [sim.q.copy()], [sim.qd.copy()]
    for _ in range(5000):
        assert sim.step(1) == 1, sim.stopped
        Q.append(sim.q.copy())
        QD.append(sim.qd.copy())
    Q, QD = np.array(Q), np.array(QD)
    kinetic, potential = dynamics.energy(rob, Q, QD)
    return kinetic + potential, Q, QD, len(sim.take_events())


@pytest.mark.parametrize("name, start", _energy_cases())
def test_passive_arm_on_its_stops_never_gains_energy(name, start, monkeypatch):
    """Passive, frictionless, the shipped joint limits, released at rest from a random pose:
    over 5 s the total energy never exceeds its start by more than the integrator's drift
    on the same start without stops, every impact loses kinetic energy (to 1e-12
    relative), and until the first arrival the run is bit for bit the run without stops."""
    rob = frictionless(name, limits=True)
    q0 = np.random.default_rng(1000 + start).uniform(rob.q_min, rob.q_max)
    impacts = []
    impact = joint_stops.impact

    def recorded(M, qd, *args):
        result = impact(M, qd, *args)
        impacts.append((_kinetic(M, qd), _kinetic(M, result[0])))
        return result

    monkeypatch.setattr(joint_stops, "impact", recorded)
    energy, Q, QD, events = _energy_run(rob, q0)
    energy_free, Q_free, QD_free, _ = _energy_run(frictionless(name), q0)
    drift = np.abs(energy_free - energy_free[0]).max()
    assert (energy - energy[0]).max() <= drift
    assert len(impacts) == events
    for before, after in impacts:
        assert after <= before * (1 + 1e-12)
    outside = np.flatnonzero(((Q_free < rob.q_min) | (Q_free > rob.q_max)).any(axis=1))
    first = outside[0] if outside.size else len(Q)
    np.testing.assert_array_equal(Q[:first], Q_free[:first])
    np.testing.assert_array_equal(QD[:first], QD_free[:first])
    assert (events > 0) == (outside.size > 0)
