"""Time-optimal retiming (TOPP-RA): limits met at every sample, one limit active at every
sample, rest at both ends, q/q̇/q̈ consistent, closed-form bang-bang durations, the
spline through the waypoints, stops at repeated waypoints, effort through inverse
dynamics (friction included), errors."""
from __future__ import annotations

import numpy as np
import pytest

from kin_helpers import robot
from robot_sim.dynamics import inverse_dynamics
from robot_sim.planning.cartesian import qd_limits, qdd_limits
from robot_sim.planning.retime import retime
from robot_sim.planning.spline import JointSpline
from robot_sim.planning.topp import InfeasiblePath

RTOL = 1e-6


def random_path(arm, rng, k=4, step=0.4):
    lo, hi = arm.q_min, arm.q_max
    mid, width = (lo + hi) / 2, np.minimum(hi - lo, 2 * np.pi)
    q0 = mid + (rng.random(arm.n_dofs) - 0.5) * width * 0.5
    return np.clip(np.cumsum(np.vstack([q0, rng.normal(size=(k - 1, arm.n_dofs)) * step]), axis=0), lo, hi)


def effort_limits(arm):
    return np.asarray(arm.drives.effort_limit, dtype=float)


def ratios(arm, traj, v, a, effort):
    r = [np.max(np.abs(traj.qd) / v, axis=1), np.max(np.abs(traj.qdd) / a, axis=1)]
    if effort:
        tau = inverse_dynamics(arm, traj.q, traj.qd, traj.qdd)
        r.append(np.max(np.abs(tau) / effort_limits(arm), axis=1))
    return np.array(r)


@pytest.mark.parametrize("name, effort, a_max", [("ur5", False, None), ("humanoid7", False, None),
                                                 ("panda", True, 60.0), ("puma560", True, 60.0)])
def test_limits_met_one_active_everywhere_rest_at_both_ends(name, effort, a_max):
    arm = robot(name)
    path = random_path(arm, np.random.default_rng(3))
    traj = retime(arm, path, effort=effort, a_max=a_max)
    v = qd_limits(arm)
    a = qdd_limits(arm) if a_max is None else np.full(arm.n_dofs, a_max)
    r = ratios(arm, traj, v, a, effort)
    assert r.max() <= 1.0 + RTOL
    active = r.max(axis=0)
    if np.any(arm.drives.coulomb if arm.drives is not None else 0.0):
        # Coulomb friction vanishes at rest: the final sample's torque bounds the last
        # deceleration, which the moving samples just before it (friction helping) do not reach
        active = active[traj.t < traj.t[-1] - 5e-3]
    # time-optimal: some limit is active at every sample, to the discretisation's 2 %
    # (the grid is refined until no sample is further from its limits than that)
    assert active.min() >= 0.975, active.min()
    assert np.median(active) >= 0.999 and np.mean(active >= 0.99) >= 0.9
    if effort:  # effort limits bind somewhere with these acceleration limits
        assert r[2].max() >= 1.0 - 1e-3
    np.testing.assert_array_equal(traj.qd[[0, -1]], 0.0)
    np.testing.assert_allclose(traj.q[[0, -1]], path[[0, -1]], atol=1e-12)
    # q̇ is the derivative of q, q̈ that of q̇ (trapezoidal integration between samples;
    # q̈ jumps at the switches of the bang-bang law, so its integral is looser)
    dt = np.diff(traj.t)[:, None]
    assert np.abs(np.diff(traj.q, axis=0) - 0.5 * (traj.qd[1:] + traj.qd[:-1]) * dt).max() < a.max() * dt.max() ** 2
    assert np.abs(np.diff(traj.qd, axis=0) - 0.5 * (traj.qdd[1:] + traj.qdd[:-1]) * dt).max() < a.max() * dt.max()
    assert np.diff(traj.t).max() <= 1e-3 + 1e-12


@pytest.mark.parametrize("distance", [0.05, 2.0])
def test_straight_single_joint_move_takes_the_bang_bang_time(distance):
    arm = robot("ur5")
    q0 = np.zeros(arm.n_dofs)
    q1 = q0.copy()
    q1[1] = distance
    v, a = 1.5, 4.0
    traj = retime(arm, np.stack([q0, q1]), v_max=v, a_max=a, effort=False)
    if distance > v * v / a:  # trapezoid
        expected = distance / v + v / a
    else:  # triangle
        expected = 2 * np.sqrt(distance / a)
    assert traj.duration == pytest.approx(expected, rel=2e-3)
    np.testing.assert_allclose(traj.q[:, [0, 2, 3, 4, 5]], 0.0, atol=1e-12)


def test_the_geometry_is_the_spline_through_the_waypoints():
    arm = robot("humanoid7")
    path = random_path(arm, np.random.default_rng(5), k=5)
    traj = retime(arm, path, effort=False)
    spline = JointSpline.through(path)
    s = np.linspace(0, spline.length, 200001)
    dense, _, _ = spline.evaluate(s)
    # every sample lies on the spline (matched by arc length, both monotone), and the
    # spline passes every waypoint
    arc = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(dense, axis=0), axis=1))])
    arc_t = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(traj.q, axis=0), axis=1))])
    k = np.clip(np.searchsorted(arc, arc_t), 0, s.size - 1)
    assert np.linalg.norm(traj.q - dense[k], axis=1).max() < 1e-4
    np.testing.assert_allclose(spline.evaluate(spline.knots)[0], path, atol=1e-12)
    for wp in path:
        assert np.min(np.linalg.norm(traj.q - wp, axis=1)) < 5e-3


def test_a_repeated_waypoint_is_a_stop():
    arm = robot("ur5")
    path = random_path(arm, np.random.default_rng(7), k=4)
    stopped = np.insert(path, 2, path[2], axis=0)
    traj = retime(arm, stopped, effort=False)
    k = int(np.argmin(np.linalg.norm(traj.q - path[2], axis=1)))
    np.testing.assert_allclose(traj.q[k], path[2], atol=1e-12)
    np.testing.assert_array_equal(traj.qd[k], 0.0)
    # the straight-through version is faster
    assert retime(arm, path, effort=False).duration < traj.duration


def test_defaults_come_from_the_drives():
    arm = robot("panda")
    path = random_path(arm, np.random.default_rng(2))
    traj = retime(arm, path)
    v, a = qd_limits(arm), qdd_limits(arm)
    np.testing.assert_allclose(v, arm.drives.velocity_limit)
    r = ratios(arm, traj, v, a, effort=True)
    assert r.max() <= 1.0 + RTOL
    assert r[:2].max() >= 1.0 - 1e-3


def test_slower_limits_give_longer_trajectories_scaling_exactly():
    arm = robot("ur5")
    path = random_path(arm, np.random.default_rng(9))
    fast = retime(arm, path, v_max=2.0, a_max=8.0, effort=False)
    slow = retime(arm, path, v_max=1.0, a_max=2.0, effort=False)
    # halving v and quartering a is the same law twice as slow
    assert slow.duration == pytest.approx(2 * fast.duration, rel=2e-3)


def test_bad_input_is_named():
    arm = robot("ur5")
    with pytest.raises(ValueError, match="path must be"):
        retime(arm, np.zeros((3, 5)))
    bad = np.zeros((2, 6))
    bad[1, 2] = np.nan
    with pytest.raises(ValueError, match=r"path\[1\] joint 3"):
        retime(arm, bad)
    out = np.zeros((2, 6))
    out[1, 0] = 10.0
    with pytest.raises(ValueError, match="joint 1"):
        retime(arm, out)
    with pytest.raises(ValueError, match="v_max"):
        retime(arm, np.zeros((2, 6)), v_max=-1.0)
    with pytest.raises(ValueError, match="dt"):
        retime(arm, np.zeros((2, 6)), dt=0.0)


def test_gravity_beyond_the_effort_limit_is_infeasible():
    arm = robot("panda")
    q = (arm.q_min + arm.q_max) / 2
    q[1] = 1.2  # shoulder out: gravity torque on joint 2 well above 1 N·m
    path = np.stack([q, q + 0.1])
    from dataclasses import replace
    weak = replace(arm, drives=replace(arm.drives, effort_limit=np.full(arm.n_dofs, 1.0)))
    with pytest.raises(InfeasiblePath, match="joint 2 needs .* above its effort limit 1"):
        retime(weak, path)


def test_a_repeated_configuration_is_a_hold_and_a_single_waypoint_is_refused():
    """Issue 31: one waypoint is almost always a caller's mistake (a path cut to its start),
    so it is refused in one line; a path that stays put ([q, q]) is a hold."""
    arm = robot("ur5")
    traj = retime(arm, np.zeros((2, 6)))
    assert traj.n_samples == 1 and traj.duration == 0.0
    with pytest.raises(ValueError) as info:
        retime(arm, np.zeros((1, 6)))
    assert str(info.value) == "path holds one waypoint: retiming needs at least 2 (to stay at q, use hold(q, duration))"
