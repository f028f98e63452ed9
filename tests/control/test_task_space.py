"""Task-space control: operational space, impedance and resolved rate, in the simulation loop.

Closed forms: on an exact model (no friction, saturation or contact) the OSC error obeys
ë + K_d ė + K_p e = 0; impedance is passive and settles at K⁻¹F; the null-space posture
leaves the tool's acceleration alone (recomputed here from forward dynamics and an
independently built projector).
"""
from __future__ import annotations

import contextlib
import dataclasses
import math

import numpy as np
import pytest

from kin_helpers import robot
from robot_sim import dynamics
from robot_sim.control.factory import make_controller
from robot_sim.sim.simulation import Simulation
from robot_sim.kinematics import forward_kinematics, jacobian, tool_kinematics
from robot_sim.model.state import RobotState
from robot_sim.planning.cartesian import cartesian_line
from robot_sim.transforms import rot_from_angle_axis, rotation_log
from sim_helpers import frictionless, quintic

RNG = np.random.default_rng(2020)


@contextlib.contextmanager
def reference_dynamics(on: bool = True):
    """Run the block on the readable (NumPy) dynamics, where the task-space law is NumPy too."""
    before = dynamics.backend()
    dynamics.set_backend("reference" if on else before)
    try:
        yield
    finally:
        dynamics.set_backend(before)
AXIS = np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)
STEP = np.array([0.03, 0.04, 0.0])  # 5 cm


def _error(T_d: np.ndarray, T: np.ndarray) -> np.ndarray:
    """e = [p_d − p; log(R_d Rᵀ)] (world frame)."""
    return np.concatenate([T_d[:3, 3] - T[:3, 3], rotation_log(T_d[:3, :3] @ T[:3, :3].T)])


def _offset(T: np.ndarray) -> np.ndarray:
    """T moved by 5 cm and turned by 10° about AXIS (world frame)."""
    out = T.copy()
    out[:3, 3] += STEP
    out[:3, :3] = rot_from_angle_axis(math.radians(10.0), AXIS) @ T[:3, :3]
    return out


def _start(rob, q0) -> RobotState:
    state = RobotState(rob)
    state.set_q(q0)
    return state


def _second_order(e0: np.ndarray, ed0: np.ndarray, w: float, zeta: float, t: float) -> np.ndarray:
    """Solution of ë + 2ζω ė + ω² e = 0 from e(0) = e0, ė(0) = ed0 (ζ ≤ 1)."""
    if zeta == 1.0:
        return (e0 + (ed0 + w * e0) * t) * math.exp(-w * t)
    wd = w * math.sqrt(1.0 - zeta**2)
    return math.exp(-zeta * w * t) * (e0 * math.cos(wd * t) + (ed0 + zeta * w * e0) / wd * math.sin(wd * t))


@pytest.mark.parametrize("name", ["ur5", "panda", "humanoid7"])
def test_osc_error_is_the_analytic_second_order_response(name: str) -> None:
    """From rest 5 cm and 10° off a fixed target, e(t) = e0 (1 + ωt) e^(−ωt) (ζ = 1) to
    1e-5 over 1 s, checked every step (measured: 4e-11)."""
    rob = frictionless(name)
    q0 = rob.q_home + 0.1
    T_d = _offset(forward_kinematics(rob, q0))
    osc = make_controller("osc", rob, bandwidth=2.0, damping=1.0)
    sim = Simulation(rob, _start(rob, q0), osc, reference=lambda t: (T_d, np.zeros(6), np.zeros(6)))
    e0 = _error(T_d, forward_kinematics(rob, q0))
    assert np.linalg.norm(e0[:3]) == pytest.approx(0.05) and np.linalg.norm(e0[3:]) == pytest.approx(math.radians(10))
    worst = 0.0
    for _ in range(1000):
        sim.step()
        e = _error(T_d, forward_kinematics(rob, sim.q))
        worst = max(worst, np.abs(e - _second_order(e0, np.zeros(6), osc.omega, 1.0, sim.time)).max())
    assert sim.stopped is None
    assert worst < 1e-5, worst
    np.testing.assert_allclose(sim.desired_pose, T_d)


def test_osc_error_is_linear_also_for_a_moving_turning_reference() -> None:
    """Underdamped (ζ = 0.5) on a reference that circles and turns at 0.4 rad/s, from rest
    with the 5 cm / 10° offset: e(t) is the second-order response from e(0) and ė(0) (the
    rate of log(R_d(t) R₀ᵀ) by central differences of the reference) to 1e-5 over 1 s: the
    rotation error's rate is the log map's, not ω_d − ω."""
    rob = frictionless("humanoid7")
    q0 = rob.q_home + 0.1
    T_start = _offset(forward_kinematics(rob, q0))
    spin = np.array([0.0, 0.6, 0.8]) * 0.4

    def reference(t: float):
        T = np.eye(4)
        T[:3, :3] = rot_from_angle_axis(0.4 * t, spin / 0.4) @ T_start[:3, :3]
        T[:3, 3] = T_start[:3, 3] + 0.05 * np.array([math.sin(2 * t), 1 - math.cos(2 * t), 0.0])
        v = np.concatenate([0.1 * np.array([math.cos(2 * t), math.sin(2 * t), 0.0]), spin])
        a = np.concatenate([0.2 * np.array([-math.sin(2 * t), math.cos(2 * t), 0.0]), np.zeros(3)])
        return T, v, a

    osc = make_controller("osc", rob, bandwidth=1.5, damping=0.5)
    sim = Simulation(rob, _start(rob, q0), osc, reference=reference)
    T0 = forward_kinematics(rob, q0)
    e0 = _error(T_start, T0)
    h = 1e-5
    ed0 = (_error(reference(h)[0], T0) - _error(reference(-h)[0], T0)) / (2 * h)
    worst = 0.0
    for _ in range(1000):
        sim.step()
        e = _error(reference(sim.time)[0], forward_kinematics(rob, sim.q))
        worst = max(worst, np.abs(e - _second_order(e0, ed0, osc.omega, 0.5, sim.time)).max())
    assert worst < 1e-5, worst


def _projector(rob, q) -> tuple[np.ndarray, np.ndarray]:
    """J and the dynamically consistent N = I − M⁻¹Jᵀ(JM⁻¹Jᵀ)⁻¹J, built here from scratch."""
    J = jacobian(rob, q)
    Minv = np.linalg.inv(dynamics.mass_matrix(rob, q))
    Jbar = Minv @ J.T @ np.linalg.inv(J @ Minv @ J.T)
    return J, np.eye(rob.n_dofs) - Jbar @ J


@pytest.mark.parametrize("name", ["humanoid7", "panda"])
def test_a_posture_torque_leaves_the_tool_acceleration_unchanged(name: str) -> None:
    """Forward dynamics of τ with and without the posture task: the tool accelerations
    J q̈ + J̇ q̇ differ by at most 1e-9 while the torques differ by newton-metres."""
    rob = frictionless(name)
    for _ in range(5):
        q = rob.q_home + RNG.uniform(-0.3, 0.3, rob.n_dofs)
        qd = RNG.uniform(-0.5, 0.5, rob.n_dofs)
        T_d = _offset(forward_kinematics(rob, q))
        twist, accel = RNG.normal(size=6) * 0.1, RNG.normal(size=6) * 0.1
        plain = make_controller("osc", rob, null_space=None).torque(q, qd, T_d, twist, accel)
        posture = make_controller("osc", rob, null_space=rob.q_home + 0.8).torque(q, qd, T_d, twist, accel)
        assert np.abs(posture - plain).max() > 0.1
        _, J, jd = tool_kinematics(rob, q, qd)
        tool = [J @ dynamics.forward_dynamics(rob, q, qd, tau) + jd for tau in (plain, posture)]
        assert np.abs(tool[1] - tool[0]).max() < 1e-9


@pytest.mark.parametrize("name", ["humanoid7", "panda"])
def test_the_posture_converges_in_the_null_space_while_the_tool_holds(name: str) -> None:
    """Tool on its target from the start, posture target 0.5 rad along the Jacobian's null
    vector at home: after 2.5 s the posture error left in the null space, N (q₀ − q), is
    below 1e-4 of where it started and the tool never leaves its pose by more than 1e-8."""
    rob = frictionless(name)
    T_d = forward_kinematics(rob, rob.q_home)
    target = rob.q_home + 0.5 * np.linalg.svd(jacobian(rob, rob.q_home))[2][-1]
    sim = Simulation(rob, None, make_controller("osc", rob, null_space=target),
                     reference=lambda t: (T_d, np.zeros(6), np.zeros(6)))
    start = np.linalg.norm(_projector(rob, sim.q)[1] @ (target - sim.q))
    drift = 0.0
    for _ in range(25):
        sim.step(100)
        drift = max(drift, np.abs(_error(T_d, forward_kinematics(rob, sim.q))).max())
    left = np.linalg.norm(_projector(rob, sim.q)[1] @ (target - sim.q))
    assert start > 0.2
    assert left < 1e-4 * start
    assert drift < 1e-8
    assert np.abs(sim.q - rob.q_home).max() > 0.05  # it moved: the self-motion was used


@pytest.mark.parametrize("name, bandwidth, steps", [("panda", 4.0, 1000),  # the default suite's: 5 s of CPU
                                                    *(pytest.param(name, 2.0, 3000, marks=pytest.mark.slow)
                                                      for name in ("ur5", "panda", "humanoid7"))])
def test_impedance_settles_at_the_displacement_k_inverse_f(name: str, bandwidth: float, steps: int) -> None:
    """A constant wrench F at the tool: after 1 s at 4 Hz (3 s at 2 Hz) the tool sits at
    x_d + K⁻¹F (position and rotation; e = −K⁻¹F) to 1e-5 (measured: below 3e-6), at rest."""
    rob = frictionless(name)
    T_d = forward_kinematics(rob, rob.q_home)
    imp = make_controller("impedance", rob, bandwidth=bandwidth)
    sim = Simulation(rob, None, imp, reference=lambda t: (T_d, np.zeros(6), np.zeros(6)))
    F = np.array([5.0, -3.0, 4.0, 0.3, -0.2, 0.1])
    sim.set_tool_wrench(F)
    sim.step(steps)
    displacement = -_error(T_d, forward_kinematics(rob, sim.q))
    expected = np.linalg.solve(imp.K, F)
    assert np.linalg.norm(expected[:3]) > 1e-3
    np.testing.assert_allclose(displacement, expected, atol=1e-5)
    assert np.abs(sim.qd).max() < 1e-4


@pytest.mark.slow  # 3 s of a tool wrench: about 12 s of CPU
def test_impedance_with_a_full_stiffness_matrix_and_scalar_pairs() -> None:
    """A 6×6 K coupling force and rotation, D as a (translational, rotational) pair."""
    rob = frictionless("ur5")
    T_d = forward_kinematics(rob, rob.q_home)
    K = np.diag([300.0, 400.0, 500.0, 20.0, 30.0, 40.0])
    K[0, 4] = K[4, 0] = 10.0
    imp = make_controller("impedance", rob, stiffness=K, damping=(60.0, 0.3))
    np.testing.assert_array_equal(imp.K, K)
    np.testing.assert_array_equal(np.diag(imp.D), [60.0] * 3 + [0.3] * 3)
    sim = Simulation(rob, None, imp, reference=lambda t: (T_d, np.zeros(6), np.zeros(6)))
    F = np.array([4.0, 2.0, -3.0, 0.2, 0.1, -0.1])
    sim.set_tool_wrench(F)
    sim.step(3000)
    np.testing.assert_allclose(-_error(T_d, forward_kinematics(rob, sim.q)), np.linalg.solve(K, F), atol=1e-5)


@pytest.mark.parametrize("name, null_space", [("panda", "home"), *(pytest.param(name, posture, marks=pytest.mark.slow)
                                              for name in ("ur5", "panda", "humanoid7") for posture in (None, "home")
                                              if (name, posture) != ("panda", "home"))])
def test_impedance_never_gains_energy(name: str, null_space) -> None:
    """Fixed reference, no force, from rest 0.05 rad off on every joint: kinetic plus
    spring energy (½ q̇ᵀMq̇ + ½ eᵀKe) never rises from one step to the next by more than
    1e-9 of its start (measured: it falls every step), over 1 s, and ends below 1e-3 of
    it."""
    rob = frictionless(name)
    T_d = forward_kinematics(rob, rob.q_home)
    imp = make_controller("impedance", rob, null_space=null_space)
    sim = Simulation(rob, _start(rob, rob.q_home + 0.05), imp, reference=lambda t: (T_d, np.zeros(6), np.zeros(6)))

    def stored() -> float:
        e = _error(T_d, forward_kinematics(rob, sim.q))
        return dynamics.energy(rob, sim.q, sim.qd)[0] + 0.5 * e @ imp.K @ e

    energies = [stored()]
    for _ in range(1000):
        sim.step()
        energies.append(stored())
    assert max(np.diff(energies)) <= 1e-9 * energies[0]
    assert energies[-1] < 1e-3 * energies[0]


def test_osc_through_shoulder_elbow_and_wrist_singularities_stays_bounded() -> None:
    """Panda (drives and effort limits kept, joint limits removed) follows the tool
    motion of a joint path through q₂ = q₄ = q₆ = 0, where axes 1 and 3 and axes 5 and 7
    align and the elbow is stretched (the Jacobian loses rank): every commanded torque is
    finite and below the effort limits (no saturation), and the arm ends on the path's end
    pose within 1 mm."""
    base = robot("panda")
    rob = dataclasses.replace(base, q_min=np.full(7, -np.inf), q_max=np.full(7, np.inf))
    q_a = np.array([0.3, 0.4, -0.2, -1.2, 0.3, 0.8, 0.5])
    q_s = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.5])
    q_b = np.array([-0.3, -0.3, 0.2, 0.6, -0.3, -0.5, 0.3])
    assert np.linalg.svd(jacobian(rob, q_s), compute_uv=False)[-1] < 1e-12
    first, second = quintic(q_a, q_s, 2.0), quintic(q_s, q_b, 2.0)

    def joints(t: float):
        return first(t) if t < 2.0 else second(t - 2.0)

    sim = Simulation(rob, _start(rob, q_a), make_controller("osc", rob), reference=joints)
    limit = rob.drives.effort_limit
    for _ in range(5000):
        sim.step()
        assert np.isfinite(sim.effort_command).all()
        assert (np.abs(sim.effort_command) < limit).all(), sim.effort_command
    assert sim.stopped is None
    end = forward_kinematics(rob, q_b)[:3, 3]
    assert np.linalg.norm(forward_kinematics(rob, sim.q)[:3, 3] - end) < 1e-3


def test_resolved_rate_tracks_a_line_at_20_cm_per_second_within_a_millimetre() -> None:
    """UR5, resolved rate over computed torque: a 20 cm line, 0.25 s ramps to a 0.2 m/s
    cruise, orientation held; the tool stays within 1 mm of the line's point throughout."""
    rob = robot("ur5")
    T0 = forward_kinematics(rob, rob.q_home)
    direction = np.array([0.6, 0.0, -0.8])
    v, ramp = 0.2, 0.25

    def reference(t: float):
        t = min(max(t, 0.0), 1.25)  # at rest after the end
        if t < ramp:
            s, sd, sdd = 0.5 * v / ramp * t * t, v / ramp * t, v / ramp
        elif t < 1.0:
            s, sd, sdd = 0.5 * v * ramp + v * (t - ramp), v, 0.0
        else:
            r = 1.25 - t
            s, sd, sdd = 0.2 - 0.5 * v / ramp * r * r, v / ramp * r, (-v / ramp if r > 0 else 0.0)
        T = T0.copy()
        T[:3, 3] = T0[:3, 3] + s * direction
        return T, np.concatenate([sd * direction, np.zeros(3)]), np.concatenate([sdd * direction, np.zeros(3)])

    sim = Simulation(rob, None, make_controller("resolved_rate", rob), reference=reference)
    worst = 0.0
    for _ in range(1500):
        sim.step()
        worst = max(worst, np.linalg.norm(forward_kinematics(rob, sim.q)[:3, 3] - reference(sim.time)[0][:3, 3]))
    assert sim.stopped is None
    assert worst < 1e-3, worst


def test_osc_follows_a_planned_cartesian_line_through_its_poses() -> None:
    """A Trajectory with poses as the reference (its poses, not its joints): Panda follows
    a 10 cm planned line within 1 mm."""
    rob = robot("panda")
    T0 = forward_kinematics(rob, rob.q_home)
    T1 = T0.copy()
    T1[:3, 3] += [0.06, -0.03, 0.07]
    line = cartesian_line(rob, T0, T1, 1.5, rob.q_home)
    sim = Simulation(rob, None, make_controller("osc", rob), reference=line)
    worst = 0.0
    for _ in range(200):
        sim.step(10)
        k = min(int(round(sim.time * 1000)), line.n_samples - 1)
        worst = max(worst, np.linalg.norm(forward_kinematics(rob, sim.q)[:3, 3] - line.poses[k, :3, 3]))
    assert worst < 1e-3, worst


@pytest.mark.parametrize("mode, bandwidth, steps", [("osc", 5.0, 1000), ("resolved_rate", 5.0, 1000),
                                                    pytest.param("impedance", 2.0, 6000, marks=pytest.mark.slow)])
def test_task_controllers_follow_the_tool_pose_of_the_desired_joints_without_a_reference(
    mode: str, bandwidth: float, steps: int
) -> None:
    """The sliders' path: with no reference a task controller tracks FK(q_des); on the
    non-redundant UR5 the joints arrive at q_des too.  (Impedance stays at 2 Hz: its
    default rotational damping at 5 Hz is more than the UR5's light wrist takes at 1 kHz.)"""
    rob = robot("ur5")
    state = RobotState(rob)
    goal = rob.q_home + np.array([0.2, -0.1, 0.15, 0.1, -0.2, 0.1])
    state.set_q_des(goal)
    sim = Simulation(rob, state, make_controller(mode, rob, bandwidth=bandwidth))
    sim.step(steps)
    np.testing.assert_allclose(sim.q, goal, atol=1e-4)


@pytest.mark.parametrize("mode", ["osc", "impedance", "resolved_rate"])
def test_batched_evaluation_equals_one_configuration_at_a_time(mode: str) -> None:
    rob = robot("panda")
    n = rob.n_dofs
    Q = rob.q_home + RNG.uniform(-0.3, 0.3, (4, n))
    QD = RNG.uniform(-0.5, 0.5, (4, n))
    poses = np.stack([_offset(forward_kinematics(rob, q)) for q in Q])
    twists, accels = RNG.normal(size=(4, 6)) * 0.1, RNG.normal(size=(4, 6)) * 0.1
    batch = make_controller(mode, rob).torque(Q, QD, poses, twists, accels)
    assert batch.shape == (4, n)
    for k in range(4):
        single = make_controller(mode, rob).torque(Q[k], QD[k], poses[k], twists[k], accels[k])
        np.testing.assert_allclose(batch[k], single, rtol=1e-10, atol=1e-10)
    shared = make_controller(mode, rob).torque(Q, QD, poses[0], twists[0], accels[0])
    np.testing.assert_allclose(shared[1], make_controller(mode, rob).torque(Q[1], QD[1], poses[0], twists[0], accels[0]),
                               rtol=1e-10, atol=1e-10)


def test_arms_with_fewer_than_six_joints_control_position_only() -> None:
    """Planar arm: the x, y rows only; the error response is the closed form there."""
    rob = frictionless("planar3")
    osc = make_controller("osc", rob, null_space=None)
    assert osc.rows.tolist() == [0, 1]
    q0 = rob.q_home + 0.3
    T_d = forward_kinematics(rob, q0)
    T_d[:3, 3] += [0.04, -0.03, 0.0]
    sim = Simulation(rob, _start(rob, q0), osc, reference=lambda t: (T_d, np.zeros(6), np.zeros(6)))
    for _ in range(10):
        sim.step(100)
        e = T_d[:2, 3] - forward_kinematics(rob, sim.q)[:2, 3]
        np.testing.assert_allclose(e, _second_order(np.array([0.04, -0.03]), np.zeros(2), osc.omega, 1.0, sim.time),
                                   atol=1e-6)


def test_bad_options_and_references_are_refused_naming_them() -> None:
    rob = robot("ur5")
    with pytest.raises(ValueError, match="osc takes the options bandwidth, damping, null_space, got stiffness"):
        make_controller("osc", rob, stiffness=1.0)
    with pytest.raises(ValueError, match='null_space must be "home"'):
        make_controller("osc", rob, null_space="up")
    with pytest.raises(ValueError, match="null_space must be .* 6 values"):
        make_controller("osc", rob, null_space=[0.0, 1.0])
    with pytest.raises(ValueError, match="stiffness must be .* symmetric positive semi-definite 6x6"):
        make_controller("impedance", rob, stiffness=-np.eye(6))
    with pytest.raises(ValueError, match="give stiffness or K, not both"):
        make_controller("impedance", rob, stiffness=1.0, K=2.0)
    with pytest.raises(ValueError, match="the pd controller takes only bandwidth and damping, got null_space"):
        make_controller("pd", rob, null_space=None)
    with pytest.raises(ValueError, match="gain must be a positive finite number"):
        make_controller("resolved_rate", rob, gain=-1.0)
    T = forward_kinematics(rob, rob.q_home)
    pose_reference = lambda t: (T, np.zeros(6), np.zeros(6))  # noqa: E731
    sim = Simulation(rob, None, make_controller("ct", rob), reference=pose_reference)
    with pytest.raises(ValueError, match="a task-space reference .* needs a task-space controller"):
        sim.step()
    assert sim.steps == 0
    with pytest.raises(ValueError, match=r"a task reference returns \(pose \(4, 4\), twist \(6,\), acceleration \(6,\)\)"):
        Simulation(rob, None, make_controller("osc", rob), reference=lambda t: (T, np.zeros(3), np.zeros(6)))
    with pytest.raises(ValueError, match=r"pose_d must be finite with shape \(4, 4\)"):
        make_controller("osc", rob).torque(rob.q_home, np.zeros(6), np.eye(3), np.zeros(6), np.zeros(6))
    with pytest.raises(ValueError, match=r"wrench must be a finite \(6,\)"):
        sim.set_tool_wrench([1.0, 2.0])


@pytest.mark.parametrize("name, convention", [("humanoid7", None), ("panda", None), ("panda", "standard"),
                                              ("ur5", "modified"), ("stanford", None), ("planar3", None)])
def test_the_compiled_law_and_step_equal_the_numpy_reference(name: str, convention: str | None) -> None:
    """The compiled OSC (one configuration, and the fused RK4 step the simulation takes)
    equals the NumPy law run on the reference dynamics: torques, accelerations and errors
    to 1e-11 relative at random states, and a 300-step run to 1e-10 rad."""
    rob = dataclasses.replace(robot(name, convention), q_min=np.full(robot(name).n_dofs, -np.inf),
                              q_max=np.full(robot(name).n_dofs, np.inf))
    n = rob.n_dofs
    for null_space in ("home", None):
        osc = make_controller("osc", rob, null_space=null_space)
        for _ in range(3):
            q, qd = rob.q_home + RNG.uniform(-0.4, 0.4, n), RNG.uniform(-1.0, 1.0, n)
            pose, twist, accel = _offset(forward_kinematics(rob, q)), RNG.normal(size=6), RNG.normal(size=6)
            joints = (rob.q_home + 0.2, RNG.normal(size=n), RNG.normal(size=n))
            for extra in ((), (joints,)):
                compiled = osc.torque(q, qd, pose, twist, accel, *extra), osc.commanded_acceleration().copy()
                with reference_dynamics():
                    reference = osc.torque(q, qd, pose, twist, accel, *extra), osc.commanded_acceleration().copy()
                for got, want in zip(compiled, reference):
                    np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-11 * np.abs(want).max())
    q0 = rob.q_home + 0.1
    runs = []
    for backend in ("compiled", "reference"):
        with reference_dynamics(backend == "reference"):
            sim = Simulation(rob, _start(rob, q0), make_controller("osc", rob),
                             reference=lambda t: (_offset(forward_kinematics(rob, q0)), np.zeros(6), np.zeros(6)))
            sim.step(300)
            runs.append(sim.q.copy())
    np.testing.assert_allclose(runs[0], runs[1], atol=1e-10)
