"""BatchSimulation: n arms stepped at once end bit for bit where n single Simulations
with the same inputs end (gains, references and initial states per environment; effort
and velocity limits, joint stops and friction of PUMA 560's drives), and an environment
that diverges stops alone and says why."""
from __future__ import annotations

import numpy as np
import pytest

from robot_sim.sim.batch import BatchSimulation
from robot_sim.control.controllers import control_gains
from robot_sim.control.factory import make_controller
from robot_sim.sim.simulation import Simulation
from robot_sim.io.robot_file import load_robot

N_ENVS = 4
STEPS = 400


def _singles(robot, mode, gains, q0, qd0, q_des, integrator, steps, reference=None):
    sims = []
    for i in range(len(q0)):
        sim = Simulation(robot, controller=make_controller(mode, robot, gains[i]), integrator=integrator,
                         reference=None if reference is None else (lambda t, i=i: tuple(x[i] for x in reference(t))))
        sim.state.set_q(q0[i])
        sim.state.set_qd(qd0[i])
        sim.state.set_q_des(q_des[i])
        sim.load_state()
        sim.step(steps)
        sims.append(sim)
    return sims


def _assert_same(batch, sims):
    for i, sim in enumerate(sims):
        for name in ("q", "qd", "qdd", "effort", "effort_command", "saturated", "velocity_limited", "at_limit"):
            assert np.array_equal(getattr(batch, name)[i], getattr(sim, name)), f"env {i}: {name} differs"
        assert batch.stopped[i] == sim.stopped
        assert batch.time[i] == sim.time and batch.steps[i] == sim.steps
        assert [e for env, e in batch.events if env == i] == sim.events


@pytest.mark.parametrize(("name", "mode", "integrator"), [
    pytest.param("puma560", "ct", "rk4", marks=pytest.mark.slow), ("puma560", "pd", "rk4"),
    ("puma560", "pdg", "euler"), ("panda", "ct", "rk4"), pytest.param("panda", "passive", "rk4", marks=pytest.mark.slow),
    ("stanford", "pdg", "rk4"),
])
def test_batch_equals_single_simulations_bit_for_bit(name, mode, integrator):
    robot = load_robot(name)
    n = robot.n_dofs
    rng = np.random.default_rng(len(name) + len(mode))
    lo = np.where(np.isfinite(robot.q_min), robot.q_min, -np.pi)
    hi = np.where(np.isfinite(robot.q_max), robot.q_max, np.pi)
    q0 = lo + (hi - lo) * rng.uniform(0.05, 0.95, (N_ENVS, n))
    q0[0] = robot.q_home
    qd0 = rng.normal(scale=0.5, size=(N_ENVS, n))
    q_des = lo + (hi - lo) * rng.uniform(-0.2, 1.2, (N_ENVS, n))  # beyond the limits: the stops act
    gains = [control_gains(robot, bandwidth=b, damping=z) for b, z in zip(rng.uniform(1, 8, N_ENVS), rng.uniform(0.5, 1.2, N_ENVS))]
    batch = BatchSimulation(robot, N_ENVS, controller=mode, gains=None if mode == "passive" else gains, integrator=integrator)
    batch.set_state(q0, qd0)
    batch.set_reference(q=q_des)
    batch.step(STEPS)
    sims = _singles(robot, mode, [None if mode == "passive" else g for g in gains], q0, qd0, q_des, integrator, STEPS)
    _assert_same(batch, sims)
    if name == "puma560" and mode != "passive":  # the case exercises the limits it claims to
        assert batch.saturated.any() or any(s.saturated.any() for s in sims) or batch.events


def test_the_batch_resolves_its_stops_with_the_one_resolver_and_no_simulation(monkeypatch):
    """Steps that hit a stop go through sim.stops' resolver directly: no scratch
    Simulation is built (one used to lend the batch its time for a while), and every
    arrival carries its own environment's time within the step that met it."""
    robot = load_robot("puma560")
    batch = BatchSimulation(robot, 2, controller="pd", integrator="rk4")
    lo, hi = robot.q_min, robot.q_max
    assert np.isfinite(lo).all() and np.isfinite(hi).all()
    batch.set_state(np.vstack([lo + 0.01 * (hi - lo), hi - 0.01 * (hi - lo)]))
    batch.set_reference(q=np.vstack([lo - 0.5, hi + 0.5]))  # each pulled past its nearest limits

    def refused(*_args, **_kwargs):
        raise AssertionError("BatchSimulation built a Simulation")

    monkeypatch.setattr(Simulation, "__init__", refused)
    for _ in range(STEPS):
        before = batch.time.copy()
        seen = len(batch.events)
        batch.step()
        for env, event in batch.events[seen:]:
            assert before[env] <= event.time <= batch.time[env]
    assert {env for env, _ in batch.events} == {0, 1}


def test_batch_follows_a_reference_function_per_environment():
    robot = load_robot("ur5")
    n = robot.n_dofs
    amp = np.linspace(0.1, 0.4, N_ENVS)[:, None] * np.ones(n)

    def reference(t):
        return robot.q_home + amp * np.sin(2 * t), 2 * amp * np.cos(2 * t), -4 * amp * np.sin(2 * t)

    batch = BatchSimulation(robot, N_ENVS, controller="ct", reference=reference)
    batch.step(300)
    q0 = np.tile(robot.q_home, (N_ENVS, 1))
    sims = _singles(robot, "ct", [None] * N_ENVS, q0, np.zeros_like(q0), q0, "rk4", 300, reference)
    _assert_same(batch, sims)
    assert np.abs(batch.q - reference(batch.time[0])[0]).max() < 0.02 * np.abs(amp).max() / 0.1  # it tracks


def test_a_diverging_environment_stops_alone_and_says_why():
    robot = load_robot("ur5")
    n = robot.n_dofs
    gains = [control_gains(robot)] * N_ENVS
    wild = control_gains(robot, kp=np.full(n, 1e306), kd=np.zeros(n))  # its effort overflows
    gains[2] = wild
    q_des = np.tile(robot.q_home + 0.2, (N_ENVS, 1))
    batch = BatchSimulation(robot, N_ENVS, controller="pd", gains=gains)
    batch.set_reference(q=q_des)
    assert batch.step(50) == 50
    assert batch.running.tolist() == [True, True, False, True]
    assert batch.stopped[2].startswith("simulation stopped at t = 0.000 s: the pd controller returned a non-finite effort")
    assert batch.steps.tolist() == [50, 50, 0, 50]
    q0 = np.tile(robot.q_home, (N_ENVS, 1))
    _assert_same(batch, _singles(robot, "pd", gains, q0, np.zeros_like(q0), q_des, "rk4", 50))


def test_bad_arguments_are_refused_naming_them():
    robot = load_robot("ur5")
    with pytest.raises(ValueError, match=r"n_envs must be an integer 1\.\.100000, got"):
        BatchSimulation(robot, 0)
    with pytest.raises(ValueError, match="integrator must be one of rk4, euler"):
        BatchSimulation(robot, 2, integrator="rk2")
    batch = BatchSimulation(robot, 3, controller="pd")
    with pytest.raises(ValueError, match=r"q must have shape \(6,\) or \(3, 6\)"):
        batch.set_state(np.zeros((2, 6)))
    with pytest.raises(ValueError, match="q reference must be finite"):
        batch.set_reference(q=np.full(6, np.nan))
    with pytest.raises(ValueError, match="gains must be one Gains or a sequence of 3"):
        BatchSimulation(robot, 3, controller="pd", gains=[control_gains(robot)] * 2)
