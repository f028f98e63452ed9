"""Planning to a tool pose: :func:`plan_to_pose` (collision-free IK branches, then
:func:`plan_path` to the nearest one that can be reached).

World frame, tool pose 4×4 (or HomogeneousTransform), joint values in rad or m.
No Qt, no OpenGL.
"""
from __future__ import annotations

import time

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.ik.nearest import all_exact, answers
from robot_sim.kinematics import random_configurations, solve_ik
from robot_sim.model.params import RobotParams
from robot_sim.planning.edges import Checker
from robot_sim.planning.profiles import joint_vector
from robot_sim.planning.rrt import PathResult, plan_path

FloatArray = NDArray[np.float64]

#: IK descents tried (the first from the start configuration, the others from random
#: ones), and the most distinct solutions (branches) kept.
IK_ATTEMPTS = 12
MAX_BRANCHES = 6
#: Two IK solutions closer than this (joint-space distance, rad or m) are one branch.
SAME_BRANCH = 1e-3


def ik_branches(robot: RobotParams, target: ArrayLike, q_start: FloatArray, checker: Checker, *,
                seed: int | None = 0, tol: float = 1e-6) -> list[FloatArray]:
    """Distinct collision-free IK solutions of ``target`` within the limits, nearest to
    ``q_start`` first (joint-space distance): every analytic one where the arm has a
    closed form (:mod:`robot_sim.ik`), else those of descents from the start and random
    configurations."""
    if answers(robot, position_only=False):
        qs = all_exact(robot, target, q_start)
        found = list(qs[~np.asarray(checker.in_collision(qs), dtype=bool)]) if len(qs) else []
        return _nearest_first(found, q_start)
    rng = np.random.default_rng(seed)
    starts = np.vstack([q_start, random_configurations(robot, IK_ATTEMPTS - 1, rng)])
    found: list[FloatArray] = []
    for k, q0 in enumerate(starts):
        res = solve_ik(robot, target, q0, tol_pos=tol, tol_rot=tol, max_restarts=2, seed=k)
        if not res.success or any(np.linalg.norm(res.q - q) < SAME_BRANCH for q in found):
            continue
        if not np.asarray(checker.in_collision(res.q[None]), dtype=bool)[0]:
            found.append(res.q)
        if len(found) >= MAX_BRANCHES:
            break
    return _nearest_first(found, q_start)


#: Time slices of the rounds over the branches, as fractions of the time limit (a last
#: round gets the time left).
ROUND_SLICES = (1 / 64, 1 / 8)


def _nearest_first(found: list[FloatArray], q_start: FloatArray) -> list[FloatArray]:
    return sorted(found, key=lambda q: float(np.linalg.norm(q - q_start)))


def plan_to_pose(robot: RobotParams, q_start: ArrayLike, target_tf: ArrayLike, checker: Checker, *,
                 time_limit: float = 1.0, seed: int | None = 0) -> PathResult:
    """A collision-free joint path from ``q_start`` to a configuration that puts the tool
    at ``target_tf`` (world, 4×4).

    The IK branches (:func:`ik_branches`: every analytic solution, or descents from the
    start and from random configurations; those in collision dropped) are tried nearest
    first with :func:`plan_path`, in rounds of growing time slices (:data:`ROUND_SLICES`
    of ``time_limit`` [s], the last round the time left), so that a near branch that
    cannot be reached does not spend the time of one that can; the first that plans wins.
    ``success=False`` with a message when no branch is found or none can be reached.
    """
    t0 = time.perf_counter()
    qs = joint_vector("q_start", q_start, robot.n_dofs)
    branches = ik_branches(robot, target_tf, qs, checker, seed=seed)
    if not branches:
        return PathResult(False, np.zeros((0, robot.n_dofs)), "no collision-free IK solution of the target pose "
                          "within the joint limits", time.perf_counter() - t0, 0)
    checks, reasons = 0, {}
    for share in (*ROUND_SLICES, 1.0):
        for k, goal in enumerate(branches):
            left = time_limit - (time.perf_counter() - t0)
            if left <= 0.0:
                break
            res = plan_path(robot, qs, goal, checker, time_limit=min(left, share * time_limit), seed=seed)
            checks += res.checks
            if res.success:
                return PathResult(True, res.path, f"IK branch {k + 1} of {len(branches)}: {res.message}",
                                  time.perf_counter() - t0, checks)
            reasons[k] = f"branch {k + 1}: {res.message}"
    return PathResult(False, np.zeros((0, robot.n_dofs)), "no IK branch reachable: " + "; ".join(reasons.values()),
                      time.perf_counter() - t0, checks)
