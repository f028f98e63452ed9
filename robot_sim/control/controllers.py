"""Joint-space controllers: the joint state and the desired state in, joint effort out.

Every controller has one method, :meth:`Controller.torque`, taking the current joint
vector ``q`` and velocity ``qd`` and the desired ``q_des``, ``qd_des``, ``qdd_des`` (all
(n,), radians / metres and their rates) and returning the commanded joint effort (n,)
[N·m for revolute joints, N for prismatic ones].  Effort limits are applied afterwards by
the simulation (see robot_sim/sim/simulation.py), not here.

* :class:`Passive` – zero effort: the arm falls under gravity (and friction).
* :class:`PD` – ``τ = Kp (q_des − q) + Kd (qd_des − qd)``.
* :class:`PDGravity` – PD plus the gravity torque ``g(q)``: holds any pose with zero
  steady-state error.
* :class:`ComputedTorque` – inverse dynamics with PD on the error, M-weighted:
  ``τ = M(q) (qdd_des + ω² e + 2ζω ė) + C(q, qd) qd + g(q) + friction``, computed as one
  call of ``inverse_dynamics``; the error obeys ``ë + 2ζω ė + ω² e = 0`` on every joint.

Gains (:func:`control_gains`): a closed-loop natural frequency ``bandwidth`` f [Hz]
(ω = 2πf) and damping ratio ζ.  PD gains are scaled per joint by the diagonal of the mass
matrix at home, ``Kp_i = M_ii ω²``, ``Kd_i = 2ζω M_ii``, so every joint, heavy or light,
gets roughly the same bandwidth; computed torque uses ω², 2ζω directly.  Defaults:
:data:`DEFAULT_BANDWIDTH_HZ`, :data:`DEFAULT_DAMPING`; the robot file's ``[control]``
table overrides them (and may give ``kp``/``kd`` per joint), and the command line
overrides the file.  Joint errors are not wrapped: a revolute joint travels the way its
angle says, as a joint with limits must.

This module imports neither OpenGL nor Qt.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim import dynamics
from robot_sim.kernels import status
from robot_sim.model.params import RobotParams

FloatArray = NDArray[np.float64]

#: Default closed-loop natural frequency [Hz]: well below the 1 kHz step (ω·dt ≈ 0.013,
#: far inside the stability region of both integrators) and fast enough to follow the
#: sliders and the circle demo within a few tenths of a second.
DEFAULT_BANDWIDTH_HZ = 2.0
#: Default damping ratio: critically damped, no overshoot on a step of the desired value.
DEFAULT_DAMPING = 1.0

#: The joint-space controllers of this module (sampled: effort held over a step).
JOINT_MODES = ("passive", "pd", "pdg", "ct")
#: Physical motion modes (a controller in the simulation loop), ``--motion``'s choices:
#: the joint-space controllers, then operational-space and impedance control
#: (robot_sim/control/task_space.py).
PHYSICAL_MODES = (*JOINT_MODES, "osc", "impedance")
#: Motion modes of the viewer, in the order the window cycles them.  ``kinematic`` is no
#: physics at all (the joints follow the desired values directly).
MOTION_MODES = ("kinematic", *PHYSICAL_MODES)
MOTION_LABELS = {
    "kinematic": "kinematic",
    "passive": "passive",
    "pd": "PD",
    "pdg": "PD + gravity",
    "ct": "computed torque",
    "osc": "operational space",
    "impedance": "impedance",
}


@dataclass(frozen=True)
class Gains:
    """Controller gains of one robot.

    ``kp`` (n,) [N·m/rad or N/m] and ``kd`` (n,) [N·m·s/rad or N·s/m] are the joint PD gains
    of :class:`PD` and :class:`PDGravity`; ``omega`` [rad/s] and ``zeta`` set the error
    dynamics of :class:`ComputedTorque` (``Kp = ω²``, ``Kd = 2ζω``).
    """

    kp: FloatArray
    kd: FloatArray
    omega: float
    zeta: float


def _positive(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) or value <= 0:
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return float(value)


def _joint_gains(name: str, value: ArrayLike, n: int) -> FloatArray:
    arr = np.asarray(value, dtype=float)
    if arr.shape != (n,) or not np.isfinite(arr).all() or (arr < 0).any():
        raise ValueError(f"{name} must be {n} finite gains >= 0, got {value!r}")
    return arr


def control_gains(
    robot: RobotParams,
    *,
    bandwidth: float | None = None,
    damping: float | None = None,
    kp: ArrayLike | None = None,
    kd: ArrayLike | None = None,
) -> Gains:
    """Gains for ``robot``: arguments (the command line) over the robot file's ``[control]``
    table over the defaults.

    ``bandwidth`` [Hz] and ``damping`` (ζ) derive ``kp = M_ii(q_home) ω²`` and
    ``kd = 2ζω M_ii(q_home)`` unless ``kp``/``kd`` (n,) are given.  Needs the robot's
    inertial data (``dynamics`` raises naming the first link without it).  Raises
    ValueError naming the argument for a non-positive bandwidth/damping or bad gains.
    """
    table = robot.control or {}
    f = _positive("bandwidth", bandwidth if bandwidth is not None else table.get("bandwidth", DEFAULT_BANDWIDTH_HZ))
    zeta = _positive("damping", damping if damping is not None else table.get("damping", DEFAULT_DAMPING))
    omega = 2.0 * math.pi * f
    n = robot.n_dofs
    kp_arg = kp if kp is not None else table.get("kp")
    kd_arg = kd if kd is not None else table.get("kd")
    m_diag = None
    if kp_arg is None or kd_arg is None:
        m_diag = np.diagonal(dynamics.mass_matrix(robot, robot.q_home)).copy()
    kp_arr = _joint_gains("kp", kp_arg, n) if kp_arg is not None else m_diag * omega**2
    kd_arr = _joint_gains("kd", kd_arg, n) if kd_arg is not None else m_diag * 2.0 * zeta * omega
    return Gains(kp=kp_arr, kd=kd_arr, omega=omega, zeta=zeta)


@dataclass(frozen=True)
class StepContext:
    """What a controller integrating its own law over one step is given: the step's start
    time ``t`` and length ``h`` [s], the ``integrator`` ("rk4" or "euler"), the desired
    values as a function of time ``desired_at`` (in the controller's space) and at ``t``
    (``desired``), the drives' effort ``limit`` (n,) [N·m or N], the loop's one-arm ``stepper`` (the compiled step of
    the simulated robot: ``robot_sim.sim.stepper.Stepper``), whether the joint limits are
    ``stops``, and whether some joint starts ``on_stop``."""

    t: float
    h: float
    integrator: str
    desired_at: Callable[[float], tuple]
    desired: tuple
    limit: FloatArray
    stepper: Any
    stops: bool
    on_stop: bool


class Integrated(NamedTuple):
    """A step a controller integrated itself: (q, q̇) at its end, q̈, the commanded
    effort at its start (n,), and the step's ``status`` (:mod:`robot_sim.kernels.status`:
    OK, ON_LIMIT, CROSSED — then (q, q̇) is the free trial step the loop resolves the stops
    from — or AT_STOP — not stepped); with the stops held inside the step, their
    ``reaction`` at the start and the joints ``at_limit`` at the end (else None)."""

    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    command: FloatArray
    status: int
    reaction: FloatArray | None = None
    at_limit: NDArray[np.bool_] | None = None


class Controller:
    """Interface: ``torque(q, qd, q_des, qd_des, qdd_des)`` → commanded joint effort (n,)."""

    #: Motion mode key (see :data:`MOTION_MODES`).
    mode = ""
    #: What :meth:`torque` is asked to follow: ``"joint"`` (desired q, q̇, q̈) or ``"task"``
    #: (desired tool pose, twist, acceleration: robot_sim/control/task_space.py).
    space = "joint"
    #: True for a continuous-time law the simulation evaluates at every integration stage;
    #: False for a sampled one, whose effort is held over each step.
    continuous = False
    #: True when :meth:`integrate` may take a whole step (the loop skips asking otherwise).
    integrates = False

    def reset(self, q: FloatArray, dt: float) -> None:
        """Start a run at joint values ``q`` with control period ``dt`` [s]: controllers
        with internal state (resolved rate's desired joints) reinitialise it."""

    def torque(
        self, q: FloatArray, qd: FloatArray, q_des: FloatArray, qd_des: FloatArray, qdd_des: FloatArray
    ) -> FloatArray:
        raise NotImplementedError

    def commanded_acceleration(self) -> FloatArray | None:
        """The joint acceleration the last :meth:`torque` produces on this controller's
        robot model at the state it was given, if the control law knows it (computed
        torque does: it is the reference acceleration), else None."""
        return None

    def integrate(self, q: FloatArray, qd: FloatArray, step: StepContext) -> Integrated | None:
        """The one way a controller integrates its own law over a step: the whole step
        from (q, q̇) (n,) in one call (its law inside the compiled step: computed torque
        through the loop's stepper, operational space in its own kernel), or None (the
        default), and the loop evaluates :meth:`torque` (at every stage when
        :attr:`continuous`) and steps the dynamics itself."""
        return None

    def sampled_law(self) -> tuple[str, FloatArray, FloatArray] | None:
        """The law by name (``"passive"``, ``"pd"``, ``"pdg"``, ``"ct"``) and its gains
        ``kp``, ``kd`` (n,) [N·m/rad, N·m·s/rad; computed torque: ω² (1/s²) and 2ζω (1/s)
        in entry 0] when :meth:`torque` is exactly that sampled law on this controller's
        ``robot``, so a compiled loop may run several steps of it in one call
        (``Stepper.run_law``); None (the default): the loop calls :meth:`torque`."""
        return None

    def acceleration(self, q: FloatArray, qd: FloatArray, *desired: FloatArray) -> FloatArray | None:
        """The closed-loop joint acceleration on this controller's model at (q, q̇) for the
        ``desired`` values, when the law yields it without its torque (operational space
        does), else None."""
        return None


class Passive(Controller):
    """No actuation: zero effort on every joint."""

    mode = "passive"

    def __init__(self, robot: RobotParams) -> None:
        self._zero = np.zeros(robot.n_dofs)

    def sampled_law(self) -> tuple[str, FloatArray, FloatArray] | None:
        return "passive", self._zero, self._zero

    def torque(
        self, q: FloatArray, qd: FloatArray, q_des: FloatArray, qd_des: FloatArray, qdd_des: FloatArray
    ) -> FloatArray:
        return self._zero.copy()


class PD(Controller):
    """Independent joint PD: ``τ = Kp (q_des − q) + Kd (qd_des − qd)``."""

    mode = "pd"

    def __init__(self, robot: RobotParams, gains: Gains) -> None:
        self.robot = robot
        self.kp = gains.kp
        self.kd = gains.kd

    def torque(
        self, q: FloatArray, qd: FloatArray, q_des: FloatArray, qd_des: FloatArray, qdd_des: FloatArray
    ) -> FloatArray:
        return self.kp * (q_des - q) + self.kd * (qd_des - qd)

    def sampled_law(self) -> tuple[str, FloatArray, FloatArray] | None:
        return self.mode, self.kp, self.kd


class PDGravity(PD):
    """PD plus gravity compensation: ``τ = Kp e + Kd ė + g(q)``."""

    mode = "pdg"

    def torque(
        self, q: FloatArray, qd: FloatArray, q_des: FloatArray, qd_des: FloatArray, qdd_des: FloatArray
    ) -> FloatArray:
        return super().torque(q, qd, q_des, qd_des, qdd_des) + dynamics.gravity_torque(self.robot, q)


class ComputedTorque(Controller):
    """Computed torque: ``τ = ID(q, qd, qdd_des + ω² e + 2ζω ė)`` (inverse dynamics,
    friction included when the file gives drives)."""

    mode = "ct"
    integrates = True

    def __init__(self, robot: RobotParams, gains: Gains) -> None:
        self.robot = robot
        self.kp = gains.omega**2
        self.kd = 2.0 * gains.zeta * gains.omega
        self._qdd_ref: FloatArray | None = None

    def sampled_law(self) -> tuple[str, FloatArray, FloatArray] | None:
        return "ct", np.array([self.kp], dtype=float), np.array([self.kd], dtype=float)

    def torque(
        self, q: FloatArray, qd: FloatArray, q_des: FloatArray, qd_des: FloatArray, qdd_des: FloatArray
    ) -> FloatArray:
        tau, self._qdd_ref = dynamics.computed_torque(self.robot, q, qd, q_des, qd_des, qdd_des, self.kp, self.kd)
        return tau

    def commanded_acceleration(self) -> FloatArray | None:
        """The reference acceleration of the last :meth:`torque` (exact on the model)."""
        return self._qdd_ref

    def integrate(self, q: FloatArray, qd: FloatArray, step: StepContext) -> Integrated | None:
        """The law inside the compiled step (``Stepper.step_computed_torque``: the same
        bits as :meth:`torque`, the clip and the step in turn) when the loop's stepper
        steps this controller's own robot model; None for a command that is not finite
        (:meth:`torque` then says why)."""
        stepper = step.stepper
        if stepper is None or stepper.robot is not self.robot:
            return None
        desired = step.desired
        q_des, qd_des, qdd_des = desired
        if not type(q_des) is type(qd_des) is type(qdd_des) is np.ndarray:  # a reference's lists
            q_des, qd_des, qdd_des = (np.asarray(x, dtype=float) for x in desired)
        out = stepper.step_computed_torque(q[None], qd[None], q_des[None], qd_des[None], qdd_des[None], self.kp,
                                           self.kd, step.limit, stops=step.stops)
        if out.status[0] == status.BAD_EFFORT:
            return None
        return Integrated(out.q[0].copy(), out.qd[0].copy(), out.qdd[0].copy(), out.command[0].copy(),
                          int(out.status[0]), out.reaction[0].copy(), out.at_limit[0].copy())
