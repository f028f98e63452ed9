"""Every real solution of general 6R arms (issue 29, item 3): random DH tables in both
conventions with random base and tool, the 16 real solutions of Manocha and Canny's
example, and an independent oracle (Newton's method from many random starts, on
robot_sim.kinematics' forward kinematics and Jacobian) that must find nothing we miss."""
from __future__ import annotations

import numpy as np
import pytest

from ik_helpers import REACH_TOL, check_complete, pose_errors
from kin_helpers import CONVENTIONS
from robot_sim.ik.family import ik_family
from robot_sim.ik.solutions import ik_solutions
from robot_sim.kinematics import forward_kinematics, jacobian, solve_ik
from robot_sim.model.convert import to_convention
from robot_sim.model.params import RobotParams
from robot_sim.transforms import HomogeneousTransform, rot_from_rpy, rotation_log

TABLES = 10  # random tables per convention
POSES = 50  # random configurations per table: 2 × 10 × 50 = 1000 in all


def general_6r(rng: np.random.Generator, convention: str, special: tuple[str, ...] = ()) -> RobotParams:
    """A random 6R table with no two axes meeting or parallel (twists 0.3-2.8 rad, every
    length nonzero), and a random base and tool, in the given convention.  ``special``
    makes axes 1, 2 ("1-2 parallel", "1-2 meet") or 5, 6 ("5-6 parallel") so."""
    a = rng.uniform(0.05, 0.5, 6) * rng.choice([-1.0, 1.0], 6)
    d = rng.uniform(0.05, 0.4, 6) * rng.choice([-1.0, 1.0], 6)
    alpha = rng.uniform(0.3, 2.8, 6) * rng.choice([-1.0, 1.0], 6)
    if "1-2 parallel" in special:
        alpha[0] = 0.0
    if "1-2 meet" in special:
        a[0] = d[1] = 0.0
    if "5-6 parallel" in special:
        alpha[4] = 0.0

    def tf() -> HomogeneousTransform:
        return HomogeneousTransform.from_rt(rot_from_rpy(rng.uniform(-np.pi, np.pi, 3)), rng.uniform(-0.3, 0.3, 3))

    robot = RobotParams.from_arrays("random 6R", a, alpha, d, rng.uniform(-np.pi, np.pi, 6), np.zeros(6),
                                    q_min=np.full(6, -np.pi), q_max=np.full(6, np.pi), base_tf=tf(), tool_tf=tf())
    return to_convention(robot, convention)


def _wrapped(D: np.ndarray) -> np.ndarray:
    return (D + np.pi) % (2.0 * np.pi) - np.pi


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_random_general_6r_complete(convention: str) -> None:
    """1000 configurations in all: the generating one is among the solutions, every
    solution reaches T to 1e-10 m and rad, no two are the same (check_complete)."""
    rng = np.random.default_rng(29 + len(convention))
    counts = []
    for _ in range(TABLES):
        robot = general_6r(rng, convention)
        assert robot.convention == convention
        family = ik_family(robot)
        assert family.name == "general 6R" and not family.closed_form
        Q = rng.uniform(-np.pi, np.pi, (POSES, 6))
        counts.append(check_complete(robot, Q, within_limits=True))
        check_complete(robot, Q[:5], within_limits=False)
    assert sum(counts) >= 2 * TABLES * POSES  # solutions come in pairs at least


def test_limits_wider_than_a_turn_list_every_wrap() -> None:
    """Joints limited to ±1.2π: each branch comes with every turn inside the limits, so the
    generating configuration itself (not only modulo 2π) is among the solutions."""
    rng = np.random.default_rng(30)
    base = general_6r(rng, "modified")
    robot = RobotParams.from_arrays("wide 6R", base.dh_a, base.dh_alpha, base.dh_d, base.dh_th, base.jtype,
                                    convention="modified", q_min=np.full(6, -1.2 * np.pi),
                                    q_max=np.full(6, 1.2 * np.pi), base_tf=base.base_tf, tool_tf=base.tool_tf)
    Q = rng.uniform(-1.2 * np.pi, 1.2 * np.pi, (40, 6))
    check_complete(robot, Q, within_limits=True)
    raw = ik_solutions(robot, forward_kinematics(robot, Q[0]), within_limits=False)
    wide = ik_solutions(robot, forward_kinematics(robot, Q[0]))
    assert len(wide) > len(raw)  # 2^6 turn choices per branch at most, and some inside


@pytest.mark.parametrize("special", ["1-2 parallel", "1-2 meet"])
def test_axes_1_and_2_special_solved_read_from_the_tool(special: str) -> None:
    """Where axes 1 and 2 meet or run parallel the elimination's determinant vanishes for
    every q3; the chain read from the tool back is solved instead, just as completely."""
    rng = np.random.default_rng(31)
    for convention in CONVENTIONS:
        robot = general_6r(rng, convention, (special,))
        assert ik_family(robot).name == "general 6R"
        check_complete(robot, rng.uniform(-np.pi, np.pi, (40, 6)))


def test_both_ends_special_is_left_to_the_numerical_ik() -> None:
    rng = np.random.default_rng(32)
    robot = general_6r(rng, "standard", ("1-2 parallel", "5-6 parallel"))
    assert ik_family(robot).name == "general 6R"
    T = forward_kinematics(robot, rng.uniform(-np.pi, np.pi, 6))
    with pytest.raises(ValueError, match="random 6R: a general 6R whose axes 1, 2 and axes 5, 6 both meet or run "
                                         "parallel has no elimination here; use solve_ik"):
        ik_solutions(robot, T)
    result = solve_ik(robot, T)
    assert result.success and "analytic" not in result.message


#: Manocha & Canny, "Efficient inverse kinematics for general 6R manipulators", IEEE
#: T-RA 10(5), 1994, Table I (standard DH; problem 6 of Wampler & Morgan 1991, a variant of
#: Manseur & Doty's arm with 16 real solutions, IJRR 8(5), 1989): a [m], d [m], α [deg].
MC_A = [0.3, 1.0, 0.0, 1.5, 0.0, 0.0]
MC_D = [0.0, 0.0, 0.2, 0.0, 0.0, 0.0]
MC_ALPHA = [90.0, 1.0, 90.0, 1.0, 90.0, 1.0]
#: Their Table III: the 16 solutions of their pose [deg], to 0.01°.
MC_SOLUTIONS = np.array([
    [-96.28, -6.27, 179.96, 38.48, 52.55, -39.40], [-120.78, 172.33, -179.07, 31.33, -146.71, 142.82],
    [88.67, -176.72, -176.72, -63.24, 157.19, 140.43], [113.84, 5.30, -177.74, -55.92, -62.98, -43.37],
    [-178.12, 108.19, -147.73, -5.69, -164.67, 179.58], [168.32, -103.89, 146.60, -17.24, -171.87, 98.16],
    [-12.94, -105.09, -114.97, 3.02, 7.41, -79.42], [2.51, 108.07, 112.04, -10.52, 0.00, -0.10],
    [2.51, 108.07, -67.95, -169.47, 179.99, 179.89], [-12.94, -105.09, 65.02, 176.97, 172.58, 100.57],
    [168.32, -103.89, -33.39, -162.75, -8.12, -81.83], [-178.12, 108.19, 32.26, -174.30, -15.32, -0.41],
    [88.67, -176.72, 3.27, -116.75, 22.80, -39.56], [-96.28, -6.27, -0.03, 141.51, 127.44, 140.59],
    [-120.78, 172.33, 0.92, 148.66, -33.28, -37.17], [113.84, 5.30, 2.25, -124.07, -117.01, 136.62]])


def manocha_canny(convention: str = "standard") -> RobotParams:
    robot = RobotParams.from_arrays("Manocha-Canny 6R", np.array(MC_A), np.radians(MC_ALPHA), np.array(MC_D),
                                    np.zeros(6), np.zeros(6), q_min=np.full(6, -np.pi), q_max=np.full(6, np.pi))
    return to_convention(robot, convention)


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_manocha_canny_sixteen_real_solutions(convention: str) -> None:
    """The pose of their solution 8 (their pose up to the table's rounding) has 16 real
    solutions, each within 0.05° of one of their table's rows, one to one."""
    robot = manocha_canny(convention)
    assert ik_family(robot).name == "general 6R"
    T = forward_kinematics(robot, np.radians(MC_SOLUTIONS[7]))
    sols = ik_solutions(robot, T, within_limits=False)
    assert sols.count == 16 and sols.exact.all()
    pos, rot = pose_errors(robot, sols.q, T)
    assert pos.max() <= REACH_TOL and rot.max() <= REACH_TOL
    gap = np.abs(_wrapped(np.radians(MC_SOLUTIONS)[:, None] - sols.q[None])).max(axis=2)  # (theirs, ours)
    nearest = gap.argmin(axis=1)
    assert sorted(nearest) == list(range(16))
    assert np.degrees(gap.min(axis=1)).max() < 0.05
    assert sorted(sols.branch) == sorted(f"solution {k}" for k in range(1, 17))


def newton_oracle(robot: RobotParams, T: np.ndarray, starts: np.ndarray, steps: int = 60) -> np.ndarray:
    """Independent of robot_sim.ik: Newton's method from every start (N, 6) at once on
    e(q) = [p_T − p; sin θ k], θ k the rotation R_T Rᵀ still to go, with
    robot_sim.kinematics' Jacobian (least squares by the pseudo-inverse); a step that does
    not lower ‖e‖ is halved, up to 20 times, after which that start stops.  Returns the
    configurations whose position error [m] and angle θ [rad] are within 1e-11 together,
    wrapped."""

    def error(Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        F = forward_kinematics(robot, Q)
        D = T[:3, :3] @ F[:, :3, :3].transpose(0, 2, 1)
        w = 0.5 * np.stack([D[:, 2, 1] - D[:, 1, 2], D[:, 0, 2] - D[:, 2, 0], D[:, 1, 0] - D[:, 0, 1]], axis=1)
        angle = np.arctan2(np.linalg.norm(w, axis=1), 0.5 * (np.trace(D, axis1=1, axis2=2) - 1.0))
        return np.concatenate([T[:3, 3] - F[:, :3, 3], w], axis=1), angle

    Q = starts.copy()
    E, angle = error(Q)
    live = np.ones(len(Q), dtype=bool)
    for _ in range(steps):
        live &= np.linalg.norm(E, axis=1) >= 1e-12
        idx = np.flatnonzero(live)
        if idx.size == 0:
            break
        step = (np.linalg.pinv(jacobian(robot, Q[idx])) @ E[idx, :, None])[:, :, 0]
        pending = np.arange(idx.size)  # positions in idx still looking for a lower error
        for _ in range(20):
            rows = idx[pending]
            trial = Q[rows] + step[pending]
            E_trial, angle_trial = error(trial)
            better = np.linalg.norm(E_trial, axis=1) < np.linalg.norm(E[rows], axis=1)
            Q[rows[better]], E[rows[better]], angle[rows[better]] = trial[better], E_trial[better], angle_trial[better]
            pending = pending[~better]
            if pending.size == 0:
                break
            step[pending] *= 0.5
        live[idx[pending]] = False
    converged = np.hypot(np.linalg.norm(E[:, :3], axis=1), angle) < 1e-11
    return _wrapped(Q[converged]).reshape(-1, 6)


@pytest.mark.parametrize("case", range(4))
def test_no_solution_missing_against_random_start_newton(case: int) -> None:
    """Every solution Newton's method finds from 150 random starts is in our set (modulo 2π)."""
    rng = np.random.default_rng(700 + case)
    robot = manocha_canny() if case == 0 else general_6r(rng, CONVENTIONS[case % 2])
    q_true = np.radians(MC_SOLUTIONS[7]) if case == 0 else rng.uniform(-np.pi, np.pi, 6)
    T = forward_kinematics(robot, q_true)
    ours = ik_solutions(robot, T, within_limits=False).q
    oracle = newton_oracle(robot, T, rng.uniform(-np.pi, np.pi, (150, 6)))
    assert len(oracle) > 0
    gap = np.abs(_wrapped(oracle[:, None] - ours[None])).max(axis=2).min(axis=1)
    assert gap.max() < 1e-6, oracle[gap.argmax()]
    same = np.abs(_wrapped(oracle[:, None] - oracle[None])).max(axis=2) < 1e-6  # modulo 2π
    distinct = {int(np.argmax(row)) for row in same}  # the first of each one's equals
    assert len(distinct) <= len(ours)


def test_batch_equals_single() -> None:
    rng = np.random.default_rng(5)
    robot = general_6r(rng, "modified")
    T = forward_kinematics(robot, rng.uniform(-np.pi, np.pi, (6, 6)))
    batch = ik_solutions(robot, T)
    for i in range(len(T)):
        one = ik_solutions(robot, T[i])
        k = batch.count[i]
        assert one.count == k
        np.testing.assert_array_equal(one.q, batch.q[i, :k])
        assert one.branch == tuple(batch.branch[i, :k])
        assert np.isnan(batch.q[i, k:]).all()


def test_solve_ik_takes_the_nearest_solution() -> None:
    """solve_ik answers a general 6R by the solution nearest q0, and says so."""
    rng = np.random.default_rng(8)
    robot = general_6r(rng, "standard")
    T = forward_kinematics(robot, rng.uniform(-np.pi, np.pi, 6))
    q0 = rng.uniform(-np.pi, np.pi, 6)
    result = solve_ik(robot, T, q0)
    assert result.success and "analytic" in result.message
    np.testing.assert_array_equal(result.q, ik_solutions(robot, T, q0).q[0])


def test_pose_out_of_reach_gives_least_squares_configurations() -> None:
    """No exact solution: the configurations returned (exact False) are local minima of
    the pose error the solver minimises, |Δp|²/size² + |log(R_T Rᵀ)|²: no small joint
    move lowers it."""
    rng = np.random.default_rng(9)
    robot = general_6r(rng, "standard")
    T = forward_kinematics(robot, rng.uniform(-np.pi, np.pi, 6))
    T[:3, 3] *= 10.0
    sols = ik_solutions(robot, T)
    assert sols.count >= 1 and not sols.exact.any() and np.isfinite(sols.q).all()
    size = max(robot.size, 1.0)

    def cost(q: np.ndarray) -> float:
        pos, _ = pose_errors(robot, q[None], T)
        F = forward_kinematics(robot, q)
        return float(pos[0] ** 2 / size ** 2 + np.sum(rotation_log(T[:3, :3] @ F[:3, :3].T) ** 2))

    for q in sols.q:
        here = cost(q)
        for step in rng.normal(size=(20, 6)) * 1e-4:
            assert cost(q + step) >= here * (1.0 - 1e-12)
