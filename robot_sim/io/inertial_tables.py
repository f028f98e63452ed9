"""The ``[joints.inertial]`` and ``[joints.drive]`` tables of a robot file, validated into
:class:`~robot_sim.model.inertials.LinkInertials` and :class:`~robot_sim.model.inertials.Drives`."""
from __future__ import annotations

from typing import Any

import numpy as np

from robot_sim.model.arrays import frozen
from robot_sim.model.messages import clip_repr
from robot_sim.model.inertials import (
    DRIVE_DEFAULTS,
    DRIVE_KEYS,
    INERTIAL_KEYS,
    Drives,
    FloatArray,
    LinkInertials,
    balance_link_inertias,
    inertia_from_elements,
    inertia_problem,
)

from robot_sim.io.checker import FieldChecker


def parse_joint_tables(check: FieldChecker, joints: list[dict[str, Any]], balance: bool = False
                       ) -> tuple[LinkInertials | None, Drives | None]:
    """Inertials and drives from the ``[joints.inertial]`` and ``[joints.drive]`` tables of
    already-checked joint tables.  Every joint or none must have an inertial table, and a
    joint may not give both the scalar ``com`` fraction and an inertial table.  Raises
    RobotDefinitionError (through ``check``) naming file, joint, field and value.  With
    ``balance`` (the file's ``balance_inertia = true``) an inertia that only violates the
    triangle inequality is balanced instead, with an InertiaBalancedWarning naming it."""
    with_inertial = [i for i, joint in enumerate(joints) if "inertial" in joint]
    inertials = None
    if with_inertial:
        missing = [i for i in range(len(joints)) if i not in with_inertial]
        if missing:
            raise check.fail(
                f"joints[{missing[0]}].inertial",
                f"missing, but joints[{with_inertial[0]}] has one; give [joints.inertial] "
                "for every joint or for none",
            )
        rows = [_parse_inertial(check, joint, f"joints[{i}]", balance) for i, joint in enumerate(joints)]
        inertials = LinkInertials(
            frozen([r[0] for r in rows], (len(rows),)),
            frozen([r[1] for r in rows], (len(rows), 3)),
            frozen([r[2] for r in rows], (len(rows), 3, 3)),
        )
    drives = None
    if any("drive" in joint for joint in joints):
        columns = [_parse_drive(check, joint.get("drive", {}), f"joints[{i}].drive") for i, joint in enumerate(joints)]
        drives = Drives.from_arrays(len(joints), *(np.array([c[k] for c in columns]) for k in range(6)))
    return inertials, drives


def _table(check: FieldChecker, value: Any, where: str, keys: set[str]) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise check.fail(where, f"expected a table with keys {', '.join(sorted(keys))}, got {clip_repr(value)}")
    check.keys(value, keys, where)
    return value


def _parse_inertial(check: FieldChecker, joint: dict[str, Any], where: str, balance: bool
                    ) -> tuple[float, list[float], FloatArray]:
    if "com" in joint:
        raise check.fail(
            f"{where}.com",
            f"ambiguous: both the com fraction {joint['com']!r} and [joints.inertial] are given; "
            "remove com (the inertial's com places the centre of mass)",
        )
    where = f"{where}.inertial"
    table = _table(check, joint["inertial"], where, INERTIAL_KEYS)
    for key in ("mass", "com", "inertia"):
        if key not in table:
            raise check.fail(f"{where}.{key}", "missing required field")
    mass = check.number(table["mass"], f"{where}.mass")
    if mass < 0.0:
        raise check.fail(f"{where}.mass", f"mass {table['mass']!r} is negative; accepted: a mass >= 0 (kg)")
    com = check.vector(table["com"], 3, f"{where}.com")
    elements = check.vector(table["inertia"], 6, f"{where}.inertia")
    inertia = inertia_from_elements(*elements)
    if balance:
        inertia = balance_link_inertias(inertia[None], [f"{check.path}: {where}.inertia"])[0]
    problem = inertia_problem(inertia)
    if problem:
        hint = "; or set balance_inertia = true" if "triangle" in problem else ""
        raise check.fail(
            f"{where}.inertia",
            f"{clip_repr(table['inertia'])} {problem}; accepted: [Ixx, Iyy, Izz, Ixy, Iyz, Ixz] (kg m^2) of a "
            f"positive semi-definite tensor whose principal moments obey the triangle inequality{hint}",
        )
    return mass, com, inertia


def _parse_drive(check: FieldChecker, value: Any, where: str) -> tuple[float, float, float, list[float], float, float]:
    table = _table(check, value, where, DRIVE_KEYS)

    def number(key: str, default: float, ok: Any, accepted: str) -> float:
        if key not in table:
            return default
        v = check.number(table[key], f"{where}.{key}")
        if not ok(v):
            raise check.fail(f"{where}.{key}", f"{key} {table[key]!r} is out of range; accepted: {accepted}")
        return v

    jm = number("motor_inertia", DRIVE_DEFAULTS["motor_inertia"], lambda v: v >= 0.0, "a motor inertia >= 0 (kg m^2)")
    gear = number("gear_ratio", DRIVE_DEFAULTS["gear_ratio"], lambda v: v != 0.0, "a non-zero gear ratio")
    viscous = number("viscous", DRIVE_DEFAULTS["viscous"], lambda v: v >= 0.0, "a viscous friction coefficient >= 0")
    coulomb = [0.0, 0.0]
    if "coulomb" in table:
        coulomb = check.vector(table["coulomb"], 2, f"{where}.coulomb")
        if coulomb[0] < 0.0 or coulomb[1] > 0.0:
            raise check.fail(
                f"{where}.coulomb",
                f"coulomb {table['coulomb']!r} is out of range; accepted: [Tc+, Tc-] with Tc+ >= 0 and Tc- <= 0",
            )
    effort = number("effort_limit", DRIVE_DEFAULTS["effort_limit"], lambda v: v > 0.0, "an effort limit > 0")
    velocity = number("velocity_limit", DRIVE_DEFAULTS["velocity_limit"], lambda v: v > 0.0, "a velocity limit > 0")
    return jm, gear, viscous, coulomb, effort, velocity


