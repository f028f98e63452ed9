"""A batch of poses on every core: :func:`run_threads` runs the two passes of
:func:`robot_sim.ik.pipeline.run` on chunks of the poses in Python threads (the compiled
passes release the GIL).  Each pose goes through the same compiled code whichever thread
takes it, so the answer equals :func:`~robot_sim.ik.pipeline.run`'s bit for bit.

Threads of Python, not numba's parallel loops: no threading layer to choose (numba's
``workqueue`` layer aborts on concurrent calls from two threads, as the web view's server
threads make, and GNU OpenMP's is not safe across the fork of :mod:`robot_sim.sim.sweep`),
and no parallel kernel to compile.  Each call starts and joins its own threads, so
concurrent calls share nothing.
"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from typing import Callable

import numpy as np

from robot_sim.ik.pipeline import MAX_VALUES, begin, pass1, pass1_arrays, pass2, pass2_arrays, raw_is_answer, run, width

#: Batches of at least this many poses are split over threads (a thread costs tens of µs).
PARALLEL_POSES = 2000
#: Chunks per thread: chunks go to whichever thread is free, so a core slowed by other
#: work takes fewer of them.
CHUNKS_PER_THREAD = 8


def cores() -> int:
    """The cores this process may run on."""
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def each_chunk(work: Callable[[int, int], None], N: int, threads: int) -> None:
    """work(start, stop) on chunks covering 0..N-1, in ``threads`` threads (this one
    among them); each chunk once."""
    size = -(-N // (threads * CHUNKS_PER_THREAD))
    starts = iter(range(0, N, size))  # next() holds the GIL: each start goes to one thread

    def worker() -> None:
        for start in starts:
            work(start, min(start + size, N))

    if threads < 2:
        worker()
        return
    with ThreadPoolExecutor(threads - 1) as pool:
        helpers = [pool.submit(worker) for _ in range(threads - 1)]
        worker()
        for helper in helpers:
            helper.result()


def run_threads(gf: np.ndarray, gi: np.ndarray, Ts: np.ndarray, q0: np.ndarray, mode: int,
                threads: int | None = None, min_poses: int | None = None) -> tuple:
    """:func:`robot_sim.ik.pipeline.run` (same arguments, same answer) for Ts of at least
    ``min_poses`` poses (default :data:`PARALLEL_POSES`), in ``threads`` threads (default:
    one per core), with NumPy's arrays (on huge pages where the system grants them)."""
    threads = cores() if threads is None else threads
    N, n = Ts.shape[0], gi[9]
    if N < (PARALLEL_POSES if min_poses is None else min_poses):
        return run(gf, gi, Ts, q0, mode)
    bad, K = begin(gf, gi, Ts, q0)
    raw, code, count, exact, total = pass1_arrays(N, K, n)
    if bad != -1:
        return raw, code, exact, count, 0, bad
    each_chunk(lambda a, b: pass1(gf, gi, Ts, q0, mode, a, b, raw, code, count, exact, total), N, threads)
    W, needed = width(total, n)
    if raw_is_answer(mode, W, raw):
        return raw, code, exact, count, needed, -1
    out, out_code, out_exact, out_count = pass2_arrays(N, W, n)
    if needed > MAX_VALUES:
        return out, out_code, out_exact, total, needed, -1
    each_chunk(lambda a, b: pass2(gf, gi, q0, mode, a, b, raw, code, count, exact, out, out_code, out_exact,
                                  out_count), N, threads)
    return out, out_code, out_exact, out_count, needed, -1
