"""The scratch a block of poses goes through in the closed-form solvers (compiled).

A block is up to :data:`POSES` poses.  A solver works on *lanes*: lane s·POSES + g is
set s (an arm solution, or a pair of branches) of pose g, for s < :data:`SETS`.  One flat
float array ``W`` holds row r of lane l at ``W[r * LANES + l]``: the poses (12 rows, the
rotation's rows then the translation, world; each pose copied into its lane of every
set), the arm's solutions (:data:`ARM` rows, :func:`robot_sim.ik.position.arm_positions`)
and the branches (two planes of values, then of cosines and sines).  Branch b of pose g
lives in plane b mod 2 of lane (b div 2)·POSES + g (:func:`branch_lane`); its posture
bits go to the integer array ``C`` (two planes of :data:`LANES`).

Why this layout: a solver's loop over the poses of one set runs a pose per vector lane
only when the compiler can prove that no iteration writes what another reads.  Every
access of such a loop is then W's start plus a constant plus the same set offset, so the
distances between them are constants; separate arrays, or rows a run-time stride apart,
would need a run-time overlap check per pair of rows, and with dozens of rows the
compiler gives up and runs one pose at a time.
"""
from __future__ import annotations

import numba
import numpy as np

from robot_sim.kernels.jit import JIT

#: Poses per block (two AVX-512 vectors of doubles), and sets of lanes per pose.
POSES, SETS = 16, 4
#: Entries per row of W and C.
LANES = POSES * SETS
#: Floats per arm solution: the slide (NaN for a turn), then cos, sin of joints 0, 1, 2.
ARM = 7
#: Most joints a solver's chain has.
MAX_JOINTS = 6
#: First rows of the parts of W: poses (12 rows), arm solutions (:data:`ARM`), branch
#: values (2 planes × :data:`MAX_JOINTS`), their cosines and sines (2 × 2 × MAX_JOINTS).
POSE_ROWS = 0
ARM_ROWS = 12
OUT_ROWS = ARM_ROWS + ARM
CS_ROWS = OUT_ROWS + 2 * MAX_JOINTS
ROWS = CS_ROWS + 4 * MAX_JOINTS


@numba.njit(**JIT)
def scratch() -> tuple[np.ndarray, np.ndarray]:
    """W and C for one block (every entry a solver reads is written before)."""
    return np.empty(ROWS * LANES), np.empty(2 * LANES, dtype=np.int64)


@numba.njit(inline="always", **JIT)
def load_poses(Ts: np.ndarray, start: int, G: int, inverse: bool, W: np.ndarray) -> None:
    """Ts[start + g] (4, 4) for g < G, or their inverses, into W's pose rows, in the lane
    of pose g of every set."""
    for g in range(G):
        i = start + g
        for a in range(3):
            for b in range(3):
                x = Ts[i, b, a] if inverse else Ts[i, a, b]
                for s in range(SETS):
                    W[(3 * a + b) * LANES + s * POSES + g] = x
            t = -(Ts[i, 0, a] * Ts[i, 0, 3] + Ts[i, 1, a] * Ts[i, 1, 3] + Ts[i, 2, a] * Ts[i, 2, 3]) if inverse \
                else Ts[i, a, 3]
            for s in range(SETS):
                W[(9 + a) * LANES + s * POSES + g] = t


@numba.njit(inline="always", **JIT)
def pose_of(W: np.ndarray, lane: int) -> tuple:
    """The pose of a lane as a tuple (r00, r01, r02, r10, …, r22, t0, t1, t2)."""
    return (W[lane], W[LANES + lane], W[2 * LANES + lane], W[3 * LANES + lane], W[4 * LANES + lane],
            W[5 * LANES + lane], W[6 * LANES + lane], W[7 * LANES + lane], W[8 * LANES + lane],
            W[9 * LANES + lane], W[10 * LANES + lane], W[11 * LANES + lane])


@numba.njit(**JIT)
def put(W: np.ndarray, row: int, lane: int, x: float) -> None:
    W[row * LANES + lane] = x


@numba.njit(inline="always", **JIT)
def put6(W: np.ndarray, row: int, lane: int, x: tuple) -> None:
    """Six values x into rows row..row+5 of a lane, written out: a loop over them here
    would be a loop inside a solver's loop over poses, which the compiler then runs a
    pose at a time (measured: 650 ns a PUMA 560 pose instead of 160 ns)."""
    put(W, row, lane, x[0])
    put(W, row + 1, lane, x[1])
    put(W, row + 2, lane, x[2])
    put(W, row + 3, lane, x[3])
    put(W, row + 4, lane, x[4])
    put(W, row + 5, lane, x[5])


@numba.njit(**JIT)
def get(W: np.ndarray, row: int, lane: int) -> float:
    return W[row * LANES + lane]


@numba.njit(**JIT)
def branch_lane(b: int, g: int) -> tuple[int, int]:
    """(plane, lane) of branch b of pose g."""
    return b % 2, (b // 2) * POSES + g
