"""The session's drivers without a display: one at a time, each moving the arm as its
docstring says; demos run over the motion driver they interrupt and give it back; and
with_robot keeps the options."""
from __future__ import annotations

import numpy as np
import pytest

from robot_sim.io.robot_file import load_robot
from robot_sim.viewer import settings as vs
from robot_sim.viewer.builder import SessionSpec, build_session
from robot_sim.viewer.drivers import StillDriver
from robot_sim.viewer.drivers.circle import CircleDriver
from robot_sim.viewer.drivers.simulated import SimulationDriver
from robot_sim.viewer.session import ViewerSession


def test_still_driver_moves_toward_the_ghost_at_bounded_speed() -> None:
    session = ViewerSession(load_robot("puma560"))
    assert isinstance(session.driver, StillDriver) and not session.moving()
    q0 = session.state.q()
    goal = q0 + np.r_[0.3, -0.15, 0, 0, 0, 0]
    session.state.set_q_des(goal)
    assert session.moving()
    session.step(0.1)  # 1.5 rad/s for 0.1 s: 0.15 rad at most per joint
    np.testing.assert_allclose(session.state.q() - q0, [0.15, -0.15, 0, 0, 0, 0], atol=1e-12)
    session.step(0.1)
    np.testing.assert_allclose(session.state.q(), goal, atol=1e-12)
    assert not session.moving()


def test_set_motion_puts_the_simulation_driver_under_a_running_demo() -> None:
    session = ViewerSession(load_robot("puma560"))
    assert session.toggle_demo()
    demo = session.driver
    assert isinstance(demo, CircleDriver) and isinstance(demo.inner, StillDriver) and not session.physical
    session.set_motion("pdg")
    assert session.driver is demo and isinstance(demo.inner, SimulationDriver) and session.physical
    time0 = session.motion.sim.time
    session.step(0.05)
    assert session.motion.sim.time == pytest.approx(time0 + 0.05, abs=session.motion.sim.dt)
    assert not session.toggle_demo()  # the demo ends: the simulation drives again
    assert isinstance(session.driver, SimulationDriver)
    np.testing.assert_array_equal(session.state.qd_des(), np.zeros(6))


def test_setting_joints_ends_the_circle_demo() -> None:
    session = ViewerSession(load_robot("puma560"))
    session.toggle_demo()
    q = np.asarray(session.robot.q_home) + 0.2
    session.set_q(q)
    assert isinstance(session.driver, StillDriver) and session.demo is None
    np.testing.assert_allclose(session.state.q(), q)


def test_pick_playback_pauses_when_joints_are_set_and_keeps_its_task() -> None:
    from robot_sim.viewer.pick_demo import plan_for

    session = ViewerSession(load_robot("ur5"))
    plan = plan_for(session.robot)
    session.start_pick(plan, 0.5)
    assert session.pick.playing and session.moving()
    session.step(0.25)
    assert session.pick.time == pytest.approx(0.75)
    q, _, _ = plan.trajectory.evaluate(plan.trajectory.t[0] + 0.75)
    np.testing.assert_allclose(session.state.q(), q)
    session.set_q(np.asarray(session.robot.q_home))
    assert session.pick is not None and not session.pick.playing and not session.moving()
    np.testing.assert_allclose(session.state.q(), session.robot.q_home)


def test_with_robot_keeps_the_options_and_carries_the_joints() -> None:
    session = build_session(SessionSpec(load_robot("puma560"), theme="light", look="solid", wireframe=True,
                                        collision=True, trail=True, frames=[0, 2, 7], annotate=3,
                                        gains={"bandwidth": 3.0, "kp": np.ones(6)}))
    session.toggle_follow()
    session.options.toggle_alpha()
    session.camera.orthographic = True
    q = np.asarray(session.robot.q_home) + 0.1
    session.set_q(q)
    other = load_robot("stanford")
    new = session.with_robot(other, keep_q=True)
    assert new.robot is other and new is not session
    for flag in ("theme", "look", "wireframe", "alpha", "show_collision", "show_vectors", "show_labels"):
        assert getattr(new.options, flag) == getattr(session.options, flag), flag
    assert new.follow and new.camera is session.camera and new.camera.orthographic
    assert new.trail is not None and len(new.trail) <= 1  # on, and emptied
    assert new.options.show_frames == session.options.show_frames and new.options.annotate_joint == 3
    assert new.gain_overrides == {"bandwidth": 3.0}  # per-joint gains belong to the robot they named
    fresh = session.with_robot(load_robot("ur5"), keep_q=False)
    np.testing.assert_allclose(fresh.state.q(), fresh.robot.q_home)
    assert fresh.camera is not session.camera and fresh.camera.orthographic
    assert fresh.options.show_frames == [True] + [False] * 6  # another arm: its own frames
    assert fresh.options.theme == "light"


def test_a_simulated_trail_samples_the_path_every_trail_step() -> None:
    session = build_session(SessionSpec(load_robot("ur5"), motion="passive", simulate=0.5, trail=True))
    points = session.trail.points()
    # one point every TRAIL_SAMPLE_S at most (fewer where the tool moved less than TRAIL_MIN_STEP_M)
    assert 10 < len(points) <= round(0.5 / vs.TRAIL_SAMPLE_S) + 2
    assert points[0][2] - points[-1][2] > 0.05  # it fell
