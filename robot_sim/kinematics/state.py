"""The :class:`Kinematics` of one robot at one joint state: frames, tool pose, COMs,
Jacobian and twists after each :meth:`Kinematics.update` (frames and units:
:mod:`robot_sim.kinematics.chain`).  Imports neither OpenGL nor Qt.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from robot_sim.kinematics.chain import _cross, _model, _world0
from robot_sim.model.params import RobotParams
from robot_sim.model.state import JointState
from robot_sim.transforms import HomogeneousTransform

FloatArray = NDArray[np.float64]


class Kinematics:
    """Forward and differential kinematics of one robot at one joint state.

    After :meth:`update` the attributes hold, all in the world frame (metres, radians):

    * ``frames``: (n+1, 4, 4) array of frames 0..n;
    * ``h_tf``: the same frames as a list of n+1 :class:`HomogeneousTransform`;
    * ``endeff_tf``: endeffector (tool) frame = frame n · tool;
    * ``link_com``: (n_links+1, 3) centres of mass, ``link_com[0]`` at the base (frame 0
      origin), ``link_com[i]`` at ``inertials.com[i-1]`` in frame i when the robot has
      inertial data, otherwise at fraction ``link_com_frac[i-1]`` from frame i-1 to frame i;
    * ``jacobian``: (6, n) geometric Jacobian of the endeffector;
    * ``link_vel``: (n+1, 6) twist [v; ω] of each frame's origin (frame 0 is fixed);
    * ``link_com_vel``: (n_links+1, 3) linear velocity of each COM;
    * ``endeff_twist``: (6,) twist [v; ω] of the endeffector = ``jacobian @ qd``.

    ``h_tf`` and the three velocity attributes are derived on first access after each
    update (from the joint rates captured by that update), so a caller that needs only
    poses does not pay for them.
    """

    def __init__(self, robot_params: RobotParams) -> None:
        self.robot = robot_params
        self._model = _model(robot_params)
        home = JointState(robot_params.jtype)
        home.th[:], home.d[:] = self._model.th_d(np.asarray(robot_params.q_home))
        self.update(home)

    def update(self, joint_state: JointState, base_tf: HomogeneousTransform | None = None) -> None:
        """Recompute the frames, COMs and Jacobian from scratch (velocities on demand).

        ``joint_state`` supplies full DH θ and d and their rates; ``base_tf`` places the
        robot's base in the world (identity when None).
        """
        model = self._model
        frames = model.frames(joint_state.th, joint_state.d, _world0(self.robot, base_tf))
        endeff = frames[-1] @ model.tool
        self.frames = frames
        self.endeff_tf = HomogeneousTransform.wrap(endeff)
        self.link_com = model.link_com(frames)
        self.jacobian = model.jacobian(frames, endeff[:3, 3])
        self._qd = np.where(model.revolute, joint_state.thd, joint_state.dd)
        self._h_tf: list[HomogeneousTransform] | None = None
        self._velocities: tuple[FloatArray, FloatArray, FloatArray] | None = None

    @property
    def h_tf(self) -> list[HomogeneousTransform]:
        """World frames 0..n as transforms (views of ``frames``)."""
        if self._h_tf is None:
            self._h_tf = [HomogeneousTransform.wrap(f) for f in self.frames]
        return self._h_tf

    @property
    def link_vel(self) -> FloatArray:
        """(n+1, 6) twist [v (m/s); ω (rad/s)] of each frame's origin, world frame."""
        return self._derive_velocities()[0]

    @property
    def link_com_vel(self) -> FloatArray:
        """(n_links+1, 3) linear velocity (m/s) of each link COM, world frame."""
        return self._derive_velocities()[1]

    @property
    def endeff_twist(self) -> FloatArray:
        """(6,) endeffector twist [v (m/s); ω (rad/s)] in the world frame (= J q̇)."""
        return self._derive_velocities()[2]

    def _derive_velocities(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        # Accumulate joint contributions along the chain: ω_i = Σ_{j≤i} ω_j and, for any
        # point x moving with link i, v(x) = Σ_{j≤i} (ω_j × (x − p_j) + v_j^prismatic)
        # = ω_i × x + c_i with c_i = Σ_{j≤i} (v_j^prismatic − ω_j × p_j), p_j a point of
        # joint j's axis (origin of frame j-1 in standard DH, of frame j in modified).  A COM sits
        # at a fixed fraction between two frame origins, so its velocity is the same
        # blend of theirs (exact also while a prismatic joint stretches its link).
        if self._velocities is None:
            n, qd, revolute = self.robot.n_dofs, self._qd, self._model.revolute
            axes = self._model.axis_frames(self.frames)
            origins, z = self.frames[:, :3, 3], axes[:, :3, 2]
            qd_revolute = np.where(revolute, qd, 0.0)
            w_joint = z * qd_revolute[:, None]
            omega = np.cumsum(w_joint, axis=0)
            crosses = _cross(np.concatenate([w_joint, omega]), np.concatenate([axes[:, :3, 3], origins[1:]]))
            link_vel = np.zeros((n + 1, 6))
            link_vel[1:, :3] = crosses[n:] + np.cumsum(z * (qd - qd_revolute)[:, None] - crosses[:n], axis=0)
            link_vel[1:, 3:] = omega
            if self._model.com_local is None:
                com_vel = self._model.com_weights @ link_vel[:, :3]
            else:  # v_com = v_i + ω_i × (R_i c_i)
                com_vel = link_vel[:, :3].copy()
                com_vel[1:] += _cross(omega, self.link_com[1:] - origins[1:])
            self._velocities = (link_vel, com_vel, self.jacobian @ qd)
        return self._velocities


# ------------------------------------------------------------------ workspace
