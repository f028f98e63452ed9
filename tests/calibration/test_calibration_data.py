"""Calibration measurements: CalibrationData's checks, the CSV reader's errors (file, line,
column, value, what is accepted) and the round trip through the writer."""
from __future__ import annotations

import numpy as np
import pytest

import robot_sim as rs
from robot_sim.io.calibration_csv import calibration_csv_text, save_calibration_csv

UR5 = rs.load_robot("ur5")


def _write(tmp_path, text):
    path = tmp_path / "meas.csv"
    path.write_text(text)
    return str(path)


def test_round_trip_of_positions_and_poses(tmp_path):
    q = rs.calibration_poses(UR5, 12, seed=2)
    poses = rs.forward_kinematics(UR5, q)
    path = tmp_path / "m.csv"
    save_calibration_csv(path, q, UR5.is_revolute, poses=poses)
    data = rs.load_calibration_data(path)
    assert data.has_rotation and len(data) == 12 and data.joint_units == ("angle",) * 6
    np.testing.assert_allclose(data.q, q, atol=1e-15, rtol=1e-15)
    np.testing.assert_allclose(data.poses, poses, atol=1e-15)
    save_calibration_csv(path, q, UR5.is_revolute, positions=poses[:, :3, 3])
    assert not rs.load_calibration_data(path).has_rotation
    assert calibration_csv_text(q[:1], UR5.is_revolute).startswith("q1 [deg], q2 [deg], q3 [deg], q4 [deg]")


def test_units_in_brackets(tmp_path):
    path = _write(tmp_path, "q1 [rad], q2 [deg], x [m], y [mm], z [mm]\n# a comment\n\n0.5, 90, 1, 2, 3\n")
    data = rs.load_calibration_data(path)
    np.testing.assert_allclose(data.q, [[0.5, np.pi / 2]])
    np.testing.assert_allclose(data.positions, [[1.0, 0.002, 0.003]])
    assert data.lines.tolist() == [4]


@pytest.mark.parametrize("text, message", [
    ("q1 [deg], q2 [deg], x [mm], y [mm]\n1, 2, 3, 4\n",
     "line 1: missing column(s) z; expected q1 .. qn [deg|rad|m|mm], x [m|mm], y [m|mm], z [m|mm], "
     "then optionally qw, qx, qy, qz"),
    ("q1 [deg], q3 [deg], x [mm], y [mm], z [mm]\n", "line 1: joint columns must be q1 .. qn (n <= 64); q2 is missing"),
    ("q1 [deg], x [mm], y [mm], z [mm], qw, qx\n", "line 1: missing column(s) qy, qz"),
    ("q1 [deg], x [in], y [mm], z [mm]\n", "line 1, column 2: unknown column 'x [in]'; accepted: q1 .. qn"),
    ("q1 [deg], x [deg], y [mm], z [mm]\n", "line 1, column 2: x [deg]: positions are in m or mm"),
    ("q1 [deg], x [mm], x [mm], z [mm]\n", "line 1, column 3: x appears twice"),
    ("q1 [deg], x [mm], y [mm], z [mm]\n1, 2, 3, nan\n",
     "line 2, column z: expected a finite number, got 'nan'"),
    ("q1 [deg], x [mm], y [mm], z [mm]\n1, 2, 3\n", "line 2: expected 4 values, got 3"),
    ("q1 [deg], x [mm], y [mm], z [mm]\n1, 2, 3, " + "9" * 200 + "x\n",
     "line 2, column z: expected a number, got '" + "9" * 79 + "... (203 characters)"),
    ("q1 [deg], x [mm], y [mm], z [mm], qw, qx, qy, qz\n1, 2, 3, 4, 1, 1, 0, 0\n",
     "line 2: qw, qx, qy, qz must be a unit quaternion (norm within 0.001 of 1), got norm 1.41421"),
])
def test_bad_files_name_line_column_and_value(tmp_path, text, message):
    path = _write(tmp_path, text)
    with pytest.raises(rs.CalibrationDataError) as info:
        rs.load_calibration_data(path)
    assert str(info.value).startswith(f"{path} {message}") or str(info.value).startswith(f"{path}: {message}")
    assert "\n" not in str(info.value)


def test_row_count_is_bounded_before_reading_values(tmp_path, monkeypatch):
    import robot_sim.io.calibration_csv as csv

    monkeypatch.setattr(csv, "MAX_POSES", 3)
    path = _write(tmp_path, "q1 [deg], x [mm], y [mm], z [mm]\n" + "1, 2, 3, 4\n" * 4)
    with pytest.raises(rs.CalibrationDataError, match=r"4 rows; at most 3 poses are accepted$"):
        rs.load_calibration_data(path)


def test_a_joint_outside_its_limits_is_named_by_line(tmp_path):
    q = np.zeros((30, 6))
    q[17, 2] = np.deg2rad(400.0)
    path = tmp_path / "m.csv"
    save_calibration_csv(path, q, UR5.is_revolute, positions=np.zeros((30, 3)))
    data = rs.load_calibration_data(path)
    with pytest.raises(rs.CalibrationDataError) as info:
        rs.calibrate(UR5, data)
    assert str(info.value) == f"{path} line 19 (pose 18): q3 = 400 deg is outside joint 3's limits [-360, 360] deg"


def test_too_few_poses_says_how_many_are_needed():
    q = rs.random_configurations(UR5, 8, np.random.default_rng(0))
    data = rs.CalibrationData(q, positions=rs.forward_kinematics(UR5, q)[:, :3, 3])
    with pytest.raises(rs.CalibrationDataError) as info:
        rs.calibrate(UR5, data)
    assert str(info.value) == ("too few poses: identifying 36 parameters from measured positions (3 values per pose, "
                               "a fifth held out) needs at least 16 poses, got 8")
    assert rs.calibrate(UR5, data, identify=("joint_offsets",)).rms_after < 1e-12  # 6 parameters: enough


def test_data_checks_in_code():
    q = np.zeros((4, 6))
    with pytest.raises(rs.CalibrationDataError, match=r"^pose 3: positions holds NaN or infinite values$"):
        rs.CalibrationData(q, positions=np.where(np.arange(12).reshape(4, 3) == 7, np.nan, 0.0))
    with pytest.raises(rs.CalibrationDataError, match=r"^give exactly one of positions"):
        rs.CalibrationData(q)
    with pytest.raises(rs.CalibrationDataError, match=r"^positions: expected shape \(4, 3\)"):
        rs.CalibrationData(q, positions=np.zeros((3, 3)))
    with pytest.raises(rs.CalibrationDataError, match=r"^pose 2: weights\[1\] must be positive and finite, got 0.0$"):
        rs.CalibrationData(q, positions=np.zeros((4, 3)), weights=[1, 0, 1, 1])
    with pytest.raises(rs.CalibrationDataError, match=r"^q: 5 joint columns, UR5 has 6 joints$"):
        rs.calibrate(UR5, rs.CalibrationData(np.zeros((40, 5)), positions=np.zeros((40, 3))))
    with pytest.raises(ValueError, match=r"^identify: expected a non-empty tuple of 'dh', 'joint_offsets', 'base', "
                                         r"'tool', got \('dh', 'links'\)$"):
        rs.calibrate(UR5, rs.CalibrationData(np.zeros((40, 6)), positions=np.zeros((40, 3))), identify=("dh", "links"))


def test_prismatic_columns_need_lengths(tmp_path):
    stanford = rs.load_robot("stanford")
    path = _write(tmp_path, ", ".join(f"q{j} [deg]" for j in range(1, 7)) + ", x [mm], y [mm], z [mm]\n"
                  + "0, 0, 0, 0, 0, 0, 1, 2, 3\n" * 30)
    with pytest.raises(rs.CalibrationDataError, match=r"column q3: joint 3 of .* is prismatic; its unit must be m or mm$"):
        rs.calibrate(stanford, rs.load_calibration_data(path))
