"""Robots and references shared by the simulation and control tests."""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from robot_sim.model.inertials import Drives, LinkInertials
from kin_helpers import robot
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams
from robot_sim.transforms import HomogeneousTransform

PENDULUM_LENGTH = 0.5
PENDULUM_MASS = 2.0


def frictionless(name: str, *, limits: bool = False) -> RobotParams:
    """Shipped robot ``name`` with its inertials, no drives (no friction, no motor inertia,
    no effort or velocity limits) and, unless ``limits``, no joint limits."""
    rob = robot(name)
    assert rob.inertials is not None, f"{name} ships without inertial data"
    changes: dict = {"drives": None}
    if not limits:
        changes.update(q_min=np.full(rob.n_dofs, -np.inf), q_max=np.full(rob.n_dofs, np.inf))
    return dataclasses.replace(rob, **changes)


def pendulum(limits: tuple[float, float] | None = None, drives: Drives | None = None) -> RobotParams:
    """A point-mass-like rod pendulum: one revolute joint whose axis (z0) is horizontal
    (world y), link along x1 of length :data:`PENDULUM_LENGTH`; at q = 0 the link is
    horizontal, gravity pulls q toward −π/2."""
    length, mass = PENDULUM_LENGTH, PENDULUM_MASS
    inertials = LinkInertials.from_arrays(
        mass=[mass],
        com=[[-length / 2, 0.0, 0.0]],  # mid-rod, in frame 1 (at the rod's tip)
        inertia=[np.diag([1e-4, mass * length**2 / 12, mass * length**2 / 12])],
    )
    lo, hi = limits if limits is not None else (-math.inf, math.inf)
    return RobotParams.from_arrays(
        "pendulum",
        [length],
        [0.0],
        [0.0],
        [0.0],
        [JTYPE_REVOLUTE],
        q_min=[lo],
        q_max=[hi],
        base_tf=HomogeneousTransform.from_xyz_rpy([0.0, 0.0, 0.0], [math.pi / 2, 0.0, 0.0]),
        inertials=inertials,
        drives=drives,
    )


def quintic(q0: np.ndarray, q1: np.ndarray, duration: float):
    """Rest-to-rest quintic q(t) = q0 + (q1 − q0)(10s³ − 15s⁴ + 6s⁵), s = t/T, held at q1
    after T: returns ``reference(t)`` → (q, qd, qdd)."""
    delta = np.asarray(q1, dtype=float) - np.asarray(q0, dtype=float)

    def reference(t: float):
        s = min(max(t / duration, 0.0), 1.0)
        pos = 10 * s**3 - 15 * s**4 + 6 * s**5
        vel = (30 * s**2 - 60 * s**3 + 30 * s**4) / duration
        acc = (60 * s - 180 * s**2 + 120 * s**3) / duration**2
        return q0 + delta * pos, delta * vel, delta * acc

    return reference
