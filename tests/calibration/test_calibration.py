"""Calibration (robot_sim.calibration): the parameter Jacobian against central differences,
recovery of perturbed shipped arms from simulated measurements, identifiability, the exact
DH table of a Hayati fit, and pose choice."""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import robot_sim as rs
from calibration_cases import ARMS, NOISE, study
from robot_sim.calibration.chain import build_chain, parameter_jacobian, walk
from robot_sim.calibration.exact_dh import to_robot
from robot_sim.calibration.identifiability import condition_number, observability
from robot_sim.calibration.measure import rotation_vectors
from robot_sim.calibration.simulate import measured

REPRESENTATIVE = ["ur5", "panda", "puma560", "stanford", "iiwa14"]
HELD_OUT_RATIO = 1.2


def _robots():
    for name in ["ur5", "panda", "puma560", "stanford", "iiwa14", "scara"]:
        robot = rs.load_robot(name)
        yield robot
        yield rs.to_modified(robot) if not robot.is_modified else rs.to_standard(robot)


@pytest.mark.parametrize("robot", list(_robots()), ids=lambda r: f"{r.name}-{r.convention}")
def test_parameter_jacobian_equals_central_differences(robot):
    rng = np.random.default_rng(7)
    chain = build_chain(robot)
    chain = chain.with_values(chain.value + rng.normal(0, 1e-2, chain.size))  # betas and all off zero
    q = rs.random_configurations(robot, 12, rng)
    columns = np.arange(chain.size)
    _, _, J = parameter_jacobian(chain, q, columns, poses=True)
    h = 1e-6
    for k in columns:
        up, down = chain.value.copy(), chain.value.copy()
        up[k] += h
        down[k] -= h
        R1, p1, _, _ = walk(chain.with_values(up), q)
        R0, p0, _, _ = walk(chain.with_values(down), q)
        np.testing.assert_allclose(J[:, :3, k], (p1 - p0) / (2 * h), atol=1e-7, rtol=0, err_msg=chain.name[k])
        turn = rotation_vectors(R1 @ R0.transpose(0, 2, 1)) / (2 * h)
        np.testing.assert_allclose(J[:, 3:, k], turn, atol=1e-7, rtol=0, err_msg=chain.name[k])


@pytest.mark.parametrize("name", ["ur5", "panda", "stanford"])
def test_the_chain_is_the_robots_forward_kinematics(name):
    robot = rs.load_robot(name)
    q = rs.random_configurations(robot, 30, np.random.default_rng(2))
    R, p, _, _ = walk(build_chain(robot), q)
    T = rs.forward_kinematics(robot, q)
    np.testing.assert_allclose(p, T[:, :3, 3], atol=1e-14, rtol=0)
    np.testing.assert_allclose(R, T[:, :3, :3], atol=1e-14, rtol=0)


def _recovery(name):
    s = study(name)
    exact = rs.calibrate(s.nominal, s.exact)
    noisy = rs.calibrate(s.nominal, s.noisy)
    return s, exact, noisy


def _check_recovery(s, exact, noisy):
    q = rs.random_configurations(s.nominal, 200, np.random.default_rng(5))
    # Noise-free: the truth, to 1e-9 m at poses never measured.
    truth_points = rs.forward_kinematics(s.truth, q)[:, :3, 3]
    assert np.abs(rs.forward_kinematics(exact.robot, q)[:, :3, 3] - truth_points).max() < 1e-9
    assert exact.rms_after < 1e-12 and exact.table_error < 1e-12 and noisy.table_error < 1e-12
    # With noise: every identified parameter within 4 standard errors of the truth's value
    # in the same parameterisation (the noise-free fit's).
    for got, true in zip(noisy.parameters, exact.parameters):
        assert got.name == true.name
        if np.isfinite(got.std):
            assert abs(got.identified - true.identified) <= 4 * got.std, got.name
        else:
            assert got.identified == got.nominal == true.identified, got.name
    held = noisy.holdout.poses
    floor = float(np.sqrt(np.mean(np.sum(s.noise[held] ** 2, axis=1))))  # RMS of the noise itself
    before = float(np.sqrt(np.mean(noisy.before.position[held] ** 2)))
    assert before > 20 * floor  # tens of times the floor before calibration
    return noisy.holdout.position, floor, s.noise[held]


def _held_out_ratio(results):
    """Pooled held-out RMS over the arms / RMS of their measurement noise (the floor)."""
    residuals = np.concatenate([r[0] for r in results])
    noise = np.concatenate([r[2] for r in results])
    return np.sqrt(np.mean(residuals**2)) / np.sqrt(np.mean(np.sum(noise**2, axis=1)))


def test_recovery_of_representative_arms():
    results = [_check_recovery(*_recovery(name)) for name in REPRESENTATIVE]
    # Ten held-out poses per arm make one arm's RMS vary by about ±13 %; pooled over the
    # arms it is the prediction error of the fit, within 1.2x the noise.
    assert _held_out_ratio(results) <= HELD_OUT_RATIO
    assert all(np.sqrt(np.mean(r[0] ** 2)) <= 1.5 * r[1] for r in results)


@pytest.mark.slow
def test_recovery_of_every_shipped_six_and_seven_joint_arm():
    results = [_check_recovery(*_recovery(name)) for name in ARMS]
    assert _held_out_ratio(results) <= HELD_OUT_RATIO
    assert all(np.sqrt(np.mean(r[0] ** 2)) <= 1.5 * r[1] for r in results)


def test_recovery_from_full_poses_identifies_the_tool_orientation():
    s = study("ur5", measurement="pose", seed=4)
    exact = rs.calibrate(s.nominal, s.exact)
    noisy = rs.calibrate(s.nominal, s.noisy)
    # A tool rotation may move the pose exactly as a last joint's offset does, but none is unseen.
    assert not [u for u in exact.unidentifiable if u.name.startswith("tool.r") and not u.partners]
    q = rs.random_configurations(s.nominal, 100, np.random.default_rng(1))
    T_truth, T_fit = rs.forward_kinematics(s.truth, q), rs.forward_kinematics(exact.robot, q)
    assert np.abs(T_fit - T_truth).max() < 1e-9
    assert exact.rms_rotation_after < 1e-12 and noisy.rms_rotation_before > 1e-3
    assert noisy.rms_after < 2 * NOISE * np.sqrt(3)


def test_position_data_cannot_see_the_tool_orientation_and_keep_it():
    s = study("ur5")
    res = rs.calibrate(s.nominal, s.noisy)
    reasons = {u.name: u.reason for u in res.unidentifiable}
    for key in ("tool.rx", "tool.ry", "tool.rz"):
        assert reasons[key] == "does not move the measured points (positions only: the tool's orientation is not seen)"
    # d1 only moves the points as a base translation does (here along the base's own axes).
    d1 = next(u for u in res.unidentifiable if u.name == "d1")
    assert set(d1.partners) <= {"base.x", "base.y", "base.z"} and "base.z" in d1.partners
    # Nothing the data cannot identify changes.
    rows = {p.name: p for p in res.parameters}
    for u in res.unidentifiable:
        assert rows[u.name].identified == rows[u.name].nominal and np.isnan(rows[u.name].std)
    assert res.robot.dh_d[0] == s.nominal.dh_d[0] and res.robot.dh_th[0] == s.nominal.dh_th[0]
    np.testing.assert_array_equal(res.robot.tool_tf.R(), s.nominal.tool_tf.R())
    # Hayati: UR's parallel joints 2-4 carry beta2, beta3, with d2, d3 held.
    assert {"beta2", "beta3"} <= set(rows) and {"d2", "d3"} <= set(reasons)


def test_a_table_with_parallel_axes_reports_its_dependent_pairs():
    # Without Hayati's beta, a planar arm's d's all slide along the same direction.
    robot = rs.RobotParams.from_arrays("parallel", [0.4, 0.3, 0.2], [0, 0, 0], [0.1, 0.05, 0.02], [0, 0, 0], [0, 0, 0],
                                       q_min=[-3, -3, -3], q_max=[3, 3, 3])
    q = rs.random_configurations(robot, 40, np.random.default_rng(0))
    data = rs.CalibrationData(q, positions=rs.forward_kinematics(robot, q)[:, :3, 3])
    res = rs.calibrate(robot, data, identify=("dh", "joint_offsets"))
    lost = {u.name: u for u in res.unidentifiable}
    # d1, d2 held (beta in their place), d3 moves the points as... nothing else in dh: kept;
    # the first joint's offset turns the whole planar arm like nothing else asked: kept.
    assert (lost["d1"].partners, lost["d2"].partners) == (("d2",), ("d3",))
    assert lost["d1"].reason == ("held: the axes of joints 1 and 2 are (nearly) parallel, so it slides along both "
                                 "as d2 does; Hayati's beta is identified instead")
    # a3 (along the last link) and theta_offset3 are the tool point's polar coordinates: fine;
    # alpha3 turns the tool point about an axis through it.
    assert lost["alpha3"].partners == () and "does not move the measured points" in lost["alpha3"].reason
    res_base = rs.calibrate(robot, data, identify=("dh", "joint_offsets", "base"))
    pairs = {u.name: u.partners for u in res_base.unidentifiable}
    assert "base.rz" in pairs["theta_offset1"]  # turning the whole arm about axis 1
    assert "base.z" in pairs["d3"]  # d3, the one d not held, lifts the arm like the base


def test_hayati_fit_converts_to_an_exact_dh_table_with_large_cancelling_ds():
    robot = rs.load_robot("ur5")
    chain = build_chain(robot)
    values = chain.value.copy()
    values[chain.name.index("beta2")] = 1e-3  # 0.06° tilt of joint 3 about the common normal's y
    values[chain.name.index("alpha2")] = 2e-4
    tilted = chain.with_values(values)
    table = to_robot(tilted)
    assert table.convention == "standard" and abs(table.dh_d[1]) > 100  # hundreds of metres ...
    assert abs(table.dh_d[1] + table.dh_d[2]) < 1.0  # ... that cancel
    q = rs.random_configurations(robot, 100, np.random.default_rng(3))
    _, p, _, _ = walk(tilted, q)
    assert np.abs(rs.forward_kinematics(table, q)[:, :3, 3] - p).max() < 1e-12


def test_calibration_poses_beat_random_poses():
    for name, measurement in [("ur5", "position"), ("panda", "position"), ("puma560", "pose")]:
        robot = rs.load_robot(name)
        chosen = rs.calibration_poses(robot, 40, measurement=measurement)
        assert chosen.shape == (40, robot.n_dofs)
        assert ((chosen >= robot.q_min) & (chosen <= robot.q_max)).all()

        def measures(q):
            res = rs.calibrate(robot, measured(robot, q, np.zeros((len(q), 3)), poses=measurement == "pose"))
            return res.observability, res.condition_number

        best = measures(chosen)
        for seed in range(3):
            o1, cond = measures(rs.random_configurations(robot, 40, np.random.default_rng(seed)))
            assert best[0] > o1 and best[1] < cond, (name, seed)


def test_calibration_poses_avoid_collisions():
    from robot_sim.collision.checker import CollisionChecker

    robot = rs.load_robot("panda")
    checker = CollisionChecker(robot)
    q = rs.calibration_poses(robot, 20, checker=checker, seed=3)
    assert not np.asarray(checker.in_collision(q)).any()


def test_observability_and_condition_number_of_a_known_matrix():
    J = np.diag([4.0, 1.0])
    J = np.vstack([J, np.zeros((2, 2))])  # m = 4 rows
    assert observability(J) == pytest.approx(np.sqrt(4.0 * 1.0) / np.sqrt(4))
    assert condition_number(np.array([[3.0, 0.0], [0.0, 0.5]])) == pytest.approx(1.0)  # columns scaled
    assert condition_number(np.array([[1.0, 1.0], [0.0, 1e-3]])) == pytest.approx(
        np.linalg.cond(np.array([[1.0, 1.0], [0.0, 1e-3]]) / np.linalg.norm([[1.0, 1.0], [0.0, 1e-3]], axis=0)))


def test_calibrated_robot_keeps_everything_else_and_saves_with_a_note(tmp_path):
    s = study("ur5")
    res = rs.calibrate(s.nominal, s.noisy)
    for key in ("q_min", "q_max", "q_home", "jtype"):
        np.testing.assert_array_equal(getattr(res.robot, key), getattr(s.nominal, key))
    assert res.robot.inertials is s.nominal.inertials and res.robot.convention == s.nominal.convention
    path = tmp_path / "cal.toml"
    rs.save_robot(res.robot, path)
    text = path.read_text()
    assert text.startswith("# Universal Robots UR5")  # the source's comments kept
    note = [line for line in text.splitlines() if line.startswith("# Calibrated by robot-sim on ")]
    assert len(note) == 1 and "from 50 measured positions" in note[0]
    assert f"RMS {res.rms_before * 1e3:.4g} mm before, {res.rms_after * 1e3:.4g} mm after" in note[0]
    again = rs.load_robot(path)
    q = s.q
    np.testing.assert_allclose(rs.forward_kinematics(again, q), rs.forward_kinematics(res.robot, q), atol=1e-12)


def test_robust_fit_shrugs_off_an_outlier():
    s = study("ur5")
    positions = s.noisy.positions.copy()
    positions[7] += [0.01, 0, 0]  # a 10 mm blunder
    data = rs.CalibrationData(s.q, positions=positions)
    plain = rs.calibrate(s.nominal, data)
    robust = rs.calibrate(s.nominal, data, robust=True)
    q = rs.random_configurations(s.nominal, 100, np.random.default_rng(9))
    truth = rs.forward_kinematics(s.truth, q)[:, :3, 3]
    err = lambda r: np.abs(rs.forward_kinematics(r, q)[:, :3, 3] - truth).max()  # noqa: E731
    assert err(robust.robot) < 0.3 * err(plain.robot)


def test_an_instrument_frame_far_from_the_base_is_found():
    # The tracker stands 2.3 m away, turned by 92°: the fit starts from a rigid registration.
    from robot_sim.transforms import HomogeneousTransform

    s = study("ur5")
    moved = dataclasses.replace(s.truth, base_tf=HomogeneousTransform.from_xyz_rpy([2.0, -1.0, 0.5], [0.1, -0.2, 1.6])
                                @ s.truth.base_tf)
    exact = rs.calibrate(s.nominal, measured(moved, s.q, np.zeros((len(s.q), 3))))
    assert exact.rms_before > 1.0 and exact.rms_after < 1e-12
    q = rs.random_configurations(s.nominal, 100, np.random.default_rng(4))
    assert np.abs(rs.forward_kinematics(exact.robot, q)[:, :3, 3] - rs.forward_kinematics(moved, q)[:, :3, 3]).max() < 1e-9
