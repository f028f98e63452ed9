"""Optional: our solve_ik against the Robotics Toolbox for Python's ikine_LM, like for like.

RTB is not a dependency of this project.  To reproduce the comparison quoted in the
README, install it in a throwaway environment and run this script with that interpreter
from the repository root (our modules need only NumPy):

    python3 -m venv /tmp/rtb && /tmp/rtb/bin/pip install roboticstoolbox-python
    /tmp/rtb/bin/python benchmarks/compare_rtb.py

Targets are endeffector poses of configurations drawn uniformly inside the joint limits
(seeded); both solvers start from their defaults and must stay within the joint limits.

Same tolerance: RTB's ``tol`` bounds E = ½‖e‖² (e = [position error; angle·axis]), so
its default ``tol=1e-6`` accepts ‖e‖ up to 1.4e-3; ``tol=5e-13`` is ‖e‖ ≤ 1e-6, which
implies our success test (position ≤ 1e-6 m and rotation ≤ 1e-6 rad).  Every claimed
success is verified by forward kinematics (ours, checked against RTB's fkine to 1e-9):
a solution counts only if its pose is within 1e-6 m and 1e-6 rad of the target and its
joints are within the limits.  Prints, per robot and solver, the claimed and verified
success rates and the median solve time.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import roboticstoolbox as rtb  # noqa: E402
from spatialmath import SE3  # noqa: E402

from robot_sim.kinematics import forward_kinematics, random_configurations, solve_ik  # noqa: E402
from robot_sim.model.params import RobotParams
from robot_sim.io.robot_file import load_robot  # noqa: E402

N_TARGETS = 200
TOL = 1e-6  # m and rad, both solvers
RTB_TOL_SAME = 0.5 * TOL**2  # ½‖e‖² ≤ 5e-13  ⇔  ‖e‖ ≤ 1e-6


def humanoid_90() -> tuple[RobotParams, rtb.DHRobot]:
    """humanoid7 with ±90° limits, as our RobotParams and as an RTB DHRobot."""
    h = load_robot("humanoid7")
    ours = RobotParams.from_arrays(
        "humanoid7 ±90°", h.dh_a, h.dh_alpha, h.dh_d, h.dh_th, h.jtype,
        q_min=np.full(7, -np.pi / 2), q_max=np.full(7, np.pi / 2), base_tf=h.base_tf, tool_tf=h.tool_tf,
    )
    links = [
        rtb.RevoluteDH(d=d, a=a, alpha=al, offset=th, qlim=[-np.pi / 2, np.pi / 2])
        for a, al, d, th in zip(h.dh_a, h.dh_alpha, h.dh_d, h.dh_th)
    ]
    theirs = rtb.DHRobot(links, base=SE3(h.base_tf.mat), tool=SE3(h.tool_tf.mat), name=ours.name)
    return ours, theirs


def verified(robot: RobotParams, q: np.ndarray, target: np.ndarray) -> bool:
    """True if q is within the limits and puts the endeffector within TOL of ``target``."""
    q = np.asarray(q, dtype=float)
    if not (np.all(q >= robot.q_min) and np.all(q <= robot.q_max)):
        return False
    pose = forward_kinematics(robot, q)
    pos_err = np.linalg.norm(pose[:3, 3] - target[:3, 3])
    cos_angle = (np.trace(pose[:3, :3].T @ target[:3, :3]) - 1.0) / 2.0
    rot_err = float(np.arccos(np.clip(cos_angle, -1.0, 1.0)))
    return bool(pos_err <= TOL and rot_err <= TOL)


def main() -> None:
    pairs = [(load_robot("puma560"), rtb.models.DH.Puma560()), humanoid_90()]
    print(f"{N_TARGETS} targets per robot; verified = FK within {TOL:g} m and {TOL:g} rad, joints within limits")
    print("| robot | solver | claimed | verified by FK | median solve time |\n|---|---|---|---|---|")
    for ours, theirs in pairs:
        Q = random_configurations(ours, N_TARGETS, np.random.default_rng(42))
        targets = forward_kinematics(ours, Q)
        mismatch = max(np.abs(theirs.fkine(q).A - t).max() for q, t in zip(Q[:20], targets[:20]))
        assert mismatch < 1e-9, f"models differ by {mismatch}"

        def rtb_solver(tol: float):
            def solve(t: np.ndarray) -> tuple[bool, np.ndarray]:
                sol = theirs.ikine_LM(SE3(t, check=False), joint_limits=True, tol=tol, seed=0)
                return bool(sol.success), sol.q

            return solve

        def ours_solver(t: np.ndarray) -> tuple[bool, np.ndarray]:
            res = solve_ik(ours, t, tol_pos=TOL, tol_rot=TOL)
            return res.success, res.q

        solvers = (
            ("RTB ikine_LM, default tol=1e-6 (½‖e‖², ‖e‖ ≤ 1.4e-3)", rtb_solver(1e-6)),
            ("RTB ikine_LM, tol=5e-13 (‖e‖ ≤ 1e-6)", rtb_solver(RTB_TOL_SAME)),
            ("ours solve_ik, 1e-6 m and 1e-6 rad", ours_solver),
        )
        # each target goes through every solver in turn, so all see the same machine load
        times = {label: [] for label, _ in solvers}
        claimed = dict.fromkeys(times, 0)
        good = dict.fromkeys(times, 0)
        for t in targets:
            for label, solve in solvers:
                start = time.perf_counter()
                success, q = solve(t)
                times[label].append(time.perf_counter() - start)
                claimed[label] += success
                good[label] += success and verified(ours, q, t)
        for label, _ in solvers:
            print(
                f"| {ours.name} | {label} | {100 * claimed[label] / N_TARGETS:.1f} % "
                f"| {100 * good[label] / N_TARGETS:.1f} % | {np.median(times[label]) * 1e3:.2f} ms |"
            )


if __name__ == "__main__":
    main()
