"""Task-space controllers in BatchSimulation: each environment equals a Simulation of it.

The batch evaluates the laws batched (NumPy over (n_envs, n)), the Simulation one arm at a
time (the compiled OSC step): the same laws, so the states agree to round-off.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from kin_helpers import robot
from robot_sim.sim.batch import BatchSimulation
from robot_sim.control.controllers import control_gains
from robot_sim.control.factory import make_controller
from robot_sim.sim.simulation import Simulation
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.state import RobotState
from robot_sim.transforms import rot_from_angle_axis

STEPS = 100  # 0.1 s: the batch of a few arms costs about 10 ms a step (NumPy per stage)


def _goals(rob, q0: np.ndarray) -> np.ndarray:
    """Three desired poses (3, 4, 4): the start's tool moved 3–5 cm and turned 5–10°."""
    T0 = forward_kinematics(rob, q0)
    goals = np.stack([T0.copy() for _ in range(3)])
    for k, (shift, angle) in enumerate((([0.03, 0.0, 0.02], 5.0), ([0.0, -0.04, 0.0], 8.0), ([-0.02, 0.03, -0.03], 10.0))):
        goals[k, :3, 3] += shift
        goals[k, :3, :3] = rot_from_angle_axis(math.radians(angle), np.array([0.0, 0.6, 0.8])) @ T0[:3, :3]
    return goals


def _single(rob, mode: str, q0: np.ndarray, reference=None, q_des=None) -> np.ndarray:
    state = RobotState(rob)
    state.set_q(q0)
    if q_des is not None:
        state.set_q_des(q_des)
    sim = Simulation(rob, state, make_controller(mode, rob), reference=reference)
    sim.step(STEPS)
    assert sim.stopped is None
    return sim.q


@pytest.mark.parametrize("mode", ["osc", "impedance", "resolved_rate"])
def test_each_environment_follows_its_own_pose_as_a_simulation_does(mode: str) -> None:
    """Panda (effort limits kept), three environments, each with its desired pose from a
    reference returning (3, 4, 4) poses: after 0.1 s every environment sits where a
    Simulation of it does, to 1e-9 rad, and it moved (the law acted)."""
    rob = robot("panda")
    q0 = rob.q_home + 0.05
    goals = _goals(rob, q0)
    zero = np.zeros(6)
    batch = BatchSimulation(rob, 3, mode, reference=lambda t: (goals, zero, zero))
    batch.set_state(q0)
    batch.step(STEPS)
    assert batch.running.all()
    for k in range(3):
        want = _single(rob, mode, q0, reference=lambda t, k=k: (goals[k], zero, zero))
        np.testing.assert_allclose(batch.q[k], want, atol=1e-9, err_msg=f"{mode} environment {k}")
        assert np.abs(batch.q[k] - q0).max() > 1e-3


def test_without_a_reference_each_environment_follows_its_desired_joints() -> None:
    """OSC on the desired joints' tool motion (and posture), per environment, as in
    Simulation; a moving task reference that is a function of time is evaluated at every
    stage there too."""
    rob = robot("ur5")
    q0 = rob.q_home + 0.05
    targets = rob.q_home + np.array([[0.1, -0.1, 0.1, 0.0, 0.1, 0.0], [-0.1, 0.05, 0.0, 0.1, 0.0, -0.1]])
    batch = BatchSimulation(rob, 2, "osc")
    batch.set_state(q0)
    batch.set_reference(q=targets)
    batch.step(STEPS)
    for k in range(2):
        np.testing.assert_allclose(batch.q[k], _single(rob, "osc", q0, q_des=targets[k]), atol=1e-9)
    T0 = forward_kinematics(rob, q0)

    def circle(t: float):
        T = T0.copy()
        T[:3, 3] += 0.03 * np.array([math.sin(3 * t), 1 - math.cos(3 * t), 0.0])
        v = np.concatenate([0.09 * np.array([math.cos(3 * t), math.sin(3 * t), 0.0]), np.zeros(3)])
        a = np.concatenate([0.27 * np.array([-math.sin(3 * t), math.cos(3 * t), 0.0]), np.zeros(3)])
        return T, v, a

    moving = BatchSimulation(rob, 2, "osc", reference=circle)
    moving.set_state(q0)
    moving.step(STEPS)
    np.testing.assert_allclose(moving.q[1], _single(rob, "osc", q0, reference=circle), atol=1e-9)


def test_per_environment_gains_are_refused_for_a_task_space_mode() -> None:
    rob = robot("ur5")
    with pytest.raises(ValueError, match="the osc controller takes one Gains for all environments"):
        BatchSimulation(rob, 2, "osc", gains=[control_gains(rob), control_gains(rob, bandwidth=3.0)])
