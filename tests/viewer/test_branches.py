"""Keys B and Shift+B as Qt-free commands: the IK target's analytic branches cycled as the
ghost and drawn all at once (robot_sim.viewer.branches, ViewerSession.cycle_branch); the
picture has ghost pixels where the camera projects each branch's joints."""
from __future__ import annotations

import numpy as np
import pytest

import robot_sim as rs
from robot_sim.model.params import RobotParams
from robot_sim.viewer.builder import SessionSpec, build_session
from robot_sim.viewer.commands import COMMANDS
from robot_sim.viewer.session import ViewerSession

#: A PUMA 560 pose whose eight postures all lie inside the joint limits, joint 6 with 4 more turns.
Q_EIGHT = np.radians([-80.0, 120.0, -30.0, 80.0, -40.0, 110.0])
#: A pose with four solutions inside the limits, each a different posture.
Q_FOUR = np.radians([30.0, 50.0, -100.0, 20.0, 30.0, -20.0])
W, H = 400, 300


def puma_at(q: np.ndarray) -> ViewerSession:
    session = ViewerSession(rs.load_robot("puma560"))
    session.set_q(q)
    return session


def run(session: ViewerSession, action: str, argument: object = None) -> str | None:
    return COMMANDS[action](session, argument)


def test_b_cycles_the_solutions_as_the_ghost_in_order_and_wraps() -> None:
    session = puma_at(Q_FOUR)
    robot = session.robot
    session.toggle_target()  # at the endeffector: B solves that pose
    sols = rs.ik_solutions(robot, session.target_tf.mat, Q_FOUR)
    assert len(set(sols.codes.tolist())) == len(sols) >= 2  # one solution per posture: no turns dropped
    for k in [*range(len(sols)), 0]:
        message = run(session, "cycle_branch")
        assert message == f"IK branch {k + 1} of {len(sols)}: {sols.branch[k]}"
        np.testing.assert_array_equal(session.state.q_des(), sols.q[k])
        np.testing.assert_allclose(session.ghost.endeff_tf.mat, rs.forward_kinematics(robot, Q_FOUR), atol=1e-9)


def test_b_shows_a_hidden_target_at_the_endeffector() -> None:
    session = puma_at(Q_FOUR)
    assert run(session, "cycle_branch").startswith("IK branch 1 of ")
    np.testing.assert_array_equal(session.target_tf.mat, session.kin.endeff_tf.mat)


def test_b_keeps_one_solution_per_posture_the_nearest_turn() -> None:
    session = puma_at(Q_EIGHT)
    robot = session.robot
    session.toggle_target()
    sols = rs.ik_solutions(robot, session.target_tf.mat, Q_EIGHT)
    assert len(sols) > 8 and len(set(sols.codes.tolist())) == 8  # turns of joint 6 come twice
    seen: list[int] = []
    for _ in range(8):
        run(session, "cycle_branch")
        index = next(i for i in range(len(sols)) if np.array_equal(sols.q[i], session.state.q_des()))
        assert sols.codes[index] not in seen and all(c != sols.codes[index] for c in sols.codes[:index])
        seen.append(int(sols.codes[index]))
    assert sorted(seen) == list(range(8))
    assert run(session, "cycle_branch").startswith("IK branch 1 of 8: ")


def test_shift_b_draws_every_branch_labelled_and_hides_them_again() -> None:
    session = puma_at(Q_EIGHT)
    robot = session.robot
    T = rs.forward_kinematics(robot, Q_EIGHT)
    assert run(session, "toggle_all_branches") == "all 8 IK branches shown"
    shown = session.scene().branches
    names = {name for _, name in shown}
    assert len(shown) == 8 and len(names) == 8
    for kin, name in shown:
        np.testing.assert_allclose(kin.endeff_tf.mat, T, atol=1e-9)
        assert name.startswith("shoulder ") and ", elbow " in name and ", wrist " in name
    assert run(session, "toggle_all_branches") == "IK branches hidden" and session.scene().branches == []


def test_moving_the_target_forgets_its_branches() -> None:
    session = puma_at(Q_FOUR)
    run(session, "toggle_all_branches")
    assert run(session, "move_target", (2, -1)) is None
    assert session.branches is None and session.scene().branches == []


def general_6r() -> RobotParams:
    """Skewed axes that neither meet nor run parallel: no closed form, every solution by
    the general 6R elimination."""
    return RobotParams.from_arrays("general", [0.3, 0.2, 0.4, 0.15, 0.25, 0.1], [0.4, 1.1, -0.7, 0.9, -1.2, 0.5],
                                   [0.2, 0.15, 0.1, 0.25, 0.12, 0.18], np.zeros(6), np.zeros(6))


def skewed_5r() -> RobotParams:
    """Five skewed axes: neither a closed form nor a general 6R."""
    return RobotParams.from_arrays("skewed", [0.3, 0.2, 0.4, 0.15, 0.25], [0.4, 1.1, -0.7, 0.9, -1.2],
                                   [0.2, 0.15, 0.1, 0.25, 0.12], np.zeros(5), np.zeros(5))


@pytest.mark.parametrize("action", ["cycle_branch", "toggle_all_branches"])
def test_an_arm_without_a_closed_form_says_so(action: str) -> None:
    session = ViewerSession(skewed_5r())
    q_des = session.state.q_des().copy()
    assert run(session, action) == "IK branches: skewed has no closed-form IK (general)"
    np.testing.assert_array_equal(session.state.q_des(), q_des)
    assert session.branches is None and session.scene().branches == []
    with pytest.raises(ValueError, match=r"^IK branches: skewed has no closed-form IK \(general\)$"):
        build_session(SessionSpec(skewed_5r(), ik_branches=True))


def test_a_general_6r_cycles_and_shows_every_real_solution() -> None:
    robot = general_6r()
    q = np.array([0.3, -0.8, 1.1, 0.4, -0.6, 0.9])
    session = ViewerSession(robot)
    session.set_q(q)
    session.toggle_target()
    sols = rs.ik_solutions(robot, session.target_tf.mat, q)
    assert len(sols) >= 2 and all(name.startswith("solution ") for name in sols.branch)
    for k in [*range(len(sols)), 0]:
        assert run(session, "cycle_branch") == f"IK branch {k + 1} of {len(sols)}: {sols.branch[k]}"
        np.testing.assert_array_equal(session.state.q_des(), sols.q[k])
        np.testing.assert_allclose(session.ghost.endeff_tf.mat, rs.forward_kinematics(robot, q), atol=1e-9)
    assert run(session, "toggle_all_branches") == f"all {len(sols)} IK branches shown"
    assert {name for _, name in session.scene().branches} == set(sols.branch)


def test_the_picture_has_ghost_pixels_at_each_branchs_joints() -> None:
    robot = rs.load_robot("puma560")
    with rs.Visualizer(robot, size=(W, H)) as viz:
        viz.display(Q_EIGHT)
        session = viz.session
        session.toggle_target()  # the target alone, then the branches
        session.options.show_labels = False
        viz.refresh()
        without = viz.capture()
        session.toggle_all_branches()
        viz.refresh()
        with_branches = viz.capture()
        shown = session.scene().branches
    changed = np.any(np.abs(with_branches.astype(int) - without.astype(int)) > 24, axis=2)
    arm = rs.forward_kinematics(robot, Q_EIGHT, all_frames=True)[:, :3, 3]
    hits = 0
    for kin, _ in shown:
        # the joints where this branch leaves the arm (the shared ones are the arm's own)
        joints = [p for p in kin.frames[1:-1, :3, 3] if np.min(np.linalg.norm(arm - p, axis=1)) > 0.05]
        for x, y in session.camera.project(np.array(joints).reshape(-1, 3), W, H):
            if 3 <= x < W - 3 and 3 <= y < H - 3:
                hits += bool(changed[round(y) - 3:round(y) + 4, round(x) - 3:round(x) + 4].any())
    assert hits >= 12  # the elbows and wrists of the seven branches away from the arm
