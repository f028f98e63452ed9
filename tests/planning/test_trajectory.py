"""trajectory.py: closed-form boundary conditions, limits, via points, Cartesian geometry,
continuity, failure reports, CSV round trip and bad input."""
from __future__ import annotations

import numpy as np
import pytest

from kin_helpers import robot
from robot_sim.kinematics import forward_kinematics
from robot_sim.model.params import RobotParams
from robot_sim.planning.scaling import (
    CartesianPathError,
    Trajectory,
    cartesian_arc,
    cartesian_line,
    qd_limits,
    quintic,
    scale_to_limits,
    trapezoidal,
    via_points,
)
from robot_sim.transforms import rot_from_angle_axis, rotation_log

Q0, Q1 = np.array([0.3, -1.0, 2.0]), np.array([-0.5, 0.4, 2.0])


def test_quintic_meets_all_six_boundary_conditions():
    qd0, qd1, qdd0, qdd1 = [0.2, 0.0, -0.1], [0.0, 0.5, 0.0], [1.0, 0.0, 0.3], [0.0, -2.0, 0.1]
    tr = quintic(Q0, Q1, 1.7, qd0=qd0, qd1=qd1, qdd0=qdd0, qdd1=qdd1)
    assert tr.t[0] == 0.0 and tr.t[-1] == 1.7
    for got, want in [(tr.q[0], Q0), (tr.q[-1], Q1), (tr.qd[0], qd0), (tr.qd[-1], qd1),
                      (tr.qdd[0], qdd0), (tr.qdd[-1], qdd1)]:
        np.testing.assert_allclose(got, want, atol=1e-12)


def test_quintic_default_rest_to_rest_at_1khz_and_derivatives_consistent():
    tr = quintic(Q0, Q1, 2.0)
    assert tr.n_samples == 2001 and np.allclose(np.diff(tr.t), 1e-3)
    np.testing.assert_allclose(tr.qd[[0, -1]], 0.0, atol=1e-12)
    np.testing.assert_allclose(tr.qdd[[0, -1]], 0.0, atol=1e-12)
    # peak speed of the rest-to-rest quintic is 15/8 Δ/T at mid-time
    np.testing.assert_allclose(np.abs(tr.qd).max(axis=0), 15 / 8 * np.abs(Q1 - Q0) / 2.0, rtol=1e-9)
    np.testing.assert_allclose(np.gradient(tr.q, tr.t, axis=0)[1:-1], tr.qd[1:-1], atol=2e-6)


@pytest.mark.parametrize("v_max, a_max", [([1.0, 0.5, 1.0], [2.0, 2.0, 2.0]), (5.0, 0.7)])
def test_trapezoid_respects_limits_and_joints_finish_together(v_max, a_max):
    tr = trapezoidal(Q0, Q1, v_max, a_max)
    vm, am = np.broadcast_to(v_max, 3), np.broadcast_to(a_max, 3)
    assert (np.abs(tr.qd) <= vm * (1 + 1e-12)).all()
    assert (np.abs(tr.qdd) <= am * (1 + 1e-12)).all()
    # the tightest limit is met exactly (as fast as allowed)
    ratio = max(np.max(np.abs(tr.qd) / vm), np.max(np.abs(tr.qdd) / am))
    assert ratio == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(tr.q[-1], Q1, atol=1e-12)
    moving = np.abs(Q1 - Q0) > 0
    # every moving joint is still moving one sample before the end, all at rest at the end
    assert (np.abs(tr.q[-2, moving] - Q1[moving]) > 0).all()
    np.testing.assert_allclose(tr.qd[-1], 0.0, atol=1e-12)
    # synchronised: every joint has covered the same fraction of its distance at every sample
    frac = (tr.q[:, moving] - Q0[moving]) / (Q1 - Q0)[moving]
    np.testing.assert_allclose(frac, frac[:, :1].repeat(moving.sum(), axis=1), atol=1e-12)


def test_trapezoid_closed_form_duration():
    # one joint, 2 rad at v 1, a 2: blends of 0.5 s, cruise 1.5 s -> 2.5 s
    assert trapezoidal([0.0], [2.0], 1.0, 2.0).duration == pytest.approx(2.5, abs=1e-12)
    # triangle: 0.5 rad at a 2 -> 2 sqrt(0.5/2) = 1 s, peak 1 rad/s
    tri = trapezoidal([0.0], [0.5], 10.0, 2.0)
    assert tri.duration == pytest.approx(1.0, abs=1e-12)
    assert np.abs(tri.qd).max() == pytest.approx(1.0, abs=1e-9)


def test_trapezoid_times_past_the_end_hold_the_goal():
    tr = trapezoidal([0.0, 0.0], [1.0, -1.0], 1.0, 1.0, times=[0.0, 1.0, 100.0])
    np.testing.assert_allclose(tr.q[-1], [1.0, -1.0], atol=1e-12)
    np.testing.assert_allclose(tr.qd[-1], 0.0, atol=1e-12)


VIAS = np.array([[0.0, 0.0, 0.0], [1.0, 0.5, -0.2], [1.5, -0.5, 0.3], [0.2, 0.1, 0.0]])


@pytest.mark.parametrize("blend", [None, 0.3, 1.5])
def test_via_path_passes_through_via_points_within_limits(blend):
    v_max, a_max = np.array([1.0, 0.8, 1.2]), np.array([2.0, 3.0, 2.0])
    tr = via_points(VIAS, v_max, a_max, blend=blend)
    assert [m for _, m in tr.marks] == ["via 1", "via 2"]
    for (tm, _), via in zip(tr.marks, VIAS[1:-1]):
        i = int(np.argmin(np.abs(tr.t - tm)))
        assert tr.t[i] == pytest.approx(tm, abs=1e-9)
        np.testing.assert_allclose(tr.q[i], via, atol=1e-9)
        np.testing.assert_allclose(tr.evaluate(tm)[0], via, atol=1e-9)
    np.testing.assert_allclose(tr.q[[0, -1]], VIAS[[0, -1]], atol=1e-12)
    np.testing.assert_allclose(tr.qd[[0, -1]], 0.0, atol=1e-12)
    assert (np.abs(tr.qd) <= v_max * (1 + 1e-9)).all() and (np.abs(tr.qdd) <= a_max * (1 + 1e-9)).all()
    # velocity is continuous: no step larger than a_max * dt between samples
    assert (np.abs(np.diff(tr.qd, axis=0)) <= a_max * np.diff(tr.t)[:, None] * (1 + 1e-9)).all()


def test_via_points_out_of_limits_named():
    arm = robot("puma560")
    qs = np.tile(arm.q_home, (3, 1))
    qs[1, 2] = arm.q_max[2] + 0.1
    with pytest.raises(ValueError, match=r"^qs\[1\]: joint 3 = .* is outside its limits \["):
        via_points(qs, 1.0, 1.0, robot=arm)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: quintic(Q0, Q1, 0.0), "duration must be a positive finite number of seconds, got 0.0"),
        (lambda: quintic(Q0, Q1, 1.0, times=[0.0, 0.5, 0.5]), r"times must be strictly increasing: times\[1\] = 0.5 >= times\[2\] = 0.5"),
        (lambda: quintic(Q0, [0.0, np.nan, 1.0], 1.0), r"q1\[1\] is nan; expected a finite number"),
        (lambda: quintic(Q0, Q1, 1.0, times=[0.0, 2.0]), r"times must lie within \[0, 1.0\] s"),
        (lambda: trapezoidal(Q0, Q1, [1.0, 0.0, 1.0], 1.0), r"v_max\[1\] is 0.0; expected a positive number"),
        (lambda: via_points([[0.0, 1.0]], 1.0, 1.0), r"qs must have shape \(M >= 2, n\), got \(1, 2\)"),
        (lambda: via_points([[0.0], [np.inf]], 1.0, 1.0), r"qs\[1\] joint 1 is inf"),
        (lambda: Trajectory([0.0, 1.0, 0.5], np.zeros((3, 1)), np.zeros((3, 1)), np.zeros((3, 1))), r"t must be strictly increasing"),
    ],
)
def test_bad_input_names_what_and_where(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_evaluate_batched_matches_samples_and_interpolates_smoothly():
    tr = quintic(Q0, Q1, 1.0, times=np.linspace(0, 1, 101))
    q, qd, qdd = tr.evaluate(tr.t)
    np.testing.assert_allclose(q, tr.q, atol=1e-15)
    fine = quintic(Q0, Q1, 1.0, times=np.linspace(0, 1, 1001))
    q, qd, _ = tr.evaluate(fine.t)
    assert q.shape == (1001, 3)
    np.testing.assert_allclose(q, fine.q, atol=1e-7)  # Hermite: O(h^4)
    np.testing.assert_allclose(qd, fine.qd, atol=1e-3)
    q1, _, _ = tr.evaluate(0.537)
    assert q1.shape == (3,)
    np.testing.assert_allclose(tr.evaluate(50.0)[0], Q1, atol=1e-12)


def _slerp(R0, R1, s):
    w = rotation_log(R0.T @ R1)
    return R0 @ rot_from_angle_axis(s * np.linalg.norm(w), w)


@pytest.mark.parametrize("name", ["ur5", "puma560", "humanoid7"])
@pytest.mark.parametrize("scaling", ["quintic", "trapezoidal"])
def test_cartesian_line_stays_on_line_and_follows_slerp(name, scaling):
    arm = robot(name)
    q0 = arm.q_home + np.linspace(0.2, -0.3, arm.n_dofs)
    T0 = forward_kinematics(arm, q0)
    T1 = T0.copy()
    T1[:3, 3] += [0.08, -0.05, -0.12]
    T1[:3, :3] = rot_from_angle_axis(0.4, [1.0, 1.0, 0.0]) @ T0[:3, :3]
    tr = cartesian_line(arm, T0, T1, 1.0, q0, scaling=scaling)
    fk = forward_kinematics(arm, tr.q)
    p0, p1 = T0[:3, 3], T1[:3, 3]
    u = (p1 - p0) / np.linalg.norm(p1 - p0)
    rel = fk[:, :3, 3] - p0
    off_line = np.linalg.norm(rel - (rel @ u)[:, None] * u, axis=1)
    assert off_line.max() < 1e-6
    s = (rel @ u) / np.linalg.norm(p1 - p0)  # path parameter recovered from the position
    assert s.min() > -1e-6 and s.max() < 1 + 1e-6 and (np.diff(s) > -1e-9).all()
    rot_err = [np.linalg.norm(rotation_log(fk[k, :3, :3].T @ _slerp(T0[:3, :3], T1[:3, :3], s[k])))
               for k in range(0, tr.n_samples, 7)]
    assert max(rot_err) < 1e-6
    # continuity: no joint moves faster than its speed limit between two samples
    step = np.abs(np.diff(tr.q, axis=0)) / np.diff(tr.t)[:, None]
    assert (step <= qd_limits(arm)).all()
    np.testing.assert_allclose(tr.poses[-1], T1, atol=1e-12)


def test_cartesian_arc_keeps_radius_and_plane():
    arm = robot("ur5")
    q0 = arm.q_home + np.linspace(0.2, -0.3, arm.n_dofs)
    T0 = forward_kinematics(arm, q0)
    centre = T0[:3, 3] + [0.0, 0.08, 0.0]
    tr = cartesian_arc(arm, T0, centre, [0.0, 0.0, 1.0], np.pi / 2, 1.5, q0)
    p = forward_kinematics(arm, tr.q)[:, :3, 3]
    np.testing.assert_allclose(np.linalg.norm((p - centre)[:, :2], axis=1), 0.08, atol=1e-6)
    np.testing.assert_allclose(p[:, 2], centre[2], atol=1e-6)
    np.testing.assert_allclose(p[-1], centre + [0.08, 0.0, 0.0], atol=1e-6)


def test_cartesian_line_out_of_reach_reports_sample_and_stops_at_last_reachable():
    arm = robot("ur5")
    q0 = arm.q_home + np.linspace(0.2, -0.3, arm.n_dofs)
    T0 = forward_kinematics(arm, q0)
    T1 = T0.copy()
    T1[:3, 3] = T0[:3, 3] + 2.0 * T0[:3, 3] / np.linalg.norm(T0[:3, 3])  # 2 m further out
    with pytest.raises(CartesianPathError) as info:
        cartesian_line(arm, T0, T1, 1.0, q0)
    err = info.value
    assert str(err).startswith(f"Cartesian path cannot be followed at sample {err.sample} of 1001 (t = ")
    assert "; stopped at sample" in str(err)
    assert 0 < err.sample < 1000
    part = err.trajectory
    assert part.n_samples == err.sample
    np.testing.assert_allclose(forward_kinematics(arm, part.q), part.poses, atol=1e-8)
    # the failing pose is past the arm's reach from the base
    assert np.linalg.norm(err.pose[:3, 3] - arm.base_tf.t()) > np.linalg.norm(part.poses[-1][:3, 3] - arm.base_tf.t())


def test_cartesian_line_through_a_singularity_is_refused():
    # planar 2R arm: stretched out is singular; a line through the base point region folds it
    arm = RobotParams.from_arrays("2R", [1.0, 1.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0, 0])
    q0 = np.array([0.0, 0.6])
    T0 = forward_kinematics(arm, q0)
    T1 = T0.copy()
    T1[:3, 3] = [2.5, 0.0, 0.0]
    with pytest.raises(CartesianPathError) as info:
        cartesian_line(arm, T0, T1, 1.0, q0)
    assert info.value.reason.startswith(("singular", "out of reach", "joint 2 would move at"))
    assert info.value.trajectory is not None


def test_csv_round_trip(tmp_path):
    arm = robot("ur5")
    q0 = arm.q_home + 0.2
    T0 = forward_kinematics(arm, q0)
    T1 = T0.copy()
    T1[2, 3] -= 0.05
    tr = cartesian_line(arm, T0, T1, 0.5, q0, times=np.linspace(0.0, 0.5, 51))
    tr = Trajectory(tr.t, tr.q, tr.qd, tr.qdd, tr.poses, ((0.01, "approach, down"),))
    path = tmp_path / "line.csv"
    tr.to_csv(path)
    back = Trajectory.from_csv(path)
    for name in ("t", "q", "qd", "qdd", "poses"):
        np.testing.assert_array_equal(getattr(back, name), getattr(tr, name))
    assert back.marks == tr.marks
    joint = quintic(Q0, Q1, 0.1)
    joint.to_csv(path)
    back = Trajectory.from_csv(path)
    assert back.poses is None
    np.testing.assert_array_equal(back.q, joint.q)
    assert path.read_text().splitlines()[0] == "t,q1,q2,q3,qd1,qd2,qd3,qdd1,qdd2,qdd3"


def test_csv_bad_file_names_line(tmp_path):
    path = tmp_path / "bad.csv"
    path.write_text("t,q1,qd1,qdd1\n0,0,0,0\n0.1,0,zero,0\n")
    with pytest.raises(ValueError, match=r"bad.csv: line 3: not a number in '0.1,0,zero,0'"):
        Trajectory.from_csv(path)


def test_scale_to_limits_slows_uniformly_to_the_limit():
    tr = quintic(Q0, Q1, 0.5)
    slow = scale_to_limits(tr, qd_max=0.5, qdd_max=10.0)
    assert np.abs(slow.qd).max() == pytest.approx(0.5, rel=1e-12)
    np.testing.assert_array_equal(slow.q, tr.q)
    # the scaled motion is the same quintic over the longer duration
    np.testing.assert_allclose(slow.q, quintic(Q0, Q1, slow.duration, times=slow.t).q, atol=1e-12)


def test_scale_to_limits_meets_effort_limits_exactly_with_friction():
    import dataclasses

    from robot_sim import dynamics

    arm = robot("puma560")
    tr = quintic(arm.q_home, arm.q_home + [0.8, -0.6, 0.9, 0.5, -0.7, 1.0], 0.6)
    fast = np.abs(dynamics.inverse_dynamics(arm, tr.q, tr.qd, tr.qdd)).max(axis=0)
    crawl = np.abs(dynamics.inverse_dynamics(arm, tr.q, tr.qd / 1e3, tr.qdd / 1e6)).max(axis=0)
    limit = crawl + 0.3 * (fast - crawl) + 0.5
    limited = dataclasses.replace(arm, drives=dataclasses.replace(arm.drives, effort_limit=limit))
    assert (fast > limit).any()
    slow = scale_to_limits(tr, qd_max=np.inf, robot=limited, effort=True)
    ratio = np.abs(dynamics.inverse_dynamics(limited, slow.q, slow.qd, slow.qdd)) / limit
    assert ratio.max() <= 1.0 and ratio.max() > 1.0 - 1e-5  # the tightest joint at its limit
    np.testing.assert_array_equal(slow.q, tr.q)
    # gravity and friction alone above a limit: no time scaling helps, and it says where
    hopeless = dataclasses.replace(arm, drives=dataclasses.replace(arm.drives, effort_limit=0.5 * crawl + 1e-9))
    with pytest.raises(ValueError, match=r"^sample \d+ \(t = .* s\): joint \d needs more than its effort limit"):
        scale_to_limits(tr, robot=hopeless, effort=True)
