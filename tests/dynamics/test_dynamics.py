"""dynamics.py: RNEA, CRBA, Coriolis, forward dynamics and energy against closed forms
derived by hand (Lagrange) and against identities on random chains of both conventions."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from robot_sim import dynamics as dyn
from robot_sim.model.convert import to_modified
from robot_sim.model.inertials import Drives, LinkInertials
from kin_helpers import CONVENTIONS, ROBOT_NAMES, random_dh_robot, random_inertials, random_q, robot
from robot_sim.kinematics import jacobian
from robot_sim.model.params import JTYPE_PRISMATIC, JTYPE_REVOLUTE, RobotParams
from robot_sim.transforms import HomogeneousTransform

G = 9.81
#: frame 0's y axis pointing up, so planar arms (z axes horizontal) move in a vertical plane
Y_UP = HomogeneousTransform.from_xyz_rpy([0.0, 0.0, 0.0], [math.pi / 2, 0.0, 0.0])


def _planar(lengths, masses, lc, izz) -> RobotParams:
    """Planar arm in a vertical plane: link i of length a_i, COM at lc_i from joint i, Izz_i."""
    n = len(lengths)
    com = [[-(a - c), 0.0, 0.0] for a, c in zip(lengths, lc)]
    inertia = [np.diag([1e-3, i + 1e-3, i]) for i in izz]  # only Izz enters planar motion
    return RobotParams.from_arrays(
        "planar", lengths, [0.0] * n, [0.0] * n, [0.0] * n, [JTYPE_REVOLUTE] * n,
        base_tf=Y_UP, inertials=LinkInertials.from_arrays(masses, com, inertia),
    )


def _christoffel(dM: list[np.ndarray], qd: np.ndarray) -> np.ndarray:
    """C_kj = Σ_i ½ (∂M_kj/∂q_i + ∂M_ki/∂q_j − ∂M_ij/∂q_k) q̇_i from the partials dM[i]."""
    n = len(qd)
    C = np.zeros((n, n))
    for k in range(n):
        for j in range(n):
            C[k, j] = sum(0.5 * (dM[i][k, j] + dM[j][k, i] - dM[k][i, j]) * qd[i] for i in range(n))
    return C


def _assert_model(rob, q, qd, qdd, M, C, g, atol=1e-10):
    np.testing.assert_allclose(dyn.mass_matrix(rob, q), M, atol=atol)
    np.testing.assert_allclose(dyn.gravity_torque(rob, q), g, atol=atol)
    np.testing.assert_allclose(dyn.coriolis_matrix(rob, q, qd) @ qd, C @ qd, atol=atol)
    np.testing.assert_allclose(dyn.inverse_dynamics(rob, q, qd, qdd), M @ qdd + C @ qd + g, atol=atol)


# ------------------------------------------------------------------ closed forms


def test_planar_two_link_matches_lagrange():
    a1, a2, m1, m2, lc1, lc2, i1, i2 = 0.7, 0.5, 3.0, 2.0, 0.3, 0.2, 0.05, 0.02
    rob = _planar([a1, a2], [m1, m2], [lc1, lc2], [i1, i2])
    rng = np.random.default_rng(1)
    for _ in range(5):
        q, qd, qdd = rng.uniform(-3, 3, 2), rng.normal(size=2), rng.normal(size=2)
        c1, c2, c12 = math.cos(q[0]), math.cos(q[1]), math.cos(q[0] + q[1])
        M = np.array([
            [m1 * lc1**2 + m2 * (a1**2 + lc2**2 + 2 * a1 * lc2 * c2) + i1 + i2, m2 * (lc2**2 + a1 * lc2 * c2) + i2],
            [m2 * (lc2**2 + a1 * lc2 * c2) + i2, m2 * lc2**2 + i2],
        ])
        h = -m2 * a1 * lc2 * math.sin(q[1])
        C = np.array([[h * qd[1], h * (qd[0] + qd[1])], [-h * qd[0], 0.0]])
        g = np.array([(m1 * lc1 + m2 * a1) * G * c1 + m2 * lc2 * G * c12, m2 * lc2 * G * c12])
        _assert_model(rob, q, qd, qdd, M, C, g)
        np.testing.assert_allclose(dyn.coriolis_matrix(rob, q, qd), C, atol=1e-10)  # Christoffel's C


def test_planar_three_link_matches_lagrange():
    """M is linear in cos q2, cos q3 and cos(q2 + q3): M = M0 + c2 A2 + c3 A3 + c23 A23,
    so its partial derivatives, and Christoffel's C, follow exactly."""
    a, m, lc, I = [0.5, 0.4, 0.3], [4.0, 3.0, 2.0], [0.2, 0.25, 0.1], [0.08, 0.05, 0.01]
    rob = _planar(a, m, lc, I)
    M0 = np.array([
        [sum(I) + m[0] * lc[0]**2 + m[1] * (a[0]**2 + lc[1]**2) + m[2] * (a[0]**2 + a[1]**2 + lc[2]**2),
         I[1] + I[2] + m[1] * lc[1]**2 + m[2] * (a[1]**2 + lc[2]**2), I[2] + m[2] * lc[2]**2],
        [0, I[1] + I[2] + m[1] * lc[1]**2 + m[2] * (a[1]**2 + lc[2]**2), I[2] + m[2] * lc[2]**2],
        [0, 0, I[2] + m[2] * lc[2]**2],
    ])
    M0 = np.triu(M0) + np.triu(M0, 1).T
    k2 = m[1] * a[0] * lc[1] + m[2] * a[0] * a[1]
    A2 = np.array([[2 * k2, k2, 0], [k2, 0, 0], [0, 0, 0]])
    k3 = m[2] * a[1] * lc[2]
    A3 = np.array([[2 * k3, 2 * k3, k3], [2 * k3, 2 * k3, k3], [k3, k3, 0]])
    k23 = m[2] * a[0] * lc[2]
    A23 = np.array([[2 * k23, k23, k23], [k23, 0, 0], [k23, 0, 0]])
    rng = np.random.default_rng(2)
    for _ in range(5):
        q, qd, qdd = rng.uniform(-3, 3, 3), rng.normal(size=3), rng.normal(size=3)
        s2, s3, s23 = math.sin(q[1]), math.sin(q[2]), math.sin(q[1] + q[2])
        M = M0 + math.cos(q[1]) * A2 + math.cos(q[2]) * A3 + math.cos(q[1] + q[2]) * A23
        dM = [np.zeros((3, 3)), -s2 * A2 - s23 * A23, -s3 * A3 - s23 * A23]
        C = _christoffel(dM, qd)
        phi = np.cumsum(q)
        g = G * np.array([
            m[0] * lc[0] * math.cos(phi[0]) + m[1] * (a[0] * math.cos(phi[0]) + lc[1] * math.cos(phi[1]))
            + m[2] * (a[0] * math.cos(phi[0]) + a[1] * math.cos(phi[1]) + lc[2] * math.cos(phi[2])),
            m[1] * lc[1] * math.cos(phi[1]) + m[2] * (a[1] * math.cos(phi[1]) + lc[2] * math.cos(phi[2])),
            m[2] * lc[2] * math.cos(phi[2]),
        ])
        _assert_model(rob, q, qd, qdd, M, C, g)


def test_pendulum_on_a_prismatic_carriage_matches_lagrange():
    """Carriage of mass mc sliding along world x (joint 1, prismatic), pendulum of mass mp,
    COM at lc, inertia Ic swinging about world y (joint 2, hanging down at q2 = 0):
    M = [[mc + mp, −mp lc cos φ], [−mp lc cos φ, mp lc² + Ic]], C = [[0, mp lc sin φ φ̇], [0, 0]],
    g = [0, mp g lc sin φ]."""
    mc, mp, lc, ell, Ic = 5.0, 1.5, 0.35, 0.5, 0.03
    base = HomogeneousTransform.from_xyz_rpy([0.0, 0.0, 1.0], [0.0, math.pi / 2, 0.0])  # z0 along world x
    inertials = LinkInertials.from_arrays(
        [mc, mp], [[0.05, -0.02, 0.1], [-(ell - lc), 0.0, 0.0]], [np.diag([0.1, 0.2, 0.15]), np.diag([1e-3, Ic, Ic])]
    )
    rob = RobotParams.from_arrays(
        "cart", [0.0, ell], [-math.pi / 2, 0.0], [0.2, 0.0], [0.0, 0.0], [JTYPE_PRISMATIC, JTYPE_REVOLUTE],
        base_tf=base, inertials=inertials,
    )
    rng = np.random.default_rng(3)
    for _ in range(5):
        q, qd, qdd = rng.uniform(-2, 2, 2), rng.normal(size=2), rng.normal(size=2)
        phi = q[1]
        M = np.array([[mc + mp, -mp * lc * math.cos(phi)], [-mp * lc * math.cos(phi), mp * lc**2 + Ic]])
        C = np.array([[0.0, mp * lc * math.sin(phi) * qd[1]], [0.0, 0.0]])
        g = np.array([0.0, mp * G * lc * math.sin(phi)])
        _assert_model(rob, q, qd, qdd, M, C, g)


def test_drive_terms_are_reflected_inertia_and_friction():
    rob = _planar([0.7, 0.5], [3.0, 2.0], [0.3, 0.2], [0.05, 0.02])
    drives = Drives.from_arrays(2, motor_inertia=[2e-4, 1e-4], gear_ratio=[-60.0, 100.0], viscous=[1e-3, 2e-3],
                                coulomb=[[0.4, -0.3], [0.1, -0.2]])
    driven = dataclasses.replace(rob, drives=drives)
    q, qdd = np.array([0.3, -0.4]), np.array([1.5, -2.0])
    np.testing.assert_allclose(dyn.mass_matrix(driven, q) - dyn.mass_matrix(rob, q), np.diag([0.72, 1.0]), atol=1e-12)
    for qd, coulomb in (([0.5, -0.25], [60 * 0.4, 100 * -0.2]), ([-0.5, 0.0], [60 * -0.3, 0.0]), ([0.0, 0.0], [0.0, 0.0])):
        qd = np.array(qd)
        expected = np.array([0.72, 1.0]) * qdd + np.array([3600 * 1e-3, 1e4 * 2e-3]) * qd + coulomb
        diff = dyn.inverse_dynamics(driven, q, qd, qdd) - dyn.inverse_dynamics(rob, q, qd, qdd)
        np.testing.assert_allclose(diff, expected, atol=1e-10)
        np.testing.assert_allclose(dyn.forward_dynamics(driven, q, qd, dyn.inverse_dynamics(driven, q, qd, qdd)), qdd, atol=1e-10)


# ------------------------------------------------------------------ random chains


def _random_case(seed: int, n: int, convention: str):
    rng = np.random.default_rng(seed)
    rob = random_dh_robot(rng, n, convention=convention)
    rob = dataclasses.replace(rob, inertials=random_inertials(rng, n))
    return rob, rng


CASES = [(seed, n, conv) for conv in CONVENTIONS for seed, n in ((10, 1), (11, 2), (12, 4), (13, 6), (14, 7))]


@pytest.mark.parametrize(("seed", "n", "convention"), CASES)
def test_random_chains_satisfy_the_identities(seed, n, convention):
    rob, rng = _random_case(seed, n, convention)
    h = 1e-6
    for _ in range(3):
        q, qd, qdd = random_q(rob, rng), rng.normal(size=n), rng.normal(size=n)
        M, C, g = dyn.mass_matrix(rob, q), dyn.coriolis_matrix(rob, q, qd), dyn.gravity_torque(rob, q)
        tau = dyn.inverse_dynamics(rob, q, qd, qdd)
        scale = max(1.0, np.abs(tau).max())
        np.testing.assert_allclose(tau, M @ qdd + C @ qd + g, atol=1e-10 * scale)
        np.testing.assert_allclose(dyn.bias_torque(rob, q, qd), C @ qd + g, atol=1e-10 * scale)
        assert np.array_equal(M, M.T)
        assert np.linalg.eigvalsh(M).min() > 0.0
        M_dot = (dyn.mass_matrix(rob, q + h * qd) - dyn.mass_matrix(rob, q - h * qd)) / (2 * h)
        S = M_dot - 2 * C
        np.testing.assert_allclose(S, -S.T, atol=1e-6 * max(1.0, np.abs(M_dot).max()))
        np.testing.assert_allclose(dyn.forward_dynamics(rob, q, qd, tau), qdd, atol=1e-8)
        # the Jacobian sum Σ m J_vᵀJ_v + J_ωᵀ I J_ω gives the same M as the composite bodies
        parts = dyn._link_jacobians(rob, q[None], qd[None])
        Jv, Jw, inertia = parts["Jv"][0], parts["Jw"][0], parts["inertia"][0]
        M_jac = np.einsum("k,kai,kaj->ij", rob.inertials.mass, Jv, Jv) + np.einsum("kai,kab,kbj->ij", Jw, inertia, Jw)
        np.testing.assert_allclose(M, M_jac, atol=1e-10 * max(1.0, np.abs(M).max()))


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_batch_equals_single_configurations(convention):
    rob, rng = _random_case(20, 7, convention)
    rob = dataclasses.replace(rob, drives=Drives.from_arrays(7, motor_inertia=rng.uniform(0, 1e-3, 7),
                                                            gear_ratio=rng.uniform(-50, 50, 7), viscous=rng.uniform(0, 1e-3, 7),
                                                            coulomb=np.column_stack([rng.uniform(0, .1, 7), -rng.uniform(0, .1, 7)])))
    N = dyn.CHUNK + 37  # more than one chunk
    Q, QD, QDD = random_q(rob, rng, N), rng.normal(size=(N, 7)), rng.normal(size=(N, 7))
    F = rng.normal(size=(N, 6))
    batch = {
        "id": dyn.inverse_dynamics(rob, Q, QD, QDD, f_tool=F), "M": dyn.mass_matrix(rob, Q),
        "g": dyn.gravity_torque(rob, Q), "fd": dyn.forward_dynamics(rob, Q, QD, QDD, f_tool=F),
        "b": dyn.bias_torque(rob, Q, QD), "C": dyn.coriolis_matrix(rob, Q[:50], QD[:50]),
    }
    kin, pot = dyn.energy(rob, Q[:50], QD[:50])
    for k in list(range(0, N, 997)) + [N - 1]:
        single = {
            "id": dyn.inverse_dynamics(rob, Q[k], QD[k], QDD[k], f_tool=F[k]), "M": dyn.mass_matrix(rob, Q[k]),
            "g": dyn.gravity_torque(rob, Q[k]), "fd": dyn.forward_dynamics(rob, Q[k], QD[k], QDD[k], f_tool=F[k]),
            "b": dyn.bias_torque(rob, Q[k], QD[k]),
        }
        for key, value in single.items():
            np.testing.assert_allclose(batch[key][k], value, rtol=0, atol=1e-12 * max(1.0, np.abs(value).max()))
    for k in (0, 49):
        np.testing.assert_allclose(batch["C"][k], dyn.coriolis_matrix(rob, Q[k], QD[k]), rtol=0, atol=1e-12)
        assert (kin[k], pot[k]) == pytest.approx(dyn.energy(rob, Q[k], QD[k]), rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_tool_wrench_enters_as_jacobian_transpose(convention):
    rob, rng = _random_case(30, 6, convention)
    for _ in range(4):
        q, qd, qdd, f = random_q(rob, rng), rng.normal(size=6), rng.normal(size=6), rng.normal(size=6)
        diff = dyn.inverse_dynamics(rob, q, qd, qdd, f_tool=f) - dyn.inverse_dynamics(rob, q, qd, qdd)
        np.testing.assert_allclose(diff, -jacobian(rob, q).T @ f, atol=1e-10)


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_power_balance_energy_rate_is_joint_power(convention):
    """Along any motion, d(T + V)/dt = q̇ᵀ τ (no friction); the rate by central differences
    of the energy along q(t) = q + q̇ t + ½ q̈ t² with q̈ = forward_dynamics(τ)."""
    rob, rng = _random_case(40, 5, convention)
    h = 1e-5
    for _ in range(4):
        q, qd, tau = random_q(rob, rng), rng.normal(size=5), rng.normal(size=5) * 5
        qdd = dyn.forward_dynamics(rob, q, qd, tau)
        E = [sum(dyn.energy(rob, q + qd * t + 0.5 * qdd * t * t, qd + qdd * t)) for t in (-h, h)]
        assert (E[1] - E[0]) / (2 * h) == pytest.approx(qd @ tau, rel=1e-6, abs=1e-7)


def test_modified_and_standard_tables_of_one_robot_give_the_same_torques():
    """dh_convert.to_modified re-frames the links: standard frame i = modified frame i ·
    Tx(a_i)Rx(α_i), so the inertials are moved into the modified frames by hand here."""
    rng = np.random.default_rng(50)
    std = dataclasses.replace(random_dh_robot(rng, 6), inertials=random_inertials(rng, 6))
    mod = to_modified(dataclasses.replace(std, inertials=None))
    li = std.inertials
    com, inertia = np.empty((6, 3)), np.empty((6, 3, 3))
    for i in range(6):
        X = (HomogeneousTransform.from_xyz_rpy([std.dh_a[i], 0, 0], [0, 0, 0]).mat
             @ HomogeneousTransform.from_xyz_rpy([0, 0, 0], [std.dh_alpha[i], 0, 0]).mat)
        com[i] = X[:3, :3] @ li.com[i] + X[:3, 3]
        inertia[i] = X[:3, :3] @ li.inertia[i] @ X[:3, :3].T
    mod = dataclasses.replace(mod, inertials=LinkInertials.from_arrays(li.mass, com, inertia))
    Q, QD, QDD = random_q(std, rng, 20), rng.normal(size=(20, 6)), rng.normal(size=(20, 6))
    np.testing.assert_allclose(dyn.inverse_dynamics(mod, Q, QD, QDD), dyn.inverse_dynamics(std, Q, QD, QDD), atol=1e-10)
    np.testing.assert_allclose(dyn.mass_matrix(mod, Q), dyn.mass_matrix(std, Q), atol=1e-10)


def test_gravity_follows_the_base_and_the_argument():
    rob, rng = _random_case(60, 4, "standard")
    q = random_q(rob, rng)
    up = np.array([0.0, 0.0, 9.81])
    np.testing.assert_allclose(dyn.gravity_torque(rob, q, gravity=-up), dyn.gravity_torque(rob, q))
    np.testing.assert_allclose(dyn.gravity_torque(rob, q, gravity=up), -dyn.gravity_torque(rob, q), atol=1e-12)
    np.testing.assert_allclose(dyn.gravity_torque(rob, q, gravity=[0.0, 0.0, 0.0]), 0.0, atol=0)
    # g = −Jᵀ of the COM weights: gravity torque = −Σ m_k J_v,kᵀ g
    parts = dyn._link_jacobians(rob, q[None], np.zeros((1, 4)))
    expected = -np.einsum("k,kaj,a->j", rob.inertials.mass, parts["Jv"][0], [0.0, 0.0, -9.81])
    np.testing.assert_allclose(dyn.gravity_torque(rob, q), expected, atol=1e-10)


# ------------------------------------------------------------------ shipped robots


@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_every_shipped_robot_has_finite_dynamics(name):
    rob = robot(name)
    rng = np.random.default_rng(70)
    Q = random_q(rob, rng, 50)
    M = dyn.mass_matrix(rob, Q)
    assert np.isfinite(M).all() and np.linalg.eigvalsh(M).min() > 0.0
    assert np.isfinite(dyn.inverse_dynamics(rob, Q, rng.normal(size=Q.shape), rng.normal(size=Q.shape))).all()


def test_puma560_gravity_load_at_zero_by_hand():
    """q = 0: the arm stretches along x0; joint 2 carries every link's weight times its
    horizontal lever from the shoulder axis, joint 3 the wrist's over a3 = 0.0203 m."""
    tau = dyn.gravity_torque(robot("puma560"), np.zeros(6))
    lever2 = {17.4: 0.4318 - 0.3638, 4.8: 0.4318, 0.82: 0.4521, 0.34: 0.4521, 0.09: 0.4521}
    np.testing.assert_allclose(tau[1], G * sum(m * x for m, x in lever2.items()), rtol=1e-12)
    np.testing.assert_allclose(tau[2], G * (0.82 + 0.34 + 0.09) * 0.0203, rtol=1e-12)
    np.testing.assert_allclose(tau[[0, 3, 4, 5]], 0.0, atol=1e-12)


# ------------------------------------------------------------------ bad input


def test_bad_arguments_name_argument_shape_and_value():
    rob = robot("puma560")
    with pytest.raises(ValueError, match=r"^q must have shape \(6,\) or \(N, 6\), got shape \(5,\)$"):
        dyn.mass_matrix(rob, np.zeros(5))
    with pytest.raises(ValueError, match=r"^qd must have the shape of q, \(6,\), got shape \(2, 6\)$"):
        dyn.inverse_dynamics(rob, np.zeros(6), np.zeros((2, 6)), np.zeros(6))
    with pytest.raises(ValueError, match=r"^qdd must be finite, got NaN or inf in qdd$"):
        dyn.inverse_dynamics(rob, np.zeros(6), np.zeros(6), [0, 0, np.nan, 0, 0, 0])
    with pytest.raises(ValueError, match=r"^tau must have the shape of q, \(3, 6\), got shape \(6,\)$"):
        dyn.forward_dynamics(rob, np.zeros((3, 6)), np.zeros((3, 6)), np.zeros(6))
    with pytest.raises(ValueError, match=r"^f_tool must be a finite \(6,\) wrench \[force; moment\] or one per configuration \(1, 6\), got shape \(3,\)$"):
        dyn.inverse_dynamics(rob, np.zeros(6), np.zeros(6), np.zeros(6), f_tool=[1, 2, 3])
    with pytest.raises(ValueError, match=r"^gravity must be a finite \(3,\) vector in m/s\^2, got \[0, 0\]$"):
        dyn.gravity_torque(rob, np.zeros(6), gravity=[0, 0])


def test_robot_without_inertials_points_to_estimate_inertials():
    rob = RobotParams.from_arrays("bare", [0.3, 0.2], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0, 0])
    message = ("bare: joints[0] has no [joints.inertial] (the robot has no inertial data); "
               "add [joints.inertial] tables to its file, or use inertials.estimate_inertials(robot)")
    for call in (lambda: dyn.mass_matrix(rob, [0, 0]), lambda: dyn.inverse_dynamics(rob, [0, 0], [0, 0], [0, 0])):
        with pytest.raises(ValueError) as info:
            call()
        assert str(info.value) == message
