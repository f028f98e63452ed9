"""Levenberg–Marquardt on column-scaled analytic Jacobians (Moré's scaling), with optional
Huber reweighting of whole poses."""
from __future__ import annotations

from typing import Callable

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
Problem = Callable[[FloatArray], tuple[FloatArray, FloatArray]]

MAX_ITERATIONS = 100
#: Stop after a step that moves the residuals by less than this fraction of their size,
STEP_TOLERANCE = 1e-10
#: or by less than this [m].
ABSOLUTE_STEP = 1e-15
#: Huber's constant: residuals beyond this many robust standard deviations lose weight.
HUBER_K = 1.345
ROBUST_ROUNDS = 5


def least_squares(problem: Problem, x0: FloatArray, max_step: FloatArray,
                  progress: Callable[[int, float], None] | None = None) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Minimise ½|r(x)|² where ``problem(x)`` returns r (m,) and J (m, p) with
    r(x + δ) ≈ r − J δ.  Each step solves min |J δ − r|² + λ |D δ|² by a stacked least
    squares, D the largest column norms of J seen so far; λ shrinks after a step that
    lowers the cost and grows tenfold after one that does not or that moves a parameter
    by more than its ``max_step`` (p,) (so weakly seen parameters cannot run away along
    flat directions).  Returns x, r(x) and J(x)."""
    x = np.array(x0, dtype=float)
    r, J = problem(x)
    cost = float(r @ r)
    D = np.linalg.norm(J, axis=0)
    lam = 1e-3
    for iteration in range(MAX_ITERATIONS):
        D = np.maximum(D, np.linalg.norm(J, axis=0))
        scale = np.where(D > 0, D, 1.0)
        Js = J / scale
        while True:
            A = np.vstack([Js, np.sqrt(lam) * np.eye(len(x))])
            z = np.linalg.lstsq(A, np.concatenate([r, np.zeros(len(x))]), rcond=None)[0]
            trial = x + z / scale
            if (np.abs(z / scale) <= max_step).all():
                r_new, J_new = problem(trial)
                cost_new = float(r_new @ r_new)
                if cost_new <= cost:
                    break
            lam *= 10.0
            if lam > 1e16:
                return x, r, J
        moved = float(np.linalg.norm(Js @ z))  # how far the step moves the residuals
        x, r, J, cost_old, cost = trial, r_new, J_new, cost, cost_new
        lam = max(lam / 10.0, 1e-12)
        if progress is not None:
            progress(iteration + 1, cost)
        if moved <= STEP_TOLERANCE * np.sqrt(cost_old) + ABSOLUTE_STEP:
            break
    return x, r, J


def huber_weights(pose_norms: FloatArray) -> FloatArray:
    """Huber weights (N,) of poses with residual sizes ``pose_norms``: 1 within HUBER_K
    robust standard deviations (1.4826 × the median absolute size), k σ/|r| beyond."""
    sigma = 1.4826 * float(np.median(pose_norms))
    if sigma == 0.0:
        return np.ones_like(pose_norms)
    limit = HUBER_K * sigma
    return np.where(pose_norms <= limit, 1.0, limit / np.maximum(pose_norms, limit))
