"""The driver protocol without a display: the session asks its one driver whatever depends
on what moves the arm, switching the motion mode replaces the driver and keeps what the
session shows (options, camera, trail, target), and each driver's advance moves its own
clock by the wall time given."""
from __future__ import annotations

import numpy as np
import pytest

from robot_sim.graphics import defs as gd
from robot_sim.io.robot_file import load_robot
from robot_sim.viewer.drivers import SimulationDriver, StillDriver, TaskSpaceDriver, motion_driver
from robot_sim.viewer.drivers.circle import CircleDriver
from robot_sim.viewer.readout import pose_readout, session_readout
from robot_sim.viewer.session import ViewerSession


def test_the_motion_mode_chooses_the_driver() -> None:
    session = ViewerSession(load_robot("ur5"))
    for mode, kind in (("pdg", SimulationDriver), ("ct", SimulationDriver), ("osc", TaskSpaceDriver),
                       ("impedance", TaskSpaceDriver), ("kinematic", StillDriver)):
        session.set_motion(mode)
        assert type(session.driver) is kind and type(motion_driver(session.motion)) is kind, mode
        assert session.driver.mode == mode and session.physical == (mode != "kinematic")
        assert session.task_space == (kind is TaskSpaceDriver)


def test_switching_drivers_keeps_what_the_session_shows() -> None:
    session = ViewerSession(load_robot("puma560"))
    session.toggle_trail()
    session.toggle_follow()
    session.options.toggle_wireframe()
    session.options.show_only_frames([0, 3])
    session.camera.orthographic = True
    session.move_target(translation=np.array([0.0, 0.05, 0.0]))
    options, camera, trail, target = session.options, session.camera, session.trail, session.target_tf
    session.step(0.5)  # the arm walks to the ghost: the trail grows
    walked = len(trail)
    assert walked > 1
    for mode in ("pdg", "osc", "kinematic"):
        session.set_motion(mode)
        assert session.options is options and session.camera is camera and session.trail is trail, mode
        assert session.target_tf is target and session.follow, mode
        assert options.wireframe and options.show_frames == [True, False, False, True, False, False, False]
        assert len(trail) >= walked  # kept, not emptied
    assert session.toggle_demo() and session.trail is trail and session.options is options
    session.step(0.25)
    assert len(trail) > walked  # the circle extends the same trail


def test_each_driver_advances_its_clock_by_the_wall_time() -> None:
    session = ViewerSession(load_robot("puma560"))
    session.toggle_demo()
    circle = session.demo
    for _ in range(7):
        session.step(0.03)
    assert circle.time == pytest.approx(0.21, abs=1e-12)  # the circle's own time, kinematic
    for mode in ("pdg", "osc"):  # the simulation underneath: its time too
        session.set_motion(mode)
        sim = session.motion.sim
        t0, c0 = sim.time, circle.time
        for _ in range(5):
            session.step(0.02)
        assert circle.time == pytest.approx(c0 + 0.1, abs=1e-12), mode
        assert sim.time == pytest.approx(t0 + 0.1, abs=sim.dt), mode
    session.toggle_demo()
    assert isinstance(session.driver, TaskSpaceDriver)
    t0 = sim.time
    session.step(0.04)
    assert sim.time == pytest.approx(t0 + 0.04, abs=sim.dt)


def test_the_pick_playback_advances_by_wall_time_times_its_speed() -> None:
    from robot_sim.viewer.pick_demo import plan_for

    session = ViewerSession(load_robot("ur5"))
    plan = plan_for(session.robot)
    session.start_pick(plan, 0.5)
    session.pick.speed = 2.0
    session.step(0.1)
    assert session.pick.time == pytest.approx(0.7)
    q, _, _ = plan.trajectory.evaluate(plan.trajectory.t[0] + 0.7)
    np.testing.assert_allclose(session.state.q(), q)
    np.testing.assert_allclose(session.state.q_des(), q)  # no ghost apart while played
    assert session.scene().task is not None and session.driver.task_scene() is not None


def test_a_view_timer_steps_by_the_wall_time_only_when_simulated() -> None:
    """The still arm and its demos take bounded steps (1 ms .. longest); a simulation keeps
    wall-clock time itself, under a demo too."""
    session = ViewerSession(load_robot("puma560"))
    assert session.driver.wall_step(0.5, 0.06) == 0.06 and session.driver.wall_step(0.0, 0.06) == 1e-3
    session.toggle_demo()
    assert session.driver.wall_step(0.5, 0.06) == 0.06
    session.set_motion("pdg")
    assert session.driver.wall_step(0.5, 0.06) == 0.5
    session.toggle_demo()
    assert session.driver.wall_step(0.5, 0.06) == 0.5


def test_a_joint_set_in_a_physical_mode_keeps_the_other_set_joints() -> None:
    """Sliders set the controller's set point: one joint moved keeps the others' desired
    values although the arm has not reached them."""
    session = ViewerSession(load_robot("puma560"))
    session.set_motion("pdg")
    goal = session.state.q() + np.array([0.3, -0.2, 0.2, 0.0, 0.1, 0.0])
    session.set_q(goal)
    session.step(0.05)
    assert np.abs(session.state.q() - goal).max() > 0.05  # still on its way
    np.testing.assert_array_equal(session.q_set_point(), goal)
    session.set_joint(3, 0.4)
    np.testing.assert_array_equal(session.state.q_des(), np.r_[goal[:3], 0.4, goal[4:]])
    session.set_motion("kinematic")
    np.testing.assert_array_equal(session.q_set_point(), session.state.q())


def test_the_ghost_shows_a_simulated_arm_away_from_its_set_point() -> None:
    session = ViewerSession(load_robot("puma560"))
    session.state.set_q_des(session.state.q() + 2 * gd.GHOST_APART_TOL)
    session.update_kinematics()
    assert session.scene().ghost is None  # kinematic: the ghost only with the IK target
    session.set_motion("pdg")
    session.state.set_q_des(session.state.q() + 2 * gd.GHOST_APART_TOL)
    session.update_kinematics()
    assert session.scene().ghost is session.ghost
    session.state.set_q_des(session.state.q() + 0.5 * gd.GHOST_APART_TOL)
    assert session.scene().ghost is None


def test_what_only_a_simulated_arm_or_a_task_can_do_says_so() -> None:
    session = ViewerSession(load_robot("ur5"))
    with pytest.raises(ValueError, match="^pulling needs a physical motion mode: press Shift\\+M$"):
        session.start_pull()
    with pytest.raises(ValueError, match="^simulating needs a physical motion mode$"):
        session.simulate(0.1)
    with pytest.raises(ValueError, match="^no pick task is shown$"):
        session.show_pick_at(0.5)
    assert not session.pulling and session.pull_vectors() == []
    session.end_pull()  # letting go of nothing is no error
    session.set_motion("pdg")
    session.start_pull()
    assert session.pulling
    anchor = session.driver.pull_point.copy()
    np.testing.assert_allclose(anchor, session.kin.endeff_tf.t())
    session.move_pull_in_view(10.0, 0.0, 600)
    (origin, vector, _), = session.pull_vectors()
    np.testing.assert_allclose(origin + vector, session.driver.pull_point)
    assert np.linalg.norm(session.driver.pull_point - anchor) > 0.0
    session.end_pull()
    assert not session.pulling


def test_the_motion_chooser_names_a_replayed_run_over_the_still_arm_only() -> None:
    from robot_sim.viewer.pick_demo import plan_for

    session = ViewerSession(load_robot("ur5"))
    plan = plan_for(session.robot)
    effort = np.zeros((len(plan.trajectory.t), session.robot.n_dofs))
    session.start_pick(plan, effort=effort, mode="ct")
    assert session.driver.mode == "kinematic" and session.driver.replayed_mode == "ct"
    session.set_motion("pdg")
    assert session.pick is not None and session.driver.mode == "pdg" and session.driver.replayed_mode is None


def test_the_readout_is_the_pose_the_tracking_error_and_the_distance() -> None:
    from robot_sim.kinematics import manipulability

    session = ViewerSession(load_robot("ur5"))
    q = session.state.q()
    pose = pose_readout(session.kin.endeff_tf, manipulability(session.robot, q, session.kin.jacobian))
    assert session_readout(session) == pose
    session.set_motion("ct")
    assert session_readout(session) == pose + "\ntracking error 0.00 mm 0.00°"
    session.toggle_collision()
    assert session_readout(session) == pose + "\ntracking error 0.00 mm 0.00°\n" + session.collision_readout()


def test_a_demo_keeps_running_when_the_mode_under_it_changes() -> None:
    session = ViewerSession(load_robot("humanoid7"))
    session.toggle_demo()
    demo = session.driver
    session.set_motion("osc")
    assert session.driver is demo and isinstance(demo, CircleDriver) and isinstance(demo.inner, TaskSpaceDriver)
    assert session.motion.sim.reference is not None  # the circle is the controller's reference
    session.set_motion("pdg")
    assert session.driver is demo and type(demo.inner) is SimulationDriver
    assert session.motion.sim.reference is None
