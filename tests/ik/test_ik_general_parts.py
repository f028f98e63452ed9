"""The parts of the general 6R solver against independent references: real roots of
polynomials built from known roots, the small dense linear algebra against NumPy, the
pose error against robot_sim.transforms' rotation log, and the claim the solver's
sampling rests on (the determinant is a trigonometric polynomial of degree 8 in q3)."""
from __future__ import annotations

import numpy as np
import pytest

from robot_sim.ik.dense import apply_qt, determinant, householder, null_vector
from robot_sim.ik.family import solver
from robot_sim.ik.general import VI, general_data
from robot_sim.ik.general_kernel import eliminate, sigma
from robot_sim.ik.polish import pose_error
from robot_sim.ik.realroots import real_roots
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.params import RobotParams
from robot_sim.transforms import rot_from_rpy, rotation_log


@pytest.mark.parametrize("seed", range(6))
def test_real_roots_of_a_polynomial_with_known_roots(seed: int) -> None:
    rng = np.random.default_rng(seed)
    real = np.sort(rng.uniform(-3.0, 3.0, rng.integers(1, 7)))
    real = real[np.concatenate([[True], np.diff(real) > 0.05])]
    p = np.poly(real)
    for _ in range(rng.integers(0, 3)):  # complex pairs: no real root
        z = complex(rng.normal(), 0.2 + abs(rng.normal()))
        p = np.polymul(p, [1.0, -2.0 * z.real, abs(z) ** 2])
    c = np.ascontiguousarray(p[::-1] * rng.uniform(0.5, 5.0))
    roots, crit = np.empty(2 * (len(c) - 1)), np.empty(len(c) - 1)
    k, m = real_roots(c, 1e-12, roots, crit)
    np.testing.assert_allclose(np.sort(roots[:k]), real, atol=1e-8)
    dp = np.polyder(p)  # the critical points are the real roots of p'
    assert m == sum(abs(r.imag) < 1e-7 for r in np.roots(dp))
    np.testing.assert_allclose(np.polyval(dp, crit[:m]), 0.0, atol=1e-7 * np.abs(dp).max())


def test_a_double_root_comes_back_as_a_near_tangent_critical_point() -> None:
    c = np.ascontiguousarray(np.poly([1.0, 1.0, -2.0])[::-1])
    roots, crit = np.empty(6), np.empty(3)
    k, _ = real_roots(c, 1e-9, roots, crit)
    assert np.abs(roots[:k] - 1.0).min() < 1e-9 and np.abs(roots[:k] + 2.0).min() < 1e-12


def test_dense_linear_algebra_against_numpy() -> None:
    rng = np.random.default_rng(1)
    S = rng.normal(size=(12, 12))
    assert determinant(S.copy()) == pytest.approx(np.linalg.det(S), rel=1e-12)
    S[:, -1] = S[:, :-1] @ rng.normal(size=11)  # rank 11
    z = np.empty(12)
    null_vector(S.copy(), z)
    assert np.linalg.norm(S @ z) <= 1e-12 * np.linalg.norm(S) * np.linalg.norm(z)
    A0 = rng.normal(size=(14, 8))
    A, V, beta = A0.copy(), np.empty((14, 8)), np.empty(8)
    householder(A, V, beta)
    Qt = np.eye(14)
    apply_qt(V, beta, Qt)
    np.testing.assert_allclose(Qt @ Qt.T, np.eye(14), atol=1e-14)
    np.testing.assert_allclose(Qt @ A0, np.triu(A), atol=1e-13)  # Qᵀ A = R, zero below row 8
    assert np.abs(Qt[8:] @ A0).max() < 1e-13


@pytest.mark.parametrize("angle", [0.4, np.pi - 1e-4, np.pi])
def test_pose_error_is_the_rotation_log_and_the_scaled_offset(angle: float) -> None:
    rng = np.random.default_rng(2)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    X, T = np.eye(4), np.eye(4)
    X[:3, :3] = rot_from_rpy(rng.uniform(-1.0, 1.0, 3))
    T[:3, :3] = (np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * K @ K) @ X[:3, :3]
    T[:3, 3] = [0.3, -0.2, 0.5]
    e = np.empty(6)
    norm = pose_error(X, T, 0.5, e)
    np.testing.assert_allclose(e[:3], 0.5 * T[:3, 3], atol=1e-15)
    log = rotation_log(T[:3, :3] @ X[:3, :3].T)
    assert np.allclose(e[3:], log, atol=1e-9) or (angle == np.pi and np.allclose(e[3:], -log, atol=1e-9))
    assert norm == pytest.approx(np.linalg.norm(e))


def test_the_determinant_is_a_trigonometric_polynomial_of_degree_8() -> None:
    """det Σ(q3) sampled at 64 angles has no Fourier coefficient above 8: the (1 + x²)⁴
    factor of the degree-24 polynomial in tan(q3/2) is spurious, and 18 samples fix it."""
    rng = np.random.default_rng(3)
    robot = RobotParams.from_arrays("6R", rng.uniform(0.1, 0.5, 6), rng.uniform(0.3, 2.8, 6),
                                    rng.uniform(0.05, 0.4, 6), np.zeros(6), np.zeros(6))
    data = general_data(robot, solver(robot))
    assert data is not None and not data.reversed
    T = forward_kinematics(robot, rng.uniform(-np.pi, np.pi, 6))
    Q, A, V, beta, G, S = (np.empty((14, 9)), np.empty((14, 8)), np.empty((14, 8)), np.empty(8),
                           np.empty((6, 3, 9)), np.empty((12, 12)))
    eliminate(T, data.args[0], *data.args[1:6], VI, Q, A, V, beta, G)
    f = []
    for q3 in 2.0 * np.pi * np.arange(64) / 64:
        sigma(G, q3, S)
        f.append(determinant(S))
    spectrum = np.abs(np.fft.rfft(f))
    assert spectrum[9:].max() < 1e-10 * spectrum.max() and spectrum[8] > 1e-6 * spectrum.max()
