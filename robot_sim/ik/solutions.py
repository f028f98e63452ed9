"""Every inverse-kinematics solution of a pose, or of a batch of poses: :func:`ik_solutions`.

World frame (the robot standing at the origin: ``robot.base_tf`` is part of the chain),
tool pose 4×4, joint values in rad (revolute) or m (prismatic).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.ik.classify import Plan, aux_rows, plan
from robot_sim.ik.family import GENERAL_6R, IKFamily, Solver, solver
from robot_sim.ik.general import NAMES, general_data, general_solutions
from robot_sim.ik.pipeline import first_bad_pose, pack, run
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import RobotParams
from robot_sim.model.state import check_joint_vector

FloatArray = NDArray[np.float64]

#: A branch is exact when it puts the tool within this of T [m, rad] (scaled by the
#: robot's size for positions, 1 m at least).
EXACT_TOL = 1e-9
#: A pose is rigid when RᵀR = I and det R = 1 to this, and its last row is [0 0 0 1].
RIGID_TOL = 1e-6
#: Most poses of one batch, and most free-joint values of a sweep (bounds on the arrays).
MAX_POSES = 2_000_000
MAX_FREE_VALUES = 10_000
#: Most joint values a result may hold (about 400 MB).
MAX_VALUES = 50_000_000


@dataclass(frozen=True)
class IKSolutions:
    """Solutions of :func:`ik_solutions`.

    One pose: ``q`` (k, n) nearest to q0 first, ``branch`` the k posture names (see
    :attr:`IKFamily.postures`; "branch b" where the family names none), ``exact`` (k,)
    False for least-squares configurations of a pose out of reach, ``count`` = k.
    A batch of N poses: ``q`` (N, K, n) padded with NaN, ``branch`` (N, K) names ('' as
    padding), ``exact`` (N, K), ``count`` (N,).  ``codes`` holds the branch numbers the
    names come from (-1 as padding).
    """

    q: FloatArray
    branch: tuple[str, ...] | NDArray[np.str_]
    exact: NDArray[np.bool_]
    count: int | NDArray[np.int64]
    codes: NDArray[np.int64]
    family: IKFamily

    def __len__(self) -> int:
        return int(self.q.shape[0])


def _poses(T: ArrayLike) -> tuple[FloatArray, bool]:
    """T as a contiguous (N, 4, 4) array of rigid transforms, and whether it was one pose."""
    try:
        arr = np.asarray(T.mat if hasattr(T, "mat") else T, dtype=float)
    except (ValueError, TypeError):
        raise ValueError(f"T must be a 4x4 transform or an (N, 4, 4) array of them, got {clip_repr(T)}") from None
    single = arr.ndim == 2
    if arr.shape[-2:] != (4, 4) or arr.ndim not in (2, 3):
        raise ValueError(f"T must be a 4x4 transform or an (N, 4, 4) array of them, got shape {arr.shape}")
    arr = np.ascontiguousarray(arr.reshape(-1, 4, 4))
    if not arr.flags.writeable:
        arr = arr.copy()
    if arr.shape[0] > MAX_POSES:
        raise ValueError(f"T holds {arr.shape[0]} poses; at most {MAX_POSES} per call")
    bad = first_bad_pose(arr, RIGID_TOL)
    if bad >= 0:
        where = "T" if single else f"T[{bad}]"
        why = "holds NaN or infinite values" if not np.isfinite(arr[bad]).all() else (
            "is not a rigid transform (needs an orthonormal rotation with det +1 and bottom row [0 0 0 1])")
        raise ValueError(f"{where} {why}, got {clip_repr(arr[bad].tolist())}")
    return arr, single


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


def _packed(sv: Solver, p: Plan, values: FloatArray, robot: RobotParams) -> tuple[FloatArray, NDArray[np.int64]]:
    """The packed rows of :func:`robot_sim.ik.pipeline.run` for each free value: the chain
    the kernel solves (the free joint folded at the value, reversed if the plan says so),
    its constant rows and joint order; kept per solver when nothing is folded."""
    key = (p.kind, p.case, p.idx, p.reversed, p.free)
    if p.free is None and key in sv.prepared:
        return sv.prepared[key]
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
        row, ints = pack(p, S, aux_rows(p, S, sv.size), keep, sv.screws, robot.q_min, robot.q_max)
        rows.append(row)
    found = (np.stack(rows), ints)
    if p.free is None:
        sv.prepared[key] = found
    return found


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

    A batch is solved in compiled code, one loop over the poses; its result equals the
    single-pose results bit for bit.  Raises ValueError for a T that is not a 4×4 rigid
    transform (or a stack of them), NaN, a q0 of the wrong length, an arm without a
    closed form, and free-joint arguments that do not apply.  A general 6R arm (no closed
    form) gets every real solution by Raghavan and Roth's elimination
    (:mod:`robot_sim.ik.general`), named "solution k" in the order of q3.
    """
    if not isinstance(robot, RobotParams):
        raise ValueError(f"ik_solutions needs a RobotParams, got {type(robot).__name__}")
    Ts, single = _poses(T)
    # writable copies: numba compiles read-only arrays (the robot's) as another signature
    q0 = np.array(robot.q_home if q0 is None else check_joint_vector(q0, robot.n_dofs, "q0"))
    if q0.ndim != 1:
        raise ValueError(f"q0 must be one configuration of shape ({robot.n_dofs},), got {q0.shape}")
    sv = solver(robot)
    p, values = _free_values(robot, sv, q0, free_joint, free_values)
    names = sv.names
    general = general_data(robot, sv) if p is None and sv.family.name == GENERAL_6R else None
    if general is not None:  # every real root of Raghavan and Roth's polynomial
        out, out_code, out_exact, out_count, needed = general_solutions(
            general, robot, Ts, q0, bool(within_limits), EXACT_TOL * max(sv.size, 1.0), MAX_VALUES)
        names = NAMES
    elif p is None and sv.family.name == GENERAL_6R:
        raise ValueError(f"{robot.name}: a general 6R whose axes 1, 2 and axes 5, 6 both meet or run parallel "
                         "has no elimination here; use solve_ik")
    elif p is None:
        raise ValueError(f"{robot.name} has no closed-form inverse kinematics ({sv.family.name}); use solve_ik")
    else:
        gf, gi = _packed(sv, p, values, robot)
        out, out_code, out_exact, out_count, needed = run(
            gf, gi, Ts, q0, values, bool(within_limits), sv.family.task != "position",
            EXACT_TOL * max(sv.size, 1.0), MAX_VALUES)
    if needed > MAX_VALUES:
        raise ValueError(f"the solutions would hold {needed} joint values (at most {MAX_VALUES}): "
                         "solve fewer poses at a time, or with within_limits=False")
    if single:
        k = int(out_count[0])
        return IKSolutions(out[0, :k], tuple(names[out_code[0, :k]].tolist()), out_exact[0, :k], k,
                           out_code[0, :k], sv.family)
    return IKSolutions(out, names[out_code], out_exact, out_count, out_code, sv.family)

