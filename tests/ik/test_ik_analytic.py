"""Analytic IK on the shipped arms (issue 29): every solution, exact, distinct, the
generating configuration among them, in both DH conventions; the families found from
the axes; postures, turns inside the limits, batches, singular poses and bad input."""
from __future__ import annotations

import numpy as np
import pytest

from ik_helpers import REACH_TOL, check_complete, pose_errors
from kin_helpers import CONVENTIONS, ROBOT_NAMES, robot, sweep
from robot_sim.ik.family import ik_family
from robot_sim.ik.finish import RADIX, SHORT, TIES, TOP_SHIFT, stable_order
from robot_sim.ik.solutions import ik_solutions
from robot_sim.kinematics import forward_kinematics, random_configurations
from robot_sim.model.params import RobotParams

#: The issue's count of random configurations per arm and convention (the full sweep);
#: the default run checks FAST of them.
FULL, FAST = 1000, 60
CLOSED_FORM = [name for name in ROBOT_NAMES if ik_family(robot(name)).closed_form]

FAMILIES = {
    "puma560": "spherical wrist", "anthropomorphic6": "spherical wrist", "kr6_r900": "spherical wrist",
    "stanford": "spherical wrist", "ur5": "three parallel axes", "ur10e": "three parallel axes",
    "planar3": "parallel axes", "scara": "parallel axes", "anthropomorphic": "position arm",
    "spherical": "position arm", "iiwa14": "spherical wrist", "panda": "spherical wrist",
}


def test_every_shipped_arm_has_a_closed_form() -> None:
    assert CLOSED_FORM == list(ROBOT_NAMES)


@pytest.mark.parametrize("name", sorted(FAMILIES))
@pytest.mark.parametrize("convention", CONVENTIONS)
def test_the_family_comes_from_the_axes_in_either_convention(name: str, convention: str) -> None:
    family = ik_family(robot(name, convention))
    assert family.name == FAMILIES[name] and family.closed_form
    assert family == ik_family(robot(name))
    assert repr(family).startswith(f"<IKFamily {FAMILIES[name]} ({robot(name).n_dofs} joints)")


def test_seven_joint_arms_name_their_free_joint() -> None:
    assert ik_family(robot("iiwa14")).free_joint == 2
    panda = ik_family(robot("panda"))
    assert panda.free_joint == 6 and panda.reversed  # Franka: q7 free, spherical shoulder
    assert "joint 7 free" in repr(panda)
    assert ik_family(robot("puma560")).free_joint is None


@pytest.mark.parametrize("name", sweep(CLOSED_FORM))
@pytest.mark.parametrize("convention", CONVENTIONS)
def test_solutions_are_complete_exact_and_distinct(name: str, convention: str) -> None:
    arm = robot(name, convention)
    Q = random_configurations(arm, FAST, np.random.default_rng(29))
    check_complete(arm, Q)


@pytest.mark.slow
@pytest.mark.parametrize("name", CLOSED_FORM)
@pytest.mark.parametrize("convention", CONVENTIONS)
def test_solutions_are_complete_on_the_full_sweep(name: str, convention: str) -> None:
    arm = robot(name, convention)
    Q = random_configurations(arm, FULL, np.random.default_rng(2900))
    check_complete(arm, Q)


@pytest.mark.parametrize("name", ["puma560", "ur5", "stanford"])
def test_raw_branches_hold_the_configuration_modulo_two_pi(name: str) -> None:
    arm = robot(name)
    Q = random_configurations(arm, 40, np.random.default_rng(3))
    check_complete(arm, Q, within_limits=False)
    T = forward_kinematics(arm, Q[0])
    raw = ik_solutions(arm, T, within_limits=False)
    assert len(raw) <= ik_family(arm).branches
    q0 = arm.q_home
    rev = arm.is_revolute
    assert np.all(np.abs(raw.q[:, rev] - q0[rev]) <= np.pi + 1e-12)  # each turned nearest q0


def test_siciliano_anthropomorphic_arm_has_four_arm_and_two_wrist_postures() -> None:
    """Siciliano et al., Robotics: Modelling, Planning and Control (2009), sec. 2.12.4-2.12.5:
    shoulder right/left × elbow up/down, each with two wrist solutions."""
    arm = robot("anthropomorphic6")
    q = np.radians([30.0, 40.0, 50.0, 20.0, 35.0, -15.0])
    sols = ik_solutions(arm, forward_kinematics(arm, q), within_limits=False)
    names = {f"shoulder {s}, elbow {e}, wrist {w}" for s in ("right", "left") for e in ("up", "down")
             for w in ("not flipped", "flipped")}
    assert len(sols) == 8 and set(sols.branch) == names
    frames = forward_kinematics(arm, sols.q, all_frames=True)
    for k, name in enumerate(sols.branch):
        shoulder, elbow, wrist = frames[k, 1, :3, 3], frames[k, 2, :3, 3], frames[k, 4, :3, 3]
        heading = frames[k, 1, :3, 0]  # x of frame 1: where the arm's plane faces after joint 1
        assert ("right" in name) == (heading @ (wrist - shoulder) > 0), name
        line = (wrist - shoulder) / np.linalg.norm(wrist - shoulder)
        offset = (elbow - shoulder) - ((elbow - shoulder) @ line) * line
        assert ("up" in name) == (offset[2] > 0), name
        assert ("not flipped" in name) == (np.sin(sols.q[k, 4]) > 0), name
    assert sols.branch[0] == "shoulder right, elbow up, wrist not flipped"  # q itself, nearest
    np.testing.assert_allclose(sols.q[0], q, atol=1e-12)


def test_puma_has_eight_named_postures() -> None:
    arm = robot("puma560")
    q = np.radians([20.0, 30.0, -100.0, 40.0, 50.0, 10.0])
    sols = ik_solutions(arm, forward_kinematics(arm, q), within_limits=False)
    assert len(sols) == 8 and len(set(sols.branch)) == 8 and sols.exact.all()


def test_a_joint_beyond_pi_gives_both_turns_of_an_angle() -> None:
    base = robot("puma560")
    lim = np.radians(200.0)
    arm = RobotParams.from_arrays("puma ±200", base.dh_a, base.dh_alpha, base.dh_d, base.dh_th, base.jtype,
                                  q_min=np.r_[base.q_min[:5], -lim], q_max=np.r_[base.q_max[:5], lim])
    q = np.radians([10.0, 50.0, -20.0, 30.0, 40.0, 170.0])
    sols = ik_solutions(arm, forward_kinematics(arm, q))
    same_arm = np.abs(sols.q[:, :5] - q[:5]).max(axis=1) < 1e-9
    np.testing.assert_allclose(np.sort(sols.q[same_arm, 5]), np.radians([170.0 - 360.0, 170.0]), atol=1e-9)
    assert np.all(np.abs(sols.q[:, 5]) <= lim)


def test_ur_joints_give_every_turn_inside_their_two_turns() -> None:
    arm = robot("ur5")
    q = np.array([0.3, -1.2, 1.0, -0.5, 1.1, 0.2])
    within = ik_solutions(arm, forward_kinematics(arm, q))
    raw = ik_solutions(arm, forward_kinematics(arm, q), within_limits=False)
    assert len(raw) == 8
    assert len(within) == 8 * 2**6  # no angle here is a whole turn from a limit
    assert np.all(within.q >= arm.q_min) and np.all(within.q <= arm.q_max)
    d = np.linalg.norm(within.q - arm.q_home, axis=1)
    assert np.all(np.diff(d) >= 0.0)  # nearest to q0 first


def test_a_batch_equals_single_poses_bit_for_bit() -> None:
    arm = robot("kr6_r900")
    Q = random_configurations(arm, 25, np.random.default_rng(5))
    T = forward_kinematics(arm, Q)
    q0 = Q[3]
    batch = ik_solutions(arm, T, q0)
    assert batch.q.shape[:2] == batch.exact.shape and batch.count.shape == (25,)
    for i in range(25):
        one = ik_solutions(arm, T[i], q0)
        k = batch.count[i]
        assert k == len(one)
        assert np.array_equal(batch.q[i, :k], one.q) and tuple(batch.branch[i, :k]) == one.branch
        assert np.isnan(batch.q[i, k:]).all() and (batch.branch[i, k:] == "").all()


@pytest.mark.parametrize("m", [0, 1, 2, 7, 16, 17, 64, 420, 5000])
@pytest.mark.parametrize("keys", ["ties", "spread", "distinct", "close", "crowded"])
def test_the_solutions_sort_as_a_stable_argsort(m: int, keys: str) -> None:
    rng = np.random.default_rng(m)
    if keys == "ties":  # small whole numbers, zero among them: many equal keys
        key = rng.integers(0, max(m // 3, 1), m).astype(float)
    elif keys == "spread":  # distances over many magnitudes, some equal, some subnormal
        key = rng.uniform(0.0, 40.0, m) * 10.0 ** rng.integers(-320, 3, m)
        key[::7] = key[:1].sum()
    elif keys in ("distinct", "close"):  # no two alike in their top bytes (counting alone), or five pairs
        key = ((rng.choice(2 ** 16, m, replace=False).astype(np.uint64) + np.uint64(0x3FF000)) << np.uint64(40)
               ).view(float)
        if keys == "close":  # alike but in the lowest bits (counting, then insertion)
            key[1:10:2] = key[0:10:2][:len(key[1:10:2])] * (1.0 + 2.0 ** -40)
    else:  # "crowded": all alike in the top bytes (every byte counted)
        key = 1.0 + rng.permutation(m) * 2.0 ** -50
    if m > SHORT:  # the keys take the way they are named for
        top = np.sort(key.view(np.uint64) >> np.uint64(TOP_SHIFT))
        ties = int((top[1:] == top[:-1]).sum())
        assert {"distinct": ties == 0, "close": 0 < ties <= TIES, "crowded": ties > TIES or m <= TIES + 1}.get(keys, True)
    key = np.concatenate([key, [-1.0, -1.0, -1.0]])  # beyond m: never read
    order, spare = np.full(m + 3, -1), np.full(m + RADIX + 3, -1)
    stable_order(key, m, order, spare)
    np.testing.assert_array_equal(order[:m], np.argsort(key[:m], kind="stable"))
    assert (order[m:] == -1).all()


def test_solutions_are_read_only() -> None:
    arm = robot("puma560")
    sols = ik_solutions(arm, forward_kinematics(arm, arm.q_home))
    with pytest.raises(AttributeError):
        sols.q = None  # type: ignore[misc]
    assert len(sols.take([1, 0])) == 2 and sols.take([1, 0]).branch == (sols.branch[1], sols.branch[0])


def test_a_pose_out_of_reach_gives_least_squares_branches() -> None:
    arm = robot("puma560")
    T = forward_kinematics(arm, arm.q_home)
    T[:3, 3] *= 5.0
    sols = ik_solutions(arm, T, within_limits=False)
    assert len(sols) >= 1 and not sols.exact.any()
    assert np.isfinite(sols.q).all()
    reach = np.linalg.norm(forward_kinematics(arm, sols.q)[:, :3, 3] - T[:3, 3], axis=1)
    assert reach.min() > 1.0  # really out of reach, and said so


def test_a_singular_wrist_gives_finite_solutions_with_the_free_angle_from_q0() -> None:
    arm = robot("puma560")
    q = np.radians([15.0, 70.0, -40.0, 25.0, 0.0, 30.0])  # q5 = 0: axes 4 and 6 aligned
    q0 = np.radians([15.0, 70.0, -40.0, -10.0, 0.0, 0.0])
    T = forward_kinematics(arm, q)
    sols = ik_solutions(arm, T, q0)
    assert len(sols) >= 1 and np.isfinite(sols.q).all() and sols.exact.all()
    pos, rot = pose_errors(arm, sols.q, T)
    assert pos.max() < REACH_TOL and rot.max() < REACH_TOL
    assert sols.q[0, 3] == pytest.approx(q0[3], abs=1e-9)  # q4 held at q0's, q6 makes up the rest
    assert sols.q[0, 5] == pytest.approx(q[3] + q[5] - q0[3], abs=1e-9)


def test_a_stretched_arm_gives_its_solutions() -> None:
    arm = robot("anthropomorphic")
    q = np.radians([20.0, 30.0, 0.0])  # elbow straight: the two elbow branches merge
    T = forward_kinematics(arm, q)
    sols = ik_solutions(arm, T)
    assert sols.exact.all() and np.abs(sols.q - q).max(axis=1).min() < 1e-6


def test_a_seven_joint_arm_sweeps_its_free_joint() -> None:
    arm = robot("iiwa14")
    q = np.radians([10.0, 40.0, 20.0, -60.0, 30.0, 45.0, 10.0])
    values = np.radians([0.0, 20.0, 40.0])
    sols = ik_solutions(arm, forward_kinematics(arm, q), free_values=values)
    assert set(np.round(np.degrees(sols.q[:, 2]), 9)) <= {0.0, 20.0, 40.0}
    assert np.any(np.abs(sols.q - q).max(axis=1) < 1e-9)
    pos, rot = pose_errors(arm, sols.q, forward_kinematics(arm, q))
    assert pos.max() < REACH_TOL and rot.max() < REACH_TOL
    held = ik_solutions(arm, forward_kinematics(arm, q), q, free_joint=0)
    assert np.all(held.q[:, 0] == q[0]) and np.any(np.abs(held.q - q).max(axis=1) < 1e-9)


@pytest.mark.parametrize(("T", "message"), [
    (np.eye(3), r"T must be a 4x4 transform or an \(N, 4, 4\) array of them, got shape \(3, 3\)"),
    (np.full((4, 4), np.nan), "T holds NaN or infinite values"),
    (np.diag([2.0, 1.0, 1.0, 1.0]), "T is not a rigid transform"),
    (np.stack([np.eye(4), np.eye(4), np.diag([1.0, 1.0, -1.0, 1.0])]), r"T\[2\] is not a rigid transform"),
    ("pose", "T must be a 4x4 transform"),
])
def test_bad_poses_are_named(T: object, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        ik_solutions(robot("puma560"), T)


def test_bad_arguments_are_named() -> None:
    arm = robot("puma560")
    T = forward_kinematics(arm, arm.q_home)
    with pytest.raises(ValueError, match="q0 must have 6 joint values"):
        ik_solutions(arm, T, np.zeros(5))
    with pytest.raises(ValueError, match="free_joint applies to 7-joint arms; PUMA 560 has 6 joints"):
        ik_solutions(arm, T, free_joint=2)
    with pytest.raises(ValueError, match="free_joint must be a joint index 0..6"):
        ik_solutions(robot("iiwa14"), forward_kinematics(robot("iiwa14"), robot("iiwa14").q_home), free_joint=9)
    with pytest.raises(ValueError, match="free_values must hold 1 to"):
        ik_solutions(robot("iiwa14"), forward_kinematics(robot("iiwa14"), robot("iiwa14").q_home), free_values=[])
    with pytest.raises(ValueError, match="ik_solutions needs a RobotParams"):
        ik_solutions("puma560", T)
