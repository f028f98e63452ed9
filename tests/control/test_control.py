"""Controllers and their gains (control.py) and the robot file's [control] table."""
from __future__ import annotations

import math

import numpy as np
import pytest

from robot_sim import dynamics
from robot_sim.control.controllers import (
    DEFAULT_BANDWIDTH_HZ,
    DEFAULT_DAMPING,
    PD,
    ComputedTorque,
    Gains,
    Passive,
    PDGravity,
    control_gains,
)
from robot_sim.control.factory import make_controller
from kin_helpers import robot
from robot_sim.io.robot_file import ROBOTS_DIR, load_robot
from robot_sim.model.params import RobotDefinitionError

RNG = np.random.default_rng(8)


def _random_state(rob):
    n = rob.n_dofs
    q = rob.q_home + RNG.uniform(-0.5, 0.5, n)
    return q, RNG.normal(size=n), q + RNG.uniform(-0.3, 0.3, n), RNG.normal(size=n), RNG.normal(size=n)


def test_default_gains_come_from_the_mass_matrix_at_home_and_the_bandwidth():
    rob = robot("puma560")  # has motor inertia: reflected G²·Jm is part of M_ii
    gains = control_gains(rob)
    m_diag = np.diagonal(dynamics.mass_matrix(rob, rob.q_home))
    w = 2 * math.pi * DEFAULT_BANDWIDTH_HZ
    np.testing.assert_allclose(gains.kp, m_diag * w**2, rtol=1e-12)
    np.testing.assert_allclose(gains.kd, m_diag * 2 * DEFAULT_DAMPING * w, rtol=1e-12)
    assert (gains.omega, gains.zeta) == (w, DEFAULT_DAMPING)


def test_arguments_override_the_file_which_overrides_the_defaults(tmp_path):
    text = (ROBOTS_DIR / "humanoid7.toml").read_text()
    path = tmp_path / "h7.toml"
    path.write_text(text + "\n[control]\nbandwidth = 5.0\ndamping = 0.7\nkd = [1, 2, 3, 4, 5, 6, 7]\n")
    rob = load_robot(path)
    assert rob.control == {"bandwidth": 5.0, "damping": 0.7, "kd": (1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0)}
    m_diag = np.diagonal(dynamics.mass_matrix(rob, rob.q_home))
    from_file = control_gains(rob)
    assert from_file.omega == pytest.approx(2 * math.pi * 5.0) and from_file.zeta == 0.7
    np.testing.assert_allclose(from_file.kp, m_diag * (2 * math.pi * 5.0) ** 2)
    np.testing.assert_array_equal(from_file.kd, [1, 2, 3, 4, 5, 6, 7])
    from_args = control_gains(rob, bandwidth=1.0, kd=np.full(7, 9.0))
    assert from_args.omega == pytest.approx(2 * math.pi) and from_args.zeta == 0.7
    np.testing.assert_allclose(from_args.kp, m_diag * (2 * math.pi) ** 2)
    np.testing.assert_array_equal(from_args.kd, np.full(7, 9.0))


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ("bandwith = 3.0", "control.bandwith: unknown key 'bandwith'; accepted keys: bandwidth, damping, kd, kp"),
        ("bandwidth = -2.0", "control.bandwidth: expected a positive number, got -2.0"),
        ("damping = 0", "control.damping: expected a positive number, got 0"),
        ('damping = "high"', "control.damping: expected a number, got 'high'"),
        ("kp = [1, 2]", "control.kp: expected a list of 7 numbers, got [1, 2]"),
        ("kd = [1, 2, 3, 4, 5, 6, -7]", "control.kd: gains must be >= 0, got [1, 2, 3, 4, 5, 6, -7]"),
        ("kp = [1, 2, 3, 4, 5, 6, nan]", "control.kp[6]: expected a finite number, got nan"),
    ],
)
def test_bad_control_tables_are_refused_naming_file_field_and_value(tmp_path, table, message):
    path = tmp_path / "bad.toml"
    path.write_text((ROBOTS_DIR / "humanoid7.toml").read_text() + f"\n[control]\n{table}\n")
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    assert str(info.value) == f"{path}: {message}"


def test_control_must_be_a_table(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('control = 3\n' + (ROBOTS_DIR / "humanoid7.toml").read_text())
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    assert str(info.value) == f"{path}: control: expected a table with keys bandwidth, damping, kd, kp, got 3"


def test_bad_gain_arguments_are_refused():
    rob = robot("humanoid7")
    with pytest.raises(ValueError, match="bandwidth must be a positive finite number, got 0"):
        control_gains(rob, bandwidth=0)
    with pytest.raises(ValueError, match="damping must be a positive finite number, got nan"):
        control_gains(rob, damping=float("nan"))
    with pytest.raises(ValueError, match=r"kp must be 7 finite gains >= 0, got \[1, 2\]"):
        control_gains(rob, kp=[1, 2])
    with pytest.raises(ValueError, match="mode must be one of passive, pd, pdg, ct, osc, impedance, resolved_rate, got 'pid'"):
        make_controller("pid", rob)


def test_control_laws():
    rob = robot("humanoid7")
    gains = Gains(kp=np.arange(1.0, 8.0), kd=np.arange(2.0, 9.0), omega=3.0, zeta=0.5)
    q, qd, q_des, qd_des, qdd_des = _random_state(rob)
    np.testing.assert_array_equal(Passive(rob).torque(q, qd, q_des, qd_des, qdd_des), np.zeros(7))
    pd = gains.kp * (q_des - q) + gains.kd * (qd_des - qd)
    np.testing.assert_allclose(PD(rob, gains).torque(q, qd, q_des, qd_des, qdd_des), pd, rtol=1e-14)
    np.testing.assert_allclose(
        PDGravity(rob, gains).torque(q, qd, q_des, qd_des, qdd_des), pd + dynamics.gravity_torque(rob, q), rtol=1e-12
    )
    # computed torque: M (qdd_des + ω² e + 2ζω ė) + C qd + g
    qdd_ref = qdd_des + 9.0 * (q_des - q) + 3.0 * (qd_des - qd)
    expected = dynamics.mass_matrix(rob, q) @ qdd_ref + dynamics.bias_torque(rob, q, qd)
    np.testing.assert_allclose(ComputedTorque(rob, gains).torque(q, qd, q_des, qd_des, qdd_des), expected, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("name", ["puma560", "stanford", "humanoid7"])
def test_computed_torque_linearises_the_arm(name):
    """The arm driven by computed torque accelerates exactly as the error dynamics say:
    q̈ = q̈_des + ω² e + 2ζω ė, friction and motor inertia included (PUMA's drives)."""
    rob = robot(name)
    gains = control_gains(rob)
    q, qd, q_des, qd_des, qdd_des = _random_state(rob)
    tau = ComputedTorque(rob, gains).torque(q, qd, q_des, qd_des, qdd_des)
    qdd = dynamics.forward_dynamics(rob, q, qd, tau)
    w, z = gains.omega, gains.zeta
    np.testing.assert_allclose(qdd, qdd_des + w**2 * (q_des - q) + 2 * z * w * (qd_des - qd), atol=1e-8)


def test_make_controller_builds_each_mode_with_the_robots_gains():
    rob = robot("ur5")
    for mode, cls in (("passive", Passive), ("pd", PD), ("pdg", PDGravity), ("ct", ComputedTorque)):
        controller = make_controller(mode, rob)
        assert type(controller) is cls and controller.mode == mode
    np.testing.assert_allclose(make_controller("pd", rob).kp, control_gains(rob).kp)
