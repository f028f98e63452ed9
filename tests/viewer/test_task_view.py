"""Task-space modes in the viewer session (no Qt): the target and the circle demo as the
tool's desired pose without IK, the pull's compliance under impedance, the tracking
readout, and the pick task under operational-space control."""
from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import robot_sim.viewer.target as target_module
import robot_sim.viewer.drivers.circle_path as circle_module
from kin_helpers import robot
from robot_sim.sim.pick_run import simulate_pick
from robot_sim.io.robot_file import load_robot
from robot_sim.planning.pick_task import default_plan
from robot_sim.viewer import settings as vs
from robot_sim.viewer.readout import pose_readout
from robot_sim.viewer.session import ViewerSession


def _refuse(*args: Any, **kwargs: Any) -> Any:
    raise AssertionError("IK called in a task-space mode")


def test_moving_the_target_under_osc_is_followed_without_ik(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(target_module, "solve_ik", _refuse)
    session = ViewerSession(load_robot("ur5"))
    session.set_motion("osc")
    session.toggle_target()
    assert session.move_target(translation=np.array([0.05, -0.04, 0.03]), rpy=np.array([0.0, 0.0, 0.2]))
    for _ in range(300):
        session.step(0.01)
    T = session.kin.endeff_tf.mat
    np.testing.assert_allclose(T, session.target_tf.mat, atol=1e-5)
    error = session.tracking_error()
    assert error is not None and error[0] < 1e-5 and error[1] < 1e-5
    assert session.scene().ghost is None
    session.toggle_target()  # hidden: the arm holds where it is
    held = session.kin.endeff_tf.t().copy()
    for _ in range(100):
        session.step(0.01)
    np.testing.assert_allclose(session.kin.endeff_tf.t(), held, atol=1e-5)


def test_the_circle_demo_under_osc_is_a_cartesian_reference(monkeypatch: pytest.MonkeyPatch) -> None:
    """No differential IK: the simulation follows the circle itself.  The circle starts at
    speed, so the arm at rest lags by at most 5 mm at first (the closed form's peak,
    v/(ω e) = 4.6 mm); after 1 s the tool is on the circle to 1e-5 m (computed torque
    through diff-IK set points stays about 3 mm off)."""
    monkeypatch.setattr(circle_module, "diff_ik_velocity", _refuse)
    session = ViewerSession(load_robot("humanoid7"))
    session.set_motion("osc")
    session.toggle_demo()
    R0 = session.kin.endeff_tf.R().copy()
    sim = session.motion.sim
    start, later = 0.0, 0.0
    for _ in range(round(2 * vs.DEMO_CIRCLE_PERIOD_S / 0.01)):
        session.step(0.01)
        off = np.linalg.norm(session.kin.endeff_tf.t() - sim.reference(sim.time)[0][:3, 3])
        if sim.time < 1.0:
            start = max(start, off)
        else:
            later = max(later, off)
    assert sim.stopped is None
    assert start < 5e-3 and later < 1e-5, (start, later)
    np.testing.assert_allclose(session.kin.endeff_tf.R(), R0, atol=1e-3)
    target = session.scene().target_tf
    assert target is not None  # the moving desired pose is drawn
    session.toggle_demo()
    assert session.motion.sim.reference is None


@pytest.mark.slow  # 8 s of impedance with the pull: about 25 s of CPU
def test_the_pull_under_impedance_yields_by_f_over_k_and_springs_back() -> None:
    """Shift-drag pull: the spring's force F settles the tool at the displacement K⁻¹F of
    the impedance (to 1e-5 m); released, the tool returns to its pose (to 1e-5 m)."""
    session = ViewerSession(robot("ur5"))
    session.set_motion("impedance")
    home = session.kin.endeff_tf.t().copy()
    session.start_pull()
    session.motion.move_pull(home + np.array([0.0, 0.08, 0.05]))
    session.motion.simulate(4.0)
    session.update_kinematics()
    sim = session.motion.sim
    K = sim.controller.K
    displacement = session.kin.endeff_tf.t() - home
    assert np.linalg.norm(displacement) > 0.01
    wrench = np.concatenate([sim.pull_force, np.zeros(3)])
    np.testing.assert_allclose(displacement, np.linalg.solve(K, wrench)[:3], atol=1e-5)
    session.motion.end_pull()
    session.motion.simulate(4.0)
    session.update_kinematics()
    np.testing.assert_allclose(session.kin.endeff_tf.t(), home, atol=1e-5)


def test_sliders_under_osc_move_a_redundant_arm_to_the_set_joints() -> None:
    """The set joints are the posture in the null space: humanoid7 arrives at them."""
    session = ViewerSession(load_robot("humanoid7"))
    session.set_motion("osc")
    goal = session.state.q() + np.array([0.2, -0.15, 0.3, 0.2, -0.2, 0.1, 0.25])
    session.set_q(goal)
    for _ in range(500):
        session.step(0.01)
    np.testing.assert_allclose(session.state.q(), goal, atol=1e-4)


def test_the_readout_shows_the_tracking_error_in_physical_modes_only() -> None:
    session = ViewerSession(load_robot("ur5"))
    assert session.tracking_error() is None
    text = pose_readout(session.kin.endeff_tf, 0.1, (0.00123, np.radians(0.5)))
    assert text.endswith("tracking error 1.23 mm 0.50°")
    session.set_motion("ct")
    assert session.tracking_error() == pytest.approx((0.0, 0.0), abs=1e-12)


@pytest.mark.slow  # about 20 s: the whole task, simulated at 1 kHz
def test_the_pick_task_runs_under_osc() -> None:
    """humanoid7's default pick task under operational space (its null space tracks the
    plan's joints): the tool stays within 1 mm of the plan and the object lands within
    0.1 mm of its place pose."""
    run = simulate_pick(default_plan(load_robot("humanoid7")), "osc")
    assert run.stopped is None
    assert run.tool_error < 1e-3
    place_err = np.linalg.norm(run.placed_pose[:3, 3] - run.plan.spec.place[:3, 3])
    assert place_err < 1e-4
