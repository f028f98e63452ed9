"""The pick task run by the simulated controllers (simulation.py, control.py): computed
torque tracks the plan and places the object within 1 mm; PD tracks worse."""
from __future__ import annotations

import numpy as np
import pytest

from kin_helpers import robot
from robot_sim.kinematics import forward_kinematics
from robot_sim.sim.pick_run import simulate_pick
from robot_sim.planning.pick_task import default_plan


@pytest.fixture(scope="module")
def ur5_ct():
    return simulate_pick(default_plan(robot("ur5")), "ct")


def test_computed_torque_tracks_the_plan_and_places_within_1mm(ur5_ct):
    run = ur5_ct
    plan = run.plan
    assert run.stopped is None
    assert abs(run.motion.t[-1] - plan.trajectory.t[-1]) <= 0.5e-3 + 1e-12  # whole 1 ms steps
    assert run.tool_error < 1e-3
    assert np.linalg.norm(run.placed_pose[:3, 3] - plan.spec.place[:3, 3]) < 1e-3
    # the reported errors are the simulated motion's: recompute them independently
    q_des, _, _ = plan.trajectory.evaluate(run.motion.t)
    np.testing.assert_allclose(run.joint_error, np.abs(run.motion.q - q_des).max(axis=0), rtol=1e-12)
    tool = forward_kinematics(plan.robot, run.motion.q)[:, :3, 3]
    planned = forward_kinematics(plan.robot, q_des)[:, :3, 3]
    assert run.tool_error == pytest.approx(np.linalg.norm(tool - planned, axis=1).max(), rel=1e-12)
    assert run.effort.shape == run.motion.q.shape and np.abs(run.effort).max() > 0
    assert "UR5, ct: largest joint tracking error" in run.summary()


def test_pd_tracks_worse_than_computed_torque(ur5_ct):
    pd = simulate_pick(ur5_ct.plan, "pd")
    assert np.max(pd.joint_error) > 2 * np.max(ur5_ct.joint_error)


def test_cli_pick_with_computed_torque_reports_tracking(tmp_path):
    from cli_helpers import read_png, run

    out = tmp_path / "ct.png"
    result = run("--robot", "ur5", "--demo", "pick", "--motion", "ct", "--time", "1000", "--size", "320x240",
                 "--screenshot", str(out))
    assert result.returncode == 0, result.stderr
    first = result.stdout.splitlines()[0]
    assert first.startswith("UR5, ct: largest joint tracking error ")
    assert "mm from its place pose" in first
    assert read_png(out).shape[:2] == (240, 320)
