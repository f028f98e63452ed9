"""Where to put the arm for calibration: joint configurations that maximise the
observability of the identifiable parameters (:func:`calibration_poses`).

Random in-limit configurations (free of collision when a checker is given) are the
candidates.  A first set of n is improved by exchanges (Fedorov's algorithm for
D-optimal designs): each chosen pose in turn is swapped for the candidate that raises
det(JᵀJ) the most, by the matrix determinant lemma over all candidates at once, until a
pass swaps nothing.  det(JᵀJ) is the product of the squared singular values, so this
maximises Borm and Menq's O1 for the fixed number of measured values.
"""
from __future__ import annotations

import operator

import numpy as np
from numpy.typing import NDArray

from robot_sim.calibration.calibrate import GROUPS, angle_scaled, free_columns, generic
from robot_sim.calibration.chain import build_chain
from robot_sim.model.calibration_data import MAX_POSES
from robot_sim.calibration.identifiability import dependencies
from robot_sim.calibration.measure import jacobian_rows
from robot_sim.kinematics import CollisionQuery, random_configurations
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotParams

FloatArray = NDArray[np.float64]

MEASUREMENTS = ("position", "pose")
#: Candidates drawn per requested pose, and their bounds.
CANDIDATES_PER_POSE = 20
MIN_CANDIDATES, MAX_CANDIDATES = 1000, 20_000
MAX_PASSES = 6


def calibration_poses(robot: RobotParams, n: int, *, measurement: str = "position",
                      checker: CollisionQuery | None = None, seed: int = 0) -> FloatArray:
    """n joint configurations (n, dofs) [rad, m] within ``robot``'s limits (unlimited
    revolute joints within ±180°), free of collision when ``checker`` is given, chosen to
    maximise O1 for ``measurement`` ``"position"`` (tool point) or ``"pose"`` (tool frame)
    over all calibration parameters the poses can identify.  Deterministic for a ``seed``.
    ValueError for n outside [1, 100000], another measurement, or when fewer than n of the
    random candidates are free of collision.
    """
    try:
        count = operator.index(n)
    except TypeError:
        raise ValueError(f"n: expected a whole number of poses, got {clip_repr(n)}") from None
    if not 1 <= count <= MAX_POSES:
        raise ValueError(f"n: expected 1 to {MAX_POSES} poses, got {count}")
    if measurement not in MEASUREMENTS:
        raise ValueError(f"measurement: expected 'position' or 'pose', got {clip_repr(measurement)}")
    rng = np.random.default_rng(seed)
    pool = random_configurations(robot, min(max(CANDIDATES_PER_POSE * count, MIN_CANDIDATES), MAX_CANDIDATES), rng)
    if checker is not None:
        pool = pool[~np.asarray(checker.in_collision(pool), dtype=bool)]
        if len(pool) < count:
            raise ValueError(f"only {len(pool)} random configurations of {robot.name} are free of collision; "
                             f"{count} poses were asked for")
    chain = build_chain(robot)
    columns = free_columns(chain, GROUPS)
    at = generic(chain, columns)
    rows = jacobian_rows(at, pool, columns, measurement == "pose")
    rows = angle_scaled(rows, chain, columns)
    kept, _ = dependencies(rows.reshape(-1, len(columns)), tuple(chain.name[k] for k in columns), measurement == "pose")
    chosen = _exchange(rows[:, :, kept], count, rng)
    return pool[np.sort(chosen)]


def _exchange(J: FloatArray, n: int, rng: np.random.Generator) -> NDArray[np.int64]:
    """Indices of n of the candidates' Jacobian blocks J (C, k, P) with a large det(Σ JᵢᵀJᵢ)."""
    C, _, P = J.shape
    chosen = rng.choice(C, size=n, replace=False)
    info = np.einsum("ckp,ckq->pq", J[chosen], J[chosen])
    ridge = 1e-9 * np.trace(np.einsum("ckp,ckq->pq", J, J)) / (C * P) * np.eye(P)
    for _ in range(MAX_PASSES):
        swapped = False
        for slot in range(n):
            old = chosen[slot]
            without = info - J[old].T @ J[old]
            JM = J @ np.linalg.inv(without + ridge)
            gain = np.linalg.det(np.eye(J.shape[1]) + JM @ J.transpose(0, 2, 1))
            gain[chosen] = -np.inf
            best = int(np.argmax(gain))
            if gain[best] > np.linalg.det(np.eye(J.shape[1]) + JM[old] @ J[old].T) * (1.0 + 1e-9):
                chosen[slot] = best
                info = without + J[best].T @ J[best]
                swapped = True
        if not swapped:
            break
    return chosen
