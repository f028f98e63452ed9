"""The library of real robots in robots/: every file loads with the structure its
manufacturer publishes, reproduces a pose computed here by hand from the published table,
reaches as far as the data sheet says, and carries physical inertial and drive data.

Expected values are written from the published numbers (lengths in metres, as printed in
each file's source), never produced by the code under test.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from kin_helpers import robot
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.params import JTYPE_REVOLUTE
from robot_sim.io.robot_file import ROBOTS_DIR, available_robots

DEG = math.pi / 180.0

# name: (DOF, convention) of the real robots; all their joints are revolute.
LIBRARY = {
    "panda": (7, "modified"),
    "iiwa14": (7, "standard"),
    "lwr4": (7, "standard"),
    "gen3": (7, "standard"),
    "ur3": (6, "standard"),
    "ur3e": (6, "standard"),
    "ur5e": (6, "standard"),
    "ur10": (6, "standard"),
    "ur10e": (6, "standard"),
    "kr5_arc": (6, "standard"),
    "kr6_r900": (6, "standard"),
    "irb120": (6, "standard"),
    "irb140": (6, "standard"),
    "lrmate200id": (6, "standard"),
    "m20ia": (6, "standard"),
    "tx90": (6, "standard"),
}

# Data-sheet weight [kg] of the arms whose files give published inertials.  The files model
# the moving links only; the fixed base (link 0) is the rest of the weight.
DATASHEET_MASS = {
    "panda": 18.0,  # Franka Emika: "approx. 18 kg"
    "gen3": 8.2,  # Kinova Gen3 7 DOF
    "ur3": 11.0,
    "ur3e": 11.2,
    "ur5e": 20.6,
    "ur10": 28.9,
    "ur10e": 33.5,
}

HOME_KUKA = np.array([0.0, -90.0, 90.0, 0.0, 0.0, 0.0]) * DEG  # KUKA's HOME: A2 -90°, A3 +90°

# R of the flange frame (tool0) at the hand-computed pose, columns = its x, y, z in the world
R_DOWN = np.diag([1.0, -1.0, -1.0])  # z pointing down, x forward
R_UP = np.eye(3)
R_UR = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # x fwd, y up, z -y
R_FWD_X_DOWN = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # z fwd, x down
R_FWD_X_UP = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])  # z fwd, x up


def _ur(d1: float, a2: float, a3: float, d4: float, d5: float, d6: float):
    """UR arm at zero, stretched along -x (a2, a3 < 0): flange at (a2 + a3, -(d4 + d6),
    d1 - d5), i.e. x = -(|a2| + |a3|)."""
    return np.zeros(6), np.array([a2 + a3, -(d4 + d6), d1 - d5]), R_UR


# name: (q, flange position, flange rotation), each from the published table by hand.
HAND_POSES = {
    # Franka's table at q = 0 (Craig): twists cancel pairwise, every a lies along x and
    # every d along ±z: x = a4 + a5 + a7, z = d1 + d3 + d5 - flange, z7 pointing down.
    "panda": (np.zeros(7), np.array([0.0825 - 0.0825 + 0.088, 0.0, 0.333 + 0.316 + 0.384 - 0.107]), R_DOWN),
    # S-R-S arms at zero stand straight up: base + upper arm + forearm + flange
    "iiwa14": (np.zeros(7), np.array([0.0, 0.0, 0.36 + 0.42 + 0.4 + 0.126]), R_UP),
    "lwr4": (np.zeros(7), np.array([0.0, 0.0, 0.3105 + 0.4 + 0.39 + 0.078]), R_UP),
    # Kinova: the two small offsets d2, d4 are lateral (-y), the rest vertical
    "gen3": (
        np.zeros(7),
        np.array([0.0, -(0.0054 + 0.0064) - (0.0064 + 0.0064),
                  (0.1564 + 0.1284) + (0.2104 + 0.2104) + (0.2084 + 0.1059) + (0.1059 + 0.0615)]),
        R_UP,
    ),
    "ur3": _ur(0.1519, -0.24365, -0.21325, 0.11235, 0.08535, 0.0819),
    "ur3e": _ur(0.15185, -0.24355, -0.2132, 0.13105, 0.08535, 0.0921),
    "ur5e": _ur(0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996),
    "ur10": _ur(0.1273, -0.612, -0.5723, 0.163941, 0.1157, 0.0922),
    "ur10e": _ur(0.1807, -0.6127, -0.57155, 0.17415, 0.11985, 0.11655),
    # KUKA HOME: upper arm vertical, forearm horizontal above it by the A3-A4 offset
    "kr5_arc": (HOME_KUKA, np.array([0.18 + 0.62 + 0.115, 0.0, 0.4 + 0.6 + 0.12]), R_FWD_X_DOWN),
    "kr6_r900": (HOME_KUKA, np.array([0.025 + 0.42 + 0.08, 0.0, 0.4 + 0.455 + 0.035]), R_FWD_X_DOWN),
    # ABB and FANUC zero: upper arm vertical, forearm horizontal
    "irb120": (np.zeros(6), np.array([0.302 + 0.072, 0.0, 0.29 + 0.27 + 0.07]), R_FWD_X_DOWN),
    "irb140": (np.zeros(6), np.array([0.07 + 0.38 + 0.065, 0.0, 0.352 + 0.36]), R_FWD_X_DOWN),
    "lrmate200id": (np.zeros(6), np.array([0.05 + 0.335 + 0.08, 0.0, 0.33 + 0.33 + 0.035]), R_FWD_X_UP),
    "m20ia": (np.zeros(6), np.array([0.15 + 0.835 + 0.1, 0.0, 0.525 + 0.79 + 0.25]), R_FWD_X_UP),
    # Stäubli zero: the arm stands straight up, J3's 50 mm offset to the side (+y)
    "tx90": (np.zeros(6), np.array([0.05, 0.05, 0.478 + 0.425 + 0.425 + 0.1]), R_UP),
}

# Industrial arms: the data sheet's reach is the largest horizontal distance from the axis
# of joint 1 to the wrist centre (frame 5), reached by joints 2 and 3 alone.
# name: (reach [m] from the data sheet, the same from the published lengths)
WRIST_REACH = {
    "kr6_r900": (0.9015, 0.025 + 0.455 + math.hypot(0.42, 0.035)),
    "kr5_arc": (1.411, 0.18 + 0.6 + math.hypot(0.62, 0.12)),
    "irb120": (0.580, 0.27 + math.hypot(0.302, 0.07)),
    "irb140": (0.810, 0.07 + 0.36 + 0.38),
    "lrmate200id": (0.717, 0.05 + 0.33 + math.hypot(0.335, 0.035)),
    "m20ia": (1.811, 0.15 + 0.79 + math.hypot(0.835, 0.25)),
}


def test_library_has_at_least_twenty_robots_and_all_listed_here():
    names = available_robots()
    assert len(names) >= 20
    assert set(LIBRARY) <= set(names)


@pytest.mark.parametrize("name", available_robots())
def test_every_robot_file_loads_and_describes_itself_in_one_line(name):
    rob = robot(name)
    assert rob.n_dofs >= 1
    assert rob.description and "\n" not in rob.description and len(rob.description) <= 90
    # the file opens with where its numbers come from
    assert (ROBOTS_DIR / f"{name}.toml").read_text().lstrip().startswith("#")
    # angles were converted: no revolute range beyond ±420° (a file in degrees read as rad)
    rev = rob.jtype == JTYPE_REVOLUTE
    assert np.all(np.abs(rob.q_min[rev][np.isfinite(rob.q_min[rev])]) <= 420.0 * DEG + 1e-12)
    assert np.all(np.abs(rob.q_max[rev][np.isfinite(rob.q_max[rev])]) <= 420.0 * DEG + 1e-12)


@pytest.mark.parametrize("name, expected", LIBRARY.items())
def test_dof_joint_types_and_convention(name, expected):
    n, convention = expected
    rob = robot(name)
    assert rob.n_dofs == n
    np.testing.assert_array_equal(rob.jtype, np.full(n, JTYPE_REVOLUTE))
    assert getattr(rob, "convention", "standard") == convention
    text = (ROBOTS_DIR / f"{name}.toml").read_text()
    assert "Cross-checked" in text  # each file says what it was checked against


@pytest.mark.parametrize("name", HAND_POSES)
def test_flange_pose_computed_by_hand_from_the_published_table(name):
    q, position, rotation = HAND_POSES[name]
    T = forward_kinematics(robot(name), q)
    np.testing.assert_allclose(T[:3, 3], position, atol=1e-12)
    np.testing.assert_allclose(T[:3, :3], rotation, atol=1e-12)


@pytest.mark.parametrize("name", WRIST_REACH)
def test_industrial_reach_to_the_wrist_centre_matches_the_data_sheet(name):
    datasheet, from_lengths = WRIST_REACH[name]
    assert from_lengths == pytest.approx(datasheet, abs=1e-3)
    rob = robot(name)
    # grid over joints 2 and 3 within their limits (0.5° steps), the other joints at zero
    q2 = np.linspace(rob.q_min[1], rob.q_max[1], int(round((rob.q_max[1] - rob.q_min[1]) / (0.5 * DEG))) + 1)
    q3 = np.linspace(rob.q_min[2], rob.q_max[2], int(round((rob.q_max[2] - rob.q_min[2]) / (0.5 * DEG))) + 1)
    Q = np.zeros((q2.size * q3.size, 6))
    Q[:, 1], Q[:, 2] = np.repeat(q2, q3.size), np.tile(q3, q2.size)
    wrist = forward_kinematics(rob, Q, all_frames=True)[:, 5, :3, 3]
    reach = np.hypot(wrist[:, 0], wrist[:, 1]).max()
    # at the maximum the radius is flat in q2, q3: a grid point within 0.25° of it falls
    # short by less than 1.5 m * (0.25°)² = 0.03 mm
    assert from_lengths - 1e-4 <= reach <= from_lengths + 1e-9


@pytest.mark.parametrize(
    "name, reach, shoulder, tip",
    [
        ("iiwa14", 0.820, 1, 5),  # KUKA: 820 mm, axis A2 to the wrist point (A6)
        ("gen3", 0.902, 1, 8),  # Kinova: 902 mm, joint 2 axis to the flange
    ],
)
def test_seven_dof_reach_matches_the_data_sheet(name, reach, shoulder, tip):
    frames = forward_kinematics(robot(name), np.zeros(7), all_frames=True)
    # straight arm: the shoulder-to-tip distance along the arm, ignoring lateral offsets
    vertical = frames[tip, 2, 3] - frames[shoulder, 2, 3]
    assert vertical == pytest.approx(reach, abs=1e-3)


def test_tx90_reach_to_the_flange_matches_the_data_sheet():
    """Stäubli: 1000 mm from axis 1 to the flange, the arm stretched forward (J2 = 90°)."""
    flange = forward_kinematics(robot("tx90"), np.array([0.0, 90.0, 0.0, 0.0, 0.0, 0.0]) * DEG)[:3, 3]
    assert flange[0] == pytest.approx(0.05 + 0.425 + 0.425 + 0.1, abs=1e-12)
    assert flange[0] == pytest.approx(1.000, abs=1e-3)


def test_panda_reach_over_its_elbow_range_matches_the_data_sheet():
    """Franka: 855 mm.  Shoulder (joint 2 axis, frame 2) to flange, largest over a grid of
    the elbow (joint 4) and wrist (joint 6) within their limits, the others at zero."""
    rob = robot("panda")
    q4 = np.linspace(rob.q_min[3], rob.q_max[3], 301)
    q6 = np.linspace(rob.q_min[5], rob.q_max[5], 301)
    Q = np.zeros((q4.size * q6.size, 7))
    Q[:, 3], Q[:, 5] = np.repeat(q4, q6.size), np.tile(q6, q4.size)
    frames = forward_kinematics(rob, Q, all_frames=True)
    reach = np.linalg.norm(frames[:, 8, :3, 3] - frames[:, 2, :3, 3], axis=1).max()
    # bounded by the straight-line sum of the three segments' lengths
    bound = math.hypot(0.316, 0.0825) + math.hypot(0.384, 0.0825) + math.hypot(0.088, 0.107)
    assert reach <= bound + 1e-12
    assert reach == pytest.approx(0.855, rel=0.01)


# ------------------------------------------------------------------ inertial and drive data


def _with_inertials() -> list[str]:
    return sorted(DATASHEET_MASS)


@pytest.mark.parametrize("name", _with_inertials())
def test_published_inertials_are_physical(name):
    rob = robot(name)
    li = rob.inertials
    assert li is not None and not li.estimated
    n = rob.n_dofs
    assert li.mass.shape == (n,) and np.all(li.mass > 0.0)
    size = float(np.abs(rob.dh_a).sum() + np.abs(rob.dh_d).sum() + np.linalg.norm(rob.tool_tf.t()))
    for i in range(n):
        inertia = li.inertia[i]
        np.testing.assert_array_equal(inertia, inertia.T)
        moments = np.linalg.eigvalsh(inertia)
        assert moments[0] > 0.0, f"{name} link {i + 1}: inertia not positive definite {moments}"
        assert moments[2] <= moments[0] + moments[1] + 1e-12, f"{name} link {i + 1}: triangle inequality"
        ixx, iyy, izz = np.diag(inertia)
        assert ixx <= iyy + izz + 1e-12 and iyy <= izz + ixx + 1e-12 and izz <= ixx + iyy + 1e-12
        # a COM scaled by 1000 (mm read as m) would lie far outside the arm
        assert np.linalg.norm(li.com[i]) < 0.5 * size, f"{name} link {i + 1}: COM {li.com[i]} m"


@pytest.mark.parametrize("name", _with_inertials())
def test_moving_mass_is_the_data_sheet_weight_less_the_base(name):
    total = float(robot(name).inertials.mass.sum())
    assert 0.75 * DATASHEET_MASS[name] <= total <= DATASHEET_MASS[name]


def test_panda_inertials_are_gaz_et_al_table_viii_and_ix():
    li = robot("panda").inertials
    np.testing.assert_array_equal(
        li.mass, [4.970684, 0.646926, 3.228604, 3.587895, 1.225946, 1.666555, 0.735522]
    )
    np.testing.assert_array_equal(li.com[3], [-5.317e-02, 1.04419e-01, 2.7454e-02])
    # I4: Ixx, Iyy, Izz on the diagonal, Ixy = 7.796e-3, Iyz = 8.641e-3, Ixz = -1.332e-3
    np.testing.assert_array_equal(
        li.inertia[3],
        [[2.5853e-02, 7.7960e-03, -1.3320e-03], [7.7960e-03, 1.9552e-02, 8.6410e-03], [-1.3320e-03, 8.6410e-03, 2.8323e-02]],
    )


def test_ur_centres_of_mass_are_urs_in_dh_frame_i():
    """UR5e link 3 (forearm) COM [0.15, 0, 0.0265] in frame 3, whose origin is the wrist 1
    axis: in the world at home it sits 0.15 m from the wrist toward the elbow."""
    rob = robot("ur5e")
    np.testing.assert_array_equal(rob.inertials.com[2], [0.15, 0.0, 0.0265])
    frames = forward_kinematics(rob, np.zeros(6), all_frames=True)
    com_world = frames[3, :3, :3] @ rob.inertials.com[2] + frames[3, :3, 3]
    elbow, wrist = frames[2, :3, 3], frames[3, :3, 3]
    along = (com_world - wrist) @ (elbow - wrist) / np.linalg.norm(elbow - wrist)
    assert along == pytest.approx(0.15, abs=1e-12)


@pytest.mark.parametrize("name", sorted(LIBRARY))
def test_drive_limits_are_in_si_units(name):
    drives = robot(name).drives
    assert drives is not None
    v = drives.velocity_limit
    # rad/s: a limit entered in deg/s would be above 30
    assert np.all((v > 0.1) & (v < 30.0)), v
    e = drives.effort_limit
    assert np.all(e > 0.0)
