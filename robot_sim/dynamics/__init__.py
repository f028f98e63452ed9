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
:mod:`robot_sim.dynamics.compiled`, the same algorithms as scalar code over one
configuration, a batch being N calls of it; ``"reference"`` runs the readable recursion of
``robot_sim.dynamics.recursion`` (``_rnea_terms``, ``_crba_terms``) on arrays of configurations, or on Python
floats for one.  The tests hold the two to 1e-12.  The time step (``Stepper``) is the
physics loop's: robot_sim/sim/stepper.py.

One job per file: ``api`` (the public functions and the backend choice), ``recursion``
(the per-robot model and the reference recursion), ``algebra`` (its scalar algebra),
``compiled`` (the numba kernels); the public names are re-exported here.  Imports
neither Qt nor OpenGL.
"""
from robot_sim.dynamics.api import (
    BACKEND_ENV, BACKENDS, CHUNK, GRAVITY, _link_jacobians, _solve_spd, backend, bias_torque, compiled_kernels,
    computed_torque, constrained_forward_dynamics, coriolis_matrix, energy, forward_dynamics, friction_torque,
    gravity_torque, inverse_dynamics, mass_matrix, set_backend,
)

__all__ = [
    "BACKEND_ENV", "BACKENDS", "CHUNK", "GRAVITY", "backend", "bias_torque", "compiled_kernels", "computed_torque",
    "constrained_forward_dynamics", "coriolis_matrix", "energy", "forward_dynamics", "friction_torque",
    "gravity_torque", "inverse_dynamics", "mass_matrix", "set_backend",
]
