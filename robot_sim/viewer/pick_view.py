"""A view of the pick task in which the table hides none of the arm (no Qt, no GL).

The default camera direction can put the table between the eye and the arm (humanoid7's
tall table hid most of it).  :func:`clear_view_azimuth` tries the azimuths around the
default one, each framed as ``Camera.fit`` frames it, and keeps the nearest one from
which no sample point of the arm over the task (its joint origins and the middles of its
links, at poses along the plan) lies behind the table.  World frame, metres, degrees.
"""
from __future__ import annotations

import copy

import numpy as np
from numpy.typing import ArrayLike, NDArray

from robot_sim.graphics.camera import Camera
from robot_sim.kinematics import forward_kinematics
from robot_sim.planning.pick_task import TaskPlan

#: Poses of the plan sampled for the arm's points, and the azimuth step tried (degrees).
POSE_SAMPLES = 12
AZIMUTH_STEP_DEG = 15.0


def hidden_by_box(eye: NDArray[np.float64], points: ArrayLike, box_lo: NDArray[np.float64],
                  box_hi: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Whether the sight line from ``eye`` (3,) to each of ``points`` (N, 3) passes through
    the box ``box_lo`` .. ``box_hi`` before reaching the point (slab test)."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    d = points - eye
    with np.errstate(divide="ignore", invalid="ignore"):
        t1 = (box_lo - eye) / d
        t2 = (box_hi - eye) / d
    flat = d == 0.0
    inside = (eye >= box_lo) & (eye <= box_hi)
    t_near = np.where(flat, np.where(inside, -np.inf, np.inf), np.minimum(t1, t2)).max(axis=1)
    t_far = np.where(flat, np.where(inside, np.inf, -np.inf), np.maximum(t1, t2)).min(axis=1)
    return (t_near <= t_far) & (t_far > 0.0) & (t_near < 1.0 - 1e-9)


def arm_points(plan: TaskPlan, samples: int = POSE_SAMPLES) -> NDArray[np.float64]:
    """Joint origins and link middles (M, 3) of the arm at ``samples`` poses along ``plan``."""
    traj = plan.trajectory
    q = np.array([traj.evaluate(t)[0] for t in np.linspace(traj.t[0], traj.t[-1], samples)])
    origins = forward_kinematics(plan.robot, q, all_frames=True)[:, :, :3, 3]  # (S, n+2, 3)
    middles = 0.5 * (origins[:, 1:] + origins[:, :-1])
    return np.concatenate([origins, middles], axis=1).reshape(-1, 3)


def table_box(plan: TaskPlan) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The table's world box (lo, hi): its top face centred at ``table_top``, hanging below."""
    top, size = np.asarray(plan.spec.table_top, dtype=float), np.asarray(plan.spec.table_size, dtype=float)
    centre = top - np.array([0.0, 0.0, 0.5 * size[2]])
    return centre - 0.5 * size, centre + 0.5 * size


def clear_view_azimuth(camera: Camera, plan: TaskPlan, framed: ArrayLike, aspect: float) -> float:
    """The azimuth (degrees) nearest ``camera``'s from which, with the camera fitted to
    ``framed`` (N, 3) at its elevation, the table hides the fewest of the arm's points
    (none where possible)."""
    points = arm_points(plan)
    lo, hi = table_box(plan)
    best, best_hidden = camera.azimuth_deg, np.inf
    steps = int(round(180.0 / AZIMUTH_STEP_DEG))
    for k in sorted(range(-steps + 1, steps + 1), key=abs):  # 0, -1, 1, -2, 2, ...: nearest first
        trial = copy.copy(camera)
        trial.set_view(camera.azimuth_deg + k * AZIMUTH_STEP_DEG, camera.elevation_deg)
        trial.fit(framed, aspect)
        hidden = int(np.count_nonzero(hidden_by_box(trial.eye(), points, lo, hi)))
        if hidden < best_hidden:
            best, best_hidden = trial.azimuth_deg, hidden
            if hidden == 0:
                break
    return best
