"""Penalty contact between the robot's collision shapes and the world's obstacles (and
between its own links), as joint torques for the physics loop.

Every checked pair of a :class:`~robot_sim.collision.checker.CollisionChecker` whose
shapes overlap (signed distance d < 0, depth δ = −d) pushes them apart along the normal
with a spring-damper, applied at the witness points through their Jacobians:
τ = (J_b(p_b) − J_a(p_a))ᵀ f on the second shape (−f on the first), and

* normal: f_n = max(0, k δ − c ḋ) (ḋ the separation rate); never pulls;
* friction (``friction`` μ > 0): a tangential spring-damper between two anchors, one on
  each shape, set where the pair first touched, capped at μ f_n (Coulomb).  When the
  spring would exceed the cap the shapes slip and the anchors are moved (between steps)
  so that it sits on the cap; a link at rest on a slope within the friction cone stays
  exactly in place (no creep).

Gains, per pair, fixed from the moment it comes within :data:`MIN_MARGIN` (or the step's
motion bound) of contact until it leaves again: with m the effective mass of the pair
along the normal there, 1 / (nᵀ J M⁻¹ Jᵀ n), k = m ω² and c = 2 ζ m ω with ω·dt =
:data:`OMEGA_DT` and ζ = :data:`DAMPING_RATIO` (a critically damped contact about 20
steps per period: stable for RK4 and semi-implicit Euler at the 1 ms step).  Constant
gains make the normal spring conservative (potential ½ k δ²) and the damper and the cap
only remove energy: contact never adds energy to the arm within a step.  The resting
depth under a load f is f / k; a point mass m resting on the floor sinks g / ω² (0.11 mm
at 1 ms).

Contact frames, held over a step: its start takes each contact point's normal and
witness points from the exact narrow phase; its integrator stages take the depth along
that normal from the core points under the witness points moved with their bodies
(:func:`.contact_kernels.contact_stage`): exact at the start, second order in the
step's motion after it, exact for a sphere or capsule on a face of a fixed shape.  While
the arm has moved less than :data:`.contact_kernels.HOLD` since, later steps keep the
frames (:func:`.contact_kernels.contact_begin`).

World frame, metres, newtons, seconds; joint torques in N·m or N.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim import dynamics
from robot_sim.kernels import chain
from robot_sim.model.params import JTYPE_REVOLUTE
from robot_sim.model.state import check_joint_vector

from robot_sim.collision import batch
from robot_sim.collision.checker import CollisionChecker
from robot_sim.collision.path import lever_arms
from robot_sim.sim import contact_kernels as K
from robot_sim.sim.contact_kernels import MIN_MARGIN
from robot_sim.sim.step_kernels import contact_step
from robot_sim.sim.stepper import raise_for

FloatArray = NDArray[np.float64]

#: ω·dt of every contact's normal spring at its effective mass.
OMEGA_DT = 0.3
#: Damping ratio of the normal and tangential spring-dampers (critical).
DAMPING_RATIO = 1.0
#: Coulomb coefficient unless told otherwise (dry metal or plastic on wood): an arm lying
#: on a table comes to rest (frictionless, it would keep turning about a vertical joint).
DEFAULT_FRICTION = 0.5
#: Pairs whose relative motion along the normal costs less than this [1/kg] do not move
#: each other (a base shape on the floor) and exert no force.
IMMOBILE = 1e-12


@dataclass(frozen=True)
class ContactForce:
    """One touching pair: names (link first), ``point`` (3,) the first shape's witness
    point [m], ``normal`` (3,) the unit direction from the first shape toward the second,
    ``depth`` [m] > 0 and ``force`` (3,) [N] on the first shape (its opposite acts on
    the second)."""

    pair: tuple[str, str]
    point: FloatArray
    normal: FloatArray
    depth: float
    force: FloatArray


class ContactModel:
    """Penalty contact of ``checker``'s robot among its checked pairs (module docstring):
    ``friction`` μ >= 0 is the Coulomb coefficient (0: frictionless; default
    :data:`DEFAULT_FRICTION`).

    Stepping: :meth:`begin_step` at the start of every step (it picks the active pairs,
    sets their gains, fixes their contact frames and moves the friction anchors of
    slipping ones), then :meth:`step`
    (the whole step in one compiled call) or :meth:`torque` at every stage state of the
    integrator, with the same gains and anchors throughout the step.
    """

    def __init__(self, checker: CollisionChecker, *, friction: float = DEFAULT_FRICTION) -> None:
        if not isinstance(checker, CollisionChecker):
            raise ValueError(f"ContactModel: checker must be a CollisionChecker, got {type(checker).__name__}")
        if isinstance(friction, bool) or not isinstance(friction, (int, float)) or not 0.0 <= friction < math.inf:
            raise ValueError(f"ContactModel: friction must be a finite coefficient >= 0, got {friction!r}")
        self.checker = checker
        self.friction = float(friction)
        robot, scene = checker.robot, checker.scene
        self.robot = robot
        n = robot.n_dofs
        self._body = np.concatenate([scene.link, np.full(len(scene.owner) - scene.n_robot, -1)]).astype(np.int64)
        self._axis_frame = np.arange(n, dtype=np.int64) + (1 if robot.is_modified else 0)
        self._revolute = robot.jtype == JTYPE_REVOLUTE
        home = robot.q_home[None]
        self._arms = lever_arms(checker, home, home)[0] if self._revolute.all() else None  # else they vary with q
        self._scene = (scene.world0, scene.link, scene.local, scene.recs0, scene.kinds, scene.bc, scene.br, scene.verts,
                       self._body, self._axis_frame, self._revolute, checker.pairs,
                       self._arms if self._arms is not None else np.zeros(n))
        self._pairs = checker.pairs
        self._active = np.zeros(0, dtype=np.int64)  # rows of checker.pairs
        self._rows = np.zeros((0, 2), dtype=np.int64)  # their scene rows
        self._gains = np.zeros((0, 4))
        self._anchors = np.zeros((0, K.POINTS, 2, 3))
        self._anchored = np.zeros((0, K.POINTS), dtype=np.bool_)
        self._out = np.zeros((0, K.POINTS, K.OUT))
        # where the contact frames were last fixed, the reach of the capsule ends then left out,
        # and whether frames may be held (lever arms fixed): contact_kernels.contact_begin
        self._fixed = np.full(n + 2, -np.inf)
        self._fixed[n + 1] = 1.0 if self._arms is not None else 0.0
        self._F = np.empty((n + 1, 3, 4))
        self._near = np.zeros(1, dtype=np.bool_)  # buffers of the compiled near check
        self._stats = np.zeros(2, dtype=np.int64)
        self._work = K.contact_work(scene.dh, self.compiled(all_q=False))

    # ------------------------------------------------------------------ stepping
    @property
    def active(self) -> bool:
        """Whether some pair is active in the current step (else the contact torque is zero)."""
        return self._active.size > 0

    def compiled(self, all_q: bool = True) -> tuple | None:
        """The contact tuple of the compiled kernels (:mod:`.contact_kernels`): the scene,
        the lever arms and this step's active pairs, gains and anchors (its arrays are this
        model's: a kernel that moves the anchors moves them here).  With ``all_q``, None
        when the lever arms vary with q (a prismatic joint), which the compiled
        multi-step loop needs fixed."""
        if all_q and self._arms is None:
            return None
        return (*self._scene, self._rows, self._gains, self.friction, self._anchors, self._anchored, self._fixed,
                self._out)

    def margin(self, q: FloatArray, qd: FloatArray, dt: float) -> float:
        """How close [m] a pair must be at (q, qd) to be active in a step of ``dt`` [s]:
        twice the lever-arm bound of any shape point's motion in the step (joint j moves
        points at most R_j |q̇_j| fast, :func:`.path.lever_arms`), at least :data:`MIN_MARGIN`
        (:func:`.contact_kernels.margin`)."""
        arms = self._arms if self._arms is not None else lever_arms(self.checker, q[None], q[None])[0]
        return K.margin(arms, np.ascontiguousarray(qd, dtype=float), float(dt))

    def begin_step(self, q: ArrayLike, qd: ArrayLike, dt: float) -> bool:
        """Start a step of ``dt`` [s] from (q, qd): choose the active pairs, fix the gains of
        pairs that just became active, fix (or hold) the contact frames, move the anchors
        of slipping pairs; True when some pair is active."""
        q = np.ascontiguousarray(q, dtype=float)
        qd = np.ascontiguousarray(qd, dtype=float)
        scene = self.checker.scene
        margin = self.margin(q, qd, dt)
        if self._active.size == 0:  # nothing was near: one compiled check, usually all there is
            batch.in_collision_batch(q[None], *scene.args(), self._pairs, scene.verts, margin, self._near,
                                     self._stats)
            if not self._near[0]:
                return False
        P = self._pairs.shape[0]
        d, pts, nrm = np.empty(P), np.zeros((P, 2, 3)), np.zeros((P, 3))
        batch.pair_results(q, *scene.args(), self._pairs, scene.verts, margin, d, pts, nrm,
                           np.empty_like(scene.recs0))
        near = np.flatnonzero(d < margin)
        if np.array_equal(near, self._active):  # the same pairs as in the last step: gains and anchors stay
            if near.size:
                self._begin(q, qd, margin)
            return near.size > 0
        previous = {int(p): k for k, p in enumerate(self._active)}
        A = near.size
        gains, anchors = np.zeros((A, 4)), np.zeros((A, K.POINTS, 2, 3))
        anchored = np.zeros((A, K.POINTS), dtype=np.bool_)
        new = []
        for k, p in enumerate(near):
            old = previous.get(int(p))
            if old is None:
                new.append(k)
            else:
                gains[k], anchors[k], anchored[k] = self._gains[old], self._anchors[old], self._anchored[old]
        if new:
            self._frames(q)
            gains[new] = self._gains_of(dynamics.mass_matrix(self.robot, q), near[new], pts[near[new]],
                                        nrm[near[new]], dt)
        self._active, self._gains, self._anchors, self._anchored = near, gains, anchors, anchored
        self._rows = np.ascontiguousarray(self._pairs[near])
        self._out = np.zeros((A, K.POINTS, K.OUT))
        self._fixed[self.robot.n_dofs] = -np.inf  # new pairs: frames fixed anew
        if A:
            self._begin(q, qd, margin)
        return A > 0

    def torque(self, q: ArrayLike, qd: ArrayLike) -> FloatArray:
        """Joint torque (n,) [N·m or N] of the active pairs' contact forces at (q, qd), with
        this step's contact frames, gains and anchors (zero without active pairs)."""
        if self._active.size == 0:
            return np.zeros(self.robot.n_dofs)
        return self._stage(np.ascontiguousarray(q, dtype=float), np.ascontiguousarray(qd, dtype=float),
                           self.compiled(all_q=False))

    def step(self, q: FloatArray, qd: FloatArray, tau: FloatArray, a1: FloatArray | None, h: float, rk4: bool,
             g0: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """One step of length ``h`` [s] from (q, q̇) (n,) with the effort tau held, the
        contact torque of this step's active pairs at every stage (one compiled call,
        :func:`.step_kernels.contact_step`; RK4 when ``rk4``, else semi-implicit
        Euler; gravity ``g0`` in frame 0; ``a1`` the start's acceleration when known):
        (q, q̇) after it and the start's acceleration.  StepDiverged if a stage state or
        acceleration is not finite."""
        n = self.robot.n_dofs
        q1, qd1, qdd1 = np.empty(n), np.empty(n), np.empty(n)
        status = contact_step(self.checker.scene.dh, rk4, h, q, qd, tau, qd if a1 is None else a1, a1 is not None, g0,
                              self.compiled(all_q=False), q1, qd1, qdd1)
        raise_for(status)
        return q1, qd1, qdd1

    @property
    def forces(self) -> list[ContactForce]:
        """The touching pairs at the last evaluated state (the last stage of the last step)."""
        owner = self.checker.scene.owner
        found = []
        for k, p in enumerate(self._active):
            i, j = self._pairs[p]
            for out in self._out[k]:
                if out[K.O_D] < 0.0:
                    found.append(ContactForce((owner[i], owner[j]), out[K.O_POINT:K.O_POINT + 3].copy(),
                                              out[K.O_NORMAL:K.O_NORMAL + 3].copy(), float(-out[K.O_D]),
                                              out[K.O_FORCE:K.O_FORCE + 3].copy()))
        return found

    def stored_energy(self, q: ArrayLike) -> float:
        """Potential energy [J] in the active pairs' springs at q, with contact frames fixed
        at q (the exact distances): Σ ½ k δ² + ½ k_T |u|².  The step's own frames are kept."""
        q = check_joint_vector(q, self.robot.n_dofs)
        if self._active.size == 0:
            return 0.0
        q = np.ascontiguousarray(q, dtype=float)
        qd = np.zeros(self.robot.n_dofs)
        out = self._out.copy()
        C = self.compiled(all_q=False)[:-2] + (np.full_like(self._fixed, -np.inf), out)  # frames fixed at q
        K.contact_begin(q, qd, self.checker.scene.dh, self.robot.is_modified, C, False, False, MIN_MARGIN,
                        self._begin_work(C))
        self._stage(q, qd, C)
        depth = np.maximum(-out[:, :, K.O_D], 0.0)  # (A, POINTS)
        u = out[:, :, K.O_SLIP:K.O_SLIP + 3]
        spring = self._gains[:, K.K_N, None] * depth**2 + self._gains[:, K.K_T, None] * np.sum(u * u, axis=2)
        return float(0.5 * np.sum(np.where(depth > 0.0, spring, 0.0)))

    def reset(self) -> None:
        """Forget the active pairs, their gains and anchors (after the state was set from outside)."""
        self.__init__(self.checker, friction=self.friction)

    # ------------------------------------------------------------------ helpers
    def _begin(self, q: FloatArray, qd: FloatArray, margin: float) -> None:
        """Fix (or hold) this step's contact frames at its start (q, qd) and move the friction anchors."""
        C = self.compiled(all_q=False)
        K.contact_begin(q, qd, self.checker.scene.dh, self.robot.is_modified, C, True, False, margin,
                        self._begin_work(C))

    def _begin_work(self, C: tuple) -> tuple:
        """contact_begin's work arrays for the contact tuple C (room for its current out and fixed)."""
        return self._work[:4] + (np.empty_like(C[-1]), np.empty_like(C[-2]), self._work[6])

    def _stage(self, q: FloatArray, qd: FloatArray, C: tuple) -> FloatArray:
        tau = np.empty(self.robot.n_dofs)
        K.contact_torque(q, qd, self.checker.scene.dh, self.robot.is_modified, C, tau, self._work)
        return tau

    def _frames(self, q: FloatArray) -> None:
        """World frames 0..n at q into self._F (for the gains' Jacobians)."""
        scene = self.checker.scene
        chain.frames(scene.dh, self.robot.is_modified, scene.world0, q, self._F)

    def _gains_of(self, M: FloatArray, pairs: NDArray[np.int64], points: FloatArray, normals: FloatArray,
                  dt: float) -> FloatArray:
        """[k_n, c_n, k_t, c_t] (B, 4) of the pairs (B,) (rows of the checked pairs) with
        witness points (B, 2, 3) and normals (B, 3), at the mass matrix M and this model's
        frames: the normal gains from a pair's effective mass along its normal, the
        tangential ones from the smallest effective mass across it (never above the normal
        one); zero for a pair whose shapes cannot move each other
        (:func:`.contact_kernels.pair_gains`)."""
        rows = self._pairs[pairs]
        gains = np.empty((len(pairs), 4))
        K.pair_gains(self._F, np.array(M, dtype=float), self._body[rows[:, 0]], np.ascontiguousarray(points[:, 0]),
                     self._body[rows[:, 1]], np.ascontiguousarray(points[:, 1]), np.ascontiguousarray(normals),
                     self._axis_frame, self._revolute, OMEGA_DT / dt, DAMPING_RATIO, IMMOBILE, gains)
        return gains
