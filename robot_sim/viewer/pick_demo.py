"""Playback of a planned pick task for the viewers (window, ``--screenshot``, ``--record``):
time, speed, play/pause, and the task's drawing data at the current time.  No Qt."""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from robot_sim.viewer import settings as vs
from robot_sim.graphics.task_scene import TaskScene
from robot_sim.planning.pick_task import SceneState, TaskPlan, default_plan, default_task, plan_pick
from robot_sim.model.params import RobotParams
from robot_sim.planning.task_file import load_task, with_world_obstacles
from robot_sim.model.world import World


def plan_for(robot: RobotParams, task_path: str | Path | None = None, world: World | None = None) -> TaskPlan:
    """The plan of the task file ``task_path``, or of ``robot``'s default task when None,
    among the task's obstacles and ``world``'s (``--world``).  Raises TaskDefinitionError
    for a bad file and TaskError for an impossible task."""
    spec = default_task(robot) if task_path is None else load_task(task_path)
    among = with_world_obstacles(spec, world) if world is not None else spec
    if task_path is None and among is spec:
        return default_plan(robot)
    return plan_pick(robot, among)


@dataclass
class PickDemo:
    """A task being played: ``time`` [s] within the plan, ``speed`` (1 = real time),
    ``playing``.  Playback stops at the end; seeking past the end shows the final scene.
    ``effort`` (N, n) holds the joint efforts of a run simulated in motion ``mode``
    (whose motion is then the plan's trajectory), None for the kinematic plan."""

    plan: TaskPlan
    effort: np.ndarray | None = None
    mode: str = "kinematic"
    time: float = 0.0
    speed: float = 1.0
    playing: bool = True

    @property
    def duration(self) -> float:
        """Length of the task [s]."""
        return self.plan.duration

    def seek(self, t: float) -> None:
        """Jump to time ``t`` [s], clamped to [0, duration]; ValueError for NaN."""
        if not math.isfinite(t):
            raise ValueError(f"time must be a finite number of seconds, got {t!r}")
        self.time = min(max(float(t), 0.0), self.duration)

    def step(self, dt: float) -> None:
        """Advance by ``dt`` s of wall time times ``speed`` while playing; pause at the end."""
        if not self.playing:
            return
        self.seek(self.time + dt * self.speed)
        if self.time >= self.duration:
            self.playing = False

    def toggle(self) -> bool:
        """Play or pause (playing from the end restarts); returns whether it plays."""
        if not self.playing and self.time >= self.duration:
            self.time = 0.0
        self.playing = not self.playing
        return self.playing

    def state(self) -> SceneState:
        """The task's scene at the current time."""
        return self.plan.state_at(self.plan.trajectory.t[0] + self.time)

    def task_scene(self, state: SceneState | None = None) -> TaskScene:
        """Drawing data of ``state`` (the current one by default), with the whole
        endeffector path."""
        state = self.state() if state is None else state
        spec = self.plan.spec
        path = self.plan.trajectory.poses[:: vs.PATH_SAMPLE_STEP, :3, 3]
        path = np.vstack([path, self.plan.trajectory.poses[-1:, :3, 3]])
        return TaskScene(
            table_top=np.array(spec.table_top), table_size=np.array(spec.table_size),
            object_shape=spec.object_shape, object_size=np.array(spec.object_size),
            object_pose=state.object_pose, tool_pose=state.tool_pose,
            gripper_opening=state.gripper_opening, finger_length=spec.finger_length(), path=path,
            obstacles=spec.obstacles,
        )
