"""Issue 31, the Python API and the sweep: counts bounded before allocation, names where
objects are expected refused (or accepted) at the call, the option given blamed, collision
with the world never allowed by sampling, pick tasks among --world obstacles."""
from __future__ import annotations

import time

import numpy as np
import pytest

import robot_sim as rs
import robot_sim.app.sweep_cmd as sweep_cmd
from robot_sim.app.main import main
from robot_sim.sim.batch import MAX_ENVS
from robot_sim.planning.pick_task import TaskError, default_task, plan_pick
from robot_sim.viewer.pick_demo import plan_for


def _one_error_line(capsys, *fragments):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for fragment in fragments:
        assert fragment in err, err
    return err


def test_batch_simulation_refuses_too_many_environments_before_allocating():
    robot = rs.load_robot("puma560")
    with pytest.raises(ValueError) as info:
        rs.BatchSimulation(robot, 10**7, controller="pd")
    assert str(info.value) == f"n_envs must be an integer 1..{MAX_ENVS}, got 10000000"


def test_joint_space_controllers_take_bandwidth_and_damping():
    robot = rs.load_robot("puma560")
    ct = rs.make_controller("ct", robot, bandwidth=3, damping=0.5)
    expected = rs.control_gains(robot, bandwidth=3, damping=0.5)
    omega = 2 * np.pi * 3  # the error dynamics: kp = ω², kd = 2ζω
    assert ct.kp == pytest.approx(omega**2, rel=1e-12) and ct.kd == pytest.approx(2 * 0.5 * omega, rel=1e-12)
    pd = rs.make_controller("pd", robot, bandwidth=3)
    np.testing.assert_allclose(pd.kp, expected.kp, rtol=1e-12)
    m = np.diagonal(rs.mass_matrix(robot, robot.q_home))  # kp = M_ii(q_home) ω²
    np.testing.assert_allclose(expected.kp, m * (2 * np.pi * 3) ** 2, rtol=1e-12)
    with pytest.raises(ValueError, match="^the ct controller takes only bandwidth and damping, got stiffness$"):
        rs.make_controller("ct", robot, stiffness=3)
    with pytest.raises(ValueError, match="^the passive controller takes no options, got bandwidth$"):
        rs.make_controller("passive", robot, bandwidth=3)
    with pytest.raises(ValueError, match="^give gains or bandwidth, not both$"):
        rs.make_controller("pd", robot, expected, bandwidth=3)


def test_simulation_takes_a_mode_name_and_refuses_other_objects_at_the_call():
    robot = rs.load_robot("puma560")
    by_name = rs.Simulation(robot, controller="pd")
    by_object = rs.Simulation(robot, controller=rs.make_controller("pd", robot))
    for sim in (by_name, by_object):
        sim.state.set_q_des(robot.q_home + 0.1)
        sim.step(50)
    np.testing.assert_array_equal(by_name.state.q(), by_object.state.q())
    assert not np.allclose(by_name.state.q(), robot.q_home)  # it moved toward the desired values
    with pytest.raises(ValueError, match="^mode must be one of passive, pd, pdg, ct"):
        rs.Simulation(robot, controller="pid")
    with pytest.raises(TypeError, match="^controller must be a Controller or a mode name, got int$"):
        rs.Simulation(robot, controller=3)
    with pytest.raises(ValueError) as info:
        by_name.step("10")
    assert str(info.value) == "n_steps must be a whole number >= 0, got '10'"


def test_forward_kinematics_of_a_robot_name_is_refused_clearly():
    with pytest.raises(TypeError) as info:
        rs.forward_kinematics("puma560", np.zeros(6))
    assert str(info.value) == ("robot must be a RobotParams (load it first: rs.load_robot('puma560')), "
                               "got str 'puma560'")


def test_path_is_free_of_an_empty_path_is_a_clear_error():
    robot = rs.load_robot("ur5")
    with pytest.raises(ValueError) as info:
        rs.CollisionChecker(robot).path_is_free(np.zeros((0, 6)))
    assert str(info.value) == "path_is_free: q_path holds no configuration; expected (K, 6) waypoints with K >= 1"


def test_an_obstacle_enclosing_the_arm_is_a_collision():
    robot = rs.load_robot("ur5")
    cage = rs.World({"cage": rs.Box([3, 3, 3], np.eye(4))})
    checker = rs.CollisionChecker(robot, cage)
    assert checker.in_collision(robot.q_home)
    assert all(pair[0] == "base" for pair in checker.allowed if "cage" in pair)  # only the unmoving base rests in it
    assert ("link1", "floor") in rs.CollisionChecker(robot).allowed  # turns about a vertical axis on the floor
    spec = default_task(robot)
    inside = rs.World({"cage": rs.Box([3, 3, 3], np.eye(4))})
    with pytest.raises(TaskError, match="the start configuration is in collision"):
        plan_for(robot, None, inside)
    assert plan_pick(robot, spec).trajectory.duration > 0  # without the cage it plans


def _post_at(pose):
    tf = np.eye(4)
    tf[:3, 3] = pose[:3, 3]
    return rs.Box([0.1, 0.1, 1.0], tf)


def test_a_place_pose_inside_an_obstacle_is_reported_as_that():
    robot = rs.load_robot("ur5")
    spec = default_task(robot)
    blocked = rs.World({"post": _post_at(spec.place)})
    with pytest.raises(TaskError) as info:
        plan_for(robot, None, blocked)
    place = ", ".join(f"{v:.3f}" for v in spec.place[:3, 3])
    assert str(info.value).endswith(f"place: the place pose at xyz [{place}] m is inside obstacle 'post': "
                                    "the object would overlap it")


def test_demo_pick_plans_among_the_world_obstacles(tmp_path, capsys):
    robot = rs.load_robot("ur5")
    x, y, _ = default_task(robot).place[:3, 3]
    world = tmp_path / "world.toml"
    world.write_text(f'[[obstacles]]\nname = "post"\nshape = "box"\nsize = [0.1, 0.1, 1.0]\nxyz = [{x}, {y}, 0.0]\n')
    assert main(["--robot", "ur5", "--demo", "pick", "--world", str(world), "--print-dh"]) == 2
    _one_error_line(capsys, "place: the place pose at", "is inside obstacle 'post'")


def test_sweep_out_into_a_missing_folder_is_refused_before_the_sweep(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(sweep_cmd, "sweep", lambda *a, **k: pytest.fail("the sweep ran"))
    out = tmp_path / "missing" / "s.csv"
    assert main(["sweep", "--robot", "ur5", "--kp", "100", "--out", str(out)]) == 2
    _one_error_line(capsys, f"--out: cannot write '{out}': directory '{out.parent}' does not exist")


def test_sweep_grid_is_bounded_before_any_value_is_built(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(sweep_cmd, "parse_values", lambda *a: pytest.fail("built the values of a refused grid"))
    big = "0:1:10000000"
    argv = ["sweep", "--robot", "ur5", "--kp", big, "--kd", big, "--bandwidth", big, "--damping", big,
            "--payload", big, "--out", str(tmp_path / "s.csv")]
    assert main(argv) == 2
    _one_error_line(capsys, "--kp × --kd × --bandwidth × --damping × --payload: the grid has "
                            f"{10**35} runs; at most {sweep_cmd.MAX_RUNS}")


def test_sweep_blames_the_option_given(tmp_path, capsys):
    assert main(["sweep", "--robot", "ur5", "--motion", "ct", "--kp", "0", "--duration", "0.01",
                 "--workers", "1", "--out", str(tmp_path / "s.csv")]) == 2
    err = _one_error_line(capsys, "kp must be > 0 for computed torque")
    assert "bandwidth" not in err


@pytest.mark.parametrize("address, message", [
    ("tcp://127.0.0.1:9", "--scheduler 'tcp://127.0.0.1:9': no Dask scheduler answered within 3 s"),
    ("::::", "--scheduler '::::': not a scheduler address; expected tcp://HOST:PORT (an IPv6 host in brackets)"),
])
def test_sweep_scheduler_that_does_not_answer_is_one_line_quickly(tmp_path, capsys, address, message):
    pytest.importorskip("distributed")
    start = time.monotonic()
    assert main(["sweep", "--robot", "ur5", "--kp", "100", "--scheduler", address,
                 "--out", str(tmp_path / "s.csv")]) == 2
    assert time.monotonic() - start < 20  # a hang guard: it waited 30 s and then raised
    _one_error_line(capsys, message)
