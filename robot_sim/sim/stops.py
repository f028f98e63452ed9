"""The one stop resolver of the physics loop: a step that touches a joint stop, for
:class:`~robot_sim.sim.simulation.Simulation` and
:class:`~robot_sim.sim.batch.BatchSimulation` alike.

A step that would carry a joint past its limit is cut at the instant it arrives (the step
length found by Newton's method on the integrator's own step, to
:data:`ARRIVAL_TOLERANCE`), the stops apply the impact impulse over the joints they touch
(:func:`~robot_sim.sim.joint_stops.impact`: inelastic unless ``restitution`` is set;
kinetic energy never increases), a :class:`LimitEvent` records the arrival and the
impulse, and the rest of the step is integrated from there.  A joint resting on its stop
at zero velocity whose acceleration pushes into it is held
(:func:`~robot_sim.sim.joint_stops.hold`), and its stop's reaction torque reported.

The resolver owns no state of a run: the caller passes the step's start, its time and
the two physics functions of that step (:class:`StepPhysics`), and receives a
:class:`Resolved` step whose :class:`StopOutcome` says what the stops did.

Units: q in rad (revolute) and m (prismatic), rates per second, efforts in N·m and N,
time in s.  Imports neither OpenGL nor Qt.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np
from numpy.typing import NDArray

from robot_sim import dynamics
from robot_sim.model.params import RobotParams
from robot_sim.sim import joint_stops
from robot_sim.sim.stepper import StepDiverged

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: Arrivals slower than this [rad/s or m/s] are inelastic whatever the restitution, and
#: joints an impact would leave moving off their stops slower than this are held
#: (``joint_stops.impact``'s ``hold_speed``): bounces and knocks that small would only
#: start infinitely many ever smaller ones in finite time.
BOUNCE_MIN_SPEED = 1e-2
#: An arrival is located when the joint is within this distance of its stop [rad or m];
#: it is then put exactly on the stop.
ARRIVAL_TOLERANCE = 1e-12
#: Newton (bisection when it leaves the bracket) iterations to locate an arrival.
LOCATE_ITERATIONS = 60


@dataclass(frozen=True)
class LimitEvent:
    """Joint ``joint`` (0-based) reached its ``side`` (``"min"`` or ``"max"``) limit
    ``q`` [rad or m] at simulated time ``time`` [s], and its stop applied the joint impulse
    ``impulse`` [N·m·s or N·s] (positive pushes toward larger q; zero for an arrival at
    zero speed)."""

    time: float
    joint: int
    side: str
    q: float
    impulse: float = 0.0


@dataclass(frozen=True)
class StopOutcome:
    """What the joint stops did in one step: the stops' ``reaction`` torque (n,) [N·m or
    N] at its start (zero for free joints), the ``events`` (arrivals) within it, and the
    joints exactly on a limit at its end, ``at_limit`` (n,) bool, when the stepper flagged
    them (None: the loop finds them from the end state)."""

    reaction: FloatArray
    events: tuple[LimitEvent, ...] = ()
    at_limit: BoolArray | None = None


class Resolved(NamedTuple):
    """A step through the stops: (q, q̇) at its end, the acceleration at its start (None
    where the caller's trial step already knows it) and the stops' outcome."""

    q: FloatArray
    qd: FloatArray
    qdd: FloatArray | None
    outcome: StopOutcome


#: ``stepped(q, qd, tau, a1, h, locked)``: ((q, qd) after a step of h [s] from (q, qd)
#: with the ``locked`` joints held (None: none), the acceleration at its start (``a1``
#: when given and nothing is locked)), and the stops' reaction at the start (None without
#: locked joints).
Stepped = Callable[..., tuple[tuple[FloatArray, FloatArray, FloatArray], FloatArray | None]]


@dataclass(frozen=True)
class StepPhysics:
    """The physics of one step, as the resolver needs it: ``stepped`` (:data:`Stepped`)
    and ``rhs(q, qd, tau)``, the right-hand side τ (+ contact) − C q̇ − g (− Jᵀ f_tool) of
    M q̈ = rhs [N·m or N]."""

    stepped: Stepped
    rhs: Callable[[FloatArray, FloatArray, FloatArray], FloatArray]


class StopResolver:
    """Resolves the steps of ``robot`` that touch its joint stops, with coefficient of
    restitution ``restitution`` in [0, 1]."""

    def __init__(self, robot: RobotParams, restitution: float = 0.0) -> None:
        self.robot, self.restitution = robot, float(restitution)
        n = robot.n_dofs
        self.max_arrivals = 4 * n + 4  # per step: more means the stops cannot resolve it
        self.point_ranges = bool((robot.q_min == robot.q_max).any())  # joints held both ways
        self.no_reaction = np.zeros(n)
        self.no_reaction.flags.writeable = False

    def crosses(self, q: FloatArray) -> bool:
        """True if some joint is beyond a limit."""
        return bool(((q < self.robot.q_min) | (q > self.robot.q_max)).any())

    def resolve(
        self,
        time: float,
        dt: float,
        q: FloatArray,
        qd: FloatArray,
        tau: FloatArray,
        physics: StepPhysics,
        trial: tuple[FloatArray, FloatArray, FloatArray] | None = None,
    ) -> Resolved:
        """One step of length ``dt`` [s] from (q, qd) at simulated ``time`` [s] with effort
        ``tau`` held, that touches stops: ``trial`` is the free step (q, qd, q̈) when it
        was already taken and crossed a limit; without it the step starts on a stop.
        StepDiverged when the stops cannot resolve it (or a step in it failed)."""
        lo, hi = self.robot.q_min, self.robot.q_max
        events: list[LimitEvent] = []
        reaction, locked = self.no_reaction, None
        elapsed, h = 0.0, dt
        if trial is None:
            push = joint_stops.stop_push(q, lo, hi)
            on = (q == lo) | (q == hi)
            if (push * qd < 0.0).any() or self.point_ranges:  # set, or landed on a stop, moving into it
                into = on & (qd != 0.0) & (push * qd <= 0.0)
                if into.any():
                    qd = self._impact(time, q, qd, push, on, into, 0.0, events)
            locked, trial, reaction = self._rest(q, qd, tau, physics, push, on, h)
        qdd = None
        for _ in range(self.max_arrivals):
            if trial is None:
                trial = physics.stepped(q, qd, tau, None, h, locked)[0]
            q1, qd1, a1 = trial
            if qdd is None:
                qdd = a1
            if not self.crosses(q1):
                return Resolved(q1, qd1, qdd, StopOutcome(reaction, tuple(events)))
            s, q1, qd1, arriving = self._locate(q, qd, tau, physics, a1, h, locked, q1, qd1)
            elapsed += s * h
            h -= s * h
            push = joint_stops.stop_push(q1, lo, hi)
            on = (q1 == lo) | (q1 == hi)
            q, qd = q1, self._impact(time, q1, qd1, push, on, arriving, elapsed, events)
            if h <= 0.0:
                return Resolved(q, qd, qdd, StopOutcome(reaction, tuple(events)))
            locked, trial, _ = self._rest(q, qd, tau, physics, push, on, h)
        raise StepDiverged(f"more than {self.max_arrivals} joint stop arrivals in one step")

    def _rest(
        self, q: FloatArray, qd: FloatArray, tau: FloatArray, physics: StepPhysics, push: FloatArray, on: BoolArray,
        h: float,
    ) -> tuple[BoolArray | None, tuple[FloatArray, FloatArray, FloatArray] | None, FloatArray]:
        """Which joints on a stop at rest the stops hold (None: none), the step of length h
        from (q, qd) with them held (None: not taken yet) and the stops' reaction torque.
        Holding every candidate is the answer when every reaction pushes (one step with
        them held, the common case of a joint that stays); otherwise
        ``joint_stops.hold`` solves the complementarity problem."""
        candidates = on & (qd == 0.0)
        if not candidates.any():
            return None, None, self.no_reaction
        trial, reaction = physics.stepped(q, qd, tau, None, h, candidates)
        if (push * reaction >= 0.0).all():
            return candidates, trial, reaction
        M = dynamics.mass_matrix(self.robot, q)
        _, reaction, locked = joint_stops.hold(M, physics.rhs(q, qd, tau), push, candidates)
        if not locked.any():
            return None, None, self.no_reaction
        return locked, None, reaction

    def _impact(
        self, time: float, q: FloatArray, qd: FloatArray, push: FloatArray, on: BoolArray, arriving: BoolArray,
        elapsed: float, events: list[LimitEvent],
    ) -> FloatArray:
        """Velocities after the stops' impact at (q, qd); the ``arriving`` joints' events
        (at ``elapsed`` seconds into the step that starts at ``time``) appended to ``events``."""
        speed = float(np.abs(qd[arriving]).max()) if arriving.any() else 0.0
        restitution = self.restitution if speed > BOUNCE_MIN_SPEED else 0.0
        M = dynamics.mass_matrix(self.robot, q)
        after, impulse, _ = joint_stops.impact(M, qd, push, on, restitution, BOUNCE_MIN_SPEED)
        for j in np.flatnonzero(arriving):
            side = "min" if q[j] == self.robot.q_min[j] else "max"
            events.append(LimitEvent(time + elapsed, int(j), side, float(q[j]), float(impulse[j])))
        return after

    def _locate(
        self, q: FloatArray, qd: FloatArray, tau: FloatArray, physics: StepPhysics, a1: FloatArray, h: float,
        locked: BoolArray | None, q1: FloatArray, qd1: FloatArray,
    ) -> tuple[float, FloatArray, FloatArray, BoolArray]:
        """The first arrival within the step (q, qd) → (q1, qd1) of length h, which took a
        joint past a limit: the fraction s of the step, (q, qd) there with the arriving
        joints put exactly on their stops, and those joints.  Newton's method on the
        integrator's step length (the derivative of q(s·h) is h·q̇), bisection where
        Newton leaves the bracket."""
        lo, hi = self.robot.q_min, self.robot.q_max
        s_lo, s, target, side = 0.0, 1.0, -1, 1.0
        crossed = (1.0, q1, qd1)
        for _ in range(LOCATE_ITERATIONS):
            below, above = q1 - lo, hi - q1
            depth = np.minimum(below, above)
            if locked is not None:
                depth[locked] = np.inf
            deepest = int(np.argmin(depth))
            if target < 0 or depth[deepest] < -ARRIVAL_TOLERANCE:  # (the full step always sets the target)
                target, side = deepest, (1.0 if below[deepest] < above[deepest] else -1.0)
            distance = below[target] if side > 0 else above[target]
            if depth[deepest] < -ARRIVAL_TOLERANCE:
                crossed = (s, q1, qd1)
            elif distance > ARRIVAL_TOLERANCE:
                s_lo = s
            else:
                break
            rate = side * h * qd1[target]
            s_new = s - distance / rate if rate < 0.0 else -1.0
            if not s_lo < s_new < crossed[0]:
                s_new = 0.5 * (s_lo + crossed[0])
            s = float(s_new)
            q1, qd1, _ = physics.stepped(q, qd, tau, a1, s * h, locked)[0]
        else:
            s, q1, qd1 = crossed  # bracket closed on a grazing arrival: take its end
        q1 = q1.copy()
        free = np.ones(q1.shape, dtype=bool) if locked is None else ~locked
        at_lo = free & (q1 - lo <= ARRIVAL_TOLERANCE) & (qd1 <= 0.0)
        at_hi = free & (hi - q1 <= ARRIVAL_TOLERANCE) & (qd1 >= 0.0)
        if side > 0:
            at_lo[target] = True
        else:
            at_hi[target] = True
        q1[at_lo] = lo[at_lo]
        q1[at_hi] = hi[at_hi]
        return s, q1, qd1, at_lo | at_hi
