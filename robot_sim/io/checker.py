"""Field-by-field validation of parsed TOML (robot, task and world files): every error names the
file, the field and the value, and says what is accepted."""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from robot_sim.model.messages import clip, clip_repr
from robot_sim.model.params import RobotDefinitionError
from robot_sim.transforms import HomogeneousTransform

MAX_LENGTH = 1000.0  # m: |a|, |d|, base and tool xyz, prismatic home and limits
MAX_JOINTS = 100  # moving joints of a robot (robot files and URDF chains)
FRAME_KEYS = {"xyz", "rpy"}


class FieldChecker:
    """Validates fields of one robot file; every error names the file and the field."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def fail(self, where: str, message: str) -> RobotDefinitionError:
        return RobotDefinitionError(f"{self.path}: {where}: {message}")

    def keys(self, table: dict[str, Any], allowed: set[str], where: str) -> None:
        unknown = sorted(set(table) - allowed)
        if unknown:
            raise self.fail(
                f"{where}.{clip(unknown[0])}" if where else clip(unknown[0]),
                f"unknown key {clip_repr(unknown[0])}; accepted keys: {', '.join(sorted(allowed))}",
            )

    def number(self, value: Any, where: str, bound: "Bound | None" = None) -> float:
        """``value`` as a finite float, within ±``bound.limit`` when a bound is given."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(where, f"expected a number, got {clip_repr(value)}")
        if isinstance(value, float) and not math.isfinite(value):
            raise self.fail(where, f"expected a finite number, got {value!r}")
        try:
            number = float(value)
        except OverflowError:  # an integer beyond the float range
            number = math.inf if value > 0 else -math.inf
        if bound is not None and not abs(number) <= bound.limit:
            raise self.fail(where, f"expected {bound.what} within ±{bound.limit:g} {bound.unit}, got {clip_repr(value)}")
        if not math.isfinite(number):
            raise self.fail(where, f"expected a finite number, got {clip_repr(value)}")
        return number

    def vector(self, value: Any, length: int, where: str, bound: "Bound | None" = None) -> list[float]:
        if not isinstance(value, list) or len(value) != length:
            raise self.fail(where, f"expected a list of {length} numbers, got {clip_repr(value)}")
        return [self.number(v, f"{where}[{i}]", bound) for i, v in enumerate(value)]

    def frame(self, table: Any, where: str, angle: "Bound", to_rad: float) -> HomogeneousTransform:
        if not isinstance(table, dict):
            raise self.fail(where, f"expected a table with keys xyz and rpy, got {clip_repr(table)}")
        self.keys(table, FRAME_KEYS, where)
        xyz = self.vector(table.get("xyz", [0.0, 0.0, 0.0]), 3, f"{where}.xyz", LENGTH_BOUND)
        rpy = self.vector(table.get("rpy", [0.0, 0.0, 0.0]), 3, f"{where}.rpy", angle)
        return HomogeneousTransform.from_xyz_rpy(xyz, np.array(rpy) * to_rad)


@dataclass(frozen=True)
class Bound:
    """Largest magnitude accepted for a value, with what it is and its unit (for messages)."""

    limit: float
    what: str
    unit: str


LENGTH_BOUND = Bound(MAX_LENGTH, "a length", "m")
