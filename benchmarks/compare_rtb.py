"""Optional: our solve_ik against the Robotics Toolbox for Python's ikine_LM on the same targets.

RTB is not a dependency of this project.  To reproduce the comparison quoted in the
README, install it in a throwaway environment and run this script with that interpreter
from the repository root (our modules need only NumPy):

    python3 -m venv /tmp/rtb && /tmp/rtb/bin/pip install roboticstoolbox-python
    /tmp/rtb/bin/python benchmarks/compare_rtb.py

Targets are endeffector poses of configurations drawn uniformly inside the joint limits
(seeded); both solvers start from their defaults and must meet 1e-6 in position and
orientation within the joint limits.  Prints success rate and median solve time.
"""
from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import roboticstoolbox as rtb  # noqa: E402
from spatialmath import SE3  # noqa: E402

from kinematics import forward_kinematics, random_configurations, solve_ik  # noqa: E402
from robot_defs import RobotParams, load_robot  # noqa: E402

N_TARGETS = 200


def humanoid_90() -> tuple[RobotParams, rtb.DHRobot]:
    """humanoid7 with ±90° limits, as our RobotParams and as an RTB DHRobot."""
    h = load_robot("humanoid7")
    ours = RobotParams.from_arrays(
        "humanoid7 ±90°", h.dh_a, h.dh_alpha, h.dh_d, h.dh_th, h.jtype,
        q_min=np.full(7, -np.pi / 2), q_max=np.full(7, np.pi / 2), base_tf=h.base_tf, endeff_tf=h.endeff_tf,
    )
    links = [
        rtb.RevoluteDH(d=d, a=a, alpha=al, offset=th, qlim=[-np.pi / 2, np.pi / 2])
        for a, al, d, th in zip(h.dh_a, h.dh_alpha, h.dh_d, h.dh_th)
    ]
    theirs = rtb.DHRobot(links, base=SE3(h.base_tf.mat), tool=SE3(h.endeff_tf.mat), name=ours.name)
    return ours, theirs


def median_ms(times: list[float]) -> float:
    return float(np.median(times) * 1e3)


def main() -> None:
    pairs = [(load_robot("puma560"), rtb.models.DH.Puma560()), humanoid_90()]
    print("| robot | solver | solved | median solve time |\n|---|---|---|---|")
    for ours, theirs in pairs:
        Q = random_configurations(ours, N_TARGETS, np.random.default_rng(42))
        targets = forward_kinematics(ours, Q)
        mismatch = max(np.abs(theirs.fkine(q).A - t).max() for q, t in zip(Q[:20], targets[:20]))
        assert mismatch < 1e-9, f"models differ by {mismatch}"
        for label, solve in (
            ("RTB ikine_LM", lambda t: theirs.ikine_LM(SE3(t, check=False), joint_limits=True).success),
            ("ours solve_ik", lambda t: solve_ik(ours, t).success),
        ):
            times, ok = [], 0
            for t in targets:
                start = time.perf_counter()
                ok += bool(solve(t))
                times.append(time.perf_counter() - start)
            print(f"| {ours.name} | {label} | {100 * ok / N_TARGETS:.1f} % | {median_ms(times):.2f} ms |")


if __name__ == "__main__":
    main()
