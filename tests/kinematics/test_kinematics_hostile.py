"""Kinematics under hostile input: IK never raises for a rigid target and does not depend
on the robot's scale; API arguments are validated with ValueError; the per-robot model
cache lets robots go."""
from __future__ import annotations

import gc
import re
import warnings
import weakref

import numpy as np
import pytest

from kin_helpers import robot as shipped
from robot_sim.kinematics import (
    Kinematics,
    forward_kinematics,
    jacobian,
    random_configurations,
    solve_ik,
    workspace_points,
)
from robot_sim.model.params import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotParams
from robot_sim.model.state import JointState, RobotState
from robot_sim.transforms import HomogeneousTransform

SCALES = (1e-3, 1e-2, 1.0, 1e2, 1e3)
N_SCALE_TARGETS = 40


def scaled(robot: RobotParams, s: float) -> RobotParams:
    """``robot`` with every length (DH a and d, base and tool offsets, prismatic joint
    values) multiplied by ``s``: the same robot seen at another scale."""

    def scale_tf(tf: HomogeneousTransform) -> HomogeneousTransform:
        mat = tf.mat.copy()
        mat[:3, 3] *= s
        return HomogeneousTransform(mat)

    f = np.where(robot.jtype == JTYPE_PRISMATIC, s, 1.0)
    return RobotParams.from_arrays(
        f"{robot.name} x{s:g}", robot.dh_a * s, robot.dh_alpha, robot.dh_d * s, robot.dh_th, robot.jtype,
        q_home=robot.q_home * f, q_min=robot.q_min * f, q_max=robot.q_max * f,
        link_com_frac=robot.link_com_frac, base_tf=scale_tf(robot.base_tf),
        tool_tf=scale_tf(robot.tool_tf), convention=robot.convention,
    )


def solved(robot: RobotParams, targets: np.ndarray) -> int:
    count = 0
    for target in targets:
        result = solve_ik(robot, target)
        if result.success:  # verified independently of the solver's own error
            reached = forward_kinematics(robot, result.q)
            assert np.linalg.norm(reached[:3, 3] - target[:3, 3]) <= 1e-6
            count += 1
    return count


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_ik_success_does_not_depend_on_the_robot_scale(name: str) -> None:
    base = shipped(name)
    Q = random_configurations(base, N_SCALE_TARGETS, np.random.default_rng(3))
    counts = {}
    for s in SCALES:
        robot = scaled(base, s)
        counts[s] = solved(robot, forward_kinematics(robot, Q * np.where(robot.jtype == JTYPE_PRISMATIC, s, 1.0)))
    assert counts == {s: N_SCALE_TARGETS for s in SCALES}, counts


def long_planar_arm(length: float) -> RobotParams:
    """Two links of ``length`` metres, base turned 45° about z: stretched out at home, a
    singular configuration whose Gram matrix JJᵀ loses the damping in rounding when the
    links are long."""
    return RobotParams.from_arrays(
        "long arm", [length, length], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [JTYPE_REVOLUTE] * 2,
        base_tf=HomogeneousTransform.from_xyz_rpy([0, 0, 0], [0, 0, np.pi / 4]),
    )


@pytest.mark.parametrize("length", [1e4, 1e8])
def test_ik_on_very_long_links_returns_a_result(length: float) -> None:
    robot = long_planar_arm(length)
    target = forward_kinematics(robot, [0.3, 0.5])
    result = solve_ik(robot, target)
    assert result.success, result.message
    assert result.pos_err <= 1e-6


def test_ik_on_a_10_km_robot_never_raises() -> None:
    puma = scaled(shipped("puma560"), 1e4)  # 6.7 km shoulder, 4.3 km upper arm
    rng = np.random.default_rng(5)
    targets = list(forward_kinematics(puma, random_configurations(puma, 5, rng)))
    targets += [np.eye(4), HomogeneousTransform.from_xyz_rpy([1e5, -2e5, 3e4], [1.0, 2.0, 3.0]).mat]
    for target in targets:
        result = solve_ik(puma, target)
        assert np.isfinite(result.q).all() and np.isfinite(result.pos_err)
    assert solve_ik(puma, targets[0]).success


def test_ik_where_the_arithmetic_overflows_is_a_failed_result() -> None:
    robot = RobotParams.from_arrays("absurd", [1e300, 1e300], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [JTYPE_REVOLUTE] * 2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning leaks either
        result = solve_ik(robot, np.eye(4))
    assert not result.success
    assert np.isfinite(result.q).all()
    assert "did not converge" in result.message or "numerical" in result.message


def test_ik_singular_solves_inside_are_a_failed_result(monkeypatch) -> None:
    def singular(*args, **kwargs):
        raise np.linalg.LinAlgError("Singular matrix")

    monkeypatch.setattr(np.linalg, "solve", singular)
    robot = shipped("humanoid7")  # a 7-joint arm: the numerical path (the closed form needs no solve)
    result = solve_ik(robot, forward_kinematics(robot, robot.q_home + 0.3))
    assert not result.success
    assert np.isfinite(result.q).all()
    assert result.message.startswith("did not converge")


def test_ik_arithmetic_failure_inside_is_a_failed_result(monkeypatch) -> None:
    def overflow(*args, **kwargs):
        raise FloatingPointError("overflow encountered in matmul")

    monkeypatch.setattr(np.linalg, "solve", overflow)
    robot = shipped("humanoid7")  # a 7-joint arm: the numerical path (the closed form needs no solve)
    result = solve_ik(robot, forward_kinematics(robot, robot.q_home + 0.3))
    assert not result.success
    assert np.isfinite(result.q).all()
    assert re.match(
        r"^numerical failure \(overflow encountered in matmul\) after 0 iterations: "
        r"position error \d\.\d+ m, rotation error \d\.\d+ rad$",
        result.message,
    ), result.message


# ------------------------------------------------------------------ argument validation


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(tol_pos="1e-6"), "tol_pos must be a positive finite number, got '1e-6'"),
        (dict(tol_rot=None), "tol_rot must be a positive finite number, got None"),
        (dict(tol_pos=True), "tol_pos must be a positive finite number, got True"),
        (dict(max_iter=None), "max_iter must be a positive integer, got None"),
        (dict(max_iter=2.5), "max_iter must be a positive integer, got 2.5"),
        (dict(max_iter=0), "max_iter must be a positive integer, got 0"),
        (dict(max_restarts=-1), "max_restarts must be an integer >= 0, got -1"),
        (dict(max_restarts="3"), "max_restarts must be an integer >= 0, got '3'"),
        (dict(seed="x"), "seed must be None or a non-negative integer, got 'x'"),
        (dict(seed=-1), "seed must be None or a non-negative integer, got -1"),
        (dict(q0=[1j] * 6), "q0 must hold real numbers, got [1j, 1j, 1j, 1j, 1j, 1j]"),
        (dict(q0={"a": 1}), "q0 must be a sequence of numbers, got {'a': 1}"),
        (dict(q0="abcdef"), "q0 must be a sequence of numbers, got 'abcdef'"),
    ],
)
def test_solve_ik_rejects_bad_arguments(kwargs, message) -> None:
    robot = shipped("puma560")
    with pytest.raises(ValueError) as info:
        solve_ik(robot, np.eye(4), **kwargs)
    assert str(info.value) == message


def test_huge_bad_values_are_cut_in_messages() -> None:
    robot = shipped("puma560")
    with pytest.raises(ValueError) as info:
        solve_ik(robot, np.eye(4), tol_pos="x" * 5000)
    assert len(str(info.value)) < 200
    with pytest.raises(ValueError) as info:
        forward_kinematics(robot, np.full((1000, 7), 0.1))
    assert len(str(info.value)) < 200


@pytest.mark.parametrize(
    "q, message",
    [
        ([0.1 + 2j, 0, 0, 0, 0, 0], "q must hold real numbers, got [(0.1+2j), 0, 0, 0, 0, 0]"),
        ({"q1": 0.1}, "q must be a sequence of numbers, got {'q1': 0.1}"),
        ([None] * 6, "q must be a sequence of numbers, got [None, None, None, None, None, None]"),
        ([[0.0] * 6, [0.0] * 5], "q must be a sequence of numbers, got [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0, 0.0]]"),
    ],
)
def test_joint_vectors_must_be_real_numbers(q, message) -> None:
    robot = shipped("puma560")
    for call in (lambda: forward_kinematics(robot, q), lambda: jacobian(robot, q), lambda: RobotState(robot).set_q(q)):
        with pytest.raises(ValueError) as info:
            call()
        assert str(info.value) == message


@pytest.mark.parametrize("n_samples", [2.5, True, "100", None, 0, -3, np.float64(10.0)])
def test_workspace_points_wants_a_positive_integer(n_samples) -> None:
    with pytest.raises(ValueError, match=r"^n_samples must be a positive integer, got "):
        workspace_points(shipped("puma560"), n_samples)


def test_workspace_points_accepts_numpy_integers() -> None:
    points, manip = workspace_points(shipped("puma560"), np.int64(10), seed=1)
    assert points.shape == (10, 3) and manip.shape == (10,)


def test_workspace_points_refuses_more_than_memory_holds() -> None:
    with pytest.raises(ValueError, match=r"^n_samples = 1000000000.*\(101 characters\) needs more than 2\*\*80 bytes of memory; at most \d+ samples fit in the about .* GiB available$"):
        workspace_points(shipped("puma560"), 10**100)


def test_workspace_of_an_unlimited_prismatic_joint_is_a_clear_error() -> None:
    robot = RobotParams.from_arrays("slider", [0.0], [0.0], [0.0], [0.0], [JTYPE_PRISMATIC])
    with pytest.raises(ValueError, match=r"^slider: prismatic joint 1 has no limits; cannot sample its range$"):
        workspace_points(robot, 10)


def bad_world_transforms() -> list[np.ndarray]:
    nan = np.eye(4)
    nan[0, 3] = np.nan
    sheared = np.eye(4)
    sheared[0, 1] = 0.5
    scaled_up = np.diag([2.0, 2.0, 2.0, 1.0])
    return [nan, sheared, scaled_up, np.eye(3)]


@pytest.mark.parametrize("world", bad_world_transforms(), ids=["nan", "sheared", "scaled", "3x3"])
def test_world_transform_must_be_rigid(world) -> None:
    robot = shipped("puma560")
    calls = [
        lambda: forward_kinematics(robot, robot.q_home, world_tf=world),
        lambda: jacobian(robot, robot.q_home, world_tf=world),
    ]
    kin = Kinematics(robot)
    state = JointState(robot.jtype)
    if world.shape == (4, 4):
        calls.append(lambda: kin.update(state, HomogeneousTransform.wrap(world)))
    for call in calls:
        with pytest.raises(ValueError, match=r"^world_tf must be a rigid 4x4 transform"):
            call()


# ------------------------------------------------------------------ model cache


def test_model_cache_releases_a_robot_after_its_last_user() -> None:
    robot = RobotParams.from_arrays("temporary", [0.3, 0.2], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [JTYPE_REVOLUTE] * 2)
    forward_kinematics(robot, [0.1, 0.2])
    jacobian(robot, [[0.1, 0.2]])
    kin = Kinematics(robot)
    solve_ik(robot, forward_kinematics(robot, [0.3, 0.1]))
    workspace_points(robot, 20, seed=0)
    gone = weakref.ref(robot)
    del robot
    gc.collect()
    assert gone() is not None  # still used by kin
    del kin
    gc.collect()
    assert gone() is None
