"""The stepper of the physics loop: fixed steps of N arms of one robot with their joint
efforts held over each step, by classical RK4 or semi-implicit Euler, in one compiled
call (:func:`robot_sim.sim.step_kernels.step_batch`) or by the reference backend's batched forward
dynamics (``dynamics.set_backend("reference")``).  Joints resting on their stops are held
inside the step; what the stepper does not resolve (an impact, a release, an arrival) it
hands back by status to the stop resolver (:mod:`robot_sim.sim.stops`).

:func:`runge_kutta` is the one NumPy RK4 (and semi-implicit Euler) of the package: the
reference backend's step and the physics loop's stage-by-stage step (contact, a pull, a
continuous-time controller) both take it.

Units: q in rad (revolute) and m (prismatic), rates per second, efforts in N·m and N,
time in s.  Imports neither OpenGL nor Qt.
"""
from __future__ import annotations

import math
from typing import Callable, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim import dynamics
from robot_sim.dynamics import GRAVITY, computed_torque, constrained_forward_dynamics, forward_dynamics
from robot_sim.kernels import status
from robot_sim.kernels.model import kernel_array
from robot_sim.model.params import RobotParams

FloatArray = NDArray[np.float64]
#: Status per arm of :meth:`Stepper.step` (see there and :mod:`robot_sim.kernels.status`).
STEP_OK, STEP_BAD_STATE, STEP_BAD_ACCEL = status.OK, status.BAD_STATE, status.BAD_ACCEL
STEP_CROSSED, STEP_AT_STOP, STEP_BAD_EFFORT, STEP_ON_LIMIT = status.CROSSED, status.AT_STOP, status.BAD_EFFORT, status.ON_LIMIT
INTEGRATORS = ("rk4", "euler")


#: A stage's joint acceleration from (time offset in the step [s], q, q̇).
StageAccel = Callable[[float, FloatArray, FloatArray], FloatArray]


class StepDiverged(Exception):
    """A step produced a non-finite or unsolvable state; the message says which."""


def raise_for(status: int) -> None:
    """StepDiverged for a failed :meth:`Stepper.step` status (:data:`STEP_BAD_STATE`,
    :data:`STEP_BAD_ACCEL`); nothing for the others."""
    if status == STEP_BAD_STATE:
        raise StepDiverged("the joint state became non-finite")
    if status == STEP_BAD_ACCEL:
        raise StepDiverged("the joint acceleration became non-finite")


ONE_KNOWN = np.ones(1, dtype=bool)  # "the start acceleration is known" for one arm


def step_one_arm(
    stepper: "Stepper", q: FloatArray, qd: FloatArray, tau: FloatArray, a1: FloatArray | None, h: float,
    locked: NDArray[np.bool_] | None,
) -> tuple[tuple[FloatArray, FloatArray, FloatArray], FloatArray | None]:
    """One step of length h [s] of one arm by a one-arm ``stepper`` from (q, qd) (n,) with
    effort tau held and the ``locked`` joints held (None: none): ((q, qd) after it, the
    acceleration at its start (``a1`` when given, finite and nothing is locked)), and the
    stops' reaction at the start (None without locked joints).  StepDiverged if it failed."""
    step = stepper.step(q[None], qd[None], tau[None], None if a1 is None else a1[None], ONE_KNOWN,
                        held=None if locked is None else locked[None], dt=h)
    raise_for(step.status[0])
    reaction = None if locked is None else step.reaction[0].copy()
    return (step.q[0].copy(), step.qd[0].copy(), step.qdd[0].copy()), reaction


def runge_kutta(
    integrator: str, q: FloatArray, qd: FloatArray, h: float, a1: FloatArray, accel: StageAccel
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """(q, qd) after a step of ``h`` [s] of ``integrator`` ("rk4" or "euler":
    semi-implicit) from (q, qd) (n,) or (N, n) with start acceleration ``a1``, and a1;
    ``accel(offset, q, qd)`` gives a later stage's acceleration, ``offset`` its time in
    the step."""
    if integrator == "euler":
        qd1 = qd + h * a1
        return q + h * qd1, qd1, a1
    v2 = qd + 0.5 * h * a1
    a2 = accel(0.5 * h, q + 0.5 * h * qd, v2)
    v3 = qd + 0.5 * h * a2
    a3 = accel(0.5 * h, q + 0.5 * h * v2, v3)
    v4 = qd + h * a3
    a4 = accel(h, q + h * v3, v4)
    q1 = q + (h / 6.0) * (qd + 2.0 * (v2 + v3) + v4)
    qd1 = qd + (h / 6.0) * (a1 + 2.0 * (a2 + a3) + a4)
    return q1, qd1, a1


class StepResult(NamedTuple):
    """Outcome of :meth:`Stepper.step` for N arms: the state after the step ``q``, ``qd``
    (N, n), the acceleration at its start ``qdd`` (N, n), ``status`` (N,) per arm (see
    :meth:`Stepper.step`), the stops' reaction torque at the start ``reaction`` (N, n)
    [N·m or N] (zero on joints not held; written when joints may be held), ``at_limit``
    (N, n), the joints exactly on a limit after the step (written with ``stops``), and
    the controller's ``command`` and the ``effort`` held over the step (N, n) [N·m or N]
    (written by :meth:`Stepper.step_computed_torque`).  Rows of arms that were not
    stepped, or that failed, hold no meaningful values."""

    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    status: NDArray[np.int8]
    reaction: FloatArray
    at_limit: NDArray[np.bool_]
    command: FloatArray
    effort: FloatArray


class Stepper:
    """Fixed steps of ``dt`` [s] for N arms of ``robot`` with the joint efforts held over
    each step (no tool wrench): classical RK4 (``method="rk4"``) or semi-implicit Euler
    (``"euler"``: q̇ += h q̈; q += h q̇).  Its work and result arrays are allocated once:
    the :class:`StepResult` of :meth:`step` is overwritten by the next call.

    With the compiled backend every arm goes through the same machine code, so an arm
    stepped alone (N = 1) and the same arm in a batch give identical bits.
    """

    def __init__(self, robot: RobotParams, n_arms: int, dt: float, method: str = "rk4", gravity: ArrayLike = GRAVITY) -> None:
        if method not in INTEGRATORS:
            raise ValueError(f"method must be one of {', '.join(INTEGRATORS)}, got {method!r}")
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be a positive finite number of seconds, got {dt!r}")
        self.robot, self.dt, self.method = robot, float(dt), method
        self.shape = (int(n_arms), robot.n_dofs)
        from robot_sim.sim import step_kernels  # numba, on first use

        self._kernels = step_kernels
        _, self._table, g0 = dynamics.compiled_kernels(robot, gravity)
        self._g0 = g0.copy()
        #: Gravity in frame 0 (3,) [m/s²], as the compiled kernels take it.
        self.gravity = self._g0
        self._gravity = gravity
        self._result = StepResult(
            *(np.empty(self.shape) for _ in range(3)), np.zeros(self.shape[0], dtype=np.int8),
            np.zeros(self.shape), np.zeros(self.shape, dtype=bool), np.zeros(self.shape), np.zeros(self.shape),
        )
        self._kp, self._kd = np.zeros(self.shape[0]), np.zeros(self.shape[0])
        self._all = np.ones(self.shape[0], dtype=bool)
        self._none = np.zeros(self.shape[0], dtype=bool)
        self._no_held = np.zeros(self.shape, dtype=bool)
        self._limits = (np.zeros(self.shape[1], dtype=bool), np.zeros(self.shape[1]), np.zeros(1, dtype=bool))

    def step(
        self,
        q: FloatArray,
        qd: FloatArray,
        tau: FloatArray,
        qdd_start: FloatArray | None = None,
        known: NDArray[np.bool_] | None = None,
        active: NDArray[np.bool_] | None = None,
        *,
        held: NDArray[np.bool_] | None = None,
        stops: bool = False,
        dt: float | None = None,
    ) -> StepResult:
        """One step of the arms: q, qd, tau float64 (N, n) [rad, m, per s; N·m, N].
        ``qdd_start`` (N, n) with ``known`` (N,) bool: the acceleration at the start where
        it is known (computed torque knows it) and finite, saving one forward dynamics
        (not used for an arm holding joints or on a stop).  ``active`` (N,) bool: only
        those arms are stepped (all by default).  ``dt``: this step's length [s] (default
        the stepper's).

        Held joints are locked (q̈ = 0 in every stage; the others move with the constrained
        dynamics, as ``constrained_forward_dynamics``) and ``reaction`` is their stops'
        reaction at the start: ``held`` (N, n) bool names them, or, with ``stops``, the
        robot's joint limits do.  With ``stops`` an arm resting on stops (joints exactly
        on a limit at zero velocity whose reactions all push) is stepped with those joints
        held and status :data:`STEP_OK`, or :data:`STEP_ON_LIMIT` when a joint ends exactly
        on a limit (a held one, or one that arrived exactly); an arm that starts on a stop moving into it, on a
        one-point range, or with a reaction that would pull is not stepped
        (:data:`STEP_AT_STOP`: the caller resolves it, ``sim.stops``); an arm
        whose step ends beyond a limit is :data:`STEP_CROSSED` (its row is the free step,
        from a start holding no joint) or :data:`STEP_AT_STOP` (it held joints).
        :data:`STEP_BAD_STATE` / :data:`STEP_BAD_ACCEL`: a stage state / an acceleration
        was not finite or M not positive definite.  The reference backend resolves no
        stop itself: every arm starting on a stop is :data:`STEP_AT_STOP`."""
        if not (q.shape == qd.shape == tau.shape == self.shape):
            self._check_shapes(q=q, qd=qd, tau=tau)  # raises
        A1 = q if qdd_start is None else qdd_start
        known = self._none if known is None or qdd_start is None else known
        active = self._all if active is None else active
        h = self.dt if dt is None else float(dt)
        out = self._result
        if dynamics.backend() == "compiled":
            self._kernels.step_batch(  # one layout of each array, one machine code (kernel_array)
                self._table, self.method == "rk4", h, kernel_array(q), kernel_array(qd), kernel_array(tau),
                kernel_array(A1), known, self._g0, active,
                self._no_held if held is None else held, held is not None, stops, out.q, out.qd, out.qdd, out.reaction, out.at_limit, out.status,
            )
        else:
            _reference_step(self.robot, q, qd, tau, h, self.method, A1, known, active, held, stops, self._gravity, out)
        return out


    def step_computed_torque(
        self,
        q: FloatArray,
        qd: FloatArray,
        q_des: FloatArray,
        qd_des: FloatArray,
        qdd_des: FloatArray,
        kp: float | FloatArray,
        kd: float | FloatArray,
        effort_limit: FloatArray,
        active: NDArray[np.bool_] | None = None,
        *,
        stops: bool = False,
    ) -> StepResult:
        """Computed torque and one step in one call, per arm: the ``command``
        τ = ID(q, q̇, q̈_ref) at q̈_ref = q̈_des + kp (q_des − q) + kd (q̇_des − q̇)
        (:func:`computed_torque`), the ``effort`` the command clipped to ±``effort_limit``
        (n,) [N·m or N], and :meth:`step` with that effort (from q̈_ref where nothing
        saturated; ``stops`` as there).  Joint arrays float64 (N, n); ``kp`` [1/s²], ``kd``
        [1/s] numbers or (N,) per arm.  The same bits as computed_torque, the clip and
        :meth:`step` called in turn; an arm whose command is not finite (its sum of
        squares) is :data:`STEP_BAD_EFFORT` and not stepped."""
        if not (q.shape == qd.shape == q_des.shape == qd_des.shape == qdd_des.shape == self.shape):
            self._check_shapes(q=q, qd=qd, q_des=q_des, qd_des=qd_des, qdd_des=qdd_des)  # raises
        active = self._all if active is None else active
        for gains, value in ((self._kp, kp), (self._kd, kd)):
            if isinstance(value, float):
                gains.fill(value)
            else:
                gains[:] = value
        out = self._result
        if dynamics.backend() == "compiled":
            self._kernels.ct_step_batch(
                self._table, self.method == "rk4", self.dt, q, qd, q_des, qd_des, qdd_des, self._kp, self._kd,
                kernel_array(np.asarray(effort_limit)), self._g0, active, stops, out.command, out.effort, out.q, out.qd, out.qdd, out.reaction, out.at_limit, out.status,
            )
            return out
        command, qdd_ref = computed_torque(
            self.robot, q, qd, q_des, qd_des, qdd_des, self._kp[:, None], self._kd[:, None], self._gravity
        )
        out.command[:] = command
        finite = np.isfinite(np.einsum("ij,ij->i", command, command))
        out.status[active & ~finite] = STEP_BAD_EFFORT
        saturated = (np.abs(command) > effort_limit).any(axis=1)
        out.effort[:] = np.clip(command, -effort_limit, effort_limit)
        _reference_step(self.robot, q, qd, out.effort, self.dt, self.method, qdd_ref, ~saturated, active & finite, None,
                        stops, self._gravity, out)
        return out

    def run_law(
        self,
        law: str,
        kp: FloatArray,
        kd: FloatArray,
        desired: tuple[FloatArray, FloatArray, FloatArray],
        effort_limit: FloatArray,
        velocity_limit: FloatArray,
        q: FloatArray,
        qd: FloatArray,
        n_steps: int,
        *,
        stops: bool = False,
        on_limit: bool = False,
        contact: tuple | None = None,
    ) -> tuple[int, tuple[FloatArray, ...], tuple[NDArray[np.bool_], FloatArray] | None]:
        """Up to ``n_steps`` steps of one arm (a one-arm stepper, compiled backend) from
        (q, q̇) (n,) under the sampled ``law`` (``Controller.sampled_law``: "passive", "pd",
        "pdg", "ct" with its gains kp, kd) toward the fixed ``desired`` (q, q̇, q̈) (n,),
        in one compiled call (:func:`robot_sim.sim.step_kernels.run_steps`): per step the
        command, its clip to ±``effort_limit``, :meth:`step` (``stops`` as there: joints
        resting on their stops held) and q̇ clipped to ±``velocity_limit`` (n,).
        ``on_limit``: some joint is on a limit before the first step.  ``contact``: the
        contact tuple of a ``ContactModel`` (``ContactModel.compiled``), whose pairs then
        act at every stage.  Returns the number of steps taken (it stops before a step the
        physics loop resolves its own way: not finite, a stop met, the pairs near contact
        changed), the state after the last one: (q, q̇, q̈ at its start, command, effort
        [N·m or N], joints saturated, joints braked), and the stops' record of the last
        step that held joints or ended on a limit (joints on a limit (n,) bool, the stops'
        reaction (n,) [N·m or N]; new arrays), or None when no step did."""
        n = self.shape[1]
        q, qd = q.copy(), qd.copy()
        out = (q, qd, np.empty(n), np.empty(n), np.empty(n), np.empty(n, dtype=bool), np.empty(n, dtype=bool))
        at_limit, reaction, recorded = self._limits
        recorded[0] = False
        q_des, qd_des, qdd_des = (np.ascontiguousarray(x, dtype=float) for x in desired)
        taken = self._kernels.run_steps(
            self._table, self.method == "rk4", self.dt, n_steps, getattr(self._kernels, "LAW_" + law.upper()),
            np.ascontiguousarray(kp, dtype=float), np.ascontiguousarray(kd, dtype=float), q_des, qd_des, qdd_des,
            kernel_array(effort_limit), kernel_array(velocity_limit), self._g0, stops, *out, on_limit, at_limit, reaction,
            recorded, contact,
        )
        return taken, out, ((at_limit.copy(), reaction.copy()) if recorded[0] else None)

    def _check_shapes(self, **arrays: FloatArray) -> None:
        """ValueError naming the first array whose shape is not (N, n)."""
        for name, x in arrays.items():
            if x.shape != self.shape:
                raise ValueError(f"{name} must have shape {self.shape}, got shape {x.shape}")


def _reference_step(
    robot: RobotParams, Q: FloatArray, QD: FloatArray, TAU: FloatArray, h: float, method: str,
    A1: FloatArray, known: NDArray[np.bool_], active: NDArray[np.bool_], held: NDArray[np.bool_] | None,
    stops: bool, gravity: ArrayLike, out: StepResult,
) -> None:
    """:meth:`Stepper.step` by the reference backend's batched (constrained) forward dynamics."""
    lo, hi = robot.q_min, robot.q_max
    if stops:  # resolves no stop: an arm starting on one is the caller's
        on_stop = ((Q == lo) | (Q == hi)).any(axis=1)
        out.status[active & on_stop] = STEP_AT_STOP
        active = active & ~on_stop
    idx = np.flatnonzero(active)
    q, v, tau = Q[idx], QD[idx], TAU[idx]
    H = None if held is None else held[idx]
    ok = np.ones(len(idx), dtype=bool)
    out.status[idx] = STEP_OK

    def accel(qs: FloatArray, vs: FloatArray, first: bool = False) -> FloatArray:
        """Accelerations of the arms still ok (NaN elsewhere); marks the failing ones."""
        good = np.isfinite(qs).all(axis=1) & np.isfinite(vs).all(axis=1)
        out.status[idx[ok & ~good]] = STEP_BAD_STATE
        ok[:] &= good
        a = np.full(qs.shape, np.nan)
        if ok.any():
            if H is None:
                a[ok] = forward_dynamics(robot, qs[ok], vs[ok], tau[ok], gravity)
            else:
                a[ok], reaction = constrained_forward_dynamics(robot, qs[ok], vs[ok], tau[ok], H[ok], gravity)
                if first:
                    out.reaction[idx[ok]] = reaction
        bad = ok & ~np.isfinite(a).all(axis=1)
        out.status[idx[bad]] = STEP_BAD_ACCEL
        ok[:] &= ~bad
        return a

    use_known = known[idx] & np.isfinite(A1[idx]).all(axis=1)
    if H is not None:
        use_known &= ~H.any(axis=1)
    elif stops:
        out.reaction[idx] = 0.0
    a1 = A1[idx].copy()
    if not use_known.all():
        ok[use_known] = False  # only the arms whose start acceleration is not known
        computed = accel(q, v, first=True)
        ok[use_known] = True
        a1[~use_known] = computed[~use_known]
    if H is not None:
        out.reaction[idx[use_known]] = 0.0
    out.qdd[idx] = a1
    out.q[idx], out.qd[idx], _ = runge_kutta(method, q, v, h, a1, lambda _offset, qs, vs: accel(qs, vs))
    if stops:
        q1 = out.q[idx]
        out.at_limit[idx] = (q1 == lo) | (q1 == hi)
        crossed = ok & ((q1 < lo) | (q1 > hi)).any(axis=1)
        out.status[idx[ok & ~crossed & out.at_limit[idx].any(axis=1)]] = STEP_ON_LIMIT
        out.status[idx[crossed]] = STEP_CROSSED
