"""Command-line robot actions: --print-dh (both conventions), --export-urdf, --export-toml
(files that load back to the same robot), URDF robots with --tip and --convention, and
their errors as one line with exit status 2."""
from __future__ import annotations

import math

import numpy as np
import pytest

from paths import DATA
from robot_sim.app.robot_cmds import dh_table_text, export
from kin_helpers import CONVENTIONS, ROBOT_NAMES, random_q, robot
from robot_sim.kinematics import forward_kinematics
from robot_sim.io.robot_file import load_robot
from cli_helpers import assert_one_line_error, run
from urdf_helpers import parse, urdf_fk



def dh_rows(text: str, convention: str) -> np.ndarray:
    """Numbers (a, α°, θ°, d) of the table section of ``convention`` in --print-dh output."""
    lines = text.splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith(f"{convention} DH:")) + 2
    rows = []
    for line in lines[start:]:
        if not line[:1].isdigit():
            break
        rows.append([float(v) for v in line.split()[2:6]])
    return np.array(rows)


@pytest.mark.parametrize("name", ["puma560", "stanford"])
def test_print_dh_shows_both_conventions(name):
    result = run("--robot", name, "--print-dh")
    assert result.returncode == 0, result.stderr
    assert result.stdout.rstrip("\n") == dh_table_text(load_robot(name))
    for conv in CONVENTIONS:
        table = robot(name, conv)
        expected = np.c_[table.dh_a, np.degrees(table.dh_alpha), np.degrees(table.dh_th), table.dh_d]
        np.testing.assert_allclose(dh_rows(result.stdout, conv), expected, rtol=1e-5, atol=1e-9)
    assert "a_{i-1} [m]" in result.stdout and "joint i turns about z of frame i-1" in result.stdout


def test_print_dh_of_a_urdf_with_tip_and_convention():
    result = run("--robot", str(DATA / "branching.urdf"), "--tip", "left_finger", "--convention", "modified", "--print-dh")
    assert result.returncode == 0, result.stderr
    first = result.stdout.splitlines()[0]
    assert first == "branching: 4 joints (R R R P), convention of the source: modified"
    rob = load_robot(DATA / "branching.urdf", tip="left_finger", convention="modified")
    np.testing.assert_allclose(dh_rows(result.stdout, "modified")[:, 0], rob.dh_a, atol=1e-6)


def test_export_urdf_from_the_command_line(tmp_path):
    out = tmp_path / "puma.urdf"
    result = run("--robot", "puma560", "--export-urdf", str(out))
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == f"wrote {out}"
    rob, model = load_robot("puma560"), parse(out.read_text())
    for q in random_q(rob, np.random.default_rng(60), 10):
        np.testing.assert_allclose(urdf_fk(model, "tool0", q), forward_kinematics(rob, q), atol=1e-12)


def test_export_toml_of_a_urdf_loads_back(tmp_path):
    out = tmp_path / "arm.toml"
    result = run("--robot", str(DATA / "prismatic.urdf"), "--convention", "modified", "--export-toml", str(out))
    assert result.returncode == 0, result.stderr
    original = load_robot(DATA / "prismatic.urdf", convention="modified")
    check_same_robot(load_robot(out), original)


def check_same_robot(back, rob) -> None:
    assert back.name == rob.name and back.convention == rob.convention
    np.testing.assert_array_equal(back.jtype, rob.jtype)
    for field in ("dh_a", "dh_alpha", "dh_d", "dh_th", "q_home", "q_min", "q_max", "link_com_frac"):
        np.testing.assert_allclose(getattr(back, field), getattr(rob, field), rtol=1e-15, atol=1e-15)
    Q = random_q(rob, np.random.default_rng(61), 50)
    np.testing.assert_allclose(forward_kinematics(back, Q), forward_kinematics(rob, Q), atol=1e-12, rtol=0)
    assert (back.inertials is None) == (rob.inertials is None)
    if rob.inertials is not None:
        for field in ("mass", "com", "inertia"):
            np.testing.assert_allclose(getattr(back.inertials, field), getattr(rob.inertials, field), rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("conv", CONVENTIONS)
@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_exported_toml_loads_back_to_the_same_robot(tmp_path, name, conv):
    rob = robot(name, conv)
    path = export(rob, str(tmp_path / f"{name}.toml"), "toml")
    check_same_robot(load_robot(path), rob)


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["--robot", "puma560", "--tip", "link3"], ["--tip: applies to a URDF robot (--robot FILE.urdf), not to 'puma560'"]),
        (["--convention", "craig"], ["argument --convention: invalid choice: 'craig'"]),
        (["--robot", str(DATA / "branching.urdf")], ["the tree has several tips (camera, left_finger, right_finger)"]),
        (["--robot", str(DATA / "branching.urdf"), "--tip", "hand2"], ["tip link 'hand2' is not declared"]),
        (["--export-urdf", "/nonexistent-dir/x.urdf"], ["--export-urdf: cannot write '/nonexistent-dir/x.urdf'"]),
        (["--export-toml", "/"], ["--export-toml: cannot write '/'"]),
    ],
)
def test_robot_action_errors_are_one_line(args, fragments):
    assert_one_line_error(run(*args), *fragments)


def test_angles_in_the_table_are_degrees():
    text = dh_table_text(load_robot("anthropomorphic"))
    assert math.isclose(dh_rows(text, "standard")[0, 1], 90.0)
