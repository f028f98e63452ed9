"""Which closed form an arm has, read from its joint axes (never from its name).

Axes are compared at q = 0 in the world frame (:mod:`robot_sim.ik.geometry`), so both DH
conventions, any base and any tool give the same answer.  Two axes are *parallel* when
the sine of their angle is below :data:`ANGLE_TOL`, and *meet* when the distance between
the lines is below :data:`LENGTH_TOL` times the robot's size (1 m at least).  The
families follow EAIK's classification by intersecting and parallel axes (Ostermeier et
al., "Automatic geometric decomposition for analytical inverse kinematics", IEEE RA-L
2025, arXiv:2409.14815) and IK-Geo's table of 6R cases (Elias & Wen, arXiv:2211.05737,
Table 1); a chain that matches when read from the tool back (``reversed``) is solved
reversed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from robot_sim.ik.families import PARALLEL_AXES, POSITION_ONLY, SPHERICAL_WRIST, THREE_PARALLEL
from robot_sim.ik.geometry import Screws
from robot_sim.ik.position import (ONE_TWO_MEET, ONE_TWO_MEET_SLIDE, ONE_TWO_PARALLEL, TWO_THREE_MEET,
                                   TWO_THREE_PARALLEL)

FloatArray = NDArray[np.float64]

ANGLE_TOL = 1e-9
LENGTH_TOL = 1e-9
#: The order in which a 7-joint arm's joints are tried as the free one (0-based): the
#: elbow's neighbour (joint 3, as for the KUKA iiwa), the last (Franka's q7), then the rest.
FREE_ORDER = (2, 6, 0, 4, 1, 3, 5)
#: Angles at which a fold must keep its family (a chance alignment at one value is not one).
FOLD_PROBES = (0.0, 0.7318)

ARM_CASES = {
    ONE_TWO_MEET: "axes 1 and 2 meet",
    ONE_TWO_MEET_SLIDE: "axes 1 and 2 meet, joint 3 slides",
    TWO_THREE_PARALLEL: "axes 2 and 3 parallel",
    ONE_TWO_PARALLEL: "axes 1 and 2 parallel",
    TWO_THREE_MEET: "axes 2 and 3 meet",
}


@dataclass(frozen=True)
class Plan:
    """How the solver runs a family: the kernel ``kind`` and arm ``case``, ``idx`` (the
    parallel-axes joints), whether the chain is ``reversed``, the ``free`` joint of a
    7-joint arm (or None), and the constant rows ``aux`` (a function of the screws, since a
    fold moves them)."""

    kind: int
    case: int = 0
    idx: tuple[int, int, int, int] = (-1, -1, -1, -1)
    reversed: bool = False
    free: int | None = None


def _parallel(a: FloatArray, b: FloatArray) -> bool:
    return float(np.linalg.norm(np.cross(a, b))) < ANGLE_TOL


def meeting_point(S: Screws, i: int, j: int, tol: float) -> FloatArray | None:
    """Where axes i and j meet (the midpoint of their closest points), None if they do not."""
    hi, hj, d = S.H[i], S.H[j], S.P[j] - S.P[i]
    if _parallel(hi, hj):
        return None
    c = hi @ hj
    det = 1.0 - c * c
    s = (d @ hi - c * (d @ hj)) / det
    t = (c * (d @ hi) - d @ hj) / det
    a, b = S.P[i] + s * hi, S.P[j] + t * hj
    return 0.5 * (a + b) if np.linalg.norm(a - b) < tol else None


def _through(S: Screws, i: int, point: FloatArray, tol: float) -> bool:
    return float(np.linalg.norm(np.cross(point - S.P[i], S.H[i]))) < tol


def wrist_case(S: Screws, tol: float) -> int | None:
    """The arm case of joints 0-2 (:mod:`robot_sim.ik.position`), None if none applies."""
    rev = S.revolute
    if rev[0] and rev[1] and meeting_point(S, 0, 1, tol) is not None:
        return ONE_TWO_MEET if rev[2] else ONE_TWO_MEET_SLIDE
    if rev[0] and rev[1] and rev[2] and _parallel(S.H[1], S.H[2]) and not _parallel(S.H[0], S.H[1]):
        return TWO_THREE_PARALLEL
    if rev[0] and rev[1] and rev[2] and _parallel(S.H[0], S.H[1]) and not _parallel(S.H[1], S.H[2]):
        return ONE_TWO_PARALLEL
    if rev[0] and rev[1] and rev[2] and meeting_point(S, 1, 2, tol) is not None:
        return TWO_THREE_MEET
    return None


def _six(S: Screws, tol: float) -> Plan | None:
    """The plan of a 6-joint chain read in this direction, or None."""
    rev = S.revolute
    if rev[3:].all():
        w = meeting_point(S, 3, 4, tol)
        if w is not None and _through(S, 5, w, tol):
            case = wrist_case(S, tol)
            if case is not None:
                return Plan(SPHERICAL_WRIST, case)
    if (rev.all() and _parallel(S.H[1], S.H[2]) and _parallel(S.H[1], S.H[3]) and not _parallel(S.H[0], S.H[1])
            and not _parallel(S.H[4], S.H[1]) and meeting_point(S, 4, 5, tol) is not None):
        return Plan(THREE_PARALLEL)
    return None


def _few(S: Screws, tol: float) -> Plan | None:
    """Plans of 3- and 4-joint arms: every axis parallel (planar, SCARA), or a 3-joint
    position arm."""
    rev = S.revolute
    turning = np.flatnonzero(rev)
    sliding = np.flatnonzero(~rev)
    if all(_parallel(S.H[0], h) for h in S.H) and len(sliding) <= 1 and 2 <= len(turning) <= 3:
        idx = (int(turning[0]), int(turning[1]), int(turning[2]) if len(turning) == 3 else -1,
               int(sliding[0]) if len(sliding) else -1)
        return Plan(PARALLEL_AXES, idx=idx)
    if S.n == 3:
        case = wrist_case(S, tol)
        if case is not None:
            return Plan(POSITION_ONLY, case)
    return None


def plan(S: Screws, size: float) -> Plan | None:
    """The closed form of a chain (either direction), None for a general arm."""
    tol = LENGTH_TOL * max(size, 1.0)
    if S.n in (3, 4):
        return _few(S, tol)
    if S.n == 6:
        found = _six(S, tol)
        if found is None:
            found = _six(S.reversed(), tol)
            return None if found is None else Plan(found.kind, found.case, found.idx, True)
        return found
    if S.n == 7:
        for free in FREE_ORDER:
            plans = [plan(S.folded(free, v), size) for v in FOLD_PROBES]
            if plans[0] is not None and all(p == plans[0] for p in plans):
                p = plans[0]
                return Plan(p.kind, p.case, p.idx, p.reversed, free)
    return None


def _unit_perp(h: FloatArray) -> FloatArray:
    x = np.cross(h, np.eye(3)[int(np.argmin(np.abs(h)))])
    return x / np.linalg.norm(x)


def _reach_direction(S: Screws, point: FloatArray) -> FloatArray:
    """The arm's reach direction at q = 0 (``f0``): from axis 0 toward ``point``, without
    its components along axis 0 and along axis 1."""
    f = point - S.P[0]
    f = f - (f @ S.H[0]) * S.H[0]
    g = S.H[1] - (S.H[1] @ S.H[0]) * S.H[0]
    if np.linalg.norm(g) > ANGLE_TOL:
        g = g / np.linalg.norm(g)
        f = f - (f @ g) * g
    length = np.linalg.norm(f)
    return f / length if length > LENGTH_TOL else _unit_perp(S.H[0])


def aux_rows(p: Plan, S: Screws, size: float) -> FloatArray:
    """The constant rows the kernel of plan p reads (see :mod:`robot_sim.ik.families`)."""
    tol = LENGTH_TOL * max(size, 1.0)
    Minv_R, Mt = S.M[:3, :3].T, S.M[:3, 3]
    A = np.zeros((7, 3))
    if p.kind in (SPHERICAL_WRIST, POSITION_ONLY):
        w = meeting_point(S, 3, 4, tol) if p.kind == SPHERICAL_WRIST else Mt
        pair = (1, 2) if p.case == TWO_THREE_MEET else (0, 1)
        o = meeting_point(S, *pair, tol) if p.case in (ONE_TWO_MEET, ONE_TWO_MEET_SLIDE, TWO_THREE_MEET) else None
        A[0], A[5], A[6] = w, np.zeros(3) if o is None else o, _reach_direction(S, w)
        if p.kind == SPHERICAL_WRIST:
            x6 = _unit_perp(S.H[5])
            A[1], A[2], A[3], A[4] = Minv_R @ (w - Mt), Minv_R @ S.H[5], x6, Minv_R @ x6
    elif p.kind == THREE_PARALLEL:
        o = meeting_point(S, 4, 5, tol)
        A[0], A[1], A[2] = o, Minv_R @ (o - Mt), Minv_R @ S.H[5]
        A[3], A[4] = _unit_perp(S.H[1]), _reach_direction(S, S.P[3])
    else:
        c = p.idx[2]
        point = S.P[c] if c >= 0 else Mt
        x = _unit_perp(S.H[p.idx[0]])
        A[0], A[1], A[2], A[3] = point, Minv_R @ (point - Mt), x, Minv_R @ x
    return A
