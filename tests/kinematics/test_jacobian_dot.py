"""J̇(q, q̇) q̇ and the fused tool kinematics, against finite differences and the single path."""
from __future__ import annotations

import numpy as np
import pytest

from kin_helpers import CONVENTIONS, robot
from robot_sim.kinematics import forward_kinematics, jacobian, jacobian_dot_qd, tool_kinematics

RNG = np.random.default_rng(20)
#: Revolute arms in both conventions, and arms with prismatic joints.
NAMES = ("humanoid7", "panda", "ur5", "puma560", "stanford", "scara", "spherical")


def _state(name: str, convention: str | None = None) -> tuple:
    rob = robot(name, convention)
    q = rob.q_home + RNG.uniform(-0.6, 0.6, rob.n_dofs)
    qd = RNG.uniform(-1.5, 1.5, rob.n_dofs)
    return rob, q, qd


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("name", NAMES)
def test_jdot_qd_is_the_derivative_of_the_jacobian_along_the_motion(name: str, convention: str) -> None:
    """Central differences of J along q̇ (step 1e-6 s): (J(q + h q̇) − J(q − h q̇)) q̇ / 2h."""
    rob, q, qd = _state(name, convention)
    h = 1e-6
    expected = (jacobian(rob, q + h * qd) - jacobian(rob, q - h * qd)) @ qd / (2 * h)
    np.testing.assert_allclose(jacobian_dot_qd(rob, q, qd), expected, atol=2e-8)


@pytest.mark.parametrize("name", NAMES)
def test_jdot_qd_is_the_tool_acceleration_at_zero_joint_acceleration(name: str) -> None:
    """Independent of J: along q(t) = q + t q̇ (q̈ = 0) the tool point's second derivative
    of position and the derivative of its angular velocity ω = J_ω(q(t)) q̇."""
    rob, q, qd = _state(name)
    h = 1e-4
    p = [forward_kinematics(rob, q + k * h * qd)[:3, 3] for k in (-1, 0, 1)]
    linear = (p[2] - 2 * p[1] + p[0]) / h**2
    angular = (jacobian(rob, q + h * qd)[3:] - jacobian(rob, q - h * qd)[3:]) @ qd / (2 * h)
    got = jacobian_dot_qd(rob, q, qd)
    np.testing.assert_allclose(got[:3], linear, atol=2e-5)
    np.testing.assert_allclose(got[3:], angular, atol=1e-7)


@pytest.mark.parametrize("name", NAMES)
def test_batched_equals_single_and_the_pose_and_jacobian_are_the_usual_ones(name: str) -> None:
    rob = robot(name)
    Q = rob.q_home + RNG.uniform(-0.6, 0.6, (5, rob.n_dofs))
    QD = RNG.uniform(-1.5, 1.5, (5, rob.n_dofs))
    T, J, A = tool_kinematics(rob, Q, QD)
    assert T.shape == (5, 4, 4) and J.shape == (5, 6, rob.n_dofs) and A.shape == (5, 6)
    np.testing.assert_allclose(jacobian_dot_qd(rob, Q, QD), A, atol=0)
    for k in range(5):
        Tk, Jk, Ak = tool_kinematics(rob, Q[k], QD[k])
        np.testing.assert_allclose(Tk, T[k], atol=1e-14)
        np.testing.assert_allclose(Jk, J[k], atol=1e-14)
        np.testing.assert_allclose(Ak, A[k], atol=1e-13)
        np.testing.assert_allclose(Tk, forward_kinematics(rob, Q[k]), atol=1e-14)
        np.testing.assert_allclose(Jk, jacobian(rob, Q[k]), atol=1e-14)


def test_at_rest_there_is_no_bias_acceleration() -> None:
    rob = robot("panda")
    assert np.array_equal(jacobian_dot_qd(rob, rob.q_home, np.zeros(7)), np.zeros(6))


def test_bad_rates_are_refused_naming_the_argument() -> None:
    rob = robot("ur5")
    with pytest.raises(ValueError, match="qd must have 6 joint values"):
        jacobian_dot_qd(rob, rob.q_home, [1.0, 2.0])
    with pytest.raises(ValueError, match="qd contains NaN"):
        jacobian_dot_qd(rob, rob.q_home, [np.nan] * 6)
    with pytest.raises(ValueError, match=r"qd must have the shape of q, \(6,\), got \(2, 6\)"):
        jacobian_dot_qd(rob, rob.q_home, np.zeros((2, 6)))
