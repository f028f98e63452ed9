"""Calibration timing for ``make bench``: a 6-joint arm (UR5) from 100 measured positions.

Two rows: the whole ``calibrate`` (identifiability, two Levenberg–Marquardt fits, the DH
table), and one weighted residual and parameter Jacobian of those 100 poses against the
baseline the issue rules out for the library, central differences (two chain walks per
parameter), timed in the same run and alternated.
    python benchmarks/bench_calibration.py
"""
from __future__ import annotations

import time

import numpy as np

import robot_sim as rs
from robot_sim.calibration.calibrate import GROUPS, free_columns
from robot_sim.calibration.chain import build_chain
from robot_sim.calibration.measure import stacked
from robot_sim.calibration.simulate import measured, perturbed
from timing import Table, measure, median_iqr

POSES, NOISE, REPEATS = 100, 20e-6, 7


def _case() -> tuple[rs.RobotParams, rs.CalibrationData]:
    rng = np.random.default_rng(0)
    robot = rs.load_robot("ur5")
    truth = perturbed(robot, rng)
    q = rs.calibration_poses(robot, POSES, seed=0)
    return robot, measured(truth, q, rng.normal(0, NOISE, (POSES, 3)))


def _central_differences(chain, data, columns, h=1e-6):
    """The residual and its Jacobian by central differences (the baseline)."""
    r, _ = stacked(chain, data, columns[:0])
    J = np.empty((r.size, len(columns)))
    for i, k in enumerate(columns):
        up, down = chain.value.copy(), chain.value.copy()
        up[k] += h
        down[k] -= h
        J[:, i] = (stacked(chain.with_values(down), data, columns[:0])[0]
                   - stacked(chain.with_values(up), data, columns[:0])[0]) / (2 * h)
    return r, J


def bench_calibration(table: Table) -> None:
    """The rows of ``make bench``."""
    robot, data = _case()
    timings = []
    for _ in range(REPEATS):
        start = time.perf_counter()
        res = rs.calibrate(robot, data)
        timings.append(time.perf_counter() - start)
    med, iqr = median_iqr(timings)
    table.add(f"`calibrate` UR5, {POSES} positions (two fits: held-out fifth, then all)", f"{med * 1e3:.0f} ms",
              f"{iqr * 1e3:.0f} ms", target="≤ 1 s")
    print(f"  held-out RMS {res.holdout.rms * 1e6:.1f} µm, after {res.rms_after * 1e6:.1f} µm, "
          f"before {res.rms_before * 1e3:.2f} mm")
    chain = build_chain(robot)
    columns = free_columns(chain, GROUPS)
    analytic, central = [], []
    for _ in range(REPEATS):  # alternated
        analytic += measure(lambda: stacked(chain, data, columns), repeats=3)
        central += measure(lambda: _central_differences(chain, data, columns), repeats=3)
    a, a_iqr = median_iqr(analytic)
    c, _ = median_iqr(central)
    table.add(f"parameter Jacobian, UR5, {POSES} poses x {len(columns)} parameters", f"{a * 1e3:.2f} ms",
              f"{a_iqr * 1e3:.2f} ms", f"{c * 1e3:.1f} ms (central differences)", f"{c / a:.0f}×")


if __name__ == "__main__":
    t = Table()
    bench_calibration(t)
    t.print()
