"""Analytic IK against EAIK and ik-geo (oracles, never dependencies): solution counts,
residuals, agreement of the solution sets and time per pose, alternated in one run.

    pip install eaik==1.2.2 ik-geo==1.0.3     # into the venv, for this script only
    python benchmarks/compare_analytic_ik.py [--poses 1000]

Each arm is taken as its bare standard DH table (no joint offsets, base or tool), the
kinematics EAIK's ``DhRobot(alpha, a, d)`` builds; ik-geo gets the same chain as joint
axes H and offsets P (IK-Geo's convention: the tool frame at q = 0 turned onto the base
frame, so targets are given as R·R_M⁻¹, its rotations read by columns).  Poses are forward kinematics of random
configurations.  Ours is :func:`robot_sim.ik.solutions.ik_solutions` with
``within_limits=False`` (one configuration per branch, as the others return).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Callable

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from robot_sim.ik.classify import meeting_point  # noqa: E402
from robot_sim.ik.geometry import screws  # noqa: E402
from robot_sim.ik.solutions import ik_solutions  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.kinematics import forward_kinematics  # noqa: E402
from robot_sim.model.params import RobotParams  # noqa: E402

#: Arm -> the ik-geo constructor of its family.
ARMS = {"ur5": "three_parallel_two_intersecting", "puma560": "spherical_two_intersecting",
        "kr6_r900": "spherical_two_parallel"}


def bare(name: str) -> RobotParams:
    r = load_robot(name)
    return RobotParams.from_arrays(name, r.dh_a, r.dh_alpha, r.dh_d, np.zeros(6), np.zeros(6))


def residual(robot: RobotParams, Q: np.ndarray, T: np.ndarray) -> float:
    if len(Q) == 0:
        return float("nan")
    return float(np.abs(forward_kinematics(robot, np.asarray(Q, dtype=float)) - T).max())


def same_set(a: np.ndarray, b: np.ndarray) -> bool:
    """Every configuration of a has one of b equal modulo 2π (to 1e-6), and back."""
    if len(a) == 0 or len(b) == 0:
        return len(a) == len(b)
    d = (a[:, None] - b[None] + np.pi) % (2 * np.pi) - np.pi
    close = np.abs(d).max(axis=2) < 1e-6
    return bool(close.any(axis=1).all() and close.any(axis=0).all())


def oracles(name: str) -> tuple[RobotParams, Callable[[np.ndarray], object], Callable[[np.ndarray], list]]:
    """The bare arm ``name`` (see the module docstring) and EAIK's and ik-geo's IK of a
    4×4 pose on it; ImportError when they are not installed."""
    import ik_geo
    from eaik.IK_DH import DhRobot

    family = ARMS[name]
    robot = bare(name)
    eaik = DhRobot(robot.dh_alpha, robot.dh_a, robot.dh_d)
    S = screws(robot)
    points = S.P.copy()  # IK-Geo wants meeting axes to share their point (zero offsets between them)
    if family.startswith("spherical"):
        points[3:] = meeting_point(S, 3, 4, 1e-9)
    if family.endswith("two_intersecting") and not family.startswith("three"):
        points[:2] = meeting_point(S, 0, 1, 1e-9)
    P = np.vstack([points[0], np.diff(points, axis=0), S.M[:3, 3] - points[-1]])
    geo = getattr(ik_geo.Robot, family)(S.H.tolist(), P.tolist())
    RM = S.M[:3, :3]

    def geo_ik(t: np.ndarray) -> list:
        return geo.get_ik((t[:3, :3] @ RM.T).T.tolist(), t[:3, 3].tolist())  # ik-geo reads R by columns

    return robot, eaik.IK, geo_ik


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=1000)
    args = parser.parse_args()
    try:
        built = {name: oracles(name) for name in ARMS}
    except ImportError as exc:
        print(f"compare_analytic_ik: needs eaik and ik-geo ({exc}); pip install eaik==1.2.2 ik-geo==1.0.3",
              file=sys.stderr)
        raise SystemExit(2) from None
    rng = np.random.default_rng(29)
    print("| arm | ours µs/pose | EAIK µs/pose | ik-geo µs/pose | solutions per pose: ours / EAIK / ik-geo "
          "| max residual: ours / EAIK / ik-geo | same set as EAIK |")
    print("|---|---|---|---|---|---|---|")
    for name in ARMS:
        robot, eaik_ik, geo_ik = built[name]
        Q = rng.uniform(-np.pi, np.pi, (args.poses, 6))
        T = forward_kinematics(robot, Q)
        times = {"ours": [], "eaik": [], "geo": []}
        counts = {"ours": [], "eaik": [], "geo": []}
        worst = {"ours": 0.0, "eaik": 0.0, "geo": 0.0}
        agree = 0
        for t in T:  # alternated per pose
            start = time.perf_counter()
            ours = ik_solutions(robot, t, within_limits=False)
            times["ours"].append(time.perf_counter() - start)
            start = time.perf_counter()
            theirs = eaik_ik(t)
            times["eaik"].append(time.perf_counter() - start)
            start = time.perf_counter()
            g = geo_ik(t)
            times["geo"].append(time.perf_counter() - start)
            q_e = np.asarray(theirs.Q)[~np.asarray(theirs.is_LS, dtype=bool)] if len(theirs.Q) else np.zeros((0, 6))
            q_g = np.array([q for q, ls in g if not ls]) if g else np.zeros((0, 6))
            for key, sols in (("ours", ours.q[ours.exact]), ("eaik", q_e), ("geo", q_g)):
                counts[key].append(len(sols))
                worst[key] = max(worst[key], residual(robot, sols, t) if len(sols) else 0.0)
            agree += same_set(ours.q[ours.exact], q_e)
        med = {k: 1e6 * float(np.median(v)) for k, v in times.items()}
        cnt = {k: float(np.mean(v)) for k, v in counts.items()}
        print(f"| {name} | {med['ours']:.2f} | {med['eaik']:.2f} | {med['geo']:.2f} "
              f"| {cnt['ours']:.2f} / {cnt['eaik']:.2f} / {cnt['geo']:.2f} "
              f"| {worst['ours']:.1e} / {worst['eaik']:.1e} / {worst['geo']:.1e} | {agree}/{len(T)} |")


if __name__ == "__main__":
    main()
