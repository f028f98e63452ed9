"""Optional: our dynamics against Pinocchio's rnea, crba and aba called from Python, same run.

Pinocchio is not a dependency of this project (``pip install pin`` to run this).  The arm
is exported through our URDF writer and loaded by Pinocchio's URDF parser; drives are
removed (Pinocchio's model has none).  Before timing, both must agree on τ, M and q̈ to
1e-9 at random states.  Then, alternated and median of three:

* one configuration: ``inverse_dynamics`` / ``forward_dynamics`` per call against
  ``pin.rnea`` / ``pin.aba`` per call (targets: at most 3× their time);
* batches of N = 1e5: ``inverse_dynamics``, ``mass_matrix``, ``forward_dynamics`` in
  configurations per second against ``pin.rnea``, ``pin.crba``, ``pin.aba`` called once
  per configuration (targets: at least 3×, 2×, 2× their rate).

    python benchmarks/compare_pinocchio.py [--robot humanoid7] [--n 100000]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path
from typing import Callable

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import pinocchio as pin  # noqa: E402

from oracle_arms import without_drives  # noqa: E402
from robot_sim import dynamics  # noqa: E402
from robot_sim.io.robot_file import load_robot  # noqa: E402
from robot_sim.io.urdf_out import to_urdf  # noqa: E402

SINGLE_CALLS = 5000
N_PIN = 20_000  # configurations per Pinocchio batch sample (its per-call rate is flat in N)


def seconds(fn: Callable[[], object], calls: int = 1) -> float:
    start = time.perf_counter()
    for _ in range(calls):
        fn()
    return (time.perf_counter() - start) / calls


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--robot", default="humanoid7")
    parser.add_argument("--n", type=int, default=100_000)
    args = parser.parse_args()
    robot = without_drives(load_robot(args.robot))
    model = pin.buildModelFromXML(to_urdf(robot))
    data = model.createData()
    rng = np.random.default_rng(0)
    n, N = robot.n_dofs, args.n
    Q, QD, QDD = rng.uniform(-np.pi, np.pi, (N, n)), rng.normal(size=(N, n)), rng.normal(size=(N, n))
    for i in range(5):  # the same model
        q, v, a = Q[i], QD[i], QDD[i]
        assert np.allclose(pin.rnea(model, data, q, v, a), dynamics.inverse_dynamics(robot, q, v, a), atol=1e-9)
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        assert np.allclose(M, dynamics.mass_matrix(robot, q), atol=1e-9)
        assert np.allclose(pin.aba(model, data, q, v, a), dynamics.forward_dynamics(robot, q, v, a), atol=1e-9)
    q, v, a = Q[0], QD[0], QDD[0]
    single = {
        "ID": (lambda: dynamics.inverse_dynamics(robot, q, v, a), lambda: pin.rnea(model, data, q, v, a)),
        "FD": (lambda: dynamics.forward_dynamics(robot, q, v, a), lambda: pin.aba(model, data, q, v, a)),
    }
    batch = {
        "ID": (lambda: dynamics.inverse_dynamics(robot, Q, QD, QDD),
               lambda: [pin.rnea(model, data, Q[i], QD[i], QDD[i]) for i in range(N_PIN)]),
        "M": (lambda: dynamics.mass_matrix(robot, Q), lambda: [pin.crba(model, data, Q[i]) for i in range(N_PIN)]),
        "FD": (lambda: dynamics.forward_dynamics(robot, Q, QD, QDD),
               lambda: [pin.aba(model, data, Q[i], QD[i], QDD[i]) for i in range(N_PIN)]),
    }
    for ours, theirs in list(single.values()) + list(batch.values()):  # warm
        ours(), theirs()
    times: dict[str, list[float]] = {}
    for _ in range(3):  # alternated, median of three
        for key, (ours, theirs) in single.items():
            times.setdefault(f"single {key} ours", []).append(seconds(ours, SINGLE_CALLS))
            times.setdefault(f"single {key} pin", []).append(seconds(theirs, SINGLE_CALLS))
        for key, (ours, theirs) in batch.items():
            times.setdefault(f"batch {key} ours", []).append(seconds(ours) / N)
            times.setdefault(f"batch {key} pin", []).append(seconds(theirs) / N_PIN)
    med = {k: statistics.median(v) for k, v in times.items()}
    print(f"{args.robot}, one core, alternated, median of three")
    for key, (theirs, target) in {"ID": ("rnea", 3.0), "FD": ("aba", 3.0)}.items():
        ours, pins = med[f"single {key} ours"], med[f"single {key} pin"]
        print(f"  one configuration {key}: ours {ours * 1e6:6.2f} µs, pin.{theirs} {pins * 1e6:6.2f} µs"
              f"  -> {ours / pins:4.2f}× its time (≤ {target})")
    for key, (theirs, target) in {"ID": ("rnea", 3.0), "M": ("crba", 2.0), "FD": ("aba", 2.0)}.items():
        ours, pins = med[f"batch {key} ours"], med[f"batch {key} pin"]
        print(f"  batched {key}, N = {N}: ours {ours * 1e6:6.3f} µs/config, pin.{theirs} per call {pins * 1e6:6.3f} µs"
              f"  -> {pins / ours:4.2f}× its configurations/s (≥ {target})")


if __name__ == "__main__":
    main()
