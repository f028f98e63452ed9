"""Numerical inverse kinematics (:func:`solve_ik`, damped least squares with restarts)
and differential IK (:func:`diff_ik_velocity`).  Frames and units:
:mod:`robot_sim.kinematics.chain`.  Imports neither OpenGL nor Qt.
"""
from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from types import ModuleType
from typing import Protocol

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.kinematics.chain import _model
from robot_sim.kinematics.checks import _check_int, _check_seed, _check_tolerance
from robot_sim.kinematics.frames import characteristic_length, jacobian
from robot_sim.model.messages import clip, clip_repr
from robot_sim.model.params import RobotParams
from robot_sim.model.state import check_joint_vector
from robot_sim.transforms import HomogeneousTransform, is_rigid_transform, rotation_log

FloatArray = NDArray[np.float64]


class CollisionQuery(Protocol):
    """What :func:`solve_ik` asks of a collision checker (``robot_sim.collision``)."""

    def in_collision(self, q: FloatArray) -> bool: ...


@dataclass(frozen=True)
class IKResult:
    """Outcome of :func:`solve_ik`.

    ``q`` is the best joint vector found (never NaN), ``success`` whether it meets the
    tolerances, ``iterations`` the total damped-least-squares steps over all restarts,
    ``restarts`` how many random restarts were used, ``pos_err`` [m] and ``rot_err`` [rad]
    the remaining errors, ``position_only`` whether orientation was ignored, and
    ``message`` a one-line explanation.
    """

    q: FloatArray
    success: bool
    iterations: int
    restarts: int
    pos_err: float
    rot_err: float
    position_only: bool
    message: str


def ik_position_only_required(robot: RobotParams) -> bool:
    """True for arms with fewer than six joints, which cannot reach an arbitrary pose."""
    return robot.n_dofs < 6


def _target_matrix(target: HomogeneousTransform | ArrayLike) -> FloatArray:
    try:
        mat = target.mat if isinstance(target, HomogeneousTransform) else np.asarray(target, dtype=float)
    except (ValueError, TypeError):
        raise ValueError(f"IK target must be a 4x4 transform, got {clip_repr(target)}") from None
    if mat.shape != (4, 4):
        raise ValueError(f"IK target must be a 4x4 transform, got shape {mat.shape}")
    if not is_rigid_transform(mat):
        raise ValueError(
            "IK target is not a rigid transform (needs finite values, an orthonormal rotation "
            f"with det +1 and bottom row [0 0 0 1]), got {clip_repr(mat.tolist(), 200)}"
        )
    return mat


@dataclass(frozen=True)
class _Pose:
    """One evaluated IK iterate: joint vector, error, Jacobian and error norms."""

    q: FloatArray
    err: FloatArray
    jac: FloatArray
    pos_err: float
    rot_err: float

    @property
    def cost(self) -> float:
        return float(self.err @ self.err)


class _IKProblem:
    """Pose error, Jacobian, limits and the damped least-squares descent of one IK query."""

    # Levenberg–Marquardt damping schedule
    LAMBDA_INIT = 1e-3
    LAMBDA_MIN = 1e-9
    LAMBDA_MAX = 1e6
    LAMBDA_DOWN = 0.2
    LAMBDA_UP = 10.0
    MAX_STEP = 0.6  # largest joint step per iteration [rad, or characteristic lengths], keeps far starts stable
    STALL_RATIO = 0.999  # an iteration that keeps more of the cost than this makes no progress
    STALL_ITERS = 6  # this many in a row: the descent has stalled
    ITERS_PER_START = 40  # a start that has not converged by then is abandoned
    NULLSPACE_GAIN = 0.05  # pull of redundant joints toward home per iteration
    NULLSPACE_MIN_COST = 1e-6  # below this squared error the pull stops, so the last steps are pure Gauss-Newton
    PRISMATIC_RESTART_SPAN = 1.0  # characteristic lengths either side of the current value for an unlimited prismatic joint

    def __init__(
        self,
        robot: RobotParams,
        target: FloatArray,
        position_only: bool,
        lo: FloatArray,
        hi: FloatArray,
        tol_pos: float,
        tol_rot: float,
    ) -> None:
        self.robot = robot
        self.model = _model(robot)
        self.target = target
        self.position_only = position_only
        self.lo, self.hi = lo, hi
        self.tol_pos, self.tol_rot = tol_pos, tol_rot
        self.rows = slice(0, 3) if position_only else slice(0, 6)
        self.redundant = robot.n_dofs > (3 if position_only else 6)
        self.world0 = robot.base_tf.mat
        # The descent runs in scale-free units: positions in characteristic lengths L,
        # prismatic joint values too; angles stay radians.  ``var_scale`` turns a step in
        # those units back into joint units.
        self.length = characteristic_length(robot)
        self.var_scale = np.where(self.model.revolute, 1.0, self.length)

    def evaluate(self, q: FloatArray) -> _Pose:
        """Pose at q: error and Jacobian in scale-free units, error norms in m and rad."""
        frames = self.model.frames(*self.model.th_d(q), self.world0)
        ee = frames[-1] @ self.model.tool
        dp = self.target[:3, 3] - ee[:3, 3]
        dr = rotation_log(self.target[:3, :3] @ ee[:3, :3].T)
        jac = self.model.jacobian(frames, ee[:3, 3])[self.rows] * self.var_scale
        jac[:3] /= self.length
        err = dp / self.length if self.position_only else np.concatenate([dp / self.length, dr])
        return _Pose(q, err, jac, math.sqrt(dp @ dp), math.sqrt(dr @ dr))

    def converged(self, pose: _Pose) -> bool:
        return pose.pos_err <= self.tol_pos and (self.position_only or pose.rot_err <= self.tol_rot)

    def into_limits(self, q: FloatArray) -> FloatArray:
        """q inside the limits: a revolute joint outside its range first turns by whole
        turns when that lands inside it (the same pose), otherwise it is clipped."""
        with np.errstate(invalid="ignore"):
            turns = np.where(q < self.lo, np.ceil((self.lo - q) / (2 * np.pi)), 0.0)
            turns = np.where(q > self.hi, np.floor((self.hi - q) / (2 * np.pi)), turns)
        wrapped = q + 2 * np.pi * turns
        inside = self.model.revolute & (wrapped >= self.lo) & (wrapped <= self.hi)
        return np.clip(np.where(inside, wrapped, q), self.lo, self.hi)

    def restart_sample(self, rng: np.random.Generator, q: FloatArray) -> FloatArray:
        """A random configuration inside the limits (unlimited revolute joints over ±π,
        unlimited prismatic ones around their current value)."""
        span = self.PRISMATIC_RESTART_SPAN * self.length
        lo = np.where(np.isfinite(self.lo), self.lo, np.where(self.model.revolute, -np.pi, q - span))
        hi = np.where(np.isfinite(self.hi), self.hi, np.where(self.model.revolute, np.pi, q + span))
        return lo + (hi - lo) * rng.random(q.shape[0])

    def descend(self, q: FloatArray, bounded: bool, budget: int) -> tuple[_Pose, int]:
        """Levenberg–Marquardt from q for at most ``budget`` iterations, until converged or
        stalled; ``bounded`` keeps every iterate inside the limits.  Returns the best pose
        and the iterations used."""
        pose = self.evaluate(self.into_limits(q) if bounded else q)
        lam, stalled, used = self.LAMBDA_INIT, 0, 0
        while used < budget and stalled < self.STALL_ITERS and not self.converged(pose):
            used += 1
            try:
                q_new = pose.q + self.step(pose, lam, bounded)
            except np.linalg.LinAlgError:  # damping lost in rounding: damp more
                lam, stalled = min(lam * self.LAMBDA_UP, self.LAMBDA_MAX), stalled + 1
                continue
            new = self.evaluate(self.into_limits(q_new) if bounded else q_new)
            stalled = 0 if new.cost < pose.cost * self.STALL_RATIO else stalled + 1
            if new.cost < pose.cost:
                pose, lam = new, max(lam * self.LAMBDA_DOWN, self.LAMBDA_MIN)
            else:
                lam = min(lam * self.LAMBDA_UP, self.LAMBDA_MAX)
        return pose, used

    def step(self, pose: _Pose, lam: float, bounded: bool) -> FloatArray:
        """Damped least-squares step Jᵀ(JJᵀ + λI)⁻¹e, plus, for redundant arms still far
        from the target, a null-space pull toward home.

        When ``bounded``, joints resting on a limit that the step would push further out
        are frozen (their Jacobian column removed) and the step recomputed, so the other
        joints make up for them instead of the clipped step losing its direction.
        """
        dq = self._damped_step(pose, pose.jac, lam)
        if bounded:
            blocked = ((pose.q <= self.lo) & (dq < 0.0)) | ((pose.q >= self.hi) & (dq > 0.0))
            if blocked.any():
                dq = self._damped_step(pose, pose.jac * ~blocked, lam)
                dq[blocked] = 0.0
        largest = np.max(np.abs(dq))
        if largest > self.MAX_STEP:
            dq *= self.MAX_STEP / largest
        return dq * self.var_scale

    def _damped_step(self, pose: _Pose, jac: FloatArray, lam: float) -> FloatArray:
        gram = jac @ jac.T
        gram[np.diag_indices_from(gram)] += lam
        if self.redundant and pose.cost > self.NULLSPACE_MIN_COST:
            sol = np.linalg.solve(gram, np.column_stack([pose.err, jac]))
            null = np.eye(self.robot.n_dofs) - jac.T @ sol[:, 1:]
            pull = (self.robot.q_home - pose.q) / self.var_scale
            return jac.T @ sol[:, 0] + null @ (self.NULLSPACE_GAIN * pull)
        return jac.T @ np.linalg.solve(gram, pose.err)


def _closed_form() -> ModuleType:
    """``robot_sim.ik.nearest``, imported on first use (robot_sim.ik imports this package)."""
    from robot_sim.ik import nearest

    return nearest


def solve_ik(
    robot_params: RobotParams,
    target: HomogeneousTransform | ArrayLike,
    q0: ArrayLike | None = None,
    *,
    position_only: bool = False,
    tol_pos: float = 1e-6,
    tol_rot: float = 1e-6,
    max_iter: int = 1000,
    max_restarts: int = 50,
    respect_limits: bool = True,
    seed: int | None = 0,
    checker: CollisionQuery | None = None,
) -> IKResult:
    """Joint vector that puts the endeffector at ``target`` (world frame, 4×4 or
    :class:`HomogeneousTransform`), by damped least squares (Levenberg–Marquardt).

    Each iteration solves ``(JJᵀ + λI) y = e`` for the pose error
    e = [p* − p; log(R* Rᵀ)] and steps ``Δq = Jᵀy``, adapting λ (smaller after a step that
    lowers the error, larger after one that does not).  The first descent starts at ``q0``
    (home when None) and, with ``respect_limits``, keeps every iterate inside the joint
    limits, freezing joints that push against a limit.  A descent that stalls or has not
    converged in 40 iterations is followed by one from a random configuration, up to
    ``max_restarts`` times within ``max_iter`` iterations in total.  Restarts descend
    without bounds (far more of them converge) and then bring the solution into the
    limits by whole turns of revolute joints, or polish it with a bounded descent.
    Redundant arms add a null-space pull toward home.  Arms with fewer than six joints
    always solve position only (``position_only`` in the result says so, with a message).

    With a ``checker`` (a ``robot_sim.collision.CollisionChecker`` of this robot, or any
    object whose ``in_collision(q)`` answers for one configuration) a converged
    configuration in collision is not a solution: the search restarts past it, and the
    message of a failure says how many such minima it met.

    Success means ``pos_err <= tol_pos`` and, unless position only, ``rot_err <= tol_rot``
    (and, with a checker, no collision).  A target farther from the base than
    :attr:`RobotParams.reach` is answered by the first descent alone, with the message
    saying so (restarts cannot reach it).  A failure is a result with ``success=False``
    holding the best in-limit configuration found.  Raises ValueError for a target that is not a rigid transform, a wrong-length
    or non-finite ``q0``, or non-positive tolerances.
    """
    robot = robot_params
    # A float (4, 4) array goes to the closed form unchecked: its compiled check is as strict
    # (robot_sim.ik.pipeline.RIGID_TOL); the numerical path checks it first.
    plain = type(target) is np.ndarray and target.dtype == np.float64 and target.shape == (4, 4)
    tmat = target if plain else _target_matrix(target)
    tol_pos = _check_tolerance("tol_pos", tol_pos)
    tol_rot = _check_tolerance("tol_rot", tol_rot)
    max_iter = _check_int("max_iter", max_iter, 1)
    max_restarts = _check_int("max_restarts", max_restarts, 0)
    seed = _check_seed(seed)
    if checker is not None and not callable(getattr(checker, "in_collision", None)):
        raise ValueError(f"checker must have an in_collision(q) method (a CollisionChecker), got {clip_repr(checker)}")
    q = robot.q_home if q0 is None else check_joint_vector(q0, robot.n_dofs, "q0")  # home: checked on loading
    if q.ndim != 1:
        raise ValueError(f"q0 must be one configuration of shape ({robot.n_dofs},), got {q.shape}")

    message = ""
    if not position_only and ik_position_only_required(robot):
        position_only = True
        message = f"{robot.name} has {robot.n_dofs} joints (< 6): solved for position only. "
    nearest = sys.modules.get("robot_sim.ik.nearest") or _closed_form()
    if nearest.answers(robot, position_only):  # closed form first, where the arm has one
        found = nearest.nearest_exact(robot, tmat, q, respect_limits, None if checker is None else checker.in_collision)
        if found is not None:
            q_exact, pos_err, rot_err = found
            rot_err = 0.0 if position_only else rot_err
            if pos_err <= tol_pos and rot_err <= tol_rot:
                return IKResult(q_exact, True, 0, 0, pos_err, rot_err, position_only,
                                message + "analytic: the exact solution nearest to q0")
    if plain:
        tmat = _target_matrix(target)
    if respect_limits:
        lo, hi = np.array(robot.q_min), np.array(robot.q_max)
    else:
        lo, hi = np.full(robot.n_dofs, -np.inf), np.full(robot.n_dofs, np.inf)
    problem = _IKProblem(robot, tmat, position_only, lo, hi, tol_pos, tol_rot)
    rng = np.random.default_rng(seed)
    distance = float(np.linalg.norm(tmat[:3, 3] - robot.base_tf.mat[:3, 3]))
    if respect_limits and distance > robot.reach + tol_pos:  # no configuration gets there: one descent toward it
        message += f"target is {distance:.3g} m from the base, beyond the arm's reach of {robot.reach:.3g} m; "
        max_restarts = 0

    # From here on nothing raises: overflow on absurd robots gives inf/NaN errors that no
    # step accepts, and any arithmetic failure ends the search with the best pose so far.
    best, iterations, restarts, bounded, failure, colliding = None, 0, 0, True, "", 0

    def accepted(pose: _Pose) -> bool:
        """False for a converged pose that the checker finds in collision."""
        nonlocal colliding
        if checker is None or not problem.converged(pose) or not checker.in_collision(pose.q):
            return True
        colliding += 1
        return False

    with np.errstate(all="ignore"):
        try:
            while True:
                pose, used = problem.descend(q, bounded, min(problem.ITERS_PER_START, max_iter - iterations))
                iterations += used
                if not bounded:
                    pose = problem.evaluate(problem.into_limits(pose.q))
                    if not problem.converged(pose) and iterations < max_iter:
                        pose, used = problem.descend(pose.q, True, min(problem.ITERS_PER_START, max_iter - iterations))
                        iterations += used
                if accepted(pose) and (best is None or pose.cost < best.cost):
                    best = pose
                done = best is not None and problem.converged(best)
                if done or restarts >= max_restarts or iterations >= max_iter:
                    break
                restarts += 1
                q, bounded = problem.restart_sample(rng, pose.q if best is None else best.q), False
        except (np.linalg.LinAlgError, ArithmeticError) as exc:
            failure = f"numerical failure ({clip(str(exc))}) after {iterations} iterations: "
        if best is None:  # failed in the first descent, or every minimum collided: report where it started
            q_start = problem.into_limits(q) if np.isfinite(q).all() else np.array(robot.q_home)
            try:
                best = problem.evaluate(q_start)
            except (np.linalg.LinAlgError, ArithmeticError):
                best = _Pose(q_start, np.full(1, np.inf), np.zeros((1, robot.n_dofs)), math.inf, math.inf)

    success = problem.converged(best) and not failure and (checker is None or not checker.in_collision(best.q))
    if success:
        message += f"converged in {iterations} iterations ({restarts} restarts)"
    else:
        message += failure or f"did not converge in {iterations} iterations ({restarts} restarts): "
        message += f"position error {best.pos_err:.3g} m"
        message += "" if position_only else f", rotation error {best.rot_err:.3g} rad"
        if colliding:
            message += f"; {colliding} converged configuration{'s were' if colliding > 1 else ' was'} in collision"
    return IKResult(
        q=best.q.copy(),
        success=success,
        iterations=iterations,
        restarts=restarts,
        pos_err=best.pos_err,
        rot_err=best.rot_err,
        position_only=position_only,
        message=message,
    )


def diff_ik_velocity(
    robot_params: RobotParams, q: ArrayLike, twist_des: ArrayLike, damping: float = 1e-2
) -> FloatArray:
    """Joint velocities (n,) that best produce the endeffector twist ``twist_des``.

    ``twist_des`` is (6,) [v (m/s); ω (rad/s)] or (3,) linear velocity only, in the world
    frame.  Uses the damped pseudo-inverse ``Jᵀ(JJᵀ + damping² I)⁻¹``, which stays bounded
    near singularities at the cost of a small tracking error there.
    """
    v = np.asarray(twist_des, dtype=float)
    if v.shape not in ((6,), (3,)) or not np.isfinite(v).all():
        raise ValueError(f"twist_des must be a finite (6,) or (3,) vector, got {v!r}")
    jac = jacobian(robot_params, q)[: v.shape[0]]
    gram = jac @ jac.T
    gram[np.diag_indices_from(gram)] += damping**2
    return jac.T @ np.linalg.solve(gram, v)
