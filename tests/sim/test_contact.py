"""Penalty contact in the physics loop: closed-form resting depth and force, the joint
torque against finite differences of the springs' energy, Coulomb friction on a slope
(sliding acceleration g(sin θ − μ cos θ), no creep inside the cone), a passive UR5
dropped onto a box coming to rest, energy never gained, shipped robots dropped onto the
floor without divergence, and steps far from contact unchanged."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from contact_helpers import MASS, RADIUS, panda_in_self_contact, planar_carriage, ur5_over_box, vertical_slider
from kin_helpers import ROBOT_NAMES, robot, sweep
from robot_sim import dynamics
from robot_sim.collision import Box, CollisionChecker, Sphere, World
from robot_sim.control.controllers import PD, Passive, control_gains
from robot_sim.sim.contact import MIN_MARGIN, OMEGA_DT, ContactModel
from robot_sim.sim.simulation import Simulation
from robot_sim.sim.stepper import runge_kutta
from robot_sim.dynamics import GRAVITY
from robot_sim.transforms import HomogeneousTransform

G = -GRAVITY[2]


def pose(xyz, rpy=(0.0, 0.0, 0.0)) -> np.ndarray:
    return np.array(HomogeneousTransform.from_xyz_rpy(xyz, rpy).mat)


@pytest.mark.parametrize("integrator", ["rk4", "euler"])
def test_a_sphere_rests_on_the_floor_at_the_closed_form_depth(integrator):
    """k = m ω² with ω·dt = OMEGA_DT: the resting depth is m g / k = g / ω² and the
    floor carries the weight."""
    rob = vertical_slider()
    sim = Simulation(rob, checker=CollisionChecker(rob), integrator=integrator)
    sim.state.set_q([RADIUS + 0.02])
    sim.step(1000)
    omega = OMEGA_DT / sim.dt
    assert sim.q[0] == pytest.approx(RADIUS - G / omega**2, abs=1e-10)
    assert abs(sim.qd[0]) < 1e-8
    (contact,) = sim.contact_forces
    assert contact.pair == ("link1", "floor")
    np.testing.assert_allclose(contact.force, [0.0, 0.0, MASS * G], rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(contact.normal, [0.0, 0.0, -1.0], atol=1e-12)
    assert contact.depth == pytest.approx(G / omega**2, rel=1e-6)


def _penetrating(rob, seed: int):
    """A configuration of ``rob`` and a world whose obstacles (a sphere, and a box's corner)
    each cut into the middle of a link capsule by 3 mm, leaving its ends free."""
    rng = np.random.default_rng(seed)
    q = rob.q_home + rng.uniform(-0.5, 0.5, rob.n_dofs)
    shapes = CollisionChecker(rob, World(floor=False)).shapes(q)
    capsules = [(name, s) for name, s in shapes if type(s).__name__ == "Capsule" and s.length > 0.15]
    (_, c1), (_, c2) = capsules[-1], capsules[-2]
    obstacles = {}
    for k, (cap, make) in enumerate([(c1, "sphere"), (c2, "box")]):
        axis, mid = cap.pose[:3, 2], cap.pose[:3, 3]
        side = np.cross(axis, rng.normal(size=3))
        side /= np.linalg.norm(side)
        if make == "sphere":
            obstacles["ball"] = Sphere(0.04, mid + side * (cap.radius + 0.04 - 0.003))
        else:  # a box in a generic orientation, its corner deepest
            frame = np.eye(4)
            frame[:3, :3] = np.linalg.qr(rng.normal(size=(3, 3)))[0]
            half = np.array([0.01, 0.03, 0.02])
            corner = frame[:3, :3] @ (half * np.sign(frame[:3, :3].T @ -side))  # support along -side
            frame[:3, 3] = mid + side * (cap.radius - 0.003) - corner
            obstacles["block"] = Box(2 * half, frame)
    return q, World(obstacles, floor=False)


@pytest.mark.parametrize("name,convention", [("ur5", None), ("panda", None), ("ur5", "modified")])
def test_contact_torque_is_minus_the_gradient_of_the_spring_energy(name, convention):
    """Without friction the contact torque is −∂U/∂q of U = Σ ½ k δ² (central differences),
    for standard and modified DH: the witness points' Jacobians are right."""
    rob = robot(name, convention)
    q, world = _penetrating(rob, 3)
    model = ContactModel(CollisionChecker(rob, world, self_collision=False))
    assert model.begin_step(q, np.zeros(rob.n_dofs), 1e-3)
    tau = model.torque(q, np.zeros(rob.n_dofs))
    assert len(model.forces) == 2 and np.abs(tau).max() > 10.0
    eps = 1e-7
    grad = np.array([(model.stored_energy(q + eps * e) - model.stored_energy(q - eps * e)) / (2 * eps)
                     for e in np.eye(rob.n_dofs)])
    np.testing.assert_allclose(tau, -grad, rtol=1e-5, atol=1e-5 * np.abs(tau).max())


def test_self_contact_torque_is_minus_the_gradient_of_the_spring_energy():
    """Links pushed into each other (the torque of equal and opposite forces at both
    witness points, a capsule end included): −∂U/∂q."""
    rob, checker, q = panda_in_self_contact()
    model = ContactModel(checker)
    assert model.begin_step(q, np.zeros(rob.n_dofs), 1e-3)
    tau = model.torque(q, np.zeros(rob.n_dofs))
    assert all(f.pair[1].startswith("link") for f in model.forces) and np.abs(tau).max() > 1.0
    eps = 1e-7
    grad = np.array([(model.stored_energy(q + eps * e) - model.stored_energy(q - eps * e)) / (2 * eps)
                     for e in np.eye(rob.n_dofs)])
    np.testing.assert_allclose(tau, -grad, rtol=1e-4, atol=1e-5 * np.abs(tau).max())


SLOPE = math.radians(20.0)


def _on_slope(friction: float, integrator: str = "rk4") -> tuple[Simulation, np.ndarray]:
    """The carriage's sphere resting on a 20° slope (a box turned about y), and the
    downhill direction in the x-z plane."""
    rob = planar_carriage()
    normal = np.array([math.sin(SLOPE), 0.0, math.cos(SLOPE)])
    slope = Box([3.0, 1.0, 0.2], pose([0.0, 0.0, 0.0], [0.0, SLOPE, 0.0]))
    sim = Simulation(rob, checker=CollisionChecker(rob, World({"slope": slope}, floor=False)), friction=friction,
                     integrator=integrator)
    centre = normal * (0.1 + RADIUS)
    sim.state.set_q([centre[0], centre[2]])
    return sim, np.array([math.cos(SLOPE), -math.sin(SLOPE)])


@pytest.mark.parametrize("friction", [0.0, 0.2])
def test_a_block_slides_down_a_slope_at_g_sin_minus_mu_cos(friction):
    sim, downhill = _on_slope(friction)
    sim.step(100)
    v1, t1 = sim.qd @ downhill, sim.time
    sim.step(200)
    v2, t2 = sim.qd @ downhill, sim.time
    expected = G * (math.sin(SLOPE) - friction * math.cos(SLOPE))
    assert (v2 - v1) / (t2 - t1) == pytest.approx(expected, rel=1e-4)


@pytest.mark.parametrize("integrator", ["rk4", "euler"])
def test_friction_holds_a_block_on_a_slope_inside_its_cone(integrator):
    """tan 20° = 0.36 < μ = 0.5: after settling the block does not creep at all."""
    sim, downhill = _on_slope(0.5, integrator)
    sim.step(300)
    held = sim.q.copy()
    sim.step(700)
    assert np.abs(sim.q - held).max() < 1e-9 and np.abs(sim.qd).max() < 1e-8
    (contact,) = sim.contact_forces
    # the slope carries the weight: normal m g cos θ, friction m g sin θ uphill
    np.testing.assert_allclose(contact.force, [0.0, 0.0, MASS * G], rtol=1e-6, atol=1e-6)


def total_energy(sim: Simulation) -> float:
    return sum(dynamics.energy(sim.robot, sim.q, sim.qd)) + sim.contact.stored_energy(sim.q)


def test_a_passive_ur5_dropped_onto_a_box_comes_to_rest_on_it():
    """The issue's number: at rest within 2 s, penetration under 5 mm; the box carries
    the arm (contact torque = gravity torque), and total energy never grows."""
    rob, world = ur5_over_box()
    checker = CollisionChecker(rob, world)
    sim = Simulation(rob, checker=checker, friction=0.5)
    energy, gained = total_energy(sim), 0.0
    for _ in range(200):
        sim.step(10)
        now = total_energy(sim)
        gained, energy = max(gained, now - energy), now
    assert sim.stopped is None and sim.time == pytest.approx(2.0)
    assert np.abs(sim.qd).max() < 1e-4
    assert min(checker.distance(sim.q).distance, 0.0) > -0.005
    assert {f.pair[1] for f in sim.contact_forces} == {"box"}
    tau = sim.contact.torque(sim.q, np.zeros(rob.n_dofs))
    np.testing.assert_allclose(tau, dynamics.gravity_torque(rob, sim.q), atol=1e-3)
    assert gained < 1e-6


@pytest.mark.parametrize("integrator", ["rk4", "euler"])
def test_the_compiled_contact_step_is_the_stage_by_stage_step(integrator):
    """ContactModel.step (one compiled call) takes the operations of the NumPy stages:
    forward dynamics of τ plus the contact torque at every stage's state, combined by
    runge_kutta, bit for bit, on the UR5 landing on the box (friction anchors held)."""
    rob, world = ur5_over_box()
    sim = Simulation(rob, checker=CollisionChecker(rob, world), friction=0.5, integrator=integrator)
    for _ in range(600):  # until the forearm meets the box
        sim.step()
        if sim.contact_forces:
            break
    contact, dt = sim.contact, sim.dt
    q, qd, tau = sim.q.copy(), sim.qd.copy(), np.full(rob.n_dofs, 0.3)
    assert contact.begin_step(q, qd, dt)

    def accel(_offset, qs, vs):
        return dynamics.forward_dynamics(rob, qs, vs, tau + contact.torque(qs, vs))

    expected = runge_kutta(integrator, q, qd, dt, accel(0.0, q, qd), accel)
    g0 = dynamics.compiled_kernels(rob)[2]
    got = contact.step(q, qd, tau, None, dt, integrator == "rk4", g0)
    assert np.abs(contact.torque(q, qd)).max() > 1.0  # the step is in contact
    for a, b in zip(got, expected):
        assert np.array_equal(a, b)


def _step_by_step(kind: type) -> type:
    """``kind`` with the same torque, evaluated by the loop one step at a time (no compiled
    multi-step call)."""
    return type(f"StepByStep{kind.__name__}", (kind,), {"sampled_law": lambda self: None})


@pytest.mark.parametrize("kind, friction, stops", [(Passive, 0.5, False), (Passive, 0.0, False), (PD, 0.5, False),
                                                   (Passive, 0.5, True)])
def test_the_compiled_multi_step_call_in_contact_equals_the_loop_step_by_step(kind, friction, stops, monkeypatch):
    """The UR5 falling onto the box, landing, bouncing and coming to rest on it (PD: driven
    toward a pose below the box's top, pressed onto it; ``stops``: its elbow's range cut
    to ±0.05 rad about home, so the elbow meets its stops while the arm touches the box):
    ``step(n)`` running the contact inside one compiled call gives the bits of the loop
    stepping once at a time (the contact torque at every stage, the friction anchors
    moved at every step's start, the stops met in contact handed back to the loop), and
    the compiled call takes the steps whose pairs near contact do not change."""
    rob, world = ur5_over_box()
    if stops:
        q_min, q_max = rob.q_min.copy(), rob.q_max.copy()
        q_min[2], q_max[2] = rob.q_home[2] - 0.05, rob.q_home[2] + 0.05
        rob = dataclasses.replace(rob, q_min=q_min, q_max=q_max)
    runs, loop_steps, events = [], [], []
    for cls in (kind, _step_by_step(kind)):
        controller = cls(rob) if kind is Passive else cls(rob, control_gains(rob, bandwidth=1.0))
        sim = Simulation(rob, controller=controller, checker=CollisionChecker(rob, world), friction=friction)
        sim.state.set_q_des(rob.q_home + [0.0, 0.5, 0.0, 0.0, 0.0, 0.0])  # PD: the shoulder turned into the box
        called = [0]
        one_step = Simulation._step

        def counted(self, desired_at, called=called, one_step=one_step):
            called[0] += 1
            return one_step(self, desired_at)

        monkeypatch.setattr(Simulation, "_step", counted)
        rows = []
        for _ in range(16):
            assert sim.step(50) == 50
            forces = sim.contact_forces
            rows.append(np.concatenate([sim.q, sim.qd, sim.qdd, sim.effort, sim.at_limit, sim.limit_torque,
                                        [sim.time, sim.steps, len(forces)],
                                        *(np.concatenate([f.point, f.normal, f.force, [f.depth]]) for f in forces)]))
        runs.append(rows)
        loop_steps.append(called[0])
        events.append(sim.take_events())
    for compiled, stepwise in zip(*runs):
        np.testing.assert_array_equal(compiled, stepwise)
    assert events[0] == events[1]
    assert not stops or any(event.joint == 2 for event in events[0])  # the elbow met its stops
    assert runs[0][-1][6 * rob.n_dofs + 2] > 0  # it ends touching the box
    # most steps in the compiled call (a step in contact holding a joint on its stop is the loop's)
    assert loop_steps[1] == 800 and loop_steps[0] < (800 if stops else 200)


@pytest.mark.parametrize("friction", [0.0, 0.5])
def test_contact_never_adds_energy_step_by_step(friction):
    """Kinetic + potential + spring energy, every RK4 step of the fall and the landing."""
    rob, world = ur5_over_box()
    sim = Simulation(rob, checker=CollisionChecker(rob, world), friction=friction)
    sim.step(200)  # the fall, before the box
    energy, gained, landed = total_energy(sim), 0.0, False
    for _ in range(300):
        sim.step()
        now = total_energy(sim)
        gained, energy = max(gained, now - energy), now
        landed |= bool(sim.contact_forces)
    assert landed and gained < 1e-6


def test_semi_implicit_euler_ends_a_landing_with_less_energy():
    """Symplectic Euler's energy wobbles by O(h) each step (0.4 J at this fall's speed), so
    only the landing as a whole is checked: it ends with less energy than it began."""
    rob, world = ur5_over_box()
    sim = Simulation(rob, checker=CollisionChecker(rob, world), integrator="euler")
    sim.step(200)
    before = total_energy(sim)
    sim.step(300)
    assert sim.contact_forces and total_energy(sim) < before - 1.0


@pytest.mark.parametrize("name", sweep([n for n in ROBOT_NAMES if robot(n).inertials is not None],
                                       keep=("ur5", "panda", "planar3")))
def test_shipped_robots_dropped_onto_the_floor_do_not_diverge(name):
    rob = robot(name)
    checker = CollisionChecker(rob)
    sim = Simulation(rob, checker=checker, friction=0.5)
    sim.step(1500)
    assert sim.stopped is None and np.isfinite(sim.q).all()
    worst = min(checker.distance(sim.q).distance, 0.0)
    assert worst > -0.005, f"{name}: {-worst * 1000:.1f} mm deep"


def test_steps_far_from_contact_are_computed_as_without_it():
    rob = dataclasses.replace(robot("ur5"), base_tf=HomogeneousTransform.from_xyz_rpy([0, 0, 5.0], [0, 0, 0]))
    free, touching = Simulation(rob), Simulation(rob, checker=CollisionChecker(rob))
    free.step(200)
    touching.step(200)
    assert np.array_equal(free.q, touching.q) and np.array_equal(free.qd, touching.qd)
    assert touching.contact_forces == [] and not touching.contact.active


def test_the_active_margin_bounds_a_step_of_motion():
    """No pair farther than the margin at a step's start can touch during it: the margin
    covers twice the lever-arm bound of every point's motion."""
    rob = robot("ur5")
    model = ContactModel(CollisionChecker(rob))
    assert model.margin(rob.q_home, np.zeros(6), 1e-3) == MIN_MARGIN
    qd = np.full(6, 3.0)
    fast = model.margin(rob.q_home, qd, 1e-3)
    Q = rob.q_home + np.linspace(0.0, 1e-3, 11)[:, None] * qd
    shapes = [CollisionChecker(rob).shapes(x) for x in Q]
    moved = max(np.linalg.norm(s[k][1].pose[:3, 3] - shapes[0][k][1].pose[:3, 3]) for s in shapes
                for k in range(len(s)))
    assert fast >= 2.0 * moved


def test_bad_arguments_are_refused():
    rob = vertical_slider()
    with pytest.raises(ValueError, match="checker must be a CollisionChecker built for this simulation's robot"):
        Simulation(rob, checker=CollisionChecker(planar_carriage()))
    with pytest.raises(ValueError, match="friction must be a finite coefficient >= 0"):
        Simulation(rob, checker=CollisionChecker(rob), friction=-0.1)
    with pytest.raises(ValueError, match="checker must be a CollisionChecker"):
        ContactModel("floor")
