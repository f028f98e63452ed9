"""The analytic answers the rest of the package asks for: the nearest exact solution
(for ``solve_ik``), every collision-free one (for ``plan_to_pose``), and one branch
followed along a path of poses (for Cartesian lines and the pick task).

Each returns None when the closed form does not answer the question asked (no closed
form, a task the family does not solve, or, but for a path followed, a 7-joint arm), so
the caller keeps its numerical path for those.
"""
from __future__ import annotations

from typing import Any, Callable

import numba
import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.ik.family import GENERAL_6R, solver
from robot_sim.ik.finish import EVERY_TURN, NEAREST_TURN, RAW, TWO_PI
from robot_sim.ik.general import reach
from robot_sim.ik.pipeline import MAX_VALUES, nearest_solution, reach_error, run_one
from robot_sim.ik.solutions import ik_solutions, packed, unsolved
from robot_sim.kernels.jit import JIT
from robot_sim.kernels.model import kernel_array
from robot_sim.model.params import RobotParams

FloatArray = NDArray[np.float64]


def answers(robot: RobotParams, position_only: bool) -> bool:
    """True when the closed form solves exactly what is asked: the pose of a 6-joint arm
    (a general 6R's by :mod:`robot_sim.ik.general`), or the position of a 3-joint
    position arm.  (A 7-joint arm's free joint, and the redundancy of planar arms solved
    for position only, are left to the numerical IK.)"""
    family = solver(robot).family
    if family.name == GENERAL_6R:  # every real root of its polynomial: no closed form, still complete
        return not position_only and unsolved(robot) is None
    if not family.closed_form or family.free_joint is not None:
        return False
    return family.task == ("position" if position_only else "pose")


def all_exact(robot: RobotParams, T: ArrayLike, q0: FloatArray, within_limits: bool = True) -> FloatArray:
    """(k, n) exact solutions of one pose, nearest to q0 first (none when out of reach)."""
    sols = ik_solutions(robot, T, q0, within_limits=within_limits)
    return sols.q[sols.exact]


def nearest_exact(robot: RobotParams, T: FloatArray, q0: FloatArray, within_limits: bool,
                  rejects: Callable[[FloatArray], Any] | None = None) -> tuple[FloatArray, float, float] | None:
    """The exact solution nearest to q0 that ``rejects`` (say, a collision check) does not
    reject, with its position [m] and rotation [rad] errors; None when there is none, or
    when T (4, 4) fails the solver's own rigidity check.  For callers that have checked
    q0 (n finite values) already: one compiled call, nothing checked again."""
    sv = solver(robot)
    if sv.plan is None:  # a general 6R: every real solution, nearest first
        for q in all_exact(robot, T, q0, within_limits):
            if rejects is None or not rejects(q):
                return (q, *reach(robot, q, T))
        return None
    gf, gi = sv.prepared.get("rows") or packed(sv, sv.plan, np.zeros(1), robot)
    flags = T.flags
    if not (flags.c_contiguous and flags.writeable and T.dtype == np.float64):
        T = np.array(T, dtype=float, order="C")
    if q0 is robot.q_home:
        q0 = sv.home
    elif not q0.flags.writeable or q0.dtype != np.float64:
        q0 = np.array(q0, dtype=float)
    if rejects is None:  # the nearest turn of each branch holds the nearest solution
        q, pos, rot, found, bad = nearest_solution(gf, gi, T, q0, NEAREST_TURN if within_limits else RAW)
        return (q, pos, rot) if found and bad == -1 else None
    Q, _, exact, needed, bad = run_one(gf, gi, T, q0, EVERY_TURN if within_limits else RAW)
    if bad != -1 or needed > MAX_VALUES:
        return None
    for k in range(Q.shape[0]):
        if exact[k] and not rejects(Q[k]):
            pos, rot = reach_error(gf, gi, Q[k], T)
            return Q[k], pos, rot
    return None


@numba.njit(**JIT)
def _continue(Q: np.ndarray, count: np.ndarray, exact: np.ndarray, q_start: np.ndarray, rev: np.ndarray,
              lo: np.ndarray, hi: np.ndarray, out: np.ndarray) -> None:
    """out[i] = the exact solution of pose i nearest to out[i-1] (q_start before the
    first), its revolute angles turned nearest to out[i-1], inside [lo, hi]; NaN from the
    first pose with none."""
    n = Q.shape[2]
    prev = q_start.copy()
    cand = np.empty(n)
    out[:, :] = np.nan
    for i in range(Q.shape[0]):
        best_d = np.inf
        for k in range(count[i]):
            if not exact[i, k]:
                continue
            d, inside = 0.0, True
            for j in range(n):
                x = Q[i, k, j]
                if rev[j]:
                    x += TWO_PI * round((prev[j] - x) / TWO_PI)
                inside = inside and lo[j] <= x <= hi[j]
                cand[j] = x
                d += (x - prev[j]) ** 2
            if inside and d < best_d:
                best_d = d
                out[i] = cand
        if best_d == np.inf:
            return
        prev[:] = out[i]


def follows(robot: RobotParams) -> bool:
    """True when the closed form can follow a path of poses: what :func:`answers` solves,
    and the pose of a 7-joint arm with its free joint held where the path starts."""
    family = solver(robot).family
    held = family.free_joint is not None and family.closed_form and family.task == "pose"
    return held or answers(robot, robot.n_dofs < 6)


def follow_branch(robot: RobotParams, poses: ArrayLike, q_start: FloatArray) -> FloatArray | None:
    """(N, n) joint path through the poses (N, 4, 4) along the branch that continues the
    previous sample's (the first nearest ``q_start``), inside the limits; rows are NaN
    from the first pose that branch cannot reach.  One batched IK for all poses.  A
    7-joint arm's free joint stays at its value in ``q_start`` all along (the closed form
    solves the other six)."""
    if not follows(robot):
        return None
    sols = ik_solutions(robot, poses, q_start, within_limits=False)
    out = np.empty((sols.q.shape[0], robot.n_dofs))
    _continue(sols.q, sols.count, sols.exact, kernel_array(np.asarray(q_start, dtype=float)), robot.is_revolute,
              np.asarray(robot.q_min), np.asarray(robot.q_max), out)
    return out
