"""robot-sim calibrate and calibration-poses, run in-process end to end."""
from __future__ import annotations

import numpy as np

import robot_sim as rs
from calibration_cases import study
from robot_sim.app.main import main
from robot_sim.io.calibration_csv import save_calibration_csv


def test_calibrate_end_to_end(tmp_path, capsys):
    s = study("ur5")
    meas, out, png = tmp_path / "meas.csv", tmp_path / "cal.toml", tmp_path / "report.png"
    save_calibration_csv(meas, s.q, s.nominal.is_revolute, positions=s.noisy.positions)
    assert main(["calibrate", "--robot", "ur5", "--data", str(meas), "--out", str(out), "--report", str(png)]) == 0
    printed, progress = capsys.readouterr()
    res = rs.calibrate(s.nominal, rs.load_calibration_data(meas))
    assert f"position error RMS {res.rms_before * 1e3:.4g} mm before, {res.rms_after * 1e3:.4g} mm after" in printed
    assert "  tool.rx: does not move the measured points (positions only: the tool's orientation is not seen)" in printed
    assert "beta2" in printed and "iteration 1: weighted RMS" in progress
    calibrated = rs.load_robot(out)
    np.testing.assert_allclose(rs.forward_kinematics(calibrated, s.q), rs.forward_kinematics(res.robot, s.q), atol=1e-12)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and b"robot-sim calibrate --robot ur5" in png.read_bytes()


def test_calibration_poses_end_to_end(tmp_path, capsys):
    out = tmp_path / "poses.csv"
    assert main(["calibration-poses", "--robot", "ur5", "-n", "30", "--out", str(out)]) == 0
    assert capsys.readouterr().out == f"wrote 30 poses of UR5 to {out}\n"
    text = out.read_text().splitlines()
    assert text[0] == "q1 [deg], q2 [deg], q3 [deg], q4 [deg], q5 [deg], q6 [deg]" and len(text) == 31
    q = np.radians(np.array([[float(v) for v in line.split(",")] for line in text[1:]]))
    np.testing.assert_allclose(q, rs.calibration_poses(rs.load_robot("ur5"), 30), atol=1e-12)


def test_bad_options_are_one_line_and_exit_2(tmp_path, capsys):
    cases = [
        (["calibration-poses", "--robot", "ur5", "-n", "0", "--out", str(tmp_path / "p.csv")],
         "robot-sim calibration-poses: error: -n: n: expected 1 to 100000 poses, got 0"),
        (["calibration-poses", "--robot", "nosuch", "-n", "5", "--out", str(tmp_path / "p.csv")],
         "robot-sim calibration-poses: error: --robot: "),
        (["calibrate", "--robot", "ur5", "--out", str(tmp_path / "c.toml")],
         "robot-sim calibrate: error: the following arguments are required: --data"),
        (["calibrate", "--robot", "ur5", "--data", str(tmp_path / "missing.csv"), "--out", str(tmp_path / "c.toml")],
         f"robot-sim calibrate: error: cannot read '{tmp_path / 'missing.csv'}': No such file or directory"),
    ]
    for argv, start in cases:
        assert main(argv) == 2
        err = capsys.readouterr().err
        assert err.startswith(start) and err.count("\n") == 1, err
