"""Command line of the physical motion modes: --motion, --duration and gain overrides."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from robot_sim import dynamics
from robot_sim.app.prepare import prepare, session_from_config
from robot_sim.control.controllers import control_gains
from kin_helpers import robot
from robot_sim.kinematics import forward_kinematics
from cli_helpers import assert_one_line_error, read_png, run


def _session(*args: str):
    return session_from_config(prepare(list(args)))


def test_motion_and_duration_simulate_before_the_screenshot(tmp_path):
    still, fallen = tmp_path / "still.png", tmp_path / "fallen.png"
    assert run("--robot", "humanoid7", "--screenshot", str(still)).returncode == 0
    result = run("--robot", "humanoid7", "--motion", "passive", "--duration", "0.5", "--screenshot", str(fallen))
    assert result.returncode == 0, result.stderr
    changed = np.any(read_png(still)[..., :3] != read_png(fallen)[..., :3], axis=-1)
    assert np.count_nonzero(changed) > 2000  # the arm fell


def test_session_simulates_the_requested_mode_and_duration():
    session = _session("--robot", "humanoid7", "--motion", "pdg", "--duration", "0.3")
    assert session.motion.mode == "pdg" and session.motion.sim.time == pytest.approx(0.3)
    rob = robot("humanoid7")
    np.testing.assert_allclose(session.state.q(), rob.q_home, atol=1e-9)  # PD + gravity holds home
    passive = _session("--robot", "humanoid7", "--motion", "passive", "--duration", "0.3")
    assert np.abs(passive.state.q() - rob.q_home).max() > 0.1
    # the drawn frames are those of the simulated state
    np.testing.assert_allclose(passive.kin.endeff_tf.mat, forward_kinematics(rob, passive.state.q()), atol=1e-12)


def test_motion_without_duration_starts_at_the_start():
    session = _session("--robot", "humanoid7", "--motion", "passive")
    assert session.motion.mode == "passive" and session.motion.sim.time == 0.0


def test_gain_options_override_the_robots_gains():
    session = _session("--robot", "ur5", "--motion", "pd", "--bandwidth", "3", "--damping", "0.5", "--kd", "1,2,3,4,5,6")
    gains = session.motion.gains
    expected = control_gains(robot("ur5"), bandwidth=3.0, damping=0.5)
    np.testing.assert_allclose(gains.kp, expected.kp)
    np.testing.assert_array_equal(gains.kd, [1, 2, 3, 4, 5, 6])
    assert gains.zeta == 0.5


def test_a_file_without_inertials_is_simulated_with_estimated_ones(tmp_path):
    # planar3's file without its [joints.inertial] and [joints.drive] tables
    kept, skip = [], False
    for line in Path(robot("planar3").source).read_text().splitlines():
        if line.startswith("[joints.inertial]") or line.startswith("[joints.drive]"):
            skip = True
            continue
        if line.startswith("[") or line.startswith("[["):
            skip = False
        if not skip:
            kept.append(line)
    path = tmp_path / "bare.toml"
    path.write_text("\n".join(kept) + "\n")
    session = _session("--robot", str(path), "--motion", "pdg", "--duration", "0.1")
    assert session.motion.estimated and session.motion.robot.inertials.estimated
    assert "estimated inertials" in session.status_text("idle")
    assert np.isfinite(dynamics.gravity_torque(session.motion.robot, session.state.q())).all()


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["--duration", "1"], ["--duration: needs --record DIR, or --motion passive|pd|pdg|ct|osc|impedance to simulate first"]),
        (["--motion", "pid"], ["argument --motion: invalid choice: 'pid'"]),
        (["--motion", "pd", "--duration", "-1"], ["--duration: expected a finite number of seconds >= 0, got '-1'"]),
        (["--motion", "pd", "--bandwidth", "0"], ["--bandwidth: expected a positive number, got '0'"]),
        (["--motion", "pd", "--kp", "1,2"], ["--kp: robot 'Anthropomorphic arm' has 3 joints, got 2 gains"]),
        (["--motion", "pd", "--kd", "1,x,3"], ["--kd: gain 2 'x' is not a finite number >= 0"]),
    ],
)
def test_bad_motion_options_are_one_line_errors(args, fragments, tmp_path):
    assert_one_line_error(run(*args, "--screenshot", str(tmp_path / "x.png")), *fragments)
