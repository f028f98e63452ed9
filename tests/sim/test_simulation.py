"""The physics loop (simulation.py): conservation, equilibria, tracking, limits, divergence."""
from __future__ import annotations

import math

import numpy as np
import pytest

from robot_sim import dynamics
from robot_sim.viewer import settings as vs
from robot_sim.control.controllers import PD, ComputedTorque, Controller, Gains, Passive, PDGravity, control_gains
from robot_sim.model.inertials import Drives
from kin_helpers import ROBOT_NAMES, robot, sweep
from robot_sim.kinematics import forward_kinematics, jacobian
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.io.robot_file import load_robot
from robot_sim.model.state import RobotState
from sim_helpers import PENDULUM_LENGTH, PENDULUM_MASS, frictionless, pendulum, quintic
from robot_sim.sim.simulation import LimitEvent, Simulation
from robot_sim.viewer.session import ViewerSession


def _energy(rob, q, qd) -> float:
    kinetic, potential = dynamics.energy(rob, q, qd)
    return float(kinetic + potential)


def _swinging(rob) -> RobotState:
    """humanoid7 15° from hanging, every joint turning (rad/s)."""
    state = RobotState(rob)
    state.set_q(np.radians([0.0, 165.0, 0.0, -20.0, 0.0, 15.0, 0.0]))
    state.set_qd([0.3, 0.0, -0.3, 0.0, 0.3, 0.0, 0.3])
    return state


def test_rk4_conserves_energy_of_the_7dof_arm_over_5_seconds():
    """No friction, no control, no limits: released 15° from hanging with every joint
    turning, the arm swings in 3-D (kinetic and potential energy trade over 10 % of the
    total) and the total energy (potential from world z = 0) stays within 1e-6 of its
    initial value, relative, at every 10 ms of 5 s at 1 kHz.

    (Released from higher up, humanoid7's light wrist whips to over 100 rad/s, and a
    1 ms RK4 step no longer resolves it to 1e-6: that is the step, not the dynamics.)"""
    rob = frictionless("humanoid7")
    sim = Simulation(rob, _swinging(rob), integrator="rk4", dt=1e-3)
    e0 = _energy(rob, sim.q, sim.qd)
    drift, kinetic, qs = [], [], []
    for _ in range(500):
        assert sim.step(10) == 10
        drift.append(abs(_energy(rob, sim.q, sim.qd) - e0))
        kinetic.append(dynamics.energy(rob, sim.q, sim.qd)[0])
        qs.append(sim.q.copy())
    assert sim.time == pytest.approx(5.0)
    assert max(kinetic) - min(kinetic) > 0.1 * abs(e0)  # energy really moves between forms
    assert np.all(np.ptp(qs, axis=0) > 0.1)  # every joint takes part
    assert max(drift) / abs(e0) < 1e-6


def test_semi_implicit_euler_energy_error_is_first_order_and_rk4_far_smaller():
    """Over 1 s of the same swing: symplectic Euler's energy error halves with the step
    (O(h), bounded), and RK4's at 1 ms is five orders of magnitude below Euler's."""
    rob = frictionless("humanoid7")

    def worst_error(integrator: str, dt: float) -> float:
        sim = Simulation(rob, _swinging(rob), integrator=integrator, dt=dt)
        e0 = _energy(rob, sim.q, sim.qd)
        steps = round(0.01 / dt)
        return max(abs(_energy(rob, sim.q, sim.qd) - e0) / abs(e0) for _ in range(100) if sim.step(steps))

    euler, euler_half = worst_error("euler", 1e-3), worst_error("euler", 5e-4)
    assert 0.35 < euler_half / euler < 0.65
    assert worst_error("rk4", 1e-3) < 1e-5 * euler


class _Damper(Controller):
    """τ = −c M(q) q̇: damps every mode of the arm at the same rate c [1/s], however light
    (joint friction B q̇ on humanoid7's nearly massless shoulder housings would make the
    equations stiff for a 1 ms explicit step)."""

    mode = "damper"

    def __init__(self, rob, rate: float) -> None:
        self.robot, self.rate = rob, rate

    def torque(self, q, qd, q_des, qd_des, qdd_des):
        return -self.rate * (dynamics.mass_matrix(self.robot, q) @ qd)


def test_damped_arm_comes_to_rest_at_the_gravity_equilibrium():
    """Released at home under gravity with a damper: the arm falls, swings, and comes to
    rest where the gravity torque vanishes (torque balance at rest), hanging below its base."""
    rob = frictionless("humanoid7")
    sim = Simulation(rob, controller=_Damper(rob, 3.0), integrator="euler")
    g0 = np.abs(dynamics.gravity_torque(rob, sim.q)).max()
    assert g0 > 1.0  # home is far from equilibrium
    sim.step(15000)
    assert sim.stopped is None
    assert np.abs(sim.qd).max() < 1e-6
    assert np.abs(dynamics.gravity_torque(rob, sim.q)).max() < 1e-6 * g0
    # the equilibrium it found is the stable one: the endeffector hangs below the base
    ee = forward_kinematics(rob, sim.q)[:3, 3]
    assert ee[2] < rob.base_tf.mat[2, 3] - 0.5


def test_computed_torque_tracks_a_quintic_joint_trajectory():
    """Exact model, 1 kHz, torque held over each step: the joint error stays below 1e-3 rad
    (measured: 4.2e-4) along a 2 s rest-to-rest quintic moving every joint by 0.5–1.5 rad
    (peak speed 1.4 rad/s), and the arm ends at the goal to 1e-6 rad."""
    rob = robot("humanoid7")
    goal = rob.q_home + np.array([1.0, 0.8, 1.2, -0.6, -0.9, -0.5, 1.5])
    reference = quintic(rob.q_home, goal, 2.0)
    sim = Simulation(rob, controller=ComputedTorque(rob, control_gains(rob)), reference=reference)
    worst = 0.0
    for _ in range(300):
        sim.step(10)
        worst = max(worst, np.abs(sim.q - reference(sim.time)[0]).max())
    assert sim.stopped is None
    assert worst < 1e-3
    assert np.abs(sim.q - goal).max() < 1e-6
    np.testing.assert_allclose(sim.state.q_des(), goal)  # the reference is published as desired


def test_computed_torque_error_follows_the_critically_damped_closed_form():
    """From rest 0.2 rad off a fixed goal, e(t) = e0 (1 + ωt) e^(−ωt) (ζ = 1) on every joint."""
    rob = robot("humanoid7")
    gains = control_gains(rob, bandwidth=2.0, damping=1.0)
    state = RobotState(rob)
    e0 = np.array([0.2, -0.2, 0.2, 0.2, -0.2, 0.2, 0.2])
    state.set_q(rob.q_home - e0)
    sim = Simulation(rob, state, controller=ComputedTorque(rob, gains))
    w = gains.omega
    for _ in range(10):
        sim.step(50)
        expected = e0 * (1 + w * sim.time) * math.exp(-w * sim.time)
        np.testing.assert_allclose(rob.q_home - sim.q, expected, atol=0.01 * 0.2)


def test_pd_plus_gravity_holds_a_pose_with_zero_steady_state_error_and_pd_alone_sags():
    """From rest at home toward a pose 0.1–0.4 rad away: PD + gravity converges to it (the
    error keeps shrinking, exponentially, below 1e-4 rad after 6 s); PD alone settles off target where its spring
    carries gravity, Kp (q_des − q) = g(q)."""
    rob = frictionless("humanoid7", limits=True)
    gains = control_gains(rob)
    target = rob.q_home + np.array([0.3, 0.4, -0.3, 0.3, 0.2, -0.3, 0.1])
    sims = {}
    for controller in (PDGravity(rob, gains), PD(rob, gains)):
        state = RobotState(rob)
        state.set_q_des(target)
        sims[controller.mode] = Simulation(rob, state, controller=controller, integrator="euler")
    pdg, pd = sims["pdg"], sims["pd"]
    pdg.step(3000)
    error_3s = np.abs(pdg.q - target).max()
    pdg.step(3000)
    error_6s = np.abs(pdg.q - target).max()
    assert error_6s < 1e-4 and error_6s < 0.05 * error_3s
    pd.step(15000)
    assert np.abs(pd.qd).max() < 1e-6
    assert np.abs(pd.q - target).max() > 1e-2
    np.testing.assert_allclose(gains.kp * (target - pd.q), dynamics.gravity_torque(rob, pd.q), atol=1e-5)


def test_joint_limit_is_a_hard_stop_reported_once():
    lo, hi = -0.4, 0.6
    rob = pendulum(limits=(lo, hi))
    sim = Simulation(rob)  # passive: falls toward q = −π/2
    sim.step(1000)
    assert sim.q[0] == lo  # stops exactly on the limit
    assert sim.qd[0] == 0.0  # velocity into the limit zeroed
    assert sim.at_limit.tolist() == [True]
    events = sim.take_events()
    assert len(events) == 1 and isinstance(events[0], LimitEvent)
    assert (events[0].joint, events[0].side, events[0].q) == (0, "min", lo)
    # free fall from 0 to lo takes about sqrt(2·|lo|/ (3g/2L · cos)) ~ 0.2 s: the event
    # time is when the joint arrived, not when it was read
    assert 0.05 < events[0].time < 0.5
    assert sim.take_events() == []
    # resting on the stop produces no new events; a controller can lift it off again
    sim.controller = PDGravity(rob, control_gains(rob))
    sim.state.set_q_des([0.0])
    sim.step(2000)
    assert sim.at_limit.tolist() == [False] and abs(sim.q[0]) < 1e-3
    assert sim.take_events() == []


def test_effort_limit_saturates_the_command_and_reports_it():
    limit = 1.5  # N·m; gravity alone needs m g L/2 = 4.9 N·m to hold the rod level
    rob = pendulum(drives=Drives.from_arrays(1, effort_limit=[limit]))
    gains = Gains(kp=np.array([500.0]), kd=np.array([20.0]), omega=1.0, zeta=1.0)
    state = RobotState(rob)
    state.set_q_des([0.5])
    sim = Simulation(rob, state, controller=PD(rob, gains))
    sim.step(1)
    assert sim.effort_command[0] == pytest.approx(250.0)
    assert sim.effort[0] == limit and sim.saturated.tolist() == [True]
    assert sim.state.joint_state.u[0] == limit  # JointState.u is the applied effort
    # the arm felt the saturated torque, not the command
    np.testing.assert_allclose(sim.qdd, dynamics.forward_dynamics(rob, [0.0], [0.0], [limit]), rtol=1e-12)
    sim.step(3000)
    assert sim.q[0] < 0.0  # too weak to lift the rod: it sags despite the PD demand


class _LawOutsideTheStep(ComputedTorque):
    """Computed torque evaluated by its own call, then stepped (neither fused into the
    step call nor run in the compiled multi-step call)."""

    integrates = False

    def sampled_law(self) -> None:
        return None


def test_computed_torque_in_the_step_call_equals_the_controller_called_first():
    """PUMA 560 with its drives (friction, effort limits that saturate on the way) and
    its stops, computed torque toward a set point beyond a limit: the fused step and the
    controller-then-step loop give identical bits; a NaN reference is refused by the
    controller's own check, naming it."""
    rob = robot("puma560")
    goal = np.clip(rob.q_home + 1.5, None, rob.q_max + 0.2)
    runs = []
    for kind in (ComputedTorque, _LawOutsideTheStep):
        state = RobotState(rob)
        state.set_q_des(goal)
        sim = Simulation(rob, state, kind(rob, control_gains(rob, bandwidth=4.0)))
        rows = []
        for _ in range(400):
            sim.step(1)
            rows.append(np.concatenate([sim.q, sim.qd, sim.qdd, sim.effort, sim.effort_command, sim.saturated, sim.at_limit]))
        runs.append(np.array(rows))
    np.testing.assert_array_equal(runs[0], runs[1])
    n = rob.n_dofs
    assert runs[0][:, 5 * n : 6 * n].any() and runs[0][:, 6 * n :].any()  # it saturated and reached a stop
    sim = Simulation(rob, controller=ComputedTorque(rob, control_gains(rob)),
                     reference=lambda t: (np.full(n, np.nan), np.zeros(n), np.zeros(n)))
    with pytest.raises(ValueError, match="q_des must be finite"):
        sim.step(1)


def _one_step_at_a_time(kind: type[Controller]) -> type[Controller]:
    """``kind`` with the same torque, evaluated by the loop step by step (no compiled law,
    no fused step)."""
    return type(f"StepByStep{kind.__name__}", (kind,), {"integrates": False, "sampled_law": lambda self: None})


@pytest.mark.parametrize("kind", [Passive, PD, PDGravity, ComputedTorque])
def test_the_compiled_multi_step_call_equals_the_loop_step_by_step(kind: type[Controller]) -> None:
    """PUMA 560 with its drives (friction, effort and velocity limits) and its stops, each
    sampled law toward a set point beyond a limit: ``step(n)`` running the law inside one
    compiled call gives the bits of the loop evaluating the controller and stepping once
    at a time, through saturation, stop arrivals and releases (handed back to the loop).
    Passive: Panda, which falls into its stops (PUMA's friction holds it)."""
    rob = robot("panda" if kind is Passive else "puma560")
    goal = np.clip(rob.q_home + 1.5, None, rob.q_max + 0.2)
    runs, events = [], []
    for cls in (kind, _one_step_at_a_time(kind)):
        state = RobotState(rob)
        state.set_q_des(goal)
        sim = Simulation(rob, state, cls(rob) if kind is Passive else cls(rob, control_gains(rob, bandwidth=4.0)))
        rows = []
        for _ in range(20):
            assert sim.step(37) == 37
            rows.append(np.concatenate([sim.q, sim.qd, sim.qdd, sim.effort, sim.effort_command, sim.saturated,
                                        sim.velocity_limited, sim.at_limit, sim.limit_torque, [sim.time, sim.steps]]))
        runs.append(np.array(rows))
        events.append(sim.take_events())
    np.testing.assert_array_equal(runs[0], runs[1])
    assert events[0] == events[1]
    n = rob.n_dofs
    if kind is not Passive:
        assert runs[0][:, 5 * n : 6 * n].any()  # it saturated
    assert events[0] or runs[0][:, 7 * n : 8 * n].any()  # it reached a stop


def test_velocity_limit_is_enforced_by_the_drive():
    vmax = 0.8
    rob = pendulum(drives=Drives.from_arrays(1, velocity_limit=[vmax]))
    sim = Simulation(rob)
    speeds, limited = [], False
    for _ in range(200):
        sim.step(5)
        speeds.append(abs(sim.qd[0]))
        limited |= bool(sim.velocity_limited[0])
    assert max(speeds) == pytest.approx(vmax) and limited


def test_divergence_stops_and_keeps_the_last_finite_state():
    rob = pendulum()
    gains = Gains(kp=np.array([1e9]), kd=np.array([0.0]), omega=1.0, zeta=1.0)
    state = RobotState(rob)
    state.set_q_des([0.3])
    sim = Simulation(rob, state, controller=PD(rob, gains), integrator="euler")
    last = (sim.q.copy(), sim.qd.copy(), sim.time)
    for _ in range(5000):
        if sim.step(1) == 0:
            break
        last = (sim.q.copy(), sim.qd.copy(), sim.time)
    assert sim.stopped is not None and "non-finite" in sim.stopped
    assert sim.stopped.startswith(f"simulation stopped at t = {last[2]:.3f} s")
    np.testing.assert_array_equal(sim.q, last[0])
    np.testing.assert_array_equal(sim.qd, last[1])
    assert np.isfinite(sim.state.q()).all() and np.isfinite(sim.state.qd()).all()
    np.testing.assert_array_equal(sim.state.q(), last[0])
    assert sim.step(10) == 0 and sim.time == last[2]


@pytest.mark.parametrize("name", sweep(ROBOT_NAMES))
def test_every_shipped_robot_simulates_2_seconds_passive(name):
    rob = robot(name)
    sim = Simulation(rob)
    assert sim.step(2000) == 2000
    assert sim.stopped is None and sim.time == pytest.approx(2.0)
    assert np.isfinite(sim.q).all() and np.isfinite(sim.qd).all()
    assert np.all(sim.q >= rob.q_min) and np.all(sim.q <= rob.q_max)


def test_advance_runs_whole_fixed_steps_and_carries_the_remainder():
    sim = Simulation(pendulum(), dt=1e-3, max_lag=0.05)
    assert sim.advance(0.0025) == 2
    assert sim.advance(0.0006) == 1  # 0.5 ms carried + 0.6 ms
    assert sim.time == pytest.approx(0.003)
    assert math.isnan(sim.real_time_factor)
    assert sim.advance(1.0) == 50  # at most max_lag of simulated time per call
    assert sim.real_time_factor == pytest.approx(0.053 / 1.0031)
    with pytest.raises(ValueError, match="dt_wall must be a finite number of seconds >= 0, got -1"):
        sim.advance(-1)


def test_pull_spring_moves_the_endeffector_and_balances_the_controller():
    """PD + gravity holding home, endeffector pulled 10 cm sideways: it moves toward the
    point and settles where the PD spring carries the pull, Kp (q_des − q) = −Jᵀ f."""
    rob = frictionless("humanoid7", limits=True)
    gains = control_gains(rob)
    sim = Simulation(rob, controller=PDGravity(rob, gains), integrator="euler")
    ee0 = forward_kinematics(rob, sim.q)[:3, 3]
    point = ee0 + np.array([0.0, 0.1, 0.0])
    sim.set_pull(point, stiffness=50.0, damping=5.0)
    sim.step(5000)
    ee = forward_kinematics(rob, sim.q)[:3, 3]
    assert np.linalg.norm(point - ee) < np.linalg.norm(point - ee0) - 0.01
    force = 50.0 * (point - ee)
    np.testing.assert_allclose(sim.pull_force, force, atol=1e-6)
    np.testing.assert_allclose(gains.kp * (rob.q_home - sim.q), -jacobian(rob, sim.q)[:3].T @ force, atol=1e-5)
    sim.clear_pull()
    sim.step(5000)
    np.testing.assert_allclose(sim.q, rob.q_home, atol=1e-6)


def test_bad_arguments_are_refused():
    rob = pendulum()
    with pytest.raises(ValueError, match="dt must be a positive finite number of seconds, got 0"):
        Simulation(rob, dt=0)
    with pytest.raises(ValueError, match="integrator must be one of rk4, euler, got 'verlet'"):
        Simulation(rob, integrator="verlet")
    with pytest.raises(ValueError, match="state must be a RobotState of a robot with 1 joints, got 6"):
        Simulation(rob, RobotState(robot("puma560")))
    sim = Simulation(rob)
    with pytest.raises(ValueError, match=r"point must be a finite \(3,\) position in metres"):
        sim.set_pull([0.0, 1.0], 10.0)
    with pytest.raises(ValueError, match="stiffness must be a finite number >= 0, got -1"):
        sim.set_pull([0.0, 0.0, 1.0], -1.0)


def test_a_robot_without_inertial_data_is_refused_naming_the_remedy():
    rob = RobotParams.from_arrays("bare", [0.3], [0.0], [0.0], [0.0], [JTYPE_REVOLUTE])
    with pytest.raises(ValueError, match="estimate_inertials"):
        Simulation(rob)


def test_pendulum_helper_is_what_it_claims():
    """Holding the level rod takes m g L/2 (positive q lifts it); hanging it needs none."""
    rob = pendulum()
    hold = dynamics.gravity_torque(rob, [0.0])[0]
    assert hold == pytest.approx(PENDULUM_MASS * 9.81 * PENDULUM_LENGTH / 2, rel=1e-12)
    assert dynamics.gravity_torque(rob, [-math.pi / 2])[0] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("name, bound_m", [("humanoid7", 0.005), ("ur5", 0.005), ("puma560", 0.015)])
def test_computed_torque_tracks_the_circle_demo(name: str, bound_m: float) -> None:
    """The viewer's circle demo (radius 0.1 m, period 4 s) sets the desired state by
    differential IK; under computed torque the simulated endeffector stays within
    ``bound_m`` of the circle's point over two periods, and the run never stops.  The
    demo gives no desired acceleration, so the residual is the 2 Hz loop's lag (about
    3 mm); PUMA 560's Coulomb friction (|G|·Tc ≈ 25 N·m at joint 1) switches sign where
    a joint reverses, which costs a few more millimetres there."""
    session = ViewerSession(load_robot(name))
    session.set_motion("ct")
    session.toggle_demo()
    errors = []
    for _ in range(round(2 * vs.DEMO_CIRCLE_PERIOD_S / 0.01)):
        session.step(0.01)
        point, _ = session.demo.point_and_velocity()
        errors.append(np.linalg.norm(session.kin.endeff_tf.t() - point))
    assert session.motion.sim.stopped is None
    assert session.motion.sim.time == pytest.approx(2 * vs.DEMO_CIRCLE_PERIOD_S, abs=1e-9)
    assert max(errors) < bound_m, f"{name}: {max(errors) * 1000:.2f} mm"


def test_state_set_from_outside_is_where_the_next_step_starts():
    """One source of truth: q and qd set through ``sim.state`` before ``step`` are simulated
    from, exactly as a fresh Simulation on that state would be (no load_state call)."""
    rob = frictionless("humanoid7")
    sim = Simulation(rob)
    sim.step(50)
    q0 = rob.q_home + 0.3
    qd0 = np.linspace(-0.5, 0.5, rob.n_dofs)
    sim.state.set_q(q0)
    sim.state.set_qd(qd0)
    sim.step(20)
    fresh_state = RobotState(rob)
    fresh_state.set_q(q0)
    fresh_state.set_qd(qd0)
    fresh = Simulation(rob, fresh_state)
    fresh.step(20)
    np.testing.assert_array_equal(sim.state.q(), fresh.state.q())
    np.testing.assert_array_equal(sim.state.qd(), fresh.state.qd())
    # and a state nobody touched keeps the loop's own (unrounded) values: 20 + 20 steps
    # in two calls equal 40 in one
    a, b = Simulation(rob), Simulation(rob)
    a.step(20)
    a.step(20)
    b.step(40)
    np.testing.assert_array_equal(a.q, b.q)
