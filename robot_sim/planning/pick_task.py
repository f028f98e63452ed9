"""The pick-and-place task as a planned motion: :func:`plan_pick`, :class:`TaskPlan`,
the scene at any time (:meth:`TaskPlan.state_at`) and a default task per robot.

The sequence (each phase a mark of the trajectory): **pre-grasp** (joint space, from the
start configuration to ``approach`` m above the grasp), **approach** (straight down),
**close** (gripper closes, arm at rest), **lift** (straight up by ``lift`` m, object
attached to the tool), **transport** (joint space, to ``lift`` m above the place pose),
**place** (straight down), **release** (gripper opens; the object stays where it is),
**retreat** (straight up by ``approach`` m).

The task's world (the floor, the table and the task file's obstacles,
:meth:`TaskSpec.world`) is never entered: the joint-space moves are planned around it
(:func:`plan_path`) and timed time-optimally under the speed, acceleration and effort
limits (:func:`retime`); the straight moves are checked continuously too.  From the
lift to the release the object is checked as a shape carried by the last link
(:class:`CheckerGroup` with :func:`held_object`; it may touch the table only while it
leaves or reaches it).
A straight move that cannot be followed (a joint reaching its limit, a joint accelerating
beyond its limit, a collision) is replaced by a joint-space plan between the same poses.
Everything is planned before anything moves: an unreachable task raises
:class:`TaskError` with one line naming the phase, the pose and why.  World frame, SI
units; no Qt, no OpenGL.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from robot_sim.collision import Box, CollisionChecker
from robot_sim.collision.distance import shape_distance
from robot_sim.kinematics import forward_kinematics, random_configurations, solve_ik
from robot_sim.model.params import RobotParams
from robot_sim.planning.carrying import CheckerGroup, held_object
from robot_sim.planning.cartesian import CartesianPathError, cartesian_line, tool_poses
from robot_sim.planning.profiles import check_in_limits, hold
from robot_sim.planning.retime import retime
from robot_sim.planning.rrt import plan_path
from robot_sim.planning.task_file import DEFAULT_GRASP, TaskSpec
from robot_sim.planning.trajectory import Trajectory
from robot_sim.transforms import rot_z, rpy_from_rot

FloatArray = np.ndarray

PHASES = ("pre-grasp", "approach", "close", "lift", "transport", "place", "release", "retreat")
#: Time given to each joint-space plan [s].
PLAN_TIME = 2.0
#: Quintic straight lines peak at 15/8 of their mean speed; shortest straight move [s].
QUINTIC_PEAK = 15.0 / 8.0
MIN_LINE_DURATION = 0.5
#: The object may sink this far into an obstacle at its start and place poses [m].
OVERLAP_TOL = 1e-6
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
#: point the tool down far above their table (the Stanford arm) get the short ones [m],
#: and the grasp with the tool at the object's centre.
CENTRE_GRASP = np.diag([1.0, -1.0, -1.0, 1.0])
DEFAULT_MOTIONS = ((0.10, 0.15), (0.06, 0.05))
TABLE_MARGIN = 0.08
TABLE_MIN_THICKNESS = 0.04
#: The default task's wall (6 and 7 joints): thickness, and how far it reaches beyond the
#: chord and the arc between pick and place and above the lifted object [m].
WALL_THICKNESS = 0.02
WALL_MARGIN = 0.04


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


def _obstacle_overlapping(spec: TaskSpec, pose: FloatArray) -> str | None:
    """The name of the first obstacle (besides the table it rests on) that the object,
    posed at ``pose``, overlaps by more than OVERLAP_TOL, or None."""
    body = spec.object_shape_at(pose)
    for name, shape in spec.world(table=False).obstacles:
        if shape_distance(body, shape).distance < -OVERLAP_TOL:
            return name
    return None


def _where(pose: FloatArray) -> str:
    rpy = np.degrees(rpy_from_rot(pose[:3, :3]))
    return (f"tool at xyz [{', '.join(f'{v:.3f}' for v in pose[:3, 3])}] m, "
            f"rpy [{', '.join(f'{v:.1f}' for v in rpy)}] deg")


class _Planner:
    """Builds the phases one after the other, each from where the previous one ended."""

    def __init__(self, robot: RobotParams, spec: TaskSpec, seed: int | None) -> None:
        self.robot, self.spec, self.seed = robot, spec, seed
        self.prefix = f"task {spec.source}: {robot.name}"
        held = robot.tool_tf.mat @ np.linalg.inv(spec.grasp)  # the object in the last link's frame
        carried = spec.object_shape_at(held)
        world = spec.world()
        #: the arm in the task's world; with the object carried; and while the object
        #: leaves or reaches the table (it rests on it at one end)
        self.free = CollisionChecker(robot, world)
        self.carry = CheckerGroup(self.free, held_object(robot, carried, world))
        self.lifting = CheckerGroup(self.free, held_object(robot, carried, spec.world(table=False)))

    def fail(self, phase: str, why: str) -> TaskError:
        return TaskError(f"{self.prefix}: {phase}: {why}")

    def ik(self, phase: str, pose: FloatArray, seed: FloatArray, checker) -> FloatArray:  # noqa: ANN001
        res = solve_ik(self.robot, pose, seed, tol_pos=1e-9, tol_rot=1e-9, checker=checker)
        if not res.success:
            raise self.fail(phase, f"{_where(pose)} is out of reach: IK {res.message}")
        return res.q

    def joint_move(self, phase: str, q0: FloatArray, q1: FloatArray, checker) -> Trajectory:  # noqa: ANN001
        """A collision-free joint-space path, retimed time-optimally."""
        res = plan_path(self.robot, q0, q1, checker, time_limit=PLAN_TIME, seed=self.seed)
        if not res.success:
            raise self.fail(phase, f"no collision-free joint path: {res.message}")
        try:
            return retime(self.robot, res.path)
        except ValueError as exc:
            raise self.fail(phase, str(exc)) from None

    def line(self, phase: str, pose0: FloatArray, pose1: FloatArray, q: FloatArray, checker) -> Trajectory:  # noqa: ANN001
        """The straight move, checked continuously; a joint-space plan to the same pose
        where it cannot be followed or would collide."""
        dist = float(np.linalg.norm(pose1[:3, 3] - pose0[:3, 3]))
        duration = max(MIN_LINE_DURATION, QUINTIC_PEAK * dist / self.spec.speed)
        try:
            traj = cartesian_line(self.robot, pose0, pose1, duration, q)
            if checker.path_is_free(traj.q):
                return traj
        except CartesianPathError:
            pass
        return self.joint_move(phase, q, self.ik(phase, pose1, q, checker), checker)


def plan_pick(robot: RobotParams, spec: TaskSpec, q_start: FloatArray | None = None, *,
              seed: int | None = 0) -> TaskPlan:
    """Plan the whole task for ``robot`` from ``q_start`` (home by default).

    Raises :class:`TaskError` (one line: task, robot, phase, pose, reason) if any phase
    cannot be done: a pose out of reach or only in collision, no collision-free path, a
    start in collision.  Nothing is returned half-planned.  ``seed`` makes the joint-space
    plans reproducible.
    """
    q0 = np.array(robot.q_home if q_start is None else q_start, dtype=float)
    check_in_limits(robot, q0, "q_start")
    p = _Planner(robot, spec, seed)
    if p.free.in_collision(q0):
        raise p.fail("pre-grasp", f"the start configuration is in collision ({p.free.distance(q0).pair})")
    for phase, pose, what in (("pre-grasp", spec.object_pose, "object"), ("place", spec.place, "place pose")):
        inside = _obstacle_overlapping(spec, pose)
        if inside is not None:
            raise p.fail(phase, f"the {what} at xyz [{', '.join(f'{v:.3f}' for v in pose[:3, 3])}] m is inside "
                                f"obstacle '{inside}': the object would overlap it")
    grasp_tool = spec.object_pose @ spec.grasp
    place_tool = spec.place @ spec.grasp
    pre_grasp = _raised(grasp_tool, spec.approach)
    lifted = _raised(grasp_tool, spec.lift)
    pre_place = _raised(place_tool, spec.lift)

    segments: list[tuple[str, Trajectory]] = []

    def last() -> FloatArray:
        return segments[-1][1].q[-1]

    segments.append(("pre-grasp", p.joint_move("pre-grasp", q0, p.ik("pre-grasp", pre_grasp, q0, p.free), p.free)))
    segments.append(("approach", p.line("approach", pre_grasp, grasp_tool, last(), p.free)))
    segments.append(("close", hold(last(), spec.dwell)))
    segments.append(("lift", p.line("lift", grasp_tool, lifted, last(), p.lifting)))
    segments.append(("transport", p.joint_move("transport", last(), p.ik("transport", pre_place, last(), p.carry),
                                               p.carry)))
    segments.append(("place", p.line("place", pre_place, place_tool, last(), p.lifting)))
    segments.append(("release", hold(last(), spec.dwell)))
    segments.append(("retreat", p.line("retreat", place_tool, _raised(place_tool, spec.approach), last(), p.free)))

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


def _candidate(robot: RobotParams, radius: float, height: float, approach: float, lift: float,
               grasp: FloatArray) -> TaskSpec:
    base = robot.base_tf.t()
    size = np.array(DEFAULT_OBJECT_SIZE)
    centres = [base + [radius * math.cos(a), radius * math.sin(a), height]
               for a in (-DEFAULT_AZIMUTH, DEFAULT_AZIMUTH)]
    top = centres[0][2] - size[2] / 2
    xy = [c[:2] for c in centres]
    obstacles: tuple = ()
    if robot.n_dofs >= 6:
        # a wall on the table between pick and place, across the chord and the arc between
        # them, rising WALL_MARGIN above the lifted object: a straight transport hits it
        near, far = radius * math.cos(DEFAULT_AZIMUTH) - WALL_MARGIN, radius + WALL_MARGIN
        wall_size = np.array([far - near, WALL_THICKNESS, size[2] + lift + WALL_MARGIN])
        pose = np.eye(4)
        pose[:3, 3] = base + [(near + far) / 2, 0.0, 0.0]
        pose[2, 3] = top + wall_size[2] / 2
        obstacles = (("wall", Box(wall_size, pose)),)
        xy += [base[:2] + [near, 0.0], base[:2] + [far, 0.0]]
    xy = np.array(xy)
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
        grasp=grasp,
        place=pose[1],
        approach=approach,
        lift=lift,
        source=f"<default for {robot.name}>",
        obstacles=obstacles,
    )


def default_task(robot: RobotParams) -> TaskSpec:
    """A task that fits ``robot``'s workspace: a box on a table in front of it, picked at
    35° to one side of the base's x axis and placed at 35° to the other, at the same height;
    for arms of 6 and 7 joints with a wall on the table between the two that the object,
    carried straight at its lift height, would hit.

    Candidates are tried at fractions of the horizontal reach (95th percentile over 2000
    random configurations), at heights around the base and with two sets of approach and
    lift heights (``DEFAULT_MOTIONS``), raising a table top below
    ``MIN_TABLE_TOP`` to it (it stands on the ground); the first whose whole task plans wins,
    with the default grasp (fingertips at the object's centre) first, then, for arms that
    cannot point the tool down that high (the Stanford arm), with the tool at the centre.
    Raises TaskError if none does.
    """
    return default_plan(robot).spec


@lru_cache(maxsize=None)
def default_plan(robot: RobotParams) -> TaskPlan:
    """The plan of :func:`default_task` from home (computed once per robot)."""
    rng = np.random.default_rng(0)
    tips = forward_kinematics(robot, random_configurations(robot, 2000, rng))[:, :3, 3]
    reach = float(np.percentile(np.linalg.norm(tips[:, :2] - robot.base_tf.t()[:2], axis=1), 95))
    errors = []
    for grasp in (DEFAULT_GRASP, CENTRE_GRASP):
        tried = set()
        for r in DEFAULT_RADII:
            for h in DEFAULT_HEIGHTS:
                lowest = MIN_TABLE_TOP + DEFAULT_OBJECT_SIZE[2] / 2 - robot.base_tf.t()[2]
                height = round(max(h * reach, lowest), 6)
                if (r, height) in tried:
                    continue
                tried.add((r, height))
                for approach, lift in DEFAULT_MOTIONS:
                    spec = _candidate(robot, r * reach, height, approach, lift, grasp)
                    try:
                        return plan_pick(robot, spec)
                    except TaskError as exc:
                        errors.append(str(exc))
    first = errors[0]
    raise TaskError(f"{robot.name}: no default pick task fits its workspace ({len(errors)} candidates "
                    f"failed; first: {first})")
