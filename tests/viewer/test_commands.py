"""The key commands without a display: each changes the session as its key promises and
returns the status text the window shows (robot_sim.viewer.commands; no Qt is imported)."""
from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from robot_sim.io.robot_file import load_robot
from robot_sim.qt.settings import KEY_BINDINGS
from robot_sim.viewer import settings as vs
from robot_sim.viewer.commands import COMMANDS, UNREACHABLE
from robot_sim.viewer.session import ViewerSession


@pytest.fixture
def session() -> ViewerSession:
    return ViewerSession(load_robot("puma560"))


def run(session: ViewerSession, action: str, argument: object = None) -> str | None:
    return COMMANDS[action](session, argument)


def test_every_command_is_a_key_action() -> None:
    assert set(COMMANDS) <= {row[2] for row in KEY_BINDINGS}


def test_the_commands_import_no_qt() -> None:
    code = "import sys, robot_sim.viewer.commands; print('PyQt5' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True).stdout.strip() == "False"


def test_camera_commands(session: ViewerSession) -> None:
    camera = session.camera
    distance, azimuth, elevation = camera.distance, camera.azimuth_deg, camera.elevation_deg
    assert run(session, "zoom", -2) is None
    assert camera.distance == pytest.approx(distance / vs.KEY_ZOOM_FACTOR**2)
    run(session, "orbit", (1, -1))
    assert camera.azimuth_deg == pytest.approx(azimuth + vs.KEY_ORBIT_STEP_DEG)
    assert camera.elevation_deg == pytest.approx(elevation - vs.KEY_ORBIT_STEP_DEG)
    assert run(session, "view_preset", "iso") == "view: iso"
    assert (camera.azimuth_deg, camera.elevation_deg) == pytest.approx(vs.VIEW_PRESETS["iso"])
    assert run(session, "toggle_orthographic") == "orthographic projection" and camera.orthographic
    assert run(session, "toggle_orthographic") == "perspective projection" and not camera.orthographic


def test_option_commands(session: ViewerSession) -> None:
    options = session.options
    run(session, "toggle_wireframe")
    assert options.wireframe
    for action, flag in (("toggle_vectors", "show_vectors"), ("toggle_labels", "show_labels"),
                         ("toggle_com", "show_com")):
        before = getattr(options, flag)
        run(session, action)
        assert getattr(options, flag) is (not before)
    assert run(session, "toggle_frame", 3) is None and options.show_frames[3]
    assert run(session, "toggle_frame", 9) == "PUMA 560 has no frame 9 (frames 0..6)"
    assert run(session, "cycle_look") == "look: solid"
    assert run(session, "cycle_look") == "look: dh"
    assert run(session, "toggle_collision") == "collision display on: shapes, contacts in red, closest pair"


def test_trail_and_follow_belong_to_the_session(session: ViewerSession) -> None:
    assert run(session, "toggle_trail") == "endeffector trail on"
    assert run(session, "toggle_follow") == "camera follows the endeffector"
    q = np.array(session.robot.q_home) + 0.4
    session.set_q(q)
    tool = session.kin.endeff_tf.t()
    np.testing.assert_allclose(session.camera.target, tool)
    np.testing.assert_allclose(session.trail.points()[-1], tool)
    np.testing.assert_allclose(session.scene().trail, session.trail.points())
    assert run(session, "toggle_trail") == "endeffector trail off" and session.scene().trail is None
    assert run(session, "toggle_follow") == "camera stays put"


def test_target_commands_move_the_ghost_by_the_step(session: ViewerSession) -> None:
    run(session, "toggle_target")
    before = session.ghost.endeff_tf.t().copy()
    assert run(session, "move_target", (2, -1)) is None
    np.testing.assert_allclose(session.ghost.endeff_tf.t() - before, [0, 0, -vs.TARGET_STEP_M], atol=1e-6)
    R_before = session.target_tf.R().copy()
    assert run(session, "rotate_target", (2, 1)) is None
    angle = math.radians(vs.TARGET_STEP_DEG)
    Rz = np.array([[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]])
    np.testing.assert_allclose(session.target_tf.R(), Rz @ R_before, atol=1e-12)
    for _ in range(200):  # up to 4 m up: out of reach before
        message = run(session, "move_target", (2, 1))
        if message is not None:
            break
    assert message == UNREACHABLE
    assert session.target_tf.t()[2] > before[2] + 0.1  # it went up, then past the reach


def test_home_and_demo(session: ViewerSession) -> None:
    session.set_q(np.array(session.robot.q_home) + 0.3)
    run(session, "go_home")
    np.testing.assert_allclose(session.state.q(), session.robot.q_home)
    assert run(session, "toggle_demo") == "circle demo started" and session.demo is not None
    assert run(session, "toggle_demo") == "circle demo stopped" and session.demo is None
