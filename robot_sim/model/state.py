"""Joint-space state of a robot: :class:`JointState` and :class:`RobotState`.

A :class:`JointState` stores, for every joint, the full DH θ and d (offsets from the robot
file included) and their first and second time derivatives, exactly what forward
kinematics reads.  The joint vector **q** (the one variable of each joint: an angle in
radians for a revolute joint, a length in metres for a prismatic one) is a view of that
state; :class:`RobotState` converts between the two and validates every vector before
changing anything.  This module knows nothing about frames.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.model.messages import clip_repr
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams

FloatArray = NDArray[np.float64]


#: JointState fields of a joint-space rate: (revolute part, prismatic part).
_VELOCITY = ("thd", "dd")
_ACCELERATION = ("thdd", "ddd")


def check_joint_vector(values: ArrayLike, n: int, what: str = "q") -> FloatArray:
    """``values`` as a float array of shape (n,) or (N, n); ValueError naming ``what`` if the
    last dimension is not n, the array is not 1- or 2-D, or an entry is NaN or infinite."""
    try:
        raw = np.asarray(values)
    except (ValueError, TypeError):  # ragged nesting
        raise ValueError(f"{what} must be a sequence of numbers, got {clip_repr(values)}") from None
    if raw.dtype.kind == "c":
        raise ValueError(f"{what} must hold real numbers, got {clip_repr(values)}")
    if raw.dtype.kind not in "iuf":
        raise ValueError(f"{what} must be a sequence of numbers, got {clip_repr(values)}")
    arr = raw.astype(float, copy=False)
    if arr.ndim not in (1, 2) or arr.shape[-1] != n:
        raise ValueError(f"{what} must have {n} joint values per configuration, got shape {arr.shape}")
    if not np.isfinite(arr).all():
        raise ValueError(f"{what} contains NaN or infinite values: {arr if arr.size <= 12 else '...'}")
    return arr


class JointState:
    """Per-joint DH variables and their derivatives, as arrays of shape (n,).

    ``th`` [rad], ``thd`` [rad/s], ``thdd`` [rad/s²] are the full DH θ of each joint and its
    derivatives; ``d`` [m], ``dd`` [m/s], ``ddd`` [m/s²] the full DH d; ``u`` the joint
    actuation (torque in N·m or force in N).  For a revolute joint d stays at its DH constant
    and its derivatives are 0; for a prismatic joint θ does.
    """

    def __init__(self, jtype: ArrayLike) -> None:
        self.jtype = np.asarray(jtype, dtype=np.int64).copy()
        n = self.jtype.shape[0]
        # one buffer, the fields its rows: θ, d, their rates and accelerations first, so that
        # one slice (:meth:`motion_snapshot`) tells whether q or q̇ (or q̈) changed
        self._rows = np.zeros((7, n))
        self.th, self.d, self.thd, self.dd, self.thdd, self.ddd, self.u = self._rows

    def motion_snapshot(self, accelerations: bool = False) -> bytes:
        """The bytes of θ, d, θ̇ and ḋ (and θ̈, d̈ with ``accelerations``): equal snapshots
        mean the joint values and rates (and accelerations) are the same."""
        return self._rows[: 6 if accelerations else 4].tobytes()

    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.jtype.shape[0])

    def _set(self, field: str, values: ArrayLike) -> None:
        getattr(self, field)[:] = check_joint_vector(values, self.n, field)

    def set_th(self, values: ArrayLike) -> None:
        """Set all DH θ [rad] (validated: length n, finite)."""
        self._set("th", values)

    def set_thd(self, values: ArrayLike) -> None:
        """Set all dθ/dt [rad/s]."""
        self._set("thd", values)

    def set_thdd(self, values: ArrayLike) -> None:
        """Set all d²θ/dt² [rad/s²]."""
        self._set("thdd", values)

    def set_d(self, values: ArrayLike) -> None:
        """Set all DH d [m]."""
        self._set("d", values)

    def set_dd(self, values: ArrayLike) -> None:
        """Set all dd/dt [m/s]."""
        self._set("dd", values)

    def set_ddd(self, values: ArrayLike) -> None:
        """Set all d²d/dt² [m/s²]."""
        self._set("ddd", values)

    def set_u(self, values: ArrayLike) -> None:
        """Set the joint actuation [N·m or N]."""
        self._set("u", values)

    def copy(self) -> "JointState":
        """Independent copy of this state."""
        other = JointState(self.jtype)
        for field in ("th", "thd", "thdd", "d", "dd", "ddd", "u"):
            getattr(other, field)[:] = getattr(self, field)
        return other


class RobotState:
    """Current and desired joint state of one robot, initialised at the robot's home.

    ``joint_state`` is where the robot is; ``joint_state_des`` where it should go (drawn as
    a ghost by the viewer, produced by inverse kinematics).
    """

    def __init__(self, robot_params: RobotParams) -> None:
        self.robot = robot_params
        self._revolute = robot_params.jtype == JTYPE_REVOLUTE
        self._all_revolute = bool(self._revolute.all())
        self._revolute_index = np.flatnonzero(self._revolute)
        self._prismatic_index = np.flatnonzero(~self._revolute)
        self.joint_state = JointState(robot_params.jtype)
        self.joint_state_des = JointState(robot_params.jtype)
        for state in (self.joint_state, self.joint_state_des):
            state.th[:] = robot_params.dh_th
            state.d[:] = robot_params.dh_d
        self.set_q(robot_params.q_home)
        self.set_q_des(robot_params.q_home)

    # q <-> (θ, d) conversion, shared by the current and the desired state
    def _q_of(self, state: JointState) -> FloatArray:
        return np.where(self._revolute, state.th - self.robot.dh_th, state.d - self.robot.dh_d)

    def _set_q_of(self, state: JointState, values: ArrayLike, what: str) -> None:
        q = check_joint_vector(values, self.robot.n_dofs, what)
        if q.ndim != 1:
            raise ValueError(f"{what} must be one configuration of shape ({self.robot.n_dofs},), got {q.shape}")
        state.th[:] = np.where(self._revolute, self.robot.dh_th + q, self.robot.dh_th)
        state.d[:] = np.where(self._revolute, self.robot.dh_d, self.robot.dh_d + q)

    def _rate_of(self, state: JointState, fields: tuple[str, str]) -> FloatArray:
        """The joint-space rate whose revolute and prismatic parts are ``fields`` of ``state``
        (``_VELOCITY`` or ``_ACCELERATION``)."""
        th, d = fields
        return np.where(self._revolute, getattr(state, th), getattr(state, d))

    def _set_rate_of(self, state: JointState, values: ArrayLike, what: str, fields: tuple[str, str]) -> None:
        rate = check_joint_vector(values, self.robot.n_dofs, what)
        if rate.ndim != 1:
            raise ValueError(f"{what} must be one vector of shape ({self.robot.n_dofs},), got {rate.shape}")
        th, d = fields
        getattr(state, th)[:] = np.where(self._revolute, rate, 0.0)
        getattr(state, d)[:] = np.where(self._revolute, 0.0, rate)

    def q(self) -> FloatArray:
        """Current joint vector (n,): radians (revolute) and metres (prismatic)."""
        return self._q_of(self.joint_state)

    def set_q(self, values: ArrayLike) -> None:
        """Set the current joint vector; ValueError for a wrong length or NaN/inf (state unchanged)."""
        self._set_q_of(self.joint_state, values, "q")

    def q_des(self) -> FloatArray:
        """Desired joint vector (n,)."""
        return self._q_of(self.joint_state_des)

    def set_q_des(self, values: ArrayLike) -> None:
        """Set the desired joint vector (validated like :meth:`set_q`)."""
        self._set_q_of(self.joint_state_des, values, "q_des")

    def qd(self) -> FloatArray:
        """Current joint velocities (n,): rad/s (revolute) and m/s (prismatic)."""
        return self._rate_of(self.joint_state, _VELOCITY)

    def set_qd(self, values: ArrayLike) -> None:
        """Set the current joint velocities (validated like :meth:`set_q`)."""
        self._set_rate_of(self.joint_state, values, "qd", _VELOCITY)

    def qdd(self) -> FloatArray:
        """Current joint accelerations (n,): rad/s² (revolute) and m/s² (prismatic)."""
        return self._rate_of(self.joint_state, _ACCELERATION)

    def set_qdd(self, values: ArrayLike) -> None:
        """Set the current joint accelerations (validated like :meth:`set_q`)."""
        self._set_rate_of(self.joint_state, values, "qdd", _ACCELERATION)

    def qd_des(self) -> FloatArray:
        """Desired joint velocities (n,)."""
        return self._rate_of(self.joint_state_des, _VELOCITY)

    def set_qd_des(self, values: ArrayLike) -> None:
        """Set the desired joint velocities (validated like :meth:`set_q`)."""
        self._set_rate_of(self.joint_state_des, values, "qd_des", _VELOCITY)

    def write_motion(self, q: FloatArray, qd: FloatArray, qdd: FloatArray, u: FloatArray) -> None:
        """Set the current q, q̇, q̈ and the actuation u from float (n,) arrays the caller
        knows to be finite (the physics loop's own state): the same values as
        :meth:`set_q`, :meth:`set_qd`, :meth:`set_qdd` and ``joint_state.set_u``, without
        their checks."""
        js = self.joint_state
        if self._all_revolute:  # θ = offset + q, d the offsets, the rates θ̇ and θ̈
            np.add(self.robot.dh_th, q, out=js.th)
            js.d[:] = self.robot.dh_d
            js.thd[:] = qd
            js.thdd[:] = qdd
            js.dd.fill(0.0)
            js.ddd.fill(0.0)
        else:  # as np.where(revolute, ...) writes them
            rev, pri = self._revolute_index, self._prismatic_index
            np.add(self.robot.dh_th, q, out=js.th)
            js.th[pri] = self.robot.dh_th[pri]
            np.add(self.robot.dh_d, q, out=js.d)
            js.d[rev] = self.robot.dh_d[rev]
            for th_rate, d_rate, rate in ((js.thd, js.dd, qd), (js.thdd, js.ddd, qdd)):
                th_rate[:] = rate
                th_rate[pri] = 0.0
                d_rate[:] = rate
                d_rate[rev] = 0.0
        js.u[:] = u

    def qdd_des(self) -> FloatArray:
        """Desired joint accelerations (n,) (the feed-forward of computed-torque control)."""
        return self._rate_of(self.joint_state_des, _ACCELERATION)

    def set_qdd_des(self, values: ArrayLike) -> None:
        """Set the desired joint accelerations (validated like :meth:`set_q`)."""
        self._set_rate_of(self.joint_state_des, values, "qdd_des", _ACCELERATION)
