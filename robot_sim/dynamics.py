"""Rigid-body dynamics of DH serial chains, for one configuration or a batch.

Every function takes a :class:`~robot_sim.model.params.RobotParams` with inertial data and joint
vectors of shape (n,) or (N, n) (batched without a per-configuration Python loop: compiled
code, or the readable recursion walking the chain joint by joint on arrays of
configurations).

Conventions
-----------
* Equation of motion: ``τ = M(q) q̈ + C(q, q̇) q̇ + g(q) + τ_f(q̇) − J(q)ᵀ f_tool``.
  τ is the joint torque [N·m] or force [N] the drives apply; M includes the reflected
  motor inertia G²·Jm on its diagonal; τ_f = G²·B·q̇ + |G|·Tc± (Tc+ when q̇ > 0, Tc− when
  q̇ < 0, none at rest) is what the drive spends on friction, i.e. the friction torque on
  the joint is −τ_f (Robotics Toolbox convention).
* Gravity: ``gravity`` (default (0, 0, −9.81) m/s²) in the world; frame 0 stands in the
  world at ``robot.base_tf``.
* ``f_tool`` (6,) or (N, 6): wrench [force (N); moment (N·m)] that the environment applies
  to the endeffector at the tool frame's origin, world frame (so a force the arm pushes
  against has the opposite sign).
* C is the factorisation with Ṁ − 2C skew-symmetric (body-wise:
  Σ m J_vᵀ J̇_v + J_ωᵀ I J̇_ω + J_ωᵀ [ω]ₓ I J_ω), linear in q̇.
* Both DH conventions: standard (joint i turns about z_{i−1}) and modified (about z_i);
  link inertials are in frame i of the robot's convention.

Algorithms: recursive Newton–Euler for inverse dynamics, gravity and bias; composite rigid
bodies for M; forward dynamics by M solve (a Cholesky factorisation, see README for the
measurement behind the choice).  Internally each link's quantities live in its own frame,
so mass, first moment and inertia are constants; vectors are triples of arrays, and terms
with structurally zero factors (twists of 0/±90°, zero offsets, a fixed base) are skipped.

Two implementations (:func:`set_backend`, or ``ROBOT_SIM_DYNAMICS=reference`` in the
environment): ``"compiled"`` (default) runs the numba kernels of
:mod:`robot_sim.dynamics_compiled`, the same algorithms as scalar code over one
configuration, a batch being N calls of it; ``"reference"`` runs the readable recursion of
this module (``_rnea_terms``, ``_crba_terms``) on arrays of configurations, or on Python
floats for one.  The tests hold the two to 1e-12; :class:`Stepper` steps N arms at once.

This module imports neither Qt nor OpenGL.
"""
from __future__ import annotations

import math
import os
from typing import Any, NamedTuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.kernels.model import (
    CA, CNEG, CPOS, HX, HZ, IXX, IXZ, MASS, REFL, SA, VISC, compiled_model, per_robot, snap as _snap,
)
from robot_sim.kinematics import cos_sin_half, forward_kinematics
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams

FloatArray = NDArray[np.float64]
Scalar = Union[float, FloatArray]  # a Python float (constant, possibly exactly 0) or an array
Vec = tuple  # three Scalars

GRAVITY = (0.0, 0.0, -9.81)
#: Configurations per chunk of the batched kernels (work arrays stay in cache).
CHUNK = 2048
#: The implementations: "compiled" (numba kernels of dynamics_compiled, the default) and
#: "reference" (the readable recursion of this module).  The environment variable
#: ``ROBOT_SIM_DYNAMICS`` picks one at import, :func:`set_backend` at run time.
BACKENDS = ("compiled", "reference")
BACKEND_ENV = "ROBOT_SIM_DYNAMICS"


def _checked_backend(name: object, where: str) -> str:
    if name not in BACKENDS:
        raise ValueError(f"{where} must be one of {', '.join(BACKENDS)}, got {name!r}")
    return str(name)


_backend = _checked_backend(os.environ.get(BACKEND_ENV, "compiled"), f"environment variable {BACKEND_ENV}")


def set_backend(name: str) -> None:
    """Run the dynamics through ``name``: ``"compiled"`` (numba kernels compiled once per
    machine and cached) or ``"reference"`` (the readable recursion, for debugging and as
    the tests' reference).  Results agree to round-off (about 1e-12 relative)."""
    global _backend
    _backend = _checked_backend(name, "backend")


def backend() -> str:
    """The implementation in use, one of :data:`BACKENDS`."""
    return _backend


# ------------------------------------------------------------------ scalar algebra
# Operands are Python floats (constants; 0.0 means "structurally zero") or arrays.


def _zero(x: Scalar) -> bool:
    return isinstance(x, float) and x == 0.0


def _add(a: Scalar, b: Scalar) -> Scalar:
    if _zero(a):
        return b
    if _zero(b):
        return a
    return a + b


def _sub(a: Scalar, b: Scalar) -> Scalar:
    if _zero(b):
        return a
    if _zero(a):
        return -b
    return a - b


def _mul(a: Scalar, b: Scalar) -> Scalar:
    if _zero(a) or _zero(b):
        return 0.0
    if isinstance(a, float) and a in (1.0, -1.0):
        return b if a == 1.0 else -b
    if isinstance(b, float) and b in (1.0, -1.0):
        return a if b == 1.0 else -a
    return a * b


def _sum(*terms: Scalar) -> Scalar:
    out: Scalar = 0.0
    for t in terms:
        out = _add(out, t)
    return out


def _vadd(a: Vec, b: Vec) -> Vec:
    return (_add(a[0], b[0]), _add(a[1], b[1]), _add(a[2], b[2]))


def _vsub(a: Vec, b: Vec) -> Vec:
    return (_sub(a[0], b[0]), _sub(a[1], b[1]), _sub(a[2], b[2]))


def _scale(s: Scalar, v: Vec) -> Vec:
    return (_mul(s, v[0]), _mul(s, v[1]), _mul(s, v[2]))


def _dot(a: Vec, b: Vec) -> Scalar:
    return _sum(_mul(a[0], b[0]), _mul(a[1], b[1]), _mul(a[2], b[2]))


def _cross(a: Vec, b: Vec) -> Vec:
    return (
        _sub(_mul(a[1], b[2]), _mul(a[2], b[1])),
        _sub(_mul(a[2], b[0]), _mul(a[0], b[2])),
        _sub(_mul(a[0], b[1]), _mul(a[1], b[0])),
    )


def _matvec(m: tuple, v: Vec) -> Vec:
    return tuple(_sum(_mul(m[r][0], v[0]), _mul(m[r][1], v[1]), _mul(m[r][2], v[2])) for r in range(3))


def _sym_matvec(s: tuple, v: Vec) -> Vec:
    """Symmetric matrix (xx, yy, zz, xy, yz, xz) times v."""
    xx, yy, zz, xy, yz, xz = s
    return (
        _sum(_mul(xx, v[0]), _mul(xy, v[1]), _mul(xz, v[2])),
        _sum(_mul(xy, v[0]), _mul(yy, v[1]), _mul(yz, v[2])),
        _sum(_mul(xz, v[0]), _mul(yz, v[1]), _mul(zz, v[2])),
    )


def _rot_z(v: Vec, c: Scalar, s: Scalar) -> Vec:
    """Rz(θ) v."""
    return (_sub(_mul(c, v[0]), _mul(s, v[1])), _add(_mul(s, v[0]), _mul(c, v[1])), v[2])


def _rot_z_t(v: Vec, c: Scalar, s: Scalar) -> Vec:
    """Rz(θ)ᵀ v."""
    return (_add(_mul(c, v[0]), _mul(s, v[1])), _sub(_mul(c, v[1]), _mul(s, v[0])), v[2])


def _rot_x(v: Vec, c: float, s: float) -> Vec:
    """Rx(α) v."""
    return (v[0], _sub(_mul(c, v[1]), _mul(s, v[2])), _add(_mul(s, v[1]), _mul(c, v[2])))


def _rot_x_t(v: Vec, c: float, s: float) -> Vec:
    """Rx(α)ᵀ v."""
    return (v[0], _add(_mul(c, v[1]), _mul(s, v[2])), _sub(_mul(c, v[2]), _mul(s, v[1])))


def _rot_sym_z(m: tuple, c: Scalar, s: Scalar) -> tuple:
    """Rz(θ) S Rz(θ)ᵀ of a symmetric S = (xx, yy, zz, xy, yz, xz)."""
    xx, yy, zz, xy, yz, xz = m
    c2, s2 = _sub(_mul(c, c), _mul(s, s)), _mul(2.0, _mul(c, s))
    mean, half = _mul(0.5, _add(xx, yy)), _mul(0.5, _sub(xx, yy))
    t = _sub(_mul(half, c2), _mul(xy, s2))
    return (
        _add(mean, t),
        _sub(mean, t),
        zz,
        _add(_mul(half, s2), _mul(xy, c2)),
        _add(_mul(s, xz), _mul(c, yz)),
        _sub(_mul(c, xz), _mul(s, yz)),
    )


def _rot_sym_x(m: tuple, c: float, s: float) -> tuple:
    """Rx(α) S Rx(α)ᵀ of a symmetric S = (xx, yy, zz, xy, yz, xz)."""
    xx, yy, zz, xy, yz, xz = m
    c2, s2 = c * c - s * s, 2.0 * c * s
    mean, half = _mul(0.5, _add(yy, zz)), _mul(0.5, _sub(yy, zz))
    t = _sub(_mul(half, c2), _mul(yz, s2))
    return (
        xx,
        _add(mean, t),
        _sub(mean, t),
        _sub(_mul(c, xy), _mul(s, xz)),
        _add(_mul(half, s2), _mul(yz, c2)),
        _add(_mul(s, xy), _mul(c, xz)),
    )


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

    def compiled(self):  # -> (module robot_sim.dynamics_compiled, model table)
        """The compiled kernels (numba is imported on first use) and the robot's compiled
        model table (:mod:`robot_sim.kernels.model`)."""
        return _import_compiled(), self.table

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


_compiled_kernels = None  # the module robot_sim.dynamics_compiled once imported


def _import_compiled():
    """Import the compiled kernels (and numba, about half a second) on first use only: a
    program that never runs dynamics never pays for it."""
    global _compiled_kernels
    if _compiled_kernels is None:
        from robot_sim import dynamics_compiled

        _compiled_kernels = dynamics_compiled
    return _compiled_kernels


def _model(robot: RobotParams) -> _DynModel:
    if robot.inertials is None:
        raise ValueError(
            f"{robot.name}: joints[0] has no [joints.inertial] (the robot has no inertial data); "
            "add [joints.inertial] tables to its file, or use inertials.estimate_inertials(robot)"
        )
    return per_robot(robot, "dynamics", _DynModel)


# ------------------------------------------------------------------ kernels


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
            if rev:
                wd = (_add(wd[0], _mul(w[1], qdj)), _sub(wd[1], _mul(w[0], qdj)), _add(wd[2], qddj))
                w = (w[0], w[1], _add(w[2], qdj))
            else:
                two_qd = _mul(2.0, qdj)
                vd = (_add(vd[0], _mul(w[1], two_qd)), _sub(vd[1], _mul(w[0], two_qd)), _add(vd[2], qddj))
            W = _w_matrix(w, wd)
        else:
            if rev:
                wd = (_add(wd[0], _mul(w[1], qdj)), _sub(wd[1], _mul(w[0], qdj)), _add(wd[2], qddj))
                w = (w[0], w[1], _add(w[2], qdj))
            else:
                two_qd = _mul(2.0, qdj)
                vd = (_add(vd[0], _mul(w[1], two_qd)), _sub(vd[1], _mul(w[0], two_qd)), _add(vd[2], qddj))
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


def _solve_spd(A: FloatArray, b: FloatArray) -> FloatArray:
    """x (n, M) with A x = b for symmetric positive definite A (n, n, M): Cholesky
    factorisation and two triangular solves, looping over joints only."""
    n = A.shape[0]
    L = [[None] * n for _ in range(n)]
    for j in range(n):
        diag = A[j, j].copy()
        for k in range(j):
            diag -= L[j][k] * L[j][k]
        L[j][j] = np.sqrt(diag)
        inv = 1.0 / L[j][j]
        for i in range(j + 1, n):
            acc = A[i, j].copy()
            for k in range(j):
                acc -= L[i][k] * L[j][k]
            acc *= inv
            L[i][j] = acc
    y = [None] * n
    for i in range(n):
        acc = b[i].copy()
        for k in range(i):
            acc -= L[i][k] * y[k]
        y[i] = acc / L[i][i]
    x = np.empty_like(b)
    for i in range(n - 1, -1, -1):
        acc = y[i].copy()
        for k in range(i + 1, n):
            acc -= L[k][i] * x[k]
        x[i] = acc / L[i][i]
    return x


# ------------------------------------------------------------------ arguments


def _joint_array(
    robot: RobotParams, value: ArrayLike, name: str, like: FloatArray | None = None, finite: bool = True
) -> FloatArray:
    n = robot.n_dofs
    if type(value) is np.ndarray and value.dtype == np.float64:
        arr = value  # the common case, without the cost of a conversion
    else:
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be an array of shape ({n},) or (N, {n}), got {type(value).__name__}") from None
    if like is None:
        if arr.ndim not in (1, 2) or arr.shape[-1] != n:
            raise ValueError(f"{name} must have shape ({n},) or (N, {n}), got shape {arr.shape}")
    elif arr.shape != like.shape:
        raise ValueError(f"{name} must have the shape of q, {like.shape}, got shape {arr.shape}")
    if finite and not np.isfinite(arr).all():
        raise ValueError(f"{name} must be finite, got NaN or inf in {name}")
    return arr


_NO_WRENCH = np.zeros((1, 6))  # the compiled kernels' placeholder for "no tool wrench"


def _check_gravity(gravity: ArrayLike) -> FloatArray:
    g = np.asarray(gravity, dtype=float)
    if g.shape != (3,) or not np.isfinite(g).all():
        raise ValueError(f"gravity must be a finite (3,) vector in m/s^2, got {gravity!r}")
    return g


def _tool_wrench_in_last_frame(robot: RobotParams, Q: FloatArray, f_tool: ArrayLike) -> FloatArray:
    """(N, 6) [force; moment about frame n's origin] in frame n from the world wrench at the tool origin."""
    f = np.asarray(f_tool, dtype=float)
    if f.shape not in ((6,), (Q.shape[0], 6)) or not np.isfinite(f).all():
        raise ValueError(
            f"f_tool must be a finite (6,) wrench [force; moment] or one per configuration ({Q.shape[0]}, 6), "
            f"got shape {f.shape}"
        )
    f = np.broadcast_to(f, (Q.shape[0], 6))
    frames = forward_kinematics(robot, Q, all_frames=True)
    n = robot.n_dofs
    R, origin, tool = frames[:, n, :3, :3], frames[:, n, :3, 3], frames[:, n + 1, :3, 3]
    moment = f[:, 3:] + np.cross(tool - origin, f[:, :3])
    out = np.empty((Q.shape[0], 6))
    out[:, :3] = np.einsum("nji,nj->ni", R, f[:, :3])
    out[:, 3:] = np.einsum("nji,nj->ni", R, moment)
    return out


def _drive_torque(model: _DynModel, QDT: FloatArray | None, QDDT: FloatArray | None) -> FloatArray | None:
    """G²·Jm·q̈ + G²·B·q̇ + |G|·Tc± (by the sign of q̇, 0 at rest), (n, N); None if nothing."""
    out = None
    if QDDT is not None and np.any(model.reflected):
        out = QDDT * model.reflected[:, None]
    if QDT is not None and model.has_friction:
        coulomb = np.where(QDT > 0.0, model.coulomb_pos[:, None], np.where(QDT < 0.0, model.coulomb_neg[:, None], 0.0))
        friction = QDT * model.viscous[:, None] + coulomb
        out = friction if out is None else out + friction
    return out


def _rows(X: FloatArray | None) -> FloatArray | None:
    """(N, n) → (n, N) contiguous: each joint's values of all configurations in one row."""
    return None if X is None else np.ascontiguousarray(X.T)


def _joint_inputs(model: _DynModel, QT: FloatArray) -> tuple[list[Scalar], list[Scalar], FloatArray | list[float]]:
    """cos θ, sin θ and q per joint for a chunk (n, M): arrays, or Python floats when M = 1
    (one configuration: float arithmetic costs far less than NumPy calls on 1-arrays)."""
    if QT.shape[1] != 1:
        return (*model.cos_sin(QT), QT)
    q = QT[:, 0].tolist()
    cos, sin = list(model.ct), list(model.st)
    for j in model.rev_index:
        cos[j], sin[j] = math.cos(model.th[j] + q[j]), math.sin(model.th[j] + q[j])
    return cos, sin, q


def _rate_inputs(X: FloatArray | None) -> list[float] | None:
    """Rates of one configuration (n, 1) as Python floats."""
    return None if X is None else X[:, 0].tolist()


def _rnea(
    robot: RobotParams,
    Q: FloatArray,
    QD: FloatArray | None,
    QDD: FloatArray | None,
    gravity: ArrayLike,
    f_tool: ArrayLike | None,
) -> FloatArray:
    """τ (n, N) by RNEA, drive terms included, for Q etc. of shape (N, n) (None: zero)."""
    model = _model(robot)
    if _backend == "compiled":
        kernels, table = model.compiled()
        zero = None if QD is not None and QDD is not None else np.zeros(Q.shape)
        ext = _NO_WRENCH if f_tool is None else _tool_wrench_in_last_frame(robot, Q, f_tool)
        tau = np.empty(Q.shape)
        finite = kernels.rnea_batch(
            table, Q, zero if QD is None else QD, zero if QDD is None else QDD,
            model.gravity_array(robot, gravity), ext, f_tool is not None, tau,
        )
        if not finite:
            _arguments(robot, Q, qd=Q if QD is None else QD, qdd=Q if QDD is None else QDD)  # raises
        return tau.T
    g0 = model.gravity_in_frame0(robot, gravity)
    wrench = None if f_tool is None else _rows(_tool_wrench_in_last_frame(robot, Q, f_tool))
    QT, QDT, QDDT = _rows(Q), _rows(QD), _rows(QDD)
    if QT.shape[1] == 1:  # one configuration: Python floats throughout
        cos, sin, q = _joint_inputs(model, QT)
        ext = None if wrench is None else _rate_inputs(wrench)
        ext = None if ext is None else (tuple(ext[:3]), tuple(ext[3:]))
        tau = np.array(_rnea_terms(model, cos, sin, q, _rate_inputs(QDT), _rate_inputs(QDDT), g0, ext), dtype=float)[:, None]
    else:
        tau = np.empty(QT.shape)
        for s in range(0, QT.shape[1], CHUNK):
            sl = slice(s, s + CHUNK)
            cos, sin, q = _joint_inputs(model, QT[:, sl])
            rates = [None if X is None else X[:, sl] for X in (QDT, QDDT)]
            ext = None if wrench is None else (tuple(wrench[:3, sl]), tuple(wrench[3:, sl]))
            for j, value in enumerate(_rnea_terms(model, cos, sin, q, rates[0], rates[1], g0, ext)):
                tau[j, sl] = value
    drive = _drive_torque(model, QDT, QDDT)
    if drive is not None:
        tau += drive
    return tau


def _crba(model: _DynModel, QT: FloatArray) -> FloatArray:
    """Mass matrices (n, n, M) of a chunk (n, M)."""
    n = model.n
    cos, sin, q = _joint_inputs(model, QT)
    values = _crba_terms(model, cos, sin, q)
    if QT.shape[1] == 1:
        return np.array(values, dtype=float).reshape(n, n, 1)
    out = np.empty((n, n, QT.shape[1]))
    for k, value in enumerate(values):
        out[k // n, k % n] = value
    return out


def _arguments(robot: RobotParams, q: ArrayLike, finite: bool = True, **rates: ArrayLike) -> tuple[bool, list[FloatArray]]:
    """Checked joint arrays as (N, n): q first, then ``rates`` (each the shape of q), and
    whether q was a single configuration.  ``finite=False`` leaves the test for NaN/inf
    to the caller (the compiled kernels test their inputs at no cost and report it: then
    the arguments are checked again with the test, which raises naming the culprit)."""
    q_arr = _joint_array(robot, q, "q", finite=finite)
    arrays = [q_arr] + [_joint_array(robot, value, name, q_arr, finite) for name, value in rates.items()]
    if q_arr.ndim == 1:
        return True, [a.reshape(1, -1) for a in arrays]
    return False, [np.ascontiguousarray(a) for a in arrays]


# ------------------------------------------------------------------ public API


def inverse_dynamics(
    robot: RobotParams,
    q: ArrayLike,
    qd: ArrayLike,
    qdd: ArrayLike,
    gravity: ArrayLike = GRAVITY,
    f_tool: ArrayLike | None = None,
) -> FloatArray:
    """Joint torques/forces τ [N·m or N] that produce accelerations ``qdd`` at ``q``, ``qd``
    (recursive Newton–Euler), including reflected motor inertia and friction when the
    robot has drives: τ = M q̈ + C q̇ + g + τ_f − Jᵀ f_tool.

    q, qd, qdd: (n,) or (N, n) [rad, m; per s; per s²]; result of the same shape.
    ``gravity`` [m/s²] in the world; ``f_tool`` (6,) or (N, 6) wrench [N; N·m] applied by
    the environment at the tool frame origin, world frame.  ValueError for wrong shapes,
    NaN/inf, or a robot without inertial data.
    """
    if f_tool is None and _backend == "compiled":  # one configuration of float64 vectors: fast
        model = _model(robot)
        kernels, table = model.compiled()
        tau = np.empty(model.n)
        try:
            if kernels.rnea_vec(table, q, qd, qdd, model.gravity_array(robot, gravity), tau):
                return tau
        except TypeError:  # not C-contiguous float64 vectors: the checked way below
            pass
    single, (Q, QD, QDD) = _arguments(robot, q, _backend != "compiled", qd=qd, qdd=qdd)
    tau = _rnea(robot, Q, QD, QDD, gravity, f_tool).T
    return tau[0] if single else tau


def computed_torque(
    robot: RobotParams,
    q: ArrayLike,
    qd: ArrayLike,
    q_des: ArrayLike,
    qd_des: ArrayLike,
    qdd_des: ArrayLike,
    kp: float | ArrayLike,
    kd: float | ArrayLike,
    gravity: ArrayLike = GRAVITY,
) -> tuple[FloatArray, FloatArray]:
    """(τ, q̈_ref): the inverse dynamics τ = ID(q, q̇, q̈_ref) [N·m or N] at the reference
    acceleration q̈_ref = q̈_des + kp (q_des − q) + kd (q̇_des − q̇) [rad/s² or m/s²], in one
    call (computed torque's law).  Joint arrays (n,) or (N, n); ``kp`` [1/s²] and ``kd``
    [1/s] numbers, or (N, 1) one per configuration.  ValueError as inverse_dynamics."""
    if _backend == "compiled" and isinstance(kp, float) and isinstance(kd, float):  # one configuration: fast
        model = _model(robot)
        kernels, table = model.compiled()
        tau, qdd_ref = np.empty(model.n), np.empty(model.n)
        try:
            if kernels.ct_vec(table, q, qd, q_des, qd_des, qdd_des, kp, kd, model.gravity_array(robot, gravity), tau, qdd_ref):
                return tau, qdd_ref
        except TypeError:  # not C-contiguous float64 vectors: the checked way below
            pass
    single, (Q, QD, QDES, QDDES, QDDDES) = _arguments(robot, q, qd=qd, q_des=q_des, qd_des=qd_des, qdd_des=qdd_des)
    gains = [np.broadcast_to(np.asarray(g, dtype=float), (Q.shape[0], 1)) for g in (kp, kd)]
    for name, g in zip(("kp", "kd"), gains):
        if not np.isfinite(g).all():
            raise ValueError(f"{name} must be finite, got {g!r}")
    if _backend == "compiled":
        model = _model(robot)
        kernels, table = model.compiled()
        tau, qdd_ref = np.empty(Q.shape), np.empty(Q.shape)
        KP, KD = (np.ascontiguousarray(g[:, 0]) for g in gains)
        kernels.ct_batch(table, Q, QD, QDES, QDDES, QDDDES, KP, KD, model.gravity_array(robot, gravity), tau, qdd_ref)
    else:
        qdd_ref = QDDDES + gains[0] * (QDES - Q) + gains[1] * (QDDES - QD)
        tau = _rnea(robot, Q, QD, qdd_ref, gravity, None).T
    return (tau[0], qdd_ref[0]) if single else (tau, qdd_ref)


def gravity_torque(robot: RobotParams, q: ArrayLike, gravity: ArrayLike = GRAVITY) -> FloatArray:
    """g(q): joint torques [N·m or N] that hold the arm still against gravity, (n,) or (N, n)."""
    if _backend == "compiled":  # one configuration of a float64 vector: fast
        model = _model(robot)
        kernels, table = model.compiled()
        tau = np.empty(model.n)
        try:
            if kernels.rnea_vec(table, q, model.zero, model.zero, model.gravity_array(robot, gravity), tau):
                return tau
        except TypeError:  # not a C-contiguous float64 vector: the checked way below
            pass
    single, (Q,) = _arguments(robot, q, _backend != "compiled")
    tau = _rnea(robot, Q, None, None, gravity, None).T
    return tau[0] if single else tau


def bias_torque(
    robot: RobotParams, q: ArrayLike, qd: ArrayLike, gravity: ArrayLike = GRAVITY, f_tool: ArrayLike | None = None
) -> FloatArray:
    """C(q, q̇) q̇ + g(q) + τ_f(q̇) (− Jᵀ f_tool when given): inverse dynamics at q̈ = 0."""
    single, (Q, QD) = _arguments(robot, q, _backend != "compiled", qd=qd)
    tau = _rnea(robot, Q, QD, None, gravity, f_tool).T
    return tau[0] if single else tau


def compiled_kernels(robot: RobotParams, gravity: ArrayLike = GRAVITY) -> tuple[Any, FloatArray, FloatArray]:
    """(the compiled kernels module, ``robot``'s parameter table, gravity in frame 0 (3,)):
    for other compiled code built on these kernels (the operational-space step passes
    ``crba_batch`` and ``rnea_batch`` into its own kernel).  Imports numba."""
    model = _model(robot)
    kernels, table = model.compiled()
    return kernels, table, model.gravity_array(robot, gravity)


def friction_torque(robot: RobotParams, qd: ArrayLike) -> FloatArray:
    """τ_f(q̇) = G²·B·q̇ + |G|·Tc± [N·m or N], (n,) or (N, n): what the drives spend on
    friction at joint rates ``qd`` (Tc+ when q̇ > 0, Tc− when q̇ < 0, none at rest); zero
    without drives.  Included in :func:`inverse_dynamics` and :func:`bias_torque`."""
    qd_arr = _joint_array(robot, qd, "qd")
    single, QD = qd_arr.ndim == 1, np.atleast_2d(qd_arr)
    friction = _drive_torque(_model(robot), _rows(QD), None)
    tau = np.zeros(QD.shape) if friction is None else friction.T
    return tau[0] if single else tau


def mass_matrix(robot: RobotParams, q: ArrayLike) -> FloatArray:
    """Joint-space inertia matrix M(q) (n, n) or (N, n, n) [kg·m², kg], symmetric positive
    definite, reflected motor inertia G²·Jm on the diagonal (composite rigid bodies)."""
    single, (Q,) = _arguments(robot, q, _backend != "compiled")
    model = _model(robot)
    if _backend == "compiled":
        kernels, table = model.compiled()
        M = np.empty((Q.shape[0], model.n, model.n))
        if not kernels.crba_batch(table, Q, M):
            _arguments(robot, q)  # raises
        return M[0] if single else M
    QT = _rows(Q)
    out = np.empty((robot.n_dofs, robot.n_dofs, QT.shape[1]))
    for s in range(0, QT.shape[1], CHUNK):
        out[:, :, s : s + CHUNK] = _crba(model, QT[:, s : s + CHUNK])
    out = out.transpose(2, 0, 1)
    return out[0].copy() if single else out


def forward_dynamics(
    robot: RobotParams,
    q: ArrayLike,
    qd: ArrayLike,
    tau: ArrayLike,
    gravity: ArrayLike = GRAVITY,
    f_tool: ArrayLike | None = None,
) -> FloatArray:
    """Joint accelerations q̈ = M⁻¹ (τ − C q̇ − g − τ_f + Jᵀ f_tool), (n,) or (N, n), by a
    batched Cholesky solve of the composite-rigid-body M (see the README for why)."""
    if f_tool is None and _backend == "compiled":  # as in inverse_dynamics
        model = _model(robot)
        kernels, table = model.compiled()
        qdd = np.empty(model.n)
        try:
            if kernels.fd_vec(table, q, qd, tau, model.gravity_array(robot, gravity), qdd):
                return qdd
        except TypeError:
            pass
    single, (Q, QD, TAU) = _arguments(robot, q, _backend != "compiled", qd=qd, tau=tau)
    model = _model(robot)
    if _backend == "compiled":
        kernels, table = model.compiled()
        ext = _NO_WRENCH if f_tool is None else _tool_wrench_in_last_frame(robot, Q, f_tool)
        qdd = np.empty(Q.shape)
        g0 = model.gravity_array(robot, gravity)
        if not kernels.fd_batch(table, Q, QD, TAU, g0, ext, f_tool is not None, qdd):
            _arguments(robot, q, qd=qd, tau=tau)  # raises
        return qdd[0] if single else qdd
    rhs = _rows(TAU) - _rnea(robot, Q, QD, None, gravity, f_tool)
    QT = _rows(Q)
    if single:
        return np.linalg.solve(_crba(model, QT)[:, :, 0], rhs[:, 0])
    out = np.empty(QT.shape)
    for s in range(0, QT.shape[1], CHUNK):
        sl = slice(s, s + CHUNK)
        out[:, sl] = _solve_spd(_crba(model, QT[:, sl]), rhs[:, sl])
    return out.T


def constrained_forward_dynamics(
    robot: RobotParams,
    q: ArrayLike,
    qd: ArrayLike,
    tau: ArrayLike,
    held: ArrayLike,
    gravity: ArrayLike = GRAVITY,
    f_tool: ArrayLike | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Forward dynamics with the ``held`` joints locked (by joint stops): (q̈, λ), each
    (n,) or (N, n).  ``held`` is bool, (n,) for every configuration or the shape of q.

    M q̈ = τ − C q̇ − g − τ_f + Jᵀ f_tool + λ with q̈ exactly zero on the held joints and λ
    zero on the others: the free joints solve their rows and columns of M (the held rows
    and columns replaced by the identity's), and λ [N·m or N] is the torque the
    constraint exerts on each held joint (its reaction).  The held joints' velocities
    should be zero (a held joint does not move)."""
    single, (Q, QD, TAU) = _arguments(robot, q, qd=qd, tau=tau)
    n = robot.n_dofs
    mask = np.asarray(held)
    if mask.dtype != np.bool_ or mask.shape not in ((n,), np.shape(q)):
        raise ValueError(
            f"held must be a bool array of shape ({n},) or of the shape of q, {np.shape(q)}, "
            f"got {mask.dtype} of shape {mask.shape}"
        )
    if single:  # plain (n, n) algebra: a batch of one costs far more in NumPy's stacked calls
        M1 = mass_matrix(robot, Q[0])
        rhs1 = TAU[0] - bias_torque(robot, Q[0], QD[0], gravity, f_tool)
        A1 = M1.copy()
        A1[mask] = 0.0
        A1[:, mask] = 0.0
        A1[mask, mask] = 1.0
        qdd1 = np.linalg.solve(A1, np.where(mask, 0.0, rhs1))
        qdd1[mask] = 0.0
        return qdd1, (M1 @ qdd1 - rhs1) * mask
    H = np.broadcast_to(mask, Q.shape)
    M = mass_matrix(robot, Q)
    rhs = TAU - bias_torque(robot, Q, QD, gravity, f_tool)
    A = np.where(H[:, :, None] | H[:, None, :], 0.0, M)
    A[:, np.arange(n), np.arange(n)] += H
    qdd = np.where(H, 0.0, np.linalg.solve(A, np.where(H, 0.0, rhs)[..., None])[..., 0])
    reaction = np.where(H, np.einsum("nij,nj->ni", M, qdd) - rhs, 0.0)
    return qdd, reaction


def _link_jacobians(robot: RobotParams, Q: FloatArray, QD: FloatArray) -> dict[str, FloatArray]:
    """World-frame per-link quantities (N configurations, k = link, j = joint): COM
    Jacobians ``Jv``, ``Jw`` (N, k, 3, j) and their time derivatives ``Jv_dot``, ``Jw_dot``
    along q̇, link angular velocities ``omega`` (N, k, 3), world inertias ``inertia``
    (N, k, 3, 3) about the COMs, and ``com`` (N, k, 3)."""
    model = _model(robot)
    li = robot.inertials
    n = robot.n_dofs
    frames = forward_kinematics(robot, Q, all_frames=True)[:, : n + 1]
    axis_frames = frames[:, 1:] if model.modified else frames[:, :-1]
    a, p = axis_frames[..., :3, 2], axis_frames[..., :3, 3]  # (N, j, 3)
    rev = np.asarray(model.revolute)
    R = frames[:, 1:, :3, :3]
    com = frames[:, 1:, :3, 3] + np.einsum("nkab,kb->nka", R, li.com)
    w_joint = a * (QD * rev)[..., None]
    omega = np.cumsum(w_joint, axis=1)
    omega_before = np.concatenate([np.zeros_like(omega[:, :1]), omega[:, :-1]], axis=1)
    a_dot = np.cross(omega_before, a)
    slide = a * (QD * ~rev)[..., None]

    def velocity(x: FloatArray, mask: FloatArray) -> FloatArray:
        """Velocity of points x (N, k, 3), point k moved by the joints j with mask[k, j]."""
        contrib = np.cross(w_joint[:, None], x[:, :, None] - p[:, None]) + slide[:, None]
        return np.einsum("kj,nkja->nka", mask, contrib)

    lower = np.tril(np.ones((n, n)))
    com_vel = velocity(com, lower)
    p_vel = velocity(p, np.tril(np.ones((n, n)), -1))  # axis point as a point of the link before
    lever = com[:, :, None] - p[:, None]  # (N, k, j, 3)
    Jv = np.where(rev[None, None, :, None], np.cross(a[:, None], lever), a[:, None])
    Jv_dot = np.where(
        rev[None, None, :, None],
        np.cross(a_dot[:, None], lever) + np.cross(a[:, None], com_vel[:, :, None] - p_vel[:, None]),
        a_dot[:, None],
    )
    mask = (lower[None, :, :, None] * rev[None, None, :, None])
    Jw = a[:, None] * mask
    Jw_dot = a_dot[:, None] * mask
    Jv, Jv_dot = Jv * lower[None, :, :, None], Jv_dot * lower[None, :, :, None]
    inertia = np.einsum("nkab,kbc,nkdc->nkad", R, li.inertia, R)
    return {
        "Jv": Jv.transpose(0, 1, 3, 2), "Jw": Jw.transpose(0, 1, 3, 2),
        "Jv_dot": Jv_dot.transpose(0, 1, 3, 2), "Jw_dot": Jw_dot.transpose(0, 1, 3, 2),
        "omega": omega, "inertia": inertia, "com": com,
    }


def coriolis_matrix(robot: RobotParams, q: ArrayLike, qd: ArrayLike) -> FloatArray:
    """C(q, q̇) (n, n) or (N, n, n) with C q̇ the Coriolis and centrifugal torques and
    Ṁ − 2C skew-symmetric: Σ_k m_k J_vᵀ J̇_v + J_ωᵀ I_k J̇_ω + J_ωᵀ [ω_k]ₓ I_k J_ω over the
    links (COM Jacobians and inertias in the world frame).  Motor inertia adds nothing."""
    single, (Q, QD) = _arguments(robot, q, qd=qd)
    _model(robot)  # refuses a robot without inertial data
    mass = np.asarray(robot.inertials.mass)
    parts = _link_jacobians(robot, Q, QD)
    Jv, Jw, Jv_dot, Jw_dot = parts["Jv"], parts["Jw"], parts["Jv_dot"], parts["Jw_dot"]
    inertia, omega = parts["inertia"], parts["omega"]
    spin = np.cross(omega[:, :, :, None], inertia, axis=2)  # [ω]ₓ I, column by column
    C = np.einsum("k,nkai,nkaj->nij", mass, Jv, Jv_dot)
    C += np.einsum("nkai,nkab,nkbj->nij", Jw, inertia, Jw_dot)
    C += np.einsum("nkai,nkab,nkbj->nij", Jw, spin, Jw)
    return C[0] if single else C


def energy(
    robot: RobotParams, q: ArrayLike, qd: ArrayLike, gravity: ArrayLike = GRAVITY
) -> tuple[FloatArray | float, FloatArray | float]:
    """(kinetic, potential) energy [J]: ½ q̇ᵀ M q̇ (motor inertia included) and
    −Σ m_k g·c_k with the COMs c_k in the world (zero at the world origin's height)."""
    single, (Q, QD) = _arguments(robot, q, qd=qd)
    g = _check_gravity(gravity)
    M = mass_matrix(robot, Q)
    kinetic = 0.5 * np.einsum("ni,nij,nj->n", QD, M, QD)
    n = robot.n_dofs
    frames = forward_kinematics(robot, Q, all_frames=True)[:, 1 : n + 1]
    com = frames[..., :3, 3] + np.einsum("nkab,kb->nka", frames[..., :3, :3], robot.inertials.com)
    potential = -np.einsum("k,nka,a->n", np.asarray(robot.inertials.mass), com, g)
    if single:
        return float(kinetic[0]), float(potential[0])
    return kinetic, potential


# ------------------------------------------------------------------ one time step

#: Status per arm of :meth:`Stepper.step` (see there).
STEP_OK, STEP_BAD_STATE, STEP_BAD_ACCEL, STEP_CROSSED, STEP_AT_STOP, STEP_BAD_EFFORT, STEP_ON_LIMIT = 0, 1, 2, 3, 4, 5, 6
INTEGRATORS = ("rk4", "euler")


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
        self._model = _model(robot)
        self._g0 = self._model.gravity_array(robot, gravity).copy()
        self._gravity = gravity
        self._result = StepResult(
            *(np.empty(self.shape) for _ in range(3)), np.zeros(self.shape[0], dtype=np.int8),
            np.zeros(self.shape), np.zeros(self.shape, dtype=bool), np.zeros(self.shape), np.zeros(self.shape),
        )
        self._kp, self._kd = np.zeros(self.shape[0]), np.zeros(self.shape[0])
        self._all = np.ones(self.shape[0], dtype=bool)
        self._none = np.zeros(self.shape[0], dtype=bool)
        self._no_held = np.zeros(self.shape, dtype=bool)

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
        (:data:`STEP_AT_STOP`: the caller resolves it, ``control.joint_stops``); an arm
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
        if _backend == "compiled":
            kernels, table = self._model.compiled()
            kernels.step_batch(
                table, self.method == "rk4", h, q, qd, tau, A1, known, self._g0, active,
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
        if _backend == "compiled":
            kernels, table = self._model.compiled()
            kernels.ct_step_batch(
                table, self.method == "rk4", self.dt, q, qd, q_des, qd_des, qdd_des, self._kp, self._kd,
                np.asarray(effort_limit, dtype=float), self._g0, active, stops, out.command, out.effort, out.q, out.qd, out.qdd, out.reaction, out.at_limit, out.status,
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
    if method == "euler":
        out.qd[idx] = v + h * a1
        out.q[idx] = q + h * out.qd[idx]
    else:
        v2 = v + 0.5 * h * a1
        a2 = accel(q + 0.5 * h * v, v2)
        v3 = v + 0.5 * h * a2
        a3 = accel(q + 0.5 * h * v2, v3)
        v4 = v + h * a3
        a4 = accel(q + h * v3, v4)
        out.q[idx] = q + (h / 6.0) * (v + 2.0 * (v2 + v3) + v4)
        out.qd[idx] = v + (h / 6.0) * (a1 + 2.0 * (a2 + a3) + a4)
    if stops:
        q1 = out.q[idx]
        out.at_limit[idx] = (q1 == lo) | (q1 == hi)
        crossed = ok & ((q1 < lo) | (q1 > hi)).any(axis=1)
        out.status[idx[ok & ~crossed & out.at_limit[idx].any(axis=1)]] = STEP_ON_LIMIT
        out.status[idx[crossed]] = STEP_CROSSED
