"""The compiled dynamics kernels (robot_sim.dynamics.compiled) against the readable
recursion of robot_sim.dynamics (backend "reference") on random chains of both
conventions, with prismatic joints, drives and tool wrenches; the backend switch; the
kernels' own sine and cosine; one fixed step against the reference step."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from kin_helpers import CONVENTIONS, random_dh_robot, random_inertials, random_q
from robot_sim import dynamics as dyn
from robot_sim.kernels.algebra import cos_sin
from robot_sim.sim import stepper as stepping
from robot_sim.model.inertials import Drives

TOL = 1e-12  # relative to the size of the quantity


def _chain(seed: int, n: int, convention: str, drives: bool):
    rng = np.random.default_rng(seed)
    rob = random_dh_robot(rng, n, convention=convention)
    rob = dataclasses.replace(rob, inertials=random_inertials(rng, n))
    if drives:
        rob = dataclasses.replace(rob, drives=Drives.from_arrays(
            n, motor_inertia=rng.uniform(0, 1e-3, n), gear_ratio=rng.uniform(-50, 50, n),
            viscous=rng.uniform(0, 1e-3, n), coulomb=np.column_stack([rng.uniform(0, .1, n), -rng.uniform(0, .1, n)])))
    return rob, rng


def _both(fn):
    """fn() under each backend: (compiled, reference)."""
    out = []
    for name in ("compiled", "reference"):
        dyn.set_backend(name)
        try:
            out.append(fn())
        finally:
            dyn.set_backend("compiled")
    return out


def _close(a, b, what):
    a, b = np.asarray(a), np.asarray(b)
    scale = max(1.0, float(np.abs(b).max()))
    assert np.abs(a - b).max() <= TOL * scale, f"{what}: compiled and reference differ by {np.abs(a - b).max():.3g}"


CASES = [(seed, n, conv, drives) for conv in CONVENTIONS for seed, n, drives in ((1, 1, False), (2, 3, True), (3, 6, False), (4, 7, True))]


@pytest.mark.parametrize(("seed", "n", "convention", "drives"), CASES)
def test_compiled_equals_reference_on_random_chains(seed, n, convention, drives):
    rob, rng = _chain(seed, n, convention, drives)
    N = 40
    Q, QD, QDD = random_q(rob, rng, N), rng.normal(size=(N, n)), rng.normal(size=(N, n))
    F = rng.normal(size=(N, 6))
    for what, fn in {
        "inverse_dynamics": lambda: dyn.inverse_dynamics(rob, Q, QD, QDD),
        "inverse_dynamics with f_tool": lambda: dyn.inverse_dynamics(rob, Q, QD, QDD, f_tool=F),
        "gravity_torque": lambda: dyn.gravity_torque(rob, Q),
        "bias_torque": lambda: dyn.bias_torque(rob, Q, QD),
        "mass_matrix": lambda: dyn.mass_matrix(rob, Q),
        "single inverse_dynamics": lambda: dyn.inverse_dynamics(rob, Q[0], QD[0], QDD[0]),
        "single gravity_torque": lambda: dyn.gravity_torque(rob, Q[1]),
        "single mass_matrix": lambda: dyn.mass_matrix(rob, Q[2]),
        "other gravity": lambda: dyn.inverse_dynamics(rob, Q[3], QD[3], QDD[3], gravity=(1.0, -2.0, -9.0)),
        "computed_torque": lambda: dyn.computed_torque(rob, Q[4], QD[4], Q[5], QD[5], QDD[5], 30.0, 11.0),
        "batched computed_torque": lambda: dyn.computed_torque(rob, Q, QD, Q[::-1], QD[::-1], QDD, np.full((N, 1), 30.0), 11.0),
    }.items():
        _close(*_both(fn), what)
    # forward dynamics: the same accelerations, measured by the torques they need
    for what, fn in {
        "forward_dynamics": lambda: dyn.forward_dynamics(rob, Q, QD, QDD, f_tool=F),
        "single forward_dynamics": lambda: dyn.forward_dynamics(rob, Q[0], QD[0], QDD[0]),
    }.items():
        compiled, reference = _both(fn)
        M = dyn.mass_matrix(rob, Q if compiled.ndim == 2 else Q[0])
        diff = np.einsum("...ij,...j->...i", M, compiled - reference)
        assert np.abs(diff).max() <= TOL * max(1.0, np.abs(QDD).max() * np.abs(M).max()), what


def test_computed_torque_is_inverse_dynamics_at_the_reference_acceleration():
    rob, rng = _chain(6, 5, "modified", True)
    q, qd, q_des, qd_des, qdd_des = rng.normal(size=(5, 5))
    tau, qdd_ref = dyn.computed_torque(rob, q, qd, q_des, qd_des, qdd_des, 25.0, 10.0)
    assert np.array_equal(qdd_ref, qdd_des + 25.0 * (q_des - q) + 10.0 * (qd_des - qd))
    assert np.array_equal(tau, dyn.inverse_dynamics(rob, q, qd, qdd_ref))
    with pytest.raises(ValueError, match="q_des must be finite"):
        dyn.computed_torque(rob, q, qd, np.full(5, np.inf), qd_des, qdd_des, 25.0, 10.0)


def test_one_configuration_equals_its_row_of_a_batch_bit_for_bit():
    rob, rng = _chain(7, 7, "modified", True)
    Q, QD, QDD = random_q(rob, rng, 5), rng.normal(size=(5, 7)), rng.normal(size=(5, 7))
    batch_id, batch_fd = dyn.inverse_dynamics(rob, Q, QD, QDD), dyn.forward_dynamics(rob, Q, QD, QDD)
    for i in range(5):
        assert np.array_equal(dyn.inverse_dynamics(rob, Q[i], QD[i], QDD[i]), batch_id[i])
        assert np.array_equal(dyn.forward_dynamics(rob, Q[i], QD[i], QDD[i]), batch_fd[i])


@pytest.mark.parametrize("method", ["rk4", "euler"])
def test_one_step_equals_the_reference_step(method):
    rob, rng = _chain(8, 6, "standard", True)
    N = 6
    Q, QD, TAU = random_q(rob, rng, N), rng.normal(size=(N, 6)), rng.normal(size=(N, 6))
    known = np.array([True, False] * 3)
    A1 = dyn.forward_dynamics(rob, Q, QD, TAU)
    active = np.array([True] * 5 + [False])

    def run():
        out = stepping.Stepper(rob, N, 1e-3, method).step(Q, QD, TAU, A1, known, active)
        return out.q.copy(), out.qd.copy(), out.qdd.copy(), out.status.copy()

    (q_c, qd_c, a_c, s_c), (q_r, qd_r, a_r, s_r) = _both(run)
    assert (s_c[:5] == stepping.STEP_OK).all() and (s_r[:5] == stepping.STEP_OK).all()
    for c, r, what in ((q_c, q_r, "q"), (qd_c, qd_r, "qd"), (a_c, a_r, "qdd")):
        _close(c[:5], r[:5], what)
    # RK4 against a much finer Euler integration of the same dynamics, as an independent check
    if method == "rk4":
        q, qd = Q[:1].copy(), QD[:1].copy()
        fine = stepping.Stepper(rob, 1, 1e-6, "euler")
        for _ in range(1000):
            out = fine.step(q, qd, TAU[:1])
            q, qd = out.q.copy(), out.qd.copy()
        np.testing.assert_allclose(q[0], q_c[0], atol=1e-8)


def test_a_failing_arm_is_reported_and_the_others_stepped():
    rob, rng = _chain(9, 3, "standard", False)
    Q, QD, TAU = random_q(rob, rng, 3), rng.normal(size=(3, 3)), rng.normal(size=(3, 3))
    QD[1] = 1e200  # stage velocities overflow
    TAU[2, 0] = np.inf
    out = stepping.Stepper(rob, 3, 1e-3).step(Q, QD, TAU)
    assert out.status[0] == stepping.STEP_OK and np.isfinite(out.q[0]).all()
    assert out.status[1] in (stepping.STEP_BAD_STATE, stepping.STEP_BAD_ACCEL)
    assert out.status[2] == stepping.STEP_BAD_ACCEL


@pytest.mark.parametrize("backend", ["compiled", "reference"])
def test_non_finite_arguments_are_named_under_both_backends(backend):
    rob, rng = _chain(5, 4, "standard", False)
    q, qd = random_q(rob, rng), rng.normal(size=4)
    bad = qd.copy()
    bad[2] = np.nan
    dyn.set_backend(backend)
    try:
        with pytest.raises(ValueError, match="qd must be finite"):
            dyn.inverse_dynamics(rob, q, bad, qd)
        with pytest.raises(ValueError, match="tau must be finite"):
            dyn.forward_dynamics(rob, q, qd, bad)
        with pytest.raises(ValueError, match="q must be finite"):
            dyn.mass_matrix(rob, np.tile(bad, (3, 1)))
        with pytest.raises(ValueError, match="q must be finite"):
            dyn.gravity_torque(rob, bad)
        with pytest.raises(ValueError, match=r"shape \(4,\)"):
            dyn.inverse_dynamics(rob, q[:3], qd[:3], qd[:3])
        # lists and non-contiguous rows go the checked way and give the same numbers
        Q = np.asfortranarray(np.tile(q, (2, 1)))
        assert np.array_equal(dyn.inverse_dynamics(rob, list(q), list(qd), list(qd)), dyn.inverse_dynamics(rob, Q[0], qd, qd))
    finally:
        dyn.set_backend("compiled")


def test_backend_switch_is_checked():
    with pytest.raises(ValueError, match="backend must be one of compiled, reference"):
        dyn.set_backend("fast")
    assert dyn.backend() == "compiled"


def test_kernel_sine_and_cosine_match_the_c_library():
    rng = np.random.default_rng(0)
    x = np.concatenate([rng.normal(scale=s, size=2000) for s in (0.1, 1.0, 10.0, 1e3, 1e5, 1e7)])
    x = np.concatenate([x, [0.0, -0.0, math.pi / 2, -math.pi, 3 * math.pi / 4, 1e5, -1e5, 2e5]])
    out = np.array([cos_sin(v) for v in x[:: 7]])  # interpreted calls: the same formulas
    ref = np.column_stack([np.cos(x[:: 7]), np.sin(x[:: 7])])
    assert np.abs(out - ref).max() <= 2.3e-16 * 2


@pytest.mark.parametrize("convention", CONVENTIONS)
@pytest.mark.parametrize("method", ["rk4", "euler"])
def test_a_step_with_held_joints_equals_the_reference_step(method, convention):
    """Joints held in the step (q̈ = 0 in every stage): the compiled step equals the
    reference backend's (constrained_forward_dynamics), held joints stay put exactly, and
    the reaction at the start is constrained_forward_dynamics' reaction."""
    rob, rng = _chain(10, 6, convention, True)
    N = 5
    Q, QD, TAU = random_q(rob, rng, N), rng.normal(size=(N, 6)), rng.normal(size=(N, 6))
    HELD = rng.random((N, 6)) < 0.4
    HELD[0] = False
    HELD[1] = True
    QD[HELD] = 0.0

    def run():
        out = stepping.Stepper(rob, N, 1e-3, method).step(Q, QD, TAU, held=HELD)
        return out.q.copy(), out.qd.copy(), out.qdd.copy(), out.reaction.copy(), out.status.copy()

    (q_c, qd_c, a_c, r_c, s_c), (q_r, qd_r, a_r, r_r, s_r) = _both(run)
    assert (s_c == stepping.STEP_OK).all() and (s_r == stepping.STEP_OK).all()
    for c, r, what in ((q_c, q_r, "q"), (qd_c, qd_r, "qd"), (a_c, a_r, "qdd"), (r_c, r_r, "reaction")):
        _close(c, r, what)
    assert np.array_equal(q_c[HELD], Q[HELD]) and not qd_c[HELD].any() and not a_c[HELD].any()
    assert not r_c[~HELD].any() and r_c[HELD].all()
    qdd, reaction = dyn.constrained_forward_dynamics(rob, Q, QD, TAU, HELD)
    _close(a_c, qdd, "start acceleration against constrained_forward_dynamics")
    _close(r_c, reaction, "reaction against constrained_forward_dynamics")
    free = stepping.Stepper(rob, N, 1e-3, method).step(Q, QD, TAU, held=np.zeros_like(HELD))
    assert np.array_equal(free.q[0], q_c[0]) and np.array_equal(free.qd[0], qd_c[0])  # nothing held: the same bits


def test_the_stepper_holds_joints_resting_on_their_stops_and_leaves_the_rest_to_the_caller():
    """With stops: a joint on a stop at rest that its acceleration presses onto it is held
    (the same bits as naming it held); one the acceleration pulls off, one moving into its
    stop and a one-point range are left to the caller (AT_STOP); a free step that ends
    beyond a limit is CROSSED with the free step's row; at_limit flags the end on a limit."""
    rob, rng = _chain(11, 4, "standard", False)
    q0 = random_q(rob, rng)
    a0 = dyn.forward_dynamics(rob, q0, np.zeros(4), np.zeros(4))
    pressed = 1 if abs(a0[1]) > 1e-6 else 2
    lo, hi = np.full(4, -np.inf), np.full(4, np.inf)
    # joint `pressed` on the stop its acceleration pushes it onto
    (lo if a0[pressed] < 0 else hi)[pressed] = q0[pressed]
    stops = dataclasses.replace(rob, q_min=lo, q_max=hi)
    Q = np.tile(q0, (5, 1))
    QD = np.zeros((5, 4))
    QD[2, pressed] = -1.0 if a0[pressed] < 0 else 1.0  # env 2 moves into its stop
    QD[3, 0] = 50.0  # env 3: joint 0 would cross (given a limit just ahead)
    TAU = np.zeros((5, 4))
    TAU[1, pressed] = -1e3 * np.sign(a0[pressed]) * (1 + abs(dyn.mass_matrix(rob, q0)[pressed, pressed]))  # env 1: pulled off
    lo3, hi3 = np.full(4, -np.inf), np.full(4, np.inf)
    hi3[0] = q0[0] + 1e-3  # only joint 0 limited: env 3 crosses, from a start on no stop
    out = stepping.Stepper(stops, 5, 1e-3).step(Q, QD, TAU, stops=True)
    status, q1, reaction, at = out.status.copy(), out.q.copy(), out.reaction.copy(), out.at_limit.copy()
    assert status.tolist()[:3] == [stepping.STEP_ON_LIMIT, stepping.STEP_AT_STOP, stepping.STEP_AT_STOP]  # env 0 ends on its stop
    assert q1[0, pressed] == q0[pressed] and at[0].tolist() == [j == pressed for j in range(4)]
    named = stepping.Stepper(stops, 5, 1e-3).step(Q, QD, TAU, held=np.eye(4, dtype=bool)[[pressed] * 5])
    assert np.array_equal(named.q[0], q1[0]) and np.array_equal(named.reaction[0], reaction[0])
    assert np.sign(reaction[0, pressed]) == -np.sign(a0[pressed])  # the stop pushes against the fall
    crossing = dataclasses.replace(rob, q_min=lo3, q_max=hi3)
    out = stepping.Stepper(crossing, 5, 1e-3).step(Q, QD, TAU, stops=True)
    free = stepping.Stepper(rob, 5, 1e-3).step(Q, QD, TAU)
    assert out.status[3] == stepping.STEP_CROSSED and np.array_equal(out.q[3], free.q[3])
    point = dataclasses.replace(rob, q_min=q0.copy(), q_max=np.where(np.arange(4) == 0, q0, np.inf))
    assert stepping.Stepper(point, 5, 1e-3).step(Q, QD, TAU, stops=True).status[0] == stepping.STEP_AT_STOP


@pytest.mark.parametrize("method", ["rk4", "euler"])
def test_computed_torque_fused_into_the_step_is_the_law_then_the_step(method):
    """step_computed_torque = computed_torque, the clip at the effort limit, then step (from
    the reference acceleration where nothing saturated): the same bits compiled, round-off
    against the reference backend; a non-finite command is BAD_EFFORT and not stepped."""
    rob, rng = _chain(12, 5, "modified", True)
    N = 6
    Q, QD, QDES, QDDES, QDDDES = random_q(rob, rng, N), *rng.normal(size=(4, N, 5))
    KP, KD = rng.uniform(10, 100, N), rng.uniform(1, 20, N)
    peak = np.abs(dyn.computed_torque(rob, Q, QD, QDES, QDDES, QDDDES, KP[:, None], KD[:, None])[0]).max(axis=1)
    limit = np.full(5, np.median(peak))  # about half the arms saturate
    QDDDES[5, 2] = np.inf
    stepper = stepping.Stepper(rob, N, 1e-3, method)

    def fused():
        out = stepper.step_computed_torque(Q, QD, QDES, QDDES, QDDDES, KP, KD, limit)
        return out.command.copy(), out.effort.copy(), out.q.copy(), out.qd.copy(), out.qdd.copy(), out.status.copy()

    command, effort, q1, qd1, qdd1, status = fused()
    assert status[:5].tolist() == [stepping.STEP_OK] * 5 and status[5] == stepping.STEP_BAD_EFFORT
    tau, qdd_ref = dyn.computed_torque(rob, Q[:5], QD[:5], QDES[:5], QDDES[:5], QDDDES[:5], KP[:5, None], KD[:5, None])
    saturated = (np.abs(tau) > limit).any(axis=1)
    assert saturated.any() and not saturated.all()
    clipped = np.clip(tau, -limit, limit)
    plain = stepping.Stepper(rob, 5, 1e-3, method).step(Q[:5], QD[:5], clipped, qdd_ref, ~saturated)
    for got, want in ((command[:5], tau), (effort[:5], clipped), (q1[:5], plain.q), (qd1[:5], plain.qd), (qdd1[:5], plain.qdd)):
        assert np.array_equal(got, want)
    QDDDES[5, 2] = 0.0
    compiled, reference = _both(fused)
    assert (reference[-1] == stepping.STEP_OK).all()
    for c, r, what in zip(compiled[:5], reference[:5], ("command", "effort", "q", "qd", "qdd")):
        _close(c, r, what)
