"""A batch of poses solved on several threads (robot_sim.ik.threads) gives the one-thread
answer bit for bit, and the single-pose answers; errors and the output bound are the
same; two threads of the caller solving at once both get their answer."""
from __future__ import annotations

import threading

import numpy as np
import pytest

import robot_sim.ik.threads as threads
from kin_helpers import robot
from robot_sim.ik.family import solver
from robot_sim.ik.finish import EVERY_TURN, RAW
from robot_sim.ik.pipeline import MAX_VALUES, run
from robot_sim.ik.solutions import ik_solutions, packed
from robot_sim.kinematics import forward_kinematics, random_configurations


def bits(a: np.ndarray) -> np.ndarray:
    """The array's bytes as integers (NaN payloads and signed zeros compared too)."""
    return a.view(np.uint64) if a.dtype == np.float64 else a


def same(a: tuple, b: tuple) -> bool:
    return all(np.shape(x) == np.shape(y) and np.array_equal(bits(np.asarray(x)), bits(np.asarray(y)))
               for x, y in zip(a, b, strict=True))


def poses(name: str, N: int, seed: int) -> tuple:
    """A batch of N poses of the arm (pose 7 out of reach), and a q0 (holding a 7-joint
    arm's free joint where pose 0 has it)."""
    arm = robot(name)
    Q = random_configurations(arm, N + 1, np.random.default_rng(seed))
    T = forward_kinematics(arm, Q[:N])
    T[7, :3, 3] *= 5.0  # least-squares branches, not exact
    free = solver(arm).plan.free
    if free is not None:
        Q[N, free] = Q[0, free]
    return arm, T, Q[N]


@pytest.mark.parametrize(("name", "mode"), [("puma560", EVERY_TURN), ("ur5", RAW), ("ur5", EVERY_TURN),
                                            ("stanford", EVERY_TURN), ("panda", EVERY_TURN)])
def test_threads_give_the_one_thread_answer_bit_for_bit(name: str, mode: int) -> None:
    arm, T, q0 = poses(name, 301, 8)
    sv = solver(arm)
    free = sv.plan.free
    gf, gi = packed(sv, sv.plan, np.zeros(1) if free is None else q0[free:free + 1], arm)
    serial = run(gf, gi, T, q0, mode)
    for n_threads in (2, 3):
        assert same(threads.run_threads(gf, gi, T, q0, mode, threads=n_threads, min_poses=1), serial)
    q, code, exact, count, _, bad = serial
    assert bad == -1 and not exact[7].any() and exact[0, 0]
    for i in (0, 7, 150, 300):
        one = ik_solutions(arm, T[i], q0, within_limits=mode != RAW)
        k = count[i]
        assert same((q[i, :k], code[i, :k], exact[i, :k]), (one.q, one.codes, one.exact))
        assert np.isnan(q[i, k:]).all() and (code[i, k:] == -1).all() and not exact[i, k:].any()


def test_a_threaded_batch_names_its_bad_pose_and_q0(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(threads, "PARALLEL_POSES", 10)
    arm, T, q0 = poses("puma560", 200, 9)
    T[137, 1, 2] = np.nan
    with pytest.raises(ValueError, match=r"^T\[137\] holds NaN or infinite values, got "):
        ik_solutions(arm, T)
    with pytest.raises(ValueError, match="q0"):
        ik_solutions(arm, T[:136], np.r_[q0[:5], np.inf])


def test_a_threaded_batch_is_bounded_before_its_output_is_allocated(monkeypatch: pytest.MonkeyPatch) -> None:
    """A UR5 pose with 8 branches × 2⁶ turns: 3072 joint values a pose."""
    monkeypatch.setattr(threads, "PARALLEL_POSES", 10)
    arm = robot("ur5")
    T = forward_kinematics(arm, np.array([0.3, -1.2, 1.0, -0.5, 1.1, 0.2]))
    N = MAX_VALUES // 3072 + 1
    message = (f"the solutions would hold {N * 3072} joint values (at most {MAX_VALUES}): "
               "solve fewer poses at a time, or with within_limits=False")
    with pytest.raises(ValueError, match=f"^{message}$".replace("(", r"\(").replace(")", r"\)")):
        ik_solutions(arm, np.broadcast_to(T, (N, 4, 4)))
    assert len(ik_solutions(arm, np.broadcast_to(T, (N, 4, 4)), within_limits=False).q[0]) == 8


def test_two_callers_solving_at_once_both_get_their_answer(monkeypatch: pytest.MonkeyPatch) -> None:
    work = [poses("puma560", 3000, 10), poses("ur5", 3000, 11)]
    expected = [ik_solutions(arm, T, q0) for arm, T, q0 in work]  # one thread: below PARALLEL_POSES
    monkeypatch.setattr(threads, "PARALLEL_POSES", 64)
    got: list = [None, None]

    def solve(k: int) -> None:
        arm, T, q0 = work[k]
        got[k] = [ik_solutions(arm, T, q0) for _ in range(3)]

    callers = [threading.Thread(target=solve, args=(k,)) for k in range(2)]
    for caller in callers:
        caller.start()
    for caller in callers:
        caller.join()
    for k in range(2):
        for sols in got[k]:
            assert same((sols.q, sols.codes, sols.exact, sols.count),
                        (expected[k].q, expected[k].codes, expected[k].exact, expected[k].count))


@pytest.mark.parametrize("reach", [1.0, 5.0])
def test_raw_branches_sorted_by_pass_1_equal_those_of_pass_2(reach: float) -> None:
    """Within reach a PUMA 560 batch has a pose with all 8 raw branches, so pass 1's sorted
    and padded arrays are the answer; five times out of reach the least-squares branches
    merge, at most 4 remain and pass 2 writes the answer.  Both equal the single-pose
    answers."""
    arm, T, q0 = poses("puma560", 40, 11)
    T[:, :3, 3] *= reach
    sols = ik_solutions(arm, T, q0, within_limits=False)
    assert (sols.q.shape[1] == 8) == (reach == 1.0)
    for i in range(len(T)):
        one = ik_solutions(arm, T[i], q0, within_limits=False)
        k = sols.count[i]
        assert same((sols.q[i, :k], sols.codes[i, :k], sols.exact[i, :k]), (one.q, one.codes, one.exact))
        assert np.isnan(sols.q[i, k:]).all() and (sols.codes[i, k:] == -1).all() and not sols.exact[i, k:].any()
        d = np.linalg.norm(one.q - q0, axis=1)
        assert np.all(np.diff(d) >= 0.0)  # nearest q0 first
