"""Every inverse-kinematics solution of a pose, or of a batch of poses: :func:`ik_solutions`.

World frame (the robot standing at the origin: ``robot.base_tf`` is part of the chain),
tool pose 4×4, joint values in rad (revolute) or m (prismatic).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.ik.classify import Plan, aux_rows, plan
from robot_sim.ik.family import GENERAL_6R, IKFamily, Solver, solver
from robot_sim.ik.finish import EVERY_TURN, RAW
from robot_sim.ik.general import NAMES, general_data, general_solutions
from robot_sim.ik.pipeline import BAD_Q0, MAX_VALUES, RIGID_TOL, first_bad_pose, pack, run_one
from robot_sim.ik.threads import run_threads
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotParams
from robot_sim.model.state import check_joint_vector

FloatArray = NDArray[np.float64]

#: A branch is exact when it puts the tool within this of T [m, rad] (scaled by the
#: robot's size for positions, 1 m at least).
EXACT_TOL = 1e-9
#: Most poses of one batch, and most free-joint values of a sweep (bounds on the arrays).
MAX_POSES = 2_000_000
MAX_FREE_VALUES = 10_000

class _Fields(NamedTuple):
    q: FloatArray
    exact: NDArray[np.bool_]
    count: int | NDArray[np.int64]
    codes: NDArray[np.int64]
    family: IKFamily
    names: NDArray[np.str_]  # branch number -> name, '' at index -1


class IKSolutions(_Fields):
    """Solutions of :func:`ik_solutions` (a named tuple of the fields below: read only,
    and cheap to build).

    One pose: ``q`` (k, n) nearest to q0 first, ``branch`` the k posture names (see
    :attr:`IKFamily.postures`; "branch b" where the family names none), ``exact`` (k,)
    False for least-squares configurations of a pose out of reach, ``count`` = k.
    A batch of N poses: ``q`` (N, K, n) padded with NaN, ``branch`` (N, K) names ('' as
    padding), ``exact`` (N, K), ``count`` (N,).  ``codes`` holds the branch numbers the
    names come from (-1 as padding); ``len()`` is the number of solutions (of poses for
    a batch).
    """

    __slots__ = ()

    @property
    def branch(self) -> tuple[str, ...] | NDArray[np.str_]:
        names = self.names[self.codes]
        return tuple(names.tolist()) if self.codes.ndim == 1 else names

    def __len__(self) -> int:
        return int(self.q.shape[0])

    def __repr__(self) -> str:
        return f"<IKSolutions of {self.family.name}: q {self.q.shape}, count {self.count}>"

    def take(self, rows: ArrayLike) -> "IKSolutions":
        """The solutions ``rows`` (indices) of one pose's solutions, in that order."""
        rows = np.asarray(rows, dtype=np.int64)
        return IKSolutions(self.q[rows], self.exact[rows], len(rows), self.codes[rows], self.family, self.names)


_SHAPE_ERROR = "T must be a 4x4 transform or an (N, 4, 4) array of them"


_F64 = np.dtype(np.float64)


def _poses(T: ArrayLike) -> tuple[FloatArray, bool]:
    """T as a contiguous writable (4, 4) or (N, 4, 4) float array, and whether it is one
    pose (its rigidity is checked by the compiled :func:`robot_sim.ik.pipeline.run`)."""
    if type(T) is np.ndarray and T.dtype is _F64:
        arr = T
    else:
        try:
            arr = np.asarray(T.mat if hasattr(T, "mat") else T, dtype=float)
        except (ValueError, TypeError):
            raise ValueError(f"{_SHAPE_ERROR}, got {clip_repr(T)}") from None
    shape = arr.shape
    if shape != (4, 4) and (len(shape) != 3 or shape[1:] != (4, 4)):
        raise ValueError(f"{_SHAPE_ERROR}, got shape {shape}")
    if len(shape) == 3 and shape[0] > MAX_POSES:
        raise ValueError(f"T holds {shape[0]} poses; at most {MAX_POSES} per call")
    flags = arr.flags
    if not (flags.c_contiguous and flags.writeable):  # numba compiles read-only arrays as another signature
        arr = np.array(arr, order="C")
    return arr, len(shape) == 2


def _bad_pose(arr: FloatArray, bad: int) -> ValueError:
    """The error for pose ``bad`` of T, which is not a rigid transform."""
    pose = arr if arr.ndim == 2 else arr[bad]
    where = "T" if arr.ndim == 2 else f"T[{bad}]"
    why = "holds NaN or infinite values" if not np.isfinite(pose).all() else (
        "is not a rigid transform (needs an orthonormal rotation with det +1 and bottom row [0 0 0 1])")
    return ValueError(f"{where} {why}, got {clip_repr(pose.tolist())}")


def _start(robot: RobotParams, sv: Solver, q0: ArrayLike | None) -> FloatArray:
    """q0 as a writable float (n,) array (its finiteness is checked by the compiled run)."""
    if q0 is None:
        return sv.home
    if type(q0) is np.ndarray and q0.dtype == np.float64 and q0.shape == (robot.n_dofs,) and q0.flags.writeable:
        return q0
    q = np.array(check_joint_vector(q0, robot.n_dofs, "q0"))
    if q.ndim != 1:
        raise ValueError(f"q0 must be one configuration of shape ({robot.n_dofs},), got {q.shape}")
    return q


def _free_values(robot: RobotParams, sv: Solver, q0: FloatArray, free_joint: object,
                 free_values: object) -> tuple[Plan | None, FloatArray]:
    """The plan for the free joint asked (or the automatic one) and its values."""
    p = sv.plan
    if free_joint is not None:
        if robot.n_dofs != 7:
            raise ValueError(f"free_joint applies to 7-joint arms; {robot.name} has {robot.n_dofs} joints")
        if not (isinstance(free_joint, (int, np.integer)) and not isinstance(free_joint, bool)
                and 0 <= free_joint < 7):
            raise ValueError(f"free_joint must be a joint index 0..6, got {clip_repr(free_joint)}")
        folded = [plan(sv.screws.folded(int(free_joint), v), sv.size) for v in (0.0, 0.7318)]
        if folded[0] is None or folded[0] != folded[1]:
            raise ValueError(f"{robot.name}: with joint {int(free_joint) + 1} free the other six have no closed form")
        f = folded[0]
        p = Plan(f.kind, f.case, f.idx, f.reversed, int(free_joint))
    if free_values is not None:
        if p is None or p.free is None:
            raise ValueError(f"free_values applies to 7-joint arms with a closed form; {robot.name} has none")
        try:
            vals = np.asarray(free_values, dtype=float).reshape(-1)
        except (ValueError, TypeError):
            raise ValueError(f"free_values must be a sequence of numbers, got {clip_repr(free_values)}") from None
        if vals.size == 0 or vals.size > MAX_FREE_VALUES or not np.isfinite(vals).all():
            raise ValueError(f"free_values must hold 1 to {MAX_FREE_VALUES} finite numbers, got {clip_repr(free_values)}")
        return p, vals
    return p, np.array([q0[p.free]]) if p is not None and p.free is not None else np.zeros(1)


def packed(sv: Solver, p: Plan, values: FloatArray, robot: RobotParams) -> tuple[FloatArray, NDArray[np.int64]]:
    """The packed rows of :func:`robot_sim.ik.pipeline.run` for each free value: the chain
    the kernel solves (the free joint folded at the value, reversed if the plan says so),
    its constant rows and joint order; kept per solver when nothing is folded (the
    solver's own plan)."""
    if p.free is None and "rows" in sv.prepared:
        return sv.prepared["rows"]
    tol, check_rot = EXACT_TOL * max(sv.size, 1.0), sv.family.task != "position"
    rows, ints = [], None
    for value in values:
        S = sv.screws
        keep = np.arange(S.n)
        if p.free is not None:
            S = S.folded(p.free, float(value))
            keep = keep[keep != p.free]
        if p.reversed:
            S = S.reversed()
            keep = keep[::-1].copy()
        row, ints = pack(p, S, aux_rows(p, S, sv.size), keep, sv.screws, robot.q_min, robot.q_max, float(value), tol,
                         check_rot)
        rows.append(row)
    found = (np.stack(rows), ints)
    if p.free is None:
        sv.prepared["rows"] = found
    return found


def unsolved(robot: RobotParams) -> str | None:
    """Why :func:`ik_solutions` cannot answer ``robot`` ("no closed-form IK (family)"),
    or None when it can: a closed form, or a general 6R that the elimination solves."""
    sv = solver(robot)
    if sv.family.closed_form:
        return None
    if sv.family.name == GENERAL_6R:
        if general_data(robot, sv) is not None:
            return None
        return f"no closed-form IK ({GENERAL_6R} whose axes 1, 2 and axes 5, 6 both meet or run parallel)"
    return f"no closed-form IK ({sv.family.name})"


def ik_solutions(robot: RobotParams, T: ArrayLike, q0: ArrayLike | None = None, *, within_limits: bool = True,
                 free_joint: int | None = None, free_values: ArrayLike | None = None) -> IKSolutions:
    """Every joint vector that puts ``robot``'s tool at the pose ``T`` (world, 4×4), or
    at each pose of an (N, 4, 4) batch, by the closed form of its family
    (:func:`robot_sim.ik.family.ik_family`).

    Solutions come nearest to ``q0`` first (Euclidean joint distance; default: home).
    With ``within_limits`` only configurations inside the joint limits are returned, and
    a revolute joint whose range exceeds 2π gives every turn of an angle that lies in it;
    without, each branch comes once, its revolute angles turned nearest to q0.  A pose
    out of reach gives the least-squares branches, ``exact`` False.  Angles a singular
    pose leaves free (wrist axes aligned, a point on an axis) take their value in q0.
    A 7-joint arm holds its free joint (automatic, or ``free_joint``, a 0-based index)
    at q0's value, or at each of ``free_values`` (the solutions of all are returned).
    Arms with fewer joints solve what they can place (:attr:`IKFamily.task`).

    A batch is solved in compiled code, with no Python loop over the poses, on every core
    for a large one (:mod:`robot_sim.ik.threads`); its result equals the single-pose
    results bit for bit.  Raises ValueError for a T that is not a 4×4 rigid
    transform (or a stack of them), NaN, a q0 of the wrong length, an arm without a
    closed form, and free-joint arguments that do not apply.  A general 6R arm (no closed
    form) gets every real solution by Raghavan and Roth's elimination
    (:mod:`robot_sim.ik.general`), named "solution k" in the order of q3.
    """
    if not isinstance(robot, RobotParams):
        raise ValueError(f"ik_solutions needs a RobotParams, got {type(robot).__name__}")
    Ts, single = _poses(T)
    sv = solver(robot)
    start = _start(robot, sv, q0)
    rows = sv.prepared.get("rows") if free_joint is None and free_values is None else None
    if rows is not None:  # the solver's own plan, packed before
        gf, gi = rows
    else:
        p, values = _free_values(robot, sv, start, free_joint, free_values)
        if p is None and sv.family.name == GENERAL_6R:
            return _general(robot, sv, Ts, single, start, q0, within_limits)
        if p is None:
            raise ValueError(f"{robot.name} has no closed-form inverse kinematics ({sv.family.name}); use solve_ik")
        gf, gi = packed(sv, p, values, robot)
    mode = EVERY_TURN if within_limits else RAW
    if single:
        q, code, exact, needed, bad = run_one(gf, gi, Ts, start, mode)
        count = len(q)
    else:
        q, code, exact, count, needed, bad = run_threads(gf, gi, Ts, start, mode)
    _check(robot, Ts, q0, bad, needed)
    return IKSolutions(q, exact, count, code, sv.family, sv.names)


def _check(robot: RobotParams, Ts: FloatArray, q0: ArrayLike | None, bad: int, needed: int) -> None:
    """Raise for what a compiled run reported: a q0 with NaN or infinite values, pose
    ``bad`` of T not rigid, or more joint values than the output may hold."""
    if bad == BAD_Q0:
        check_joint_vector(q0, robot.n_dofs, "q0")  # raises, naming what is not finite
    if bad != -1:
        raise _bad_pose(Ts, bad)
    if needed > MAX_VALUES:
        raise ValueError(f"the solutions would hold {needed} joint values (at most {MAX_VALUES}): "
                         "solve fewer poses at a time, or with within_limits=False")


def _general(robot: RobotParams, sv: Solver, Ts: FloatArray, single: bool, start: FloatArray,
             q0: ArrayLike | None, within_limits: bool) -> IKSolutions:
    """Every real solution of a general 6R arm by Raghavan and Roth's elimination
    (:mod:`robot_sim.ik.general`), named "solution k" in the order of q3."""
    data = general_data(robot, sv)
    if data is None:
        raise ValueError(f"{robot.name}: a general 6R whose axes 1, 2 and axes 5, 6 both meet or run parallel "
                         "has no elimination here; use solve_ik")
    batch = Ts[None] if single else Ts
    _check(robot, Ts, q0, BAD_Q0 if not np.isfinite(start).all() else first_bad_pose(batch, RIGID_TOL), 0)
    q, code, exact, count, needed = general_solutions(data, robot, batch, start, bool(within_limits),
                                                      EXACT_TOL * max(sv.size, 1.0), MAX_VALUES)
    _check(robot, Ts, q0, -1, needed)
    if single:
        k = int(count[0])
        return IKSolutions(q[0, :k], exact[0, :k], k, code[0, :k], sv.family, NAMES)
    return IKSolutions(q, exact, count, code, sv.family, NAMES)
