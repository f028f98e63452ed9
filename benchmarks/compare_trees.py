"""Kinematics, dynamics, collision and planning rows of two trees, alternated in one run.

    .venv/bin/python benchmarks/compare_trees.py --base 68e50b6 [--rounds 5]

Exports the ``--base`` revision with ``git archive`` into a folder under the system's
temporary directory (kept, so its numba cache survives between runs), then runs the same
rows in a fresh process of each tree in turn — base, this tree, base, this tree, … — each
process importing ``robot_sim`` from its own tree through the public ``import robot_sim
as rs`` API only.  Every process compiles and warms up first, then times each row as the
median of seven repeats.  The table gives each row's median over the rounds and this
tree's time over the base's: the restructure's floor is "no row slower by more than 5 %".
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable

from timing import measure, median_iqr  # benchmarks/ is on sys.path when this script runs

ROOT = Path(__file__).resolve().parents[1]
REPEATS = 7


def _per_call(fn: Callable[[], object], budget: float = 0.05) -> float:
    """Median seconds per call of ``fn`` over REPEATS runs of about ``budget`` s each."""
    fn()
    t0 = time.perf_counter()
    fn()
    number = max(1, int(budget / max(time.perf_counter() - t0, 1e-9)))
    return median_iqr(measure(fn, REPEATS, number))[0]


def rows() -> dict[str, float]:
    """Seconds per call of each row, in the tree on ``sys.path``."""
    import numpy as np
    import robot_sim as rs

    out: dict[str, float] = {}
    rng = np.random.default_rng(0)
    for name in ("humanoid7", "ur5", "panda"):
        robot = rs.load_robot(name)
        q = rs.random_configurations(robot, 1, rng)[0]
        Q = rs.random_configurations(robot, 1000, rng)
        qd = 0.3 * np.ones(robot.n_dofs)
        out[f"forward_kinematics {name}, one"] = _per_call(lambda: rs.forward_kinematics(robot, q))
        out[f"forward_kinematics {name}, 1000 (per config)"] = _per_call(lambda: rs.forward_kinematics(robot, Q)) / 1000
        out[f"jacobian {name}, one"] = _per_call(lambda: rs.jacobian(robot, q))
        out[f"jacobian {name}, 1000 (per config)"] = _per_call(lambda: rs.jacobian(robot, Q)) / 1000
        out[f"inverse_dynamics {name}, one"] = _per_call(lambda: rs.inverse_dynamics(robot, q, qd, qd))
        out[f"mass_matrix {name}, one"] = _per_call(lambda: rs.mass_matrix(robot, q))
        out[f"forward_dynamics {name}, one"] = _per_call(lambda: rs.forward_dynamics(robot, q, qd, qd))
    panda = rs.load_robot("panda")
    poses = [np.eye(4) for _ in range(5)]
    for k, pose in enumerate(poses):
        pose[:3, 3] = (0.5, 0.2 * k - 0.4, 0.3 + 0.1 * k)
    items = [(f"box{k}", rs.Box(np.full(3, 0.2), pose=pose)) for k, pose in enumerate(poses)]
    checker = rs.CollisionChecker(panda, rs.World(items, floor=False))
    Q = rs.random_configurations(panda, 10000, rng)
    out["in_collision panda + 5 boxes, 10^4 (per config)"] = _per_call(lambda: checker.in_collision(Q), 0.2) / 1e4
    out["in_collision panda + 5 boxes, one"] = _per_call(lambda: checker.in_collision(Q[0]))
    free = Q[~checker.in_collision(Q)]
    pairs = [(free[2 * k], free[2 * k + 1]) for k in range(8)]

    def plan() -> None:
        for k, (a, b) in enumerate(pairs):
            rs.plan_path(panda, a, b, checker, time_limit=2.0, seed=k)
    out["plan_path panda + 5 boxes, 8 goals (per goal)"] = _per_call(plan, 0.5) / len(pairs)
    return out


def export(rev: str) -> Path:
    """The tree of ``rev`` as files under the temporary directory (made once)."""
    sha = subprocess.run(["git", "rev-parse", rev], cwd=ROOT, check=True, capture_output=True,
                         text=True).stdout.strip()
    dest = Path(tempfile.gettempdir()) / "robot_sim_trees" / sha
    if not (dest / "robot_sim").is_dir():
        dest.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "archive", sha], cwd=ROOT, check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    return dest


def measure_tree(tree: Path) -> dict[str, float]:
    """``rows()`` in a fresh process that imports ``robot_sim`` from ``tree``."""
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    done = subprocess.run([sys.executable, __file__, "--rows"], env=env, cwd=tree, check=True,
                          capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--base", default="68e50b6", help="the revision to compare against")
    parser.add_argument("--rounds", type=int, default=5, choices=range(1, 21), metavar="1..20")
    parser.add_argument("--rows", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.rows:
        print(json.dumps(rows()))
        return
    base = export(args.base)
    runs: dict[str, list[dict[str, float]]] = {"base": [], "head": []}
    for k in range(args.rounds):
        for label, tree in (("base", base), ("head", ROOT)):
            runs[label].append(measure_tree(tree))
        print(f"round {k + 1}/{args.rounds} done, load {os.getloadavg()[0]:.2f}", file=sys.stderr)
    med = {label: {row: sorted(r[row] for r in rs_)[len(rs_) // 2] for row in rs_[0]} for label, rs_ in runs.items()}
    print(f"| row | {args.base} | head | head / base |\n|---|---|---|---|")
    worst = 0.0
    for row, b in med["base"].items():
        h = med["head"][row]
        worst = max(worst, h / b)
        print(f"| {row} | {b * 1e6:.2f} µs | {h * 1e6:.2f} µs | {h / b:.2f} |")
    print(f"\nslowest ratio {worst:.2f} (floor ≤ 1.05): {'met' if worst <= 1.05 else 'NOT met'}")


if __name__ == "__main__":
    main()
