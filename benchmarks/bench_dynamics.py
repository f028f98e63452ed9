"""Dynamics rows of ``make bench`` and their baseline, measured in the same run: each row
for both backends of ``dynamics`` (the compiled kernels and the readable recursion).

The baseline is the textbook recursive Newton–Euler algorithm (Luh, Walker & Paul) written
straightforwardly with NumPy 3-vectors and 3×3 matrices, one configuration at a time; its
mass matrix takes n such calls with unit accelerations, its forward dynamics solves
M q̈ = τ − bias with ``np.linalg.solve``.  Standard DH only (the benchmark robot's table).
"""
from __future__ import annotations

import math
from contextlib import contextmanager
from typing import Callable, Iterator

import numpy as np

from robot_sim import dynamics
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams

N_BATCH = 10**5
N_BASELINE = 300


@contextmanager
def using(backend: str) -> Iterator[None]:
    """Run the block with ``dynamics`` on ``backend``, then back to the compiled one."""
    dynamics.set_backend(backend)
    try:
        yield
    finally:
        dynamics.set_backend("compiled")


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """3-vector cross product written out (np.cross costs about 10 µs per call on 3-vectors,
    which would make the baseline look slower than a straightforward implementation is)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def naive_rnea(robot: RobotParams, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, gravity: np.ndarray) -> np.ndarray:
    """Joint torques of one configuration (standard DH, rigid bodies only)."""
    li, n = robot.inertials, robot.n_dofs
    z = np.array([0.0, 0.0, 1.0])
    w, wd = np.zeros(3), np.zeros(3)
    vd = -robot.base_tf.R().T @ gravity
    rotations, offsets, forces, moments = [], [], [], []
    for i in range(n):
        revolute = robot.jtype[i] == JTYPE_REVOLUTE
        th = robot.dh_th[i] + (q[i] if revolute else 0.0)
        d = robot.dh_d[i] + (0.0 if revolute else q[i])
        ct, st, ca, sa = math.cos(th), math.sin(th), math.cos(robot.dh_alpha[i]), math.sin(robot.dh_alpha[i])
        R = np.array([[ct, -st * ca, st * sa], [st, ct * ca, -ct * sa], [0.0, sa, ca]])  # frame i in frame i-1
        p = np.array([robot.dh_a[i], d * sa, d * ca])  # origin i from origin i-1, frame i
        Rt = R.T
        if revolute:
            wd = Rt @ (wd + cross(w, z * qd[i]) + z * qdd[i])
            w = Rt @ (w + z * qd[i])
            vd = Rt @ vd + cross(wd, p) + cross(w, cross(w, p))
        else:
            vd = Rt @ (vd + z * qdd[i] + 2.0 * cross(w, z * qd[i]))
            w, wd = Rt @ w, Rt @ wd
            vd = vd + cross(wd, p) + cross(w, cross(w, p))
        c = li.com[i]
        vc = vd + cross(wd, c) + cross(w, cross(w, c))
        forces.append(li.mass[i] * vc)
        moments.append(li.inertia[i] @ wd + cross(w, li.inertia[i] @ w))
        rotations.append(R)
        offsets.append(p)
    tau = np.empty(n)
    f, m = np.zeros(3), np.zeros(3)  # force on link i+1 and its moment about origin i, frame i+1
    for i in range(n - 1, -1, -1):
        R_next = rotations[i + 1] if i + 1 < n else np.eye(3)
        f_child = R_next @ f
        # moment about origin i-1, frame i
        m = R_next @ m + cross(offsets[i], f_child) + cross(offsets[i] + li.com[i], forces[i]) + moments[i]
        f = f_child + forces[i]
        axis = rotations[i].T @ z
        tau[i] = axis @ m if robot.jtype[i] == JTYPE_REVOLUTE else axis @ f
    return tau


def naive_mass_matrix(robot: RobotParams, q: np.ndarray) -> np.ndarray:
    n = robot.n_dofs
    zero = np.zeros(n)
    return np.column_stack([naive_rnea(robot, q, zero, np.eye(n)[j], np.zeros(3)) for j in range(n)])


def naive_forward(robot: RobotParams, q: np.ndarray, qd: np.ndarray, tau: np.ndarray, gravity: np.ndarray) -> np.ndarray:
    bias = naive_rnea(robot, q, qd, np.zeros(robot.n_dofs), gravity)
    return np.linalg.solve(naive_mass_matrix(robot, q), tau - bias)


def bench_dynamics(
    table, robot: RobotParams, rng: np.random.Generator,
    measure: Callable, median_iqr: Callable, us: Callable,
) -> None:
    """Rows: batched inverse dynamics, mass matrix and forward dynamics at N = 1e5 against the
    per-configuration baseline; single-call latency; the solve behind forward dynamics."""
    n, g = robot.n_dofs, np.array(dynamics.GRAVITY)
    lo, hi = np.where(np.isfinite(robot.q_min), robot.q_min, -np.pi), np.where(np.isfinite(robot.q_max), robot.q_max, np.pi)
    Q = lo + (hi - lo) * rng.random((N_BATCH, n))
    QD, QDD = rng.normal(size=(N_BATCH, n)), rng.normal(size=(N_BATCH, n))
    q0, qd0, qdd0 = Q[:N_BASELINE], QD[:N_BASELINE], QDD[:N_BASELINE]
    # the baseline agrees with the module before it is timed
    np.testing.assert_allclose(naive_rnea(robot, q0[0], qd0[0], qdd0[0], g), dynamics.inverse_dynamics(robot, q0[0], qd0[0], qdd0[0]), atol=1e-9)
    np.testing.assert_allclose(naive_mass_matrix(robot, q0[0]), dynamics.mass_matrix(robot, q0[0]), atol=1e-9)
    rows = [
        ("inverse dynamics (RNEA)", "≤ 0.6 µs/config",
         lambda: dynamics.inverse_dynamics(robot, Q, QD, QDD),
         lambda: [naive_rnea(robot, *x, g) for x in zip(q0, qd0, qdd0)]),
        ("mass matrix (CRBA)", "≤ 1 µs/config",
         lambda: dynamics.mass_matrix(robot, Q),
         lambda: [naive_mass_matrix(robot, x) for x in q0]),
        ("forward dynamics (bias + CRBA + Cholesky)", "≤ 2 µs/config",
         lambda: dynamics.forward_dynamics(robot, Q, QD, QDD),
         lambda: [naive_forward(robot, *x, g) for x in zip(q0, qd0, qdd0)]),
    ]
    for what, target, ours, base in rows:
        base_per = median_iqr(measure(base, repeats=5))[0] / N_BASELINE
        for backend in dynamics.BACKENDS:  # compiled kernels, then the readable recursion on arrays
            with using(backend):
                med, iqr = median_iqr(measure(ours, repeats=7 if backend == "compiled" else 3))
            per = med / N_BATCH
            table.add(
                f"batched {what}, {robot.name}, N = 1e5, {backend} (µs/config)",
                f"{per * 1e6:.3f} µs", f"{iqr / N_BATCH * 1e6:.3f} µs",
                f"{base_per * 1e6:.1f} µs", f"{base_per / per:.0f}×", target,
            )
    for what, fn in (
        ("inverse dynamics", lambda: dynamics.inverse_dynamics(robot, q0[0], qd0[0], qdd0[0])),
        ("forward dynamics", lambda: dynamics.forward_dynamics(robot, q0[0], qd0[0], qdd0[0])),
    ):
        for backend in dynamics.BACKENDS:
            with using(backend):
                med, iqr = median_iqr(measure(fn, repeats=15, number=200 if backend == "compiled" else 10))
            table.add(f"single-configuration {what} call, {robot.name}, {backend}", us(med), us(iqr))
    # what the forward-dynamics solve costs: our batched Cholesky vs NumPy's batched LAPACK solve
    M = dynamics.mass_matrix(robot, Q)
    b = np.ascontiguousarray(QDD.T)
    Mt = np.ascontiguousarray(M.transpose(1, 2, 0))
    med, iqr = median_iqr(measure(lambda: dynamics._solve_spd(Mt, b), repeats=7))
    lap = median_iqr(measure(lambda: np.linalg.solve(M, QDD[..., None]), repeats=7))[0] / N_BATCH
    table.add(
        f"solve M q̈ = b, batched Cholesky, N = 1e5 (µs/config; baseline np.linalg.solve batched)",
        f"{med / N_BATCH * 1e6:.3f} µs", f"{iqr / N_BATCH * 1e6:.3f} µs",
        f"{lap * 1e6:.2f} µs", f"{lap / (med / N_BATCH):.1f}×",
    )
