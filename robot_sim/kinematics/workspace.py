"""Workspace sampling: random configurations inside the joint limits and the tool
points they reach, bounded by the memory available (read from ``/proc/meminfo`` where
there is one).  Imports neither OpenGL nor Qt.
"""
from __future__ import annotations

import os
from typing import Callable

import numpy as np
from numpy.typing import NDArray

from robot_sim.kinematics.chain import CHUNK
from robot_sim.kinematics.checks import _check_int, _check_seed
from robot_sim.kinematics.frames import forward_kinematics, jacobian, manipulability
from robot_sim.model.messages import clip_repr
from robot_sim.model.params import JTYPE_REVOLUTE, RobotParams

FloatArray = NDArray[np.float64]


def sampling_bounds(robot: RobotParams) -> tuple[FloatArray, FloatArray]:
    """Finite per-joint sampling ranges: the joint limits, with unlimited revolute joints
    sampled over [−π, π].  ValueError naming the joint if a prismatic joint has no limits."""
    lo, hi = np.array(robot.q_min), np.array(robot.q_max)
    for i in np.flatnonzero(~np.isfinite(lo) | ~np.isfinite(hi)):
        if robot.jtype[i] != JTYPE_REVOLUTE:
            raise ValueError(f"{robot.name}: prismatic joint {i + 1} has no limits; cannot sample its range")
        lo[i], hi[i] = max(lo[i], -np.pi), min(hi[i], np.pi)
    return lo, hi


def random_configurations(robot: RobotParams, n_samples: int, rng: np.random.Generator) -> FloatArray:
    """(n_samples, n) joint vectors drawn uniformly inside :func:`sampling_bounds`."""
    lo, hi = sampling_bounds(robot)
    return lo + (hi - lo) * rng.random((n_samples, robot.n_dofs))


class WorkspaceCancelled(Exception):
    """Raised by :func:`workspace_points` when its ``cancelled`` callback returns True."""


def workspace_points(
    robot: RobotParams,
    n_samples: int,
    seed: int | None = None,
    cancelled: Callable[[], bool] | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Endeffector positions (n_samples, 3) [m, world] of uniformly sampled in-limit
    configurations, and the manipulability (n_samples,) of each (see :func:`manipulability`).

    ValueError for an ``n_samples`` that is not a positive integer or needs more memory
    than :func:`max_workspace_samples` allows, a bad ``seed``, or a prismatic joint
    without limits (its range cannot be sampled).  ``cancelled()`` is called between
    chunks of samples (from a worker thread, say); when it returns True the computation
    stops with :class:`WorkspaceCancelled`."""
    n_samples = _check_int("n_samples", n_samples, 1)
    seed = _check_seed(seed)
    limit = max_workspace_samples(robot)
    if n_samples > limit:
        raise ValueError(
            f"n_samples = {clip_repr(n_samples)} needs {_size_text(n_samples * _workspace_bytes(robot))} "
            f"of memory; at most {limit} samples fit in the {_size_text(available_memory())} available"
        )
    Q = random_configurations(robot, n_samples, np.random.default_rng(seed))
    points = np.empty((Q.shape[0], 3))
    manip = np.empty(Q.shape[0])
    for s in range(0, Q.shape[0], CHUNK * 8):
        if cancelled is not None and cancelled():
            raise WorkspaceCancelled(f"workspace of {robot.name} cancelled after {s} of {n_samples} samples")
        chunk = Q[s : s + CHUNK * 8]
        jac = jacobian(robot, chunk)
        points[s : s + len(chunk)] = forward_kinematics(robot, chunk)[:, :3, 3]
        manip[s : s + len(chunk)] = manipulability(robot, chunk, jac)
    return points, manip


def available_memory() -> int:
    """Bytes of memory the system can give this process without swapping (Linux
    ``MemAvailable``; elsewhere the free physical pages)."""
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")


def _workspace_bytes(robot: RobotParams) -> int:
    """Bytes :func:`workspace_points` holds per sample: its configuration, point and
    manipulability (float64)."""
    return 8 * (robot.n_dofs + 4)


def max_workspace_samples(robot: RobotParams) -> int:
    """Most samples :func:`workspace_points` accepts: what fits in half the available
    memory (the other half is left for drawing them and for everything else)."""
    return max(1, available_memory() // 2 // _workspace_bytes(robot))


def _size_text(n_bytes: int) -> str:
    return f"about {n_bytes / 2**30:.3g} GiB" if n_bytes < 2**80 else "more than 2**80 bytes"


# ------------------------------------------------------------------ inverse kinematics
