"""print(robot) shows the DH table (Robotics Toolbox style) and --print-dh snaps values
within 1e-15 of a round number: the cells read back equal the robot's arrays."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from paths import DATA
from cli_helpers import run
from robot_sim.io.robot_file import load_robot
from robot_sim.model.table_text import number, snap


@pytest.mark.parametrize("value, expected", [
    (2.46519e-32, 0.0), (-1.8735e-16, 0.0), (0.1 + 0.2, 0.3), (-0.0, 0.0), (1.0 - 1e-16, 1.0),
    (1.0 / 3.0, 1.0 / 3.0), (1e-9, 1e-9), (123456.7 + 1e-11, 123456.7), (math.inf, math.inf),
])
def test_snap_goes_only_to_a_round_number_within_1e_15(value: float, expected: float) -> None:
    got = snap(value)
    assert got == expected and math.copysign(1.0, got) == math.copysign(1.0, expected)


def test_numbers_never_read_minus_zero_or_a_tiny_exponent() -> None:
    assert [number(v) for v in (-0.0, -1e-17, 2.46519e-32, 0.4318, -math.inf)] == ["0", "0", "0", "0.4318", "-inf"]


def rows_of(text: str) -> list[list[str]]:
    return [[c.strip() for c in line.strip("│").split("│")] for line in text.splitlines() if line.startswith("│")]


def value(cell: str) -> float:
    return float(cell.rstrip("°").rstrip(" m"))


@pytest.mark.parametrize("name", ["puma560", "panda", "stanford", "scara"])
def test_print_shows_the_dh_table(name: str, capsys: pytest.CaptureFixture[str]) -> None:
    robot = load_robot(name)
    print(robot)
    text = capsys.readouterr().out
    lines = text.splitlines()
    assert lines[0].startswith(f"{robot.name}: {robot.n_dofs} joints") and f"{robot.convention} DH" in lines[0]
    header, *rows = rows_of(text)
    assert header[:5] == ["j", "θ", "d", "a(j-1)" if robot.is_modified else "a(j)", "α(j-1)" if robot.is_modified else "α(j)"]
    assert len(rows) == robot.n_dofs
    for j, (index, theta, d, a, alpha, offset, limits) in enumerate(rows):
        assert index == str(j + 1)
        assert value(a) == pytest.approx(robot.dh_a[j], rel=1e-5, abs=1e-12)
        assert math.radians(value(alpha)) == pytest.approx(robot.dh_alpha[j], rel=1e-5, abs=1e-12)
        if robot.is_revolute[j]:
            assert theta == f"q{j + 1}" and value(d) == pytest.approx(robot.dh_d[j], rel=1e-5, abs=1e-12)
            assert math.radians(value(offset)) == pytest.approx(robot.dh_th[j], rel=1e-5, abs=1e-12)
            lo, hi = (math.radians(value(v)) for v in limits.split(" .. "))
        else:
            assert d == f"q{j + 1}" and math.radians(value(theta)) == pytest.approx(robot.dh_th[j], abs=1e-9)
            assert value(offset) == pytest.approx(robot.dh_d[j], abs=1e-12)
            lo, hi = (value(v) for v in limits.split(" .. "))
        assert (lo, hi) == (pytest.approx(robot.q_min[j], rel=1e-5), pytest.approx(robot.q_max[j], rel=1e-5))
    assert lines[-2].startswith("base: xyz [") and lines[-1].startswith("tool: xyz [")
    assert len(lines) == robot.n_dofs + 7  # title, 3 rules, heading, rows, base, tool
    assert repr(robot) == f"<RobotParams {robot.name!r}: {robot.n_dofs} joints, {robot.convention} DH>"


@pytest.mark.parametrize("urdf", sorted((DATA).glob("*.urdf")), ids=lambda p: p.name)
def test_print_dh_of_an_imported_urdf_has_no_rounding_dust(urdf) -> None:
    tip = ["--tip", "left_finger"] if urdf.name == "branching.urdf" else []  # a tree: name its tip
    result = run("--robot", str(urdf), *tip, "--print-dh")
    assert result.returncode == 0, result.stderr
    dust = [n for n in re.findall(r"-?\d+(?:\.\d+)?e-\d+", result.stdout) if abs(float(n)) < 1e-9]
    assert dust == [], dust
