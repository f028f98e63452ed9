"""The pick-and-place task as a planned motion: :func:`plan_pick`, :class:`TaskPlan`,
the scene at any time (:meth:`TaskPlan.state_at`) and a default task per robot.

The sequence (each phase a mark of the trajectory): **pre-grasp** (joint space, from the
start configuration to ``approach`` m above the grasp), **approach** (straight down),
**close** (gripper closes, arm at rest), **lift** (straight up by ``lift`` m, object
attached to the tool), **transport** (joint space, to ``lift`` m above the place pose),
**place** (straight down), **release** (gripper opens; the object stays where it is),
**retreat** (straight up by ``approach`` m).  Everything is planned before anything
moves: an unreachable task raises :class:`TaskError` with one line naming the phase, the
pose and why.  World frame, SI units; no Qt, no OpenGL.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from robot_sim.kinematics import forward_kinematics, random_configurations, solve_ik
from robot_sim.model.params import RobotParams
from robot_sim.planning.task_file import DEFAULT_GRASP, TaskSpec
from robot_sim.planning.scaling import (
    CartesianPathError,
    Trajectory,
    cartesian_line,
    check_in_limits,
    hold,
    qd_limits,
    tool_poses,
    trapezoidal,
)
from robot_sim.transforms import rot_z, rpy_from_rot

FloatArray = np.ndarray

PHASES = ("pre-grasp", "approach", "close", "lift", "transport", "place", "release", "retreat")
#: Joint-space moves run at this fraction of each joint's speed limit, reaching it in
#: JOINT_ACC_TIME seconds.
JOINT_SPEED_FRACTION = 0.5
JOINT_ACC_TIME = 0.3
#: Quintic straight lines peak at 15/8 of their mean speed; shortest straight move [s].
QUINTIC_PEAK = 15.0 / 8.0
MIN_LINE_DURATION = 0.5
#: Gripper opening beyond the object's width on each side [m].
GRIPPER_CLEARANCE = 0.015
#: Default task: object (box) size [m], and where candidates are tried, as fractions of the
#: robot's horizontal reach from its base.
DEFAULT_OBJECT_SIZE = (0.04, 0.04, 0.08)
DEFAULT_RADII = (0.5, 0.4, 0.6, 0.3, 0.7)
DEFAULT_HEIGHTS = (0.0, -0.2, 0.2, -0.4, 0.4)
DEFAULT_AZIMUTH = math.radians(35.0)
#: Lowest table top of a default task, above the ground z = 0 [m].
MIN_TABLE_TOP = 0.03
#: (approach, lift) heights tried for a default task, the usual first; arms that cannot
#: point the tool down far above their table (the Stanford arm) get the short ones [m].
DEFAULT_MOTIONS = ((0.10, 0.15), (0.06, 0.05))
TABLE_MARGIN = 0.08
TABLE_MIN_THICKNESS = 0.04


class TaskError(ValueError):
    """The task cannot be done by this robot; the one-line message says which phase, which
    pose and why."""


@dataclass(frozen=True)
class SceneState:
    """The scene at time ``t`` [s]: joint vector ``q``, tool pose and object pose (4×4,
    world), gripper opening [m] (distance between the fingers), whether the object is
    attached to the tool, and the current phase."""

    t: float
    q: FloatArray
    tool_pose: FloatArray
    object_pose: FloatArray
    gripper_opening: float
    attached: bool
    phase: str


@dataclass(frozen=True, eq=False)
class TaskPlan:
    """A planned task: ``trajectory`` (with tool poses and one mark per phase), the time the
    object is picked up (``t_attach``, start of the lift) and let go (``t_release``, start
    of the release), and ``placed_pose`` (4×4), where the object ends up."""

    robot: RobotParams
    spec: TaskSpec
    trajectory: Trajectory
    t_attach: float
    t_release: float
    placed_pose: FloatArray

    @property
    def duration(self) -> float:
        """Length of the whole task [s]."""
        return self.trajectory.duration

    def phase_times(self) -> dict[str, float]:
        """Start time of every phase [s]."""
        return {name: tm for tm, name in self.trajectory.marks}

    def phase_at(self, t: float) -> str:
        """Name of the phase running at ``t`` ("done" after the end)."""
        if t >= self.trajectory.t[-1]:
            return "done"
        current = PHASES[0]
        for tm, name in self.trajectory.marks:
            if tm <= t:
                current = name
        return current

    def state_at(self, t: float) -> SceneState:
        """The scene at time ``t`` [s] (clamped to the task: past the end is the final scene)."""
        if not math.isfinite(t):
            raise ValueError(f"t must be a finite number of seconds, got {t!r}")
        t = min(max(t, float(self.trajectory.t[0])), float(self.trajectory.t[-1]))
        q, _, _ = self.trajectory.evaluate(t)
        tool = forward_kinematics(self.robot, q)
        attached = self.t_attach <= t < self.t_release
        if attached:
            obj = tool @ np.linalg.inv(self.spec.grasp)
        elif t >= self.t_release:
            obj = self.placed_pose
        else:
            obj = self.spec.object_pose
        return SceneState(t, q, tool, np.array(obj), self.gripper_opening(t), attached, self.phase_at(t))

    def gripper_opening(self, t: float) -> float:
        """Distance between the fingers at ``t`` [m]: open, closing during "close" (linear),
        closed on the object, opening during "release"."""
        closed = self.spec.grip_width()
        opened = closed + 2 * GRIPPER_CLEARANCE
        marks = self.phase_times()
        close0, release0 = marks["close"], marks["release"]
        if t < close0 or t >= release0 + self.spec.dwell:
            return opened
        if t < close0 + self.spec.dwell:
            return opened + (closed - opened) * (t - close0) / self.spec.dwell
        if t < release0:
            return closed
        return closed + (opened - closed) * (t - release0) / self.spec.dwell


def _raised(pose: FloatArray, height: float) -> FloatArray:
    out = np.array(pose)
    out[2, 3] += height
    return out


def _where(pose: FloatArray) -> str:
    rpy = np.degrees(rpy_from_rot(pose[:3, :3]))
    return (f"tool at xyz [{', '.join(f'{v:.3f}' for v in pose[:3, 3])}] m, "
            f"rpy [{', '.join(f'{v:.1f}' for v in rpy)}] deg")


class _Planner:
    """Builds the phases one after the other, each from where the previous one ended."""

    def __init__(self, robot: RobotParams, spec: TaskSpec) -> None:
        self.robot, self.spec = robot, spec
        self.prefix = f"task {spec.source}: {robot.name}"
        self.v = JOINT_SPEED_FRACTION * qd_limits(robot)
        self.a = self.v / JOINT_ACC_TIME

    def ik(self, phase: str, pose: FloatArray, seed: FloatArray) -> FloatArray:
        res = solve_ik(self.robot, pose, seed, tol_pos=1e-9, tol_rot=1e-9)
        if not res.success:
            raise TaskError(f"{self.prefix}: {phase}: {_where(pose)} is out of reach: IK {res.message}")
        return res.q

    def line(self, phase: str, pose0: FloatArray, pose1: FloatArray, q: FloatArray) -> Trajectory:
        dist = float(np.linalg.norm(pose1[:3, 3] - pose0[:3, 3]))
        duration = max(MIN_LINE_DURATION, QUINTIC_PEAK * dist / self.spec.speed)
        try:
            return cartesian_line(self.robot, pose0, pose1, duration, q)
        except CartesianPathError as exc:
            raise TaskError(f"{self.prefix}: {phase}: {exc}") from None

    def joint_move(self, q0: FloatArray, q1: FloatArray) -> Trajectory:
        return trapezoidal(q0, q1, self.v, self.a)


def plan_pick(robot: RobotParams, spec: TaskSpec, q_start: FloatArray | None = None) -> TaskPlan:
    """Plan the whole task for ``robot`` from ``q_start`` (home by default).

    Raises :class:`TaskError` (one line: task, robot, phase, pose, reason) if any phase
    cannot be done: a pose out of reach, a straight move that meets a singularity or a
    joint limit.  Nothing is returned half-planned.
    """
    q0 = np.array(robot.q_home if q_start is None else q_start, dtype=float)
    check_in_limits(robot, q0, "q_start")
    p = _Planner(robot, spec)
    grasp_tool = spec.object_pose @ spec.grasp
    place_tool = spec.place @ spec.grasp
    pre_grasp = _raised(grasp_tool, spec.approach)
    lifted = _raised(grasp_tool, spec.lift)
    pre_place = _raised(place_tool, spec.lift)

    segments: list[tuple[str, Trajectory]] = []
    segments.append(("pre-grasp", p.joint_move(q0, p.ik("pre-grasp", pre_grasp, q0))))
    segments.append(("approach", p.line("approach", pre_grasp, grasp_tool, segments[-1][1].q[-1])))
    segments.append(("close", hold(segments[-1][1].q[-1], spec.dwell)))
    segments.append(("lift", p.line("lift", grasp_tool, lifted, segments[-1][1].q[-1])))
    q_lifted = segments[-1][1].q[-1]
    segments.append(("transport", p.joint_move(q_lifted, p.ik("transport", pre_place, q_lifted))))
    segments.append(("place", p.line("place", pre_place, place_tool, segments[-1][1].q[-1])))
    segments.append(("release", hold(segments[-1][1].q[-1], spec.dwell)))
    segments.append(("retreat", p.line("retreat", place_tool, _raised(place_tool, spec.approach),
                                       segments[-1][1].q[-1])))

    traj: Trajectory | None = None
    for name, seg in segments:
        seg = Trajectory(seg.t, seg.q, seg.qd, seg.qdd, None, ((float(seg.t[0]), name),))
        traj = seg if traj is None else traj.then(seg)
    assert traj is not None
    traj = tool_poses(robot, traj)
    marks = {name: tm for tm, name in traj.marks}
    q_release, _, _ = traj.evaluate(marks["release"])
    placed = forward_kinematics(robot, q_release) @ np.linalg.inv(spec.grasp)
    return TaskPlan(robot, spec, traj, marks["lift"], marks["release"], placed)


def _candidate(robot: RobotParams, radius: float, height: float, approach: float, lift: float) -> TaskSpec:
    base = robot.base_tf.t()
    size = np.array(DEFAULT_OBJECT_SIZE)
    centres = [base + [radius * math.cos(a), radius * math.sin(a), height]
               for a in (-DEFAULT_AZIMUTH, DEFAULT_AZIMUTH)]
    top = centres[0][2] - size[2] / 2
    xy = np.array([c[:2] for c in centres])
    lo, hi = xy.min(axis=0) - TABLE_MARGIN, xy.max(axis=0) + TABLE_MARGIN
    thickness = top if top > TABLE_MIN_THICKNESS else TABLE_MIN_THICKNESS
    pose = [np.block([[rot_z(0.0), c[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]]) for c in centres]
    return TaskSpec(
        name=f"default pick for {robot.name}",
        table_top=[*(lo + hi) / 2, top],
        table_size=[*(hi - lo), thickness],
        object_shape="box",
        object_size=size,
        object_pose=pose[0],
        grasp=DEFAULT_GRASP,
        place=pose[1],
        approach=approach,
        lift=lift,
        source=f"<default for {robot.name}>",
    )


def default_task(robot: RobotParams) -> TaskSpec:
    """A task that fits ``robot``'s workspace: a box on a table in front of it, picked at
    35° to one side of the base's x axis and placed at 35° to the other, at the same height.

    Candidates are tried at fractions of the horizontal reach (95th percentile over 2000
    random configurations), at heights around the base and with two sets of approach and
    lift heights (``DEFAULT_MOTIONS``), raising a table top below
    ``MIN_TABLE_TOP`` to it (it stands on the ground); the first whose whole task plans wins.  Raises
    TaskError if none does.
    """
    return default_plan(robot).spec


@lru_cache(maxsize=None)
def default_plan(robot: RobotParams) -> TaskPlan:
    """The plan of :func:`default_task` from home (computed once per robot)."""
    rng = np.random.default_rng(0)
    tips = forward_kinematics(robot, random_configurations(robot, 2000, rng))[:, :3, 3]
    reach = float(np.percentile(np.linalg.norm(tips[:, :2] - robot.base_tf.t()[:2], axis=1), 95))
    errors, tried = [], set()
    for r in DEFAULT_RADII:
        for h in DEFAULT_HEIGHTS:
            lowest = MIN_TABLE_TOP + DEFAULT_OBJECT_SIZE[2] / 2 - robot.base_tf.t()[2]
            height = round(max(h * reach, lowest), 6)
            if (r, height) in tried:
                continue
            tried.add((r, height))
            for approach, lift in DEFAULT_MOTIONS:
                spec = _candidate(robot, r * reach, height, approach, lift)
                try:
                    return plan_pick(robot, spec)
                except TaskError as exc:
                    errors.append(str(exc))
    first = errors[0]
    raise TaskError(f"{robot.name}: no default pick task fits its workspace ({len(errors)} candidates "
                    f"failed; first: {first})")
