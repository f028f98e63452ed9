"""Pass 1 within the limits checks by forward kinematics only the branches with a turn
inside them (robot_sim.ik.finish.check_within), and the screen keeps exactly what it
keeps with every branch checked: the same rows, codes, exactness and counts, on poses
reached inside the limits, reached only outside them, and out of reach."""
from __future__ import annotations

import numpy as np

from kin_helpers import robot
from robot_sim.ik.family import solver
from robot_sim.ik.finish import EVERY_TURN, LANES, NEAREST_TURN, check_within, fk_lanes, live_lanes, screen
from robot_sim.ik.solutions import EXACT_TOL
from robot_sim.kinematics import forward_kinematics


def lanes_of(arm, rng: np.random.Generator) -> tuple:  # noqa: ANN001
    """Six poses of 8 branches each, as pass 1 lays them out (lane p·8 + k): pose p's
    configuration Q[p] (inside the limits for poses 0-2, outside for 3 and 4), then 7
    others (Q[p] turned by whole turns, by a joint beyond its limit, or at random); pose 5
    is out of reach.  Returns (Q, T, q (n, 48), cs (2n, 48), pose (48,))."""
    n, L = arm.n_dofs, 8
    lo, hi = arm.q_min, arm.q_max
    Q = rng.uniform(lo, hi, (6, n))
    Q[3:5, 4] = hi[4] + 0.5  # the wrist bent past its limit: reached only outside the limits
    T = forward_kinematics(arm, Q)
    T[5, :3, 3] *= 4.0
    q = np.empty((n, 6 * L))
    for p in range(6):
        for k in range(L):
            x = Q[p].copy()
            if k in (1, 2):
                x[rng.integers(n)] += 2 * np.pi * rng.choice([-1, 1])
            elif k in (3, 4):
                j = rng.integers(n)
                x[j] = hi[j] + rng.uniform(0.01, 0.5)
            elif k >= 5:
                x = rng.uniform(lo - 1.0, hi + 1.0)
            q[:, p * L + k] = x
    cs = np.empty((2 * n, 6 * L))
    cs[0::2], cs[1::2] = np.cos(q), np.sin(q)
    return Q, T, q, cs, np.repeat(np.arange(6), L)


def screened(arm, q: np.ndarray, pos: np.ndarray, rot: np.ndarray, mode: int) -> list:  # noqa: ANN001
    """What the screen keeps of each pose's 8 branches with these errors."""
    sv = solver(arm)
    n, tol = arm.n_dofs, EXACT_TOL * max(sv.size, 1.0)
    raw = np.ascontiguousarray(q.T.reshape(6, 8, n))
    code = np.tile(np.arange(8), (6, 1))
    exact = np.zeros((6, 8), dtype=np.bool_)
    pos, rot = pos.copy(), rot.copy()
    kept = [screen(raw, code, exact, p, 8, pos, rot, 8 * p, sv.screws.revolute, arm.q_min, arm.q_max, mode, tol, True)
            for p in range(6)]
    return [(kept[p], raw[p, :kept[p][0]].tolist(), code[p, :kept[p][0]].tolist(), exact[p, :kept[p][0]].tolist())
            for p in range(6)]


def test_checking_the_branches_inside_the_limits_keeps_what_checking_all_keeps() -> None:
    arm = robot("puma560")
    S = solver(arm).screws
    tol = EXACT_TOL * max(solver(arm).size, 1.0)
    n, m = arm.n_dofs, 48
    for seed in range(20):
        Q, T, q, cs, pose = lanes_of(arm, np.random.default_rng(seed))
        pos_all, rot_all = np.empty(m), np.empty(m)
        fk_lanes(S.H, S.P, S.revolute, S.M, T, pose, q, cs, m, True, np.empty(12 * LANES), pos_all, rot_all)
        reached = np.maximum(pos_all, rot_all)[0::8] <= tol  # the first branch: the pose's own configuration
        assert reached.tolist() == [True] * 5 + [False]
        pos, rot = np.empty(m), np.empty(m)
        alive, lanes = np.empty(m, dtype=np.bool_), np.empty(m, dtype=np.int64)
        check_within(S.H, S.P, S.revolute, S.M, T, pose, q, cs, 6, 8, arm.q_min, arm.q_max, tol,
                     True, np.empty(12 * LANES), pos, rot, alive, lanes, np.empty((n, m)), np.empty((2 * n, m)),
                     np.empty(m, dtype=np.int64), np.empty(m), np.empty(m))
        lo, hi = arm.q_min[:, None], arm.q_max[:, None]  # (every joint of PUMA 560 turns)
        lowest = q + 2 * np.pi * np.ceil((lo - q) / (2 * np.pi))  # each angle's lowest turn at or above lo
        assert np.array_equal(alive, (lowest <= hi).all(axis=0))
        checked = alive | np.repeat([False, False, False, True, True, True], 8)  # poses 3-5: none reached inside
        assert np.array_equal(pos[checked], pos_all[checked]) and np.array_equal(rot[checked], rot_all[checked])
        assert np.isinf(pos[~checked]).all() and np.isinf(rot[~checked]).all()
        for mode in (EVERY_TURN, NEAREST_TURN):
            assert screened(arm, q, pos, rot, mode) == screened(arm, q, pos_all, rot_all, mode)


def test_live_lanes_lists_the_lanes_with_a_turn_inside_the_limits() -> None:
    arm = robot("ur5")  # ±2π on every joint: 3 turns, or 2, of each angle
    lo, hi = arm.q_min.copy(), arm.q_max.copy()
    lo[0], hi[0] = -1.0, 1.0
    q = np.zeros((6, 5))
    q[0] = [0.5, 1.5, 1.0 + 2 * np.pi, -1.0 - 1e-9, np.nan]  # inside, outside, a turn of 1, at the edge, NaN
    alive, lanes = np.empty(5, dtype=np.bool_), np.empty(5, dtype=np.int64)
    count = live_lanes(q, solver(arm).screws.revolute, lo, hi, 5, alive, lanes)
    assert count == 3 and lanes[:3].tolist() == [0, 2, 3] and alive.tolist() == [True, False, True, True, False]
