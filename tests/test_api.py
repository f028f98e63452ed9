"""``import robot_sim as rs`` is the flat public API: every documented name is there, and
importing the package loads neither Qt nor OpenGL."""
from __future__ import annotations

import subprocess
import sys

import pytest

import robot_sim as rs

#: The names the README's API section documents (issue 15's list, plus a few more).
DOCUMENTED = (
    "load_robot available_robots RobotParams RobotDefinitionError RobotState JointState "
    "Kinematics forward_kinematics jacobian manipulability solve_ik IKResult "
    "inverse_dynamics mass_matrix gravity_torque coriolis_matrix bias_torque forward_dynamics energy "
    "Simulation make_controller to_standard to_modified to_urdf load_urdf to_toml save_robot "
    "Trajectory quintic trapezoidal via_points cartesian_line cartesian_arc plan_pick "
    "plan_path plan_to_pose retime PathResult CartesianPathError InfeasiblePath qd_limits qdd_limits"
).split()


@pytest.mark.parametrize("name", DOCUMENTED)
def test_documented_name_is_exported(name: str) -> None:
    assert name in rs.__all__
    assert getattr(rs, name).__name__ == name


def test_flat_api_computes() -> None:
    robot = rs.load_robot("puma560")
    T = rs.forward_kinematics(robot, robot.q_home)
    M = rs.mass_matrix(robot, robot.q_home)
    assert T.shape == (4, 4) and M.shape == (6, 6)
    assert isinstance(robot, rs.RobotParams)


def test_planning_calls_as_issue_19_names_them() -> None:
    import dataclasses
    import inspect

    def keywords(fn):
        return {k: p.default for k, p in inspect.signature(fn).parameters.items() if p.kind is p.KEYWORD_ONLY}

    assert list(inspect.signature(rs.plan_path).parameters)[:4] == ["robot", "q_start", "q_goal", "checker"]
    assert keywords(rs.plan_path) == {"time_limit": 1.0, "seed": 0}
    assert list(inspect.signature(rs.plan_to_pose).parameters)[:4] == ["robot", "q_start", "target_tf", "checker"]
    assert keywords(rs.retime) == {"v_max": None, "a_max": None, "effort": True, "dt": 1e-3}
    assert [f.name for f in dataclasses.fields(rs.PathResult)] == ["success", "path", "message", "planning_time",
                                                                   "checks"]


def test_unknown_name_is_an_attribute_error() -> None:
    with pytest.raises(AttributeError, match="module 'robot_sim' has no attribute 'nonsense'"):
        rs.nonsense  # noqa: B018


def test_importing_the_package_loads_no_gui_or_gl() -> None:
    code = ("import sys, robot_sim as rs; rs.load_robot('ur5'); rs.Simulation; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('PyQt5', 'OpenGL', 'pyqtgraph')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
