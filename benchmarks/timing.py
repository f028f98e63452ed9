"""Timing helpers of the benchmarks: repeated measurement, median and IQR, the result table."""
from __future__ import annotations

import sys
import time
from typing import Callable

import numpy as np


def measure(fn: Callable[[], object], repeats: int, number: int = 1) -> list[float]:
    """Seconds per call of ``fn`` for each of ``repeats`` runs of ``number`` calls."""
    fn()  # warm caches, lazy imports and GL resources
    samples = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(number):
            fn()
        samples.append((time.perf_counter() - start) / number)
    return samples


def median_iqr(samples: list[float]) -> tuple[float, float]:
    """Median and interquartile range of the samples."""
    q1, med, q3 = np.percentile(samples, [25, 50, 75])
    return float(med), float(q3 - q1)


class Table:
    def __init__(self) -> None:
        self.rows: list[tuple[str, str, str, str, str, str]] = []

    def add(self, what: str, value: str, spread: str, baseline: str = "—", ratio: str = "—", target: str = "—") -> None:
        self.rows.append((what, value, spread, baseline, ratio, target))
        print(f"  {what}: {value} (±{spread})", file=sys.stderr, flush=True)

    def print(self) -> None:
        head = ("measurement", "median", "IQR", "per-link NumPy baseline", "speed-up", "target")
        widths = [max(len(r[i]) for r in self.rows + [head]) for i in range(len(head))]
        line = lambda r: "| " + " | ".join(c.ljust(w) for c, w in zip(r, widths)) + " |"  # noqa: E731
        print(line(head))
        print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
        for r in self.rows:
            print(line(r))


def us(x: float) -> str:
    return f"{x * 1e6:.3g} µs"


def ms(x: float) -> str:
    return f"{x * 1e3:.3g} ms"
