"""The reference recursion of the rigid-body dynamics, readable and batched over arrays
of configurations (or Python floats for one): recursive Newton–Euler (:func:`_rnea_terms`)
and composite rigid bodies (:func:`_crba_terms`), in each link's own frame, over the
per-robot model :class:`_DynModel` (kept with the robot's compiled model).  The compiled
kernels (``robot_sim.dynamics.compiled``) are the same algorithms; the tests hold the two
to 1e-12.  Conventions: :mod:`robot_sim.dynamics`."""
from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from robot_sim.dynamics.algebra import (
    FloatArray, Scalar, Vec, _add, _cross, _dot, _matvec, _mul, _rot_sym_x, _rot_sym_z, _rot_x, _rot_x_t, _rot_z,
    _rot_z_t, _scale, _sub, _sym_matvec, _vadd, _vsub,
)
from robot_sim.kernels.model import (
    CA, CNEG, CPOS, HX, HZ, IXX, IXZ, MASS, REFL, SA, VISC, compiled_model, per_robot, snap as _snap,
)
from robot_sim.kinematics import cos_sin_half
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams

# ------------------------------------------------------------------ per-robot model


class _DynModel:
    """Robot constants for the kernels, in each link's own frame (built once per robot)."""

    def __init__(self, robot: RobotParams) -> None:
        n = robot.n_dofs
        P = self.table = compiled_model(robot).table
        self.n = n
        self.modified = robot.is_modified
        self.revolute = [bool(t == JTYPE_REVOLUTE) for t in robot.jtype]
        self.rev_index = np.flatnonzero(np.asarray(self.revolute))
        self.th = robot.dh_th.copy()
        self.ca, self.sa = P[:, CA].tolist(), P[:, SA].tolist()
        self.ct = [_snap(math.cos(t)) for t in robot.dh_th]
        self.st = [_snap(math.sin(t)) for t in robot.dh_th]
        self.a = [float(v) for v in robot.dh_a]
        self.d = [float(v) for v in robot.dh_d]
        self.mass = P[:, MASS].tolist()
        self.h = [tuple(row) for row in P[:, HX : HZ + 1].tolist()]
        self.inertia_o = [tuple(row) for row in P[:, IXX : IXZ + 1].tolist()]  # about the frame origin
        self.reflected, self.viscous = P[:, REFL].copy(), P[:, VISC].copy()
        self.coulomb_pos, self.coulomb_neg = P[:, CPOS].copy(), P[:, CNEG].copy()
        self.has_friction = bool(np.any(self.viscous) or np.any(self.coulomb_pos) or np.any(self.coulomb_neg))
        self.zero = np.zeros(n)  # zero rates for the compiled kernels (read only by them)
        self.base_rotation = robot.base_tf.R().copy()
        self.q_min, self.q_max = robot.q_min.copy(), robot.q_max.copy()
        self._gravity: tuple = ((0.0, 0.0, -9.81), None)  # last (world gravity, in frame 0)
        self._gravity_array: tuple = (None, None)  # last frame-0 gravity tuple and it as an array

    def gravity_array(self, robot: RobotParams, gravity: ArrayLike) -> FloatArray:
        """:meth:`gravity_in_frame0` as a (3,) array (the last one kept)."""
        g_last = self._gravity[1]
        if gravity is self._gravity[0] and g_last is not None and self._gravity_array[0] is g_last:
            return self._gravity_array[1]
        g0 = self.gravity_in_frame0(robot, gravity)
        if g0 is not self._gravity_array[0]:
            self._gravity_array = (g0, np.array(g0))
        return self._gravity_array[1]

    def compiled(self):  # -> (module robot_sim.dynamics.compiled, model table)
        """The compiled kernels (numba is imported on first use) and the robot's compiled
        model table (:mod:`robot_sim.kernels.model`)."""
        kernels = _compiled_kernels
        return (_import_compiled() if kernels is None else kernels), self.table

    def gravity_in_frame0(self, robot: RobotParams, gravity: ArrayLike) -> tuple[float, float, float]:
        """World gravity [m/s²] in frame 0 (the last one is kept: it rarely changes)."""
        if not (isinstance(gravity, tuple) and gravity == self._gravity[0] and self._gravity[1] is not None):
            g0 = tuple(float(v) for v in self.base_rotation.T @ _check_gravity(gravity))
            if not isinstance(gravity, tuple):  # an array may change in place: not kept
                return g0
            self._gravity = (gravity, g0)
        return self._gravity[1]

    # -- geometry of joint j at joint values (arrays of one chunk) ----------------------
    def offset(self, j: int, qj: Scalar) -> Vec:
        """Standard DH: origin of frame j relative to frame j−1's, in frame j.
        Modified DH: the same vector in frame j−1."""
        d = self.d[j] if self.revolute[j] else _add(self.d[j], qj)
        ca, sa = self.ca[j], self.sa[j]
        if self.modified:
            return (self.a[j], _mul(-sa, d), _mul(ca, d))
        return (self.a[j], _mul(sa, d), _mul(ca, d))

    def to_child(self, v: Vec, j: int, c: Scalar, s: Scalar) -> Vec:
        """Vector in frame j−1 expressed in frame j (Rᵀ v)."""
        if self.modified:
            return _rot_z_t(_rot_x_t(v, self.ca[j], self.sa[j]), c, s)
        return _rot_x_t(_rot_z_t(v, c, s), self.ca[j], self.sa[j])

    def to_parent(self, v: Vec, j: int, c: Scalar, s: Scalar) -> Vec:
        """Vector in frame j expressed in frame j−1 (R v)."""
        if self.modified:
            return _rot_x(_rot_z(v, c, s), self.ca[j], self.sa[j])
        return _rot_z(_rot_x(v, self.ca[j], self.sa[j]), c, s)

    def wrench_to_parent(self, j: int, f: Vec, n: Vec, c: Scalar, s: Scalar, p: Vec) -> tuple[Vec, Vec]:
        """Wrench (force f, moment n about frame j's origin, frame j) as force and moment
        about frame j−1's origin in frame j−1 (``p`` = :meth:`offset`)."""
        if self.modified:
            f_par = self.to_parent(f, j, c, s)
            return f_par, _vadd(self.to_parent(n, j, c, s), _cross(p, f_par))
        return self.to_parent(f, j, c, s), self.to_parent(_vadd(n, _cross(p, f)), j, c, s)

    def subspace(self, j: int) -> tuple[Vec, Vec]:
        """Joint j's motion [v of frame j's origin; ω] per unit rate, in frame j."""
        if self.modified:
            axis = (0.0, 0.0, 1.0)
            return ((0.0, 0.0, 0.0), axis) if self.revolute[j] else (axis, (0.0, 0.0, 0.0))
        axis = (0.0, self.sa[j], self.ca[j])
        if self.revolute[j]:  # v = axis × (o_j − o_{j−1})
            return _cross(axis, (self.a[j], _mul(self.sa[j], self.d[j]), _mul(self.ca[j], self.d[j]))), axis
        return axis, (0.0, 0.0, 0.0)

    def cos_sin(self, QT: FloatArray) -> tuple[list[Scalar], list[Scalar]]:
        """cos θ_j and sin θ_j per joint: arrays for revolute joints, floats otherwise."""
        cos: list[Scalar] = list(self.ct)
        sin: list[Scalar] = list(self.st)
        if len(self.rev_index):
            c_all, s_all = cos_sin_half(QT[self.rev_index], 0.5 * self.th[self.rev_index, None])
            for k, j in enumerate(self.rev_index):
                cos[j], sin[j] = c_all[k], s_all[k]
        return cos, sin


_compiled_kernels = None  # the module robot_sim.dynamics.compiled once imported


def _import_compiled():
    """Import the compiled kernels (and numba, about half a second) on first use only: a
    program that never runs dynamics never pays for it."""
    global _compiled_kernels
    if _compiled_kernels is None:
        from robot_sim.dynamics import compiled

        _compiled_kernels = compiled
    return _compiled_kernels


def _model(robot: RobotParams) -> _DynModel:
    if robot.inertials is None:
        raise ValueError(
            f"{robot.name}: joints[0] has no [joints.inertial] (the robot has no inertial data); "
            "add [joints.inertial] tables to its file, or use inertials.estimate_inertials(robot)"
        )
    return per_robot(robot, "dynamics", _DynModel)


# ------------------------------------------------------------------ kernels


def _joint_rates(rev: bool, w: Vec, wd: Vec, vd: Vec, qdj: Scalar, qddj: Scalar) -> tuple[Vec, Vec, Vec]:
    """Add joint j's rate q̇ and acceleration q̈ about (revolute) or along (prismatic) its z
    axis to the frame's ω, ω̇ and v̇, all in the frame where that axis is z (a prismatic
    joint's Coriolis term 2 ω × q̇ z included)."""
    if rev:
        wd = (_add(wd[0], _mul(w[1], qdj)), _sub(wd[1], _mul(w[0], qdj)), _add(wd[2], qddj))
        return (w[0], w[1], _add(w[2], qdj)), wd, vd
    two_qd = _mul(2.0, qdj)
    return w, wd, (_add(vd[0], _mul(w[1], two_qd)), _sub(vd[1], _mul(w[0], two_qd)), _add(vd[2], qddj))


def _w_matrix(w: Vec, wd: Vec) -> tuple:
    """W = [ω̇]ₓ + [ω]ₓ²: the acceleration of a body-fixed point r relative to the origin is W r."""
    xx, yy, zz = _mul(w[0], w[0]), _mul(w[1], w[1]), _mul(w[2], w[2])
    xy, yz, xz = _mul(w[0], w[1]), _mul(w[1], w[2]), _mul(w[0], w[2])
    return (
        (_mul(-1.0, _add(yy, zz)), _sub(xy, wd[2]), _add(xz, wd[1])),
        (_add(xy, wd[2]), _mul(-1.0, _add(xx, zz)), _sub(yz, wd[0])),
        (_sub(xz, wd[1]), _add(yz, wd[0]), _mul(-1.0, _add(xx, yy))),
    )


def _rnea_terms(
    model: _DynModel,
    cos: list[Scalar],
    sin: list[Scalar],
    q: list[Scalar],
    qd: list[Scalar] | None,
    qdd: list[Scalar] | None,
    g0: tuple[float, float, float],
    f_ext: tuple[Vec, Vec] | None,
) -> list[Scalar]:
    """Joint torques of the rigid bodies (no drive terms), one entry per joint.  Per joint:
    cos θ, sin θ and, for prismatic joints, q; rates None when zero.  ``g0`` gravity in
    frame 0; ``f_ext`` the external wrench on the last link (force, moment about its
    origin) in its frame."""
    n = model.n
    w: Vec = (0.0, 0.0, 0.0)
    wd: Vec = (0.0, 0.0, 0.0)
    vd: Vec = (-g0[0], -g0[1], -g0[2])
    W_par = None
    offsets, forces, moments = [], [], []
    for j in range(n):
        c, s, rev = cos[j], sin[j], model.revolute[j]
        qdj: Scalar = 0.0 if qd is None else qd[j]
        qddj: Scalar = 0.0 if qdd is None else qdd[j]
        p = model.offset(j, 0.0 if rev else q[j])
        offsets.append(p)
        if model.modified:
            if W_par is not None:
                vd = _vadd(vd, _matvec(W_par, p))
            w, wd, vd = (model.to_child(v, j, c, s) for v in (w, wd, vd))
            w, wd, vd = _joint_rates(rev, w, wd, vd, qdj, qddj)
            W = _w_matrix(w, wd)
        else:
            w, wd, vd = _joint_rates(rev, w, wd, vd, qdj, qddj)
            w, wd, vd = (model.to_child(v, j, c, s) for v in (w, wd, vd))
            W = _w_matrix(w, wd)
            vd = _vadd(vd, _matvec(W, p))
        W_par = W
        h, io, m = model.h[j], model.inertia_o[j], model.mass[j]
        forces.append(_vadd(_scale(m, vd), _matvec(W, h)))
        moments.append(_vadd(_vadd(_sym_matvec(io, wd), _cross(w, _sym_matvec(io, w))), _cross(h, vd)))
    if f_ext is not None:
        forces[-1] = _vsub(forces[-1], f_ext[0])
        moments[-1] = _vsub(moments[-1], f_ext[1])
    tau: list[Scalar] = [0.0] * n
    for j in range(n - 1, -1, -1):
        f, nm, p = forces[j], moments[j], offsets[j]
        if model.modified:
            tau[j] = nm[2] if model.revolute[j] else f[2]
        else:
            axis = (0.0, model.sa[j], model.ca[j])
            tau[j] = _dot(axis, _vadd(nm, _cross(p, f))) if model.revolute[j] else _dot(axis, f)
        if j > 0:
            F, N = model.wrench_to_parent(j, f, nm, cos[j], sin[j], p)
            forces[j - 1] = _vadd(forces[j - 1], F)
            moments[j - 1] = _vadd(moments[j - 1], N)
    return tau


def _crba_terms(model: _DynModel, cos: list[Scalar], sin: list[Scalar], q: list[Scalar]) -> list[Scalar]:
    """Mass matrix of the rigid bodies plus reflected motor inertia, row-major n·n entries."""
    n = model.n
    offsets = [model.offset(j, 0.0 if model.revolute[j] else q[j]) for j in range(n)]
    out: list[Scalar] = [0.0] * (n * n)
    # composite inertia of the subtree of j about frame j's origin, in frame j: m, h, I
    cm: Scalar = 0.0
    ch: Vec = (0.0, 0.0, 0.0)
    ci: tuple = (0.0,) * 6
    for j in range(n - 1, -1, -1):
        cm = _add(cm, model.mass[j])
        ch = _vadd(ch, model.h[j])
        ci = tuple(_add(x, y) for x, y in zip(ci, model.inertia_o[j]))
        v, w = model.subspace(j)
        f = _vsub(_scale(cm, v), _cross(ch, w))
        nm = _vadd(_sym_matvec(ci, w), _cross(ch, v))
        out[j * n + j] = _add(_add(_dot(v, f), _dot(w, nm)), float(model.reflected[j]))
        for k in range(j, 0, -1):  # carry the force of joint j's unit acceleration to the base
            f, nm = model.wrench_to_parent(k, f, nm, cos[k], sin[k], offsets[k])
            vk, wk = model.subspace(k - 1)
            out[(k - 1) * n + j] = out[j * n + k - 1] = _add(_dot(vk, f), _dot(wk, nm))
        if j > 0:
            cm, ch, ci = _composite_to_parent(model, j, cm, ch, ci, cos[j], sin[j], offsets[j])
    return out


def _shift(m: Scalar, h: Vec, inertia: tuple, r: Vec) -> tuple[Vec, tuple]:
    """First moment and inertia of a body about a point moved by −r (r = old − new point)."""
    h_new = _vadd(h, _scale(m, r))
    hr = _dot(h, r)
    rr = _dot(r, r)
    diag = _add(_mul(2.0, hr), _mul(m, rr))
    # I + 2(h·r)1 − (r hᵀ + h rᵀ) + m(|r|² 1 − r rᵀ)
    pairs = ((0, 0), (1, 1), (2, 2), (0, 1), (1, 2), (0, 2))
    out = []
    for k, (a, b) in enumerate(pairs):
        cross_terms = _add(_add(_mul(r[a], h[b]), _mul(h[a], r[b])), _mul(m, _mul(r[a], r[b])))
        value = _sub(inertia[k], cross_terms)
        out.append(_add(value, diag) if a == b else value)
    return h_new, tuple(out)


def _composite_to_parent(
    model: _DynModel, j: int, m: Scalar, h: Vec, inertia: tuple, c: Scalar, s: Scalar, p: Vec
) -> tuple[Scalar, Vec, tuple]:
    """Composite (m, h, I) about frame j's origin in frame j → about frame j−1's, in frame j−1."""
    ca, sa = model.ca[j], model.sa[j]
    if model.modified:
        h = _rot_x(_rot_z(h, c, s), ca, sa)
        inertia = _rot_sym_x(_rot_sym_z(inertia, c, s), ca, sa)
        h, inertia = _shift(m, h, inertia, p)
        return m, h, inertia
    h, inertia = _shift(m, h, inertia, p)
    h = _rot_z(_rot_x(h, ca, sa), c, s)
    inertia = _rot_sym_z(_rot_sym_x(inertia, ca, sa), c, s)
    return m, h, inertia


def _check_gravity(gravity: ArrayLike) -> FloatArray:
    g = np.asarray(gravity, dtype=float)
    if g.shape != (3,) or not np.isfinite(g).all():
        raise ValueError(f"gravity must be a finite (3,) vector in m/s^2, got {gravity!r}")
    return g
