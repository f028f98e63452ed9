"""Inertial and drive data: robot-file tables, validation, the geometric estimate, COMs."""
from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from robot_sim.model.estimate import DEFAULT_DENSITY, ESTIMATE_RADIUS_FRAC, estimate_inertials
from robot_sim.model.inertials import Drives, LinkInertials
from kin_helpers import ROBOT_NAMES, expected_coms, random_dh_robot, random_inertials, random_q, robot
from robot_sim.kinematics import Kinematics, forward_kinematics
from robot_sim.model.params import RobotDefinitionError, RobotParams
from robot_sim.io.robot_file import load_robot
from robot_sim.model.state import RobotState

# robots whose files carry published inertial data (the library's are checked in
# test_robot_library.py); every other file ships estimate_inertials' output
PUBLISHED = {"puma560", "stanford", "ur5", "panda", "gen3", "ur3", "ur3e", "ur5e", "ur10", "ur10e"}
JOINT = """
[[joints]]
type = "revolute"
a = 0.5
alpha = 0.0
d = 0.0
theta = 0.0
"""
INERTIAL = """[joints.inertial]
mass = 2.0
com = [-0.25, 0.0, 0.0]
inertia = [0.001, 0.05, 0.05, 0.0, 0.0, 0.0]
"""


def _write(tmp_path: Path, *joints: str) -> Path:
    path = tmp_path / "arm.toml"
    path.write_text('name = "arm"\nunits = "deg"\n' + "".join(joints))
    return path


def _error(tmp_path: Path, *joints: str) -> str:
    path = _write(tmp_path, *joints)
    with pytest.raises(RobotDefinitionError) as info:
        load_robot(path)
    message = str(info.value)
    assert message.startswith(f"{path}: ")
    return message[len(f"{path}: ") :]


# ------------------------------------------------------------------ parsing


def test_inertial_and_drive_tables_are_read_in_si(tmp_path):
    drive = """[joints.drive]
motor_inertia = 2e-4
gear_ratio = -62.5
viscous = 1.5e-3
coulomb = [0.4, -0.43]
effort_limit = 97.6
velocity_limit = 3.1
"""
    rob = load_robot(_write(tmp_path, JOINT + INERTIAL + drive, JOINT + INERTIAL.replace("2.0", "1.0")))
    li, dr = rob.inertials, rob.drives
    np.testing.assert_array_equal(li.mass, [2.0, 1.0])
    np.testing.assert_array_equal(li.com, [[-0.25, 0.0, 0.0]] * 2)
    np.testing.assert_array_equal(li.inertia[0], np.diag([0.001, 0.05, 0.05]))
    assert not li.estimated
    np.testing.assert_array_equal(dr.motor_inertia, [2e-4, 0.0])
    np.testing.assert_array_equal(dr.gear_ratio, [-62.5, 1.0])
    np.testing.assert_array_equal(dr.viscous, [1.5e-3, 0.0])
    np.testing.assert_array_equal(dr.coulomb, [[0.4, -0.43], [0.0, 0.0]])
    np.testing.assert_array_equal(dr.effort_limit, [97.6, math.inf])
    np.testing.assert_array_equal(dr.velocity_limit, [3.1, math.inf])
    np.testing.assert_allclose(dr.reflected_inertia, [62.5**2 * 2e-4, 0.0])
    for arr in (li.mass, li.com, li.inertia, dr.gear_ratio, dr.coulomb):
        assert not arr.flags.writeable


def test_off_diagonal_elements_in_urdf_order(tmp_path):
    table = INERTIAL.replace("[0.001, 0.05, 0.05, 0.0, 0.0, 0.0]", "[0.05, 0.06, 0.07, 0.001, 0.002, 0.003]")
    inertia = load_robot(_write(tmp_path, JOINT + table)).inertials.inertia[0]
    np.testing.assert_array_equal(inertia, [[0.05, 0.001, 0.003], [0.001, 0.06, 0.002], [0.003, 0.002, 0.07]])


def test_files_without_tables_have_none(tmp_path):
    rob = load_robot(_write(tmp_path, JOINT))
    assert rob.inertials is None and rob.drives is None


@pytest.mark.parametrize(
    ("table", "expected"),
    [
        (INERTIAL.replace("mass = 2.0", "mass = -2.0"),
         "joints[0].inertial.mass: mass -2.0 is negative; accepted: a mass >= 0 (kg)"),
        (INERTIAL.replace("mass = 2.0", "mas = 2.0"),
         "joints[0].inertial.mas: unknown key 'mas'; accepted keys: com, inertia, mass"),
        (INERTIAL.replace("mass = 2.0\n", ""), "joints[0].inertial.mass: missing required field"),
        (INERTIAL.replace("[-0.25, 0.0, 0.0]", "[-0.25, 0.0]"),
         "joints[0].inertial.com: expected a list of 3 numbers, got [-0.25, 0.0]"),
        (INERTIAL.replace("[0.001, 0.05, 0.05, 0.0, 0.0, 0.0]", "[0.001, 0.05, 0.05]"),
         "joints[0].inertial.inertia: expected a list of 6 numbers, got [0.001, 0.05, 0.05]"),
        (INERTIAL.replace("[0.001, 0.05, 0.05, 0.0, 0.0, 0.0]", "[-0.001, 0.05, 0.05, 0.0, 0.0, 0.0]"),
         "joints[0].inertial.inertia: [-0.001, 0.05, 0.05, 0.0, 0.0, 0.0] has a negative principal moment "
         "-0.001 (principal moments [-0.001, 0.05, 0.05]); accepted: [Ixx, Iyy, Izz, Ixy, Iyz, Ixz] (kg m^2) "
         "of a positive semi-definite tensor whose principal moments obey the triangle inequality"),
        (INERTIAL.replace("[0.001, 0.05, 0.05, 0.0, 0.0, 0.0]", "[0.01, 0.05, 0.07, 0.0, 0.0, 0.0]"),
         "joints[0].inertial.inertia: [0.01, 0.05, 0.07, 0.0, 0.0, 0.0] principal moments [0.01, 0.05, 0.07] "
         "violate the triangle inequality (0.07 > 0.01 + 0.05); accepted: [Ixx, Iyy, Izz, Ixy, Iyz, Ixz] "
         "(kg m^2) of a positive semi-definite tensor whose principal moments obey the triangle inequality; "
         "or set balance_inertia = true"),
        (INERTIAL.replace("mass = 2.0", "mass = nan"), "joints[0].inertial.mass: expected a finite number, got nan"),
        ("[joints.inertial]\n", "joints[0].inertial.mass: missing required field"),
        ("inertial = 3\n", "joints[0].inertial: expected a table with keys com, inertia, mass, got 3"),
    ],
)
def test_bad_inertial_tables_name_file_joint_field_and_value(tmp_path, table, expected):
    assert _error(tmp_path, JOINT + table) == expected


def test_inertial_on_every_joint_or_none(tmp_path):
    assert _error(tmp_path, JOINT + INERTIAL, JOINT) == (
        "joints[1].inertial: missing, but joints[0] has one; give [joints.inertial] for every joint or for none"
    )
    assert _error(tmp_path, JOINT, JOINT + INERTIAL).startswith("joints[0].inertial: missing, but joints[1] has one")


def test_com_fraction_and_inertial_together_are_ambiguous(tmp_path):
    joint = JOINT + "com = 0.3\n" + INERTIAL
    assert _error(tmp_path, joint) == (
        "joints[0].com: ambiguous: both the com fraction 0.3 and [joints.inertial] are given; "
        "remove com (the inertial's com places the centre of mass)"
    )


@pytest.mark.parametrize(
    ("line", "expected"),
    [
        ("gear = 2.0", "joints[0].drive.gear: unknown key 'gear'; accepted keys: coulomb, effort_limit, "
         "gear_ratio, motor_inertia, velocity_limit, viscous"),
        ("gear_ratio = 0.0", "joints[0].drive.gear_ratio: gear_ratio 0.0 is out of range; accepted: a non-zero gear ratio"),
        ("motor_inertia = -1e-4", "joints[0].drive.motor_inertia: motor_inertia -0.0001 is out of range; "
         "accepted: a motor inertia >= 0 (kg m^2)"),
        ("viscous = -1.0", "joints[0].drive.viscous: viscous -1.0 is out of range; "
         "accepted: a viscous friction coefficient >= 0"),
        ("coulomb = [0.1]", "joints[0].drive.coulomb: expected a list of 2 numbers, got [0.1]"),
        ("coulomb = [-0.1, 0.2]", "joints[0].drive.coulomb: coulomb [-0.1, 0.2] is out of range; "
         "accepted: [Tc+, Tc-] with Tc+ >= 0 and Tc- <= 0"),
        ("effort_limit = 0.0", "joints[0].drive.effort_limit: effort_limit 0.0 is out of range; accepted: an effort limit > 0"),
        ("velocity_limit = -3.0", "joints[0].drive.velocity_limit: velocity_limit -3.0 is out of range; "
         "accepted: a velocity limit > 0"),
    ],
)
def test_bad_drive_tables_name_file_joint_field_and_value(tmp_path, line, expected):
    assert _error(tmp_path, JOINT + "[joints.drive]\n" + line + "\n") == expected


def test_from_arrays_takes_inertials_and_drives():
    li = LinkInertials.from_arrays([1.0], [[0.0, 0.0, 0.1]], [np.eye(3) * 0.01])
    rob = RobotParams.from_arrays("one", [0.3], [0.0], [0.0], [0.0], [0], inertials=li, drives=Drives.default(1))
    assert rob.inertials is li and rob.drives.gear_ratio[0] == 1.0
    with pytest.raises(ValueError, match="inertials describe 1 joints, dh_a has 2"):
        RobotParams.from_arrays("two", [0.3, 0.3], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0, 0], inertials=li)
    with pytest.raises(ValueError, match="mass of link 1 is negative"):
        LinkInertials.from_arrays([-1.0], [[0.0, 0.0, 0.0]], [np.eye(3)])
    with pytest.raises(ValueError, match="inertia of link 1 principal moments"):
        LinkInertials.from_arrays([1.0], [[0.0, 0.0, 0.0]], [np.diag([0.1, 0.1, 0.3])])
    with pytest.raises(ValueError, match=r"com must be a finite \(1, 3\) array, got shape \(3,\)"):
        LinkInertials.from_arrays([1.0], [0.0, 0.0, 0.0], [np.eye(3)])


# ------------------------------------------------------------------ shipped data


@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_every_shipped_robot_has_physical_inertials(name):
    li = robot(name).inertials
    assert li is not None and li.mass.shape == (robot(name).n_dofs,)
    assert np.all(li.mass >= 0.0) and li.mass.sum() > 0.0


@pytest.mark.parametrize("name", sorted(set(ROBOT_NAMES) - PUBLISHED))
def test_estimated_tables_in_the_files_are_estimate_inertials(name):
    """Robots without published data ship the output of estimate_inertials (6 digits)."""
    rob = robot(name)
    assert "estimate_inertials" in Path(rob.source).read_text()
    est = estimate_inertials(dataclasses.replace(rob, inertials=None)).inertials
    np.testing.assert_allclose(rob.inertials.mass, est.mass, rtol=1e-5)
    np.testing.assert_allclose(rob.inertials.com, est.com, rtol=1e-5, atol=1e-9)
    np.testing.assert_allclose(rob.inertials.inertia, est.inertia, rtol=1e-5, atol=1e-9)


def test_published_values_spot_checks():
    puma, stanford, ur5 = robot("puma560"), robot("stanford"), robot("ur5")
    assert puma.inertials.mass[1] == 17.4 and puma.inertials.inertia[0, 1, 1] == 0.35
    np.testing.assert_array_equal(puma.inertials.com[1], [-0.3638, 0.006, 0.2275])
    np.testing.assert_array_equal(puma.drives.gear_ratio, [-62.6111, 107.815, -53.7063, 76.0364, 71.923, 76.686])
    np.testing.assert_array_equal(puma.drives.coulomb[0], [0.395, -0.435])
    np.testing.assert_array_equal(puma.drives.effort_limit, [97.6, 186.4, 89.4, 24.2, 20.1, 21.3])
    np.testing.assert_array_equal(puma.drives.velocity_limit, [1.92, 1.51, 2.40, 5.34, 5.09, 5.74])
    # Stanford: COMs inside the arm (unit slips of public copies corrected), Jm at the joint
    assert np.abs(stanford.inertials.com).max() < 0.7
    np.testing.assert_array_equal(stanford.drives.motor_inertia, [0.953, 2.193, 0.782, 0.106, 0.097, 0.020])
    np.testing.assert_array_equal(ur5.inertials.mass, [3.7, 8.393, 2.33, 1.219, 1.219, 0.1879])
    np.testing.assert_array_equal(ur5.inertials.com[1], [0.2125, 0.0, 0.11336])


# ------------------------------------------------------------------ estimate


def test_estimate_of_one_straight_link_is_a_cylinder_plus_housing():
    """Link of length a along x: a cylinder from (-a, 0, 0) to the origin plus a housing
    cylinder (length 2r) on z at the origin; closed-form mass, COM and inertia."""
    a, density = 0.6, 800.0
    rob = RobotParams.from_arrays("stick", [a], [0.0], [0.0], [0.0], [0])
    r = ESTIMATE_RADIUS_FRAC * a
    est = estimate_inertials(rob, density=density).inertials
    m1, m2 = density * math.pi * r**2 * a, density * math.pi * r**2 * 2 * r
    assert est.estimated
    np.testing.assert_allclose(est.mass, [m1 + m2], rtol=1e-12)
    x = -a / 2 * m1 / (m1 + m2)
    np.testing.assert_allclose(est.com[0], [x, 0.0, 0.0], atol=1e-15)
    ixx = m1 * r**2 / 2 + m2 * (3 * r**2 + 4 * r**2) / 12
    iyy = m1 * (3 * r**2 + a**2) / 12 + m1 * (-a / 2 - x) ** 2 + m2 * (3 * r**2 + 4 * r**2) / 12 + m2 * x**2
    izz = m1 * (3 * r**2 + a**2) / 12 + m1 * (-a / 2 - x) ** 2 + m2 * r**2 / 2 + m2 * x**2
    np.testing.assert_allclose(est.inertia[0], np.diag([ixx, iyy, izz]), rtol=1e-12, atol=1e-18)


def test_estimate_is_physical_for_random_chains_and_refuses_bad_density():
    rng = np.random.default_rng(5)
    for n in (1, 3, 7):
        est = estimate_inertials(random_dh_robot(rng, n)).inertials
        assert np.all(est.mass > 0.0)
        LinkInertials.from_arrays(est.mass, est.com, est.inertia)  # validates every tensor
    with pytest.raises(ValueError, match="density must be a positive finite number"):
        estimate_inertials(robot("planar3"), density=-1.0)
    assert DEFAULT_DENSITY == 1000.0


# ------------------------------------------------------------------ drawn COMs


def test_link_coms_sit_at_the_inertial_com_and_move_with_the_link():
    rng = np.random.default_rng(9)
    for n in (2, 5):
        rob = dataclasses.replace(random_dh_robot(rng, n), inertials=random_inertials(rng, n))
        kin, state = Kinematics(rob), RobotState(rob)
        for q in random_q(rob, rng, 3):
            qd = rng.normal(size=n)
            state.set_q(q)
            state.set_qd(qd)
            kin.update(state.joint_state)
            frames = forward_kinematics(rob, q, all_frames=True)[: n + 1]
            np.testing.assert_allclose(kin.link_com, expected_coms(rob, frames), atol=1e-12)
            h = 1e-6
            plus = expected_coms(rob, forward_kinematics(rob, q + h * qd, all_frames=True)[: n + 1])
            minus = expected_coms(rob, forward_kinematics(rob, q - h * qd, all_frames=True)[: n + 1])
            np.testing.assert_allclose(kin.link_com_vel, (plus - minus) / (2 * h), atol=1e-6)
