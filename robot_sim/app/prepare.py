"""The command line of ``robot-sim``, step 2 of 3: prepare.  Load the robot and its world,
check every option that needs the robot (joint values, gains, frames, look, annotated
joint, workspace size), plan the pick task (and, with --motion, run it) and describe the
session to show as a :class:`~robot_sim.viewer.builder.SessionSpec`.  Nothing is written
and no window or GL context is made; the planner and the simulation (numba) are imported
only for --demo pick and --motion.
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import re
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from robot_sim.app.cli import PROG, RECORD_DEFAULT_DURATION_S, RECORD_DEFAULT_FPS, CliError, parse_args, parse_number
from robot_sim.graphics.looks import LOOKS, looks_of
from robot_sim.graphics.themes import DEFAULT_THEME
from robot_sim.io.meshes import MeshSkippedWarning
from robot_sim.io.robot_file import load_robot
from robot_sim.io.world_file import WorldDefinitionError, load_world
from robot_sim.io.xacro_file import parse_xacro_args
from robot_sim.kinematics import available_memory, max_workspace_samples, sampling_bounds
from robot_sim.model.messages import clip
from robot_sim.model.params import JTYPE_PRISMATIC, RobotDefinitionError, RobotParams
from robot_sim.model.world import World
from robot_sim.viewer.builder import PickShow, SessionSpec, build_session
from robot_sim.viewer.session import ViewerSession
from robot_sim.viewer.units import display_range, display_scale

if TYPE_CHECKING:
    from robot_sim.planning.pick_task import TaskPlan


@dataclass
class Config:
    """Validated command line: the robot, start q (SI), sizes in pixels, paths."""

    robot_arg: str
    robot: RobotParams
    q: np.ndarray | None
    size: tuple[int, int]
    screenshot: Path | None
    frames: list[int] | None  # exactly these frames (n_dofs + 1 = endeffector), None: default
    wireframe: bool
    workspace: int
    demo: str | None
    pick_plan: TaskPlan | None = None  # --demo pick: planned before any window opens
    pick_effort: np.ndarray | None = None  # --demo pick --motion: efforts of the simulated run
    pick_report: str | None = None  # --demo pick --motion: tracking errors, one line
    time: float = 0.0  # --time: pick demo time shown first [s]
    record: Path | None = None  # --record DIR (created by the output step)
    duration: float = RECORD_DEFAULT_DURATION_S  # --duration [s]
    fps: float = RECORD_DEFAULT_FPS  # --fps
    annotate: int | None = None  # joint number whose DH parameters are drawn
    motion: str | None = None  # --motion: physical motion mode
    simulate: float = 0.0  # --duration with --motion and no --record: seconds simulated first [s]
    gains: dict[str, Any] = field(default_factory=dict)  # --bandwidth, --damping, --kp, --kd
    theme: str = DEFAULT_THEME  # --theme
    look: str | None = None  # --look (None: the robot's default look)
    command: str = PROG  # the command line as given: pictures record it (picture_text)
    world: World | None = None  # --world: obstacles (None: the floor only)
    collision: bool = False  # --collision: the collision display shown
    trail: bool = False  # --trail: the endeffector's path drawn
    ik_branches: bool = False  # --ik-branches: every analytic IK branch of the start pose drawn


def prepare(argv: Sequence[str]) -> Config:
    """Steps 1 and 2 for ``argv``: parse (robot_sim.app.cli.parse_args), then prepare."""
    return config_from_args(parse_args(argv))


def config_from_args(args: argparse.Namespace) -> Config:
    """Prepare parsed arguments (robot_sim.app.cli.parse_args): load the robot and the
    world, check the options that need the robot, plan the pick task."""
    robot = load_robot_arg(args)
    if args.ik_branches:
        check_ik_branches(robot)
    if args.workspace:
        check_workspace(args.workspace, robot)
    try:
        world = None if args.world is None else load_world(args.world)
    except WorldDefinitionError as exc:
        raise CliError(f"--world: {exc}") from None
    pick_plan, pick_effort, pick_report = pick_arguments(args, robot, world)
    duration = RECORD_DEFAULT_DURATION_S if pick_plan is None else max(pick_plan.duration - args.time, 0.0)
    if args.duration is not None:
        duration = args.duration
    simulate = duration if args.motion is not None and args.record is None and args.duration is not None else 0.0
    return Config(
        robot_arg=args.robot,
        robot=robot,
        q=None if args.q is None else parse_q(args.q, robot),
        size=args.size,
        screenshot=args.screenshot,
        frames=parse_frames(args.frames, robot.n_dofs + 1),
        wireframe=args.wireframe,
        workspace=args.workspace,
        demo=args.demo,
        pick_plan=pick_plan,
        pick_effort=pick_effort,
        pick_report=pick_report,
        time=args.time,
        record=args.record,
        duration=duration,
        fps=args.fps,
        annotate=None if args.annotate is None else parse_joint_number("--annotate", args.annotate, robot.n_dofs),
        motion=args.motion,
        simulate=simulate,
        gains=gain_arguments(args, robot),
        theme=args.theme,
        look=parse_look(args.look, robot),
        world=world,
        collision=args.collision,
        trail=args.trail,
        ik_branches=args.ik_branches,
    )


def check_ik_branches(robot: RobotParams) -> None:
    """CliError for --ik-branches on an arm the analytic IK does not solve (the solver,
    compiled with numba, is loaded only then)."""
    from robot_sim.ik.solutions import unsolved

    why = unsolved(robot)
    if why is not None:
        raise CliError(f"--ik-branches: {robot.name} has {why}")


def load_robot_arg(args: argparse.Namespace) -> RobotParams:
    """``--robot`` (with --tip, --convention, --skip-missing-meshes, --xacro-arg) loaded;
    each mesh skipped is one warning line on stderr."""
    try:
        xacro_args = parse_xacro_args(args.xacro_arg)
        with warnings.catch_warnings(record=True) as skipped:
            warnings.simplefilter("always", MeshSkippedWarning)
            robot = load_robot(args.robot, tip=args.tip, convention=args.convention,
                               skip_missing_meshes=args.skip_missing_meshes, xacro_args=xacro_args or None)
    except RobotDefinitionError as exc:
        raise CliError(str(exc)) from None
    except ValueError as exc:  # xacro arguments, or given for a robot that is not a xacro file
        raise CliError(f"--xacro-arg: {exc}") from None
    for warning in skipped:
        if issubclass(warning.category, MeshSkippedWarning):
            print(f"{PROG}: warning: {' '.join(str(warning.message).split())}", file=sys.stderr)
        else:
            warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno)
    return robot


def session_spec(config: Config) -> SessionSpec:
    """What the session shows for ``config`` (robot_sim.viewer.builder)."""
    pick = None if config.pick_plan is None else PickShow(
        config.pick_plan, config.time, config.pick_effort,
        config.motion if config.pick_effort is not None else "kinematic")
    return SessionSpec(config.robot, size=config.size, q=config.q, theme=config.theme, look=config.look,
                       world=config.world, gains=config.gains, motion=config.motion, simulate=config.simulate,
                       frames=config.frames, wireframe=config.wireframe, collision=config.collision,
                       annotate=config.annotate, trail=config.trail, ik_branches=config.ik_branches, pick=pick,
                       demo="circle" if config.demo == "circle" else None)


def session_from_config(config: Config) -> ViewerSession:
    """The session of ``config``: q, motion (simulated for --duration), frames, wireframe,
    annotated joint, trail and demo applied, framed for all of it."""
    try:
        return build_session(session_spec(config))
    except ValueError as exc:  # e.g. dynamics refusing the robot's data, a stop in the first seconds
        raise CliError(f"--motion {config.motion}: {exc}") from None


def gain_arguments(args: argparse.Namespace, robot: RobotParams) -> dict[str, Any]:
    """--bandwidth, --damping, --kp, --kd as control.control_gains keywords."""
    gains: dict[str, Any] = {}
    for option in ("bandwidth", "damping"):
        if getattr(args, option) is not None:
            gains[option] = parse_number(f"--{option}", getattr(args, option), "a positive number", True)
    for option in ("kp", "kd"):
        if getattr(args, option) is not None:
            gains[option] = parse_gains(getattr(args, option), robot, f"--{option}")
    return gains


def parse_gains(text: str, robot: RobotParams, option: str) -> np.ndarray:
    """Parse ``--kp``/``--kd``: one finite gain >= 0 per joint, comma separated."""
    gains = []
    for i, part in enumerate(_per_joint(text, robot, option, "gains")):
        value = float(part) if _is_float(part) else math.nan
        if not (math.isfinite(value) and value >= 0):
            raise CliError(f"{option}: gain {i + 1} '{part}' is not a finite number >= 0")
        gains.append(value)
    return np.array(gains)


def _per_joint(text: str, robot: RobotParams, option: str, what: str) -> list[str]:
    """The comma-separated parts of ``text``, one per joint of ``robot``, else CliError."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != robot.n_dofs:
        raise CliError(f"{option}: robot '{robot.name}' has {robot.n_dofs} joints, got {len(parts)} {what}")
    return parts


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def parse_q(text: str, robot: RobotParams) -> np.ndarray:
    """Parse ``--q`` (degrees for revolute, metres for prismatic) into SI joint values (n,)."""
    values = []
    for i, part in enumerate(_per_joint(text, robot, "--q", "values")):
        try:
            value = float(part)
        except ValueError:
            raise CliError(f"--q: value {i + 1} '{part}' is not a number") from None
        if not math.isfinite(value):
            raise CliError(f"--q: value {i + 1} '{part}' is not a finite number")
        values.append(value)
    q = np.array(values) / display_scale(robot)
    bad = np.flatnonzero((q < robot.q_min) | (q > robot.q_max))
    if bad.size:
        i = int(bad[0])
        lo, hi = display_range(robot)
        unit = "m" if robot.jtype[i] == JTYPE_PRISMATIC else "deg"
        raise CliError(f"--q: joint {i + 1} value {values[i]:g} {unit} is outside its limits [{lo[i]:g}, {hi[i]:g}] {unit}")
    return q


def parse_frames(text: str | None, n_frames: int) -> list[int] | None:
    """Parse ``--frames all|none|i,j,...,E`` into the frame indices to show, exactly:
    0..n_frames-1 are DH frames, ``n_frames`` (written E) the endeffector frame.  None
    when the option was not given (the default frames are shown)."""
    if text is None:
        return None
    word = text.strip().lower()
    if word == "all":
        return list(range(n_frames + 1))
    if word == "none":
        return []
    frames = []
    for part in text.split(","):
        part = part.strip()
        if part.upper() == "E":
            frames.append(n_frames)
        elif re.fullmatch(r"\d+", part) and int(part) < n_frames:
            frames.append(int(part))
        else:
            raise CliError(f"--frames: expected 'all', 'none' or frame numbers 0..{n_frames - 1} and E "
                           f"separated by commas, got '{part}'")
    return frames


def check_workspace(n_points: int, robot: RobotParams) -> None:
    """CliError unless ``--workspace n_points`` can be computed for ``robot``: its joints
    can be sampled (no unlimited prismatic joint) and the points fit in memory."""
    try:
        sampling_bounds(robot)
    except ValueError as exc:
        raise CliError(f"--workspace: {exc}") from None
    limit = max_workspace_samples(robot)
    if n_points > limit:
        raise CliError(
            f"--workspace: {clip(str(n_points), 20)} points need more than the {available_memory() // 2**20} MiB "
            f"of memory available; at most {limit} points fit"
        )


def parse_look(text: str | None, robot: RobotParams) -> str | None:
    """``--look``: one of ``graphics.LOOKS`` that ``robot`` can be drawn in (``mesh`` and
    ``both`` need visual shapes); None when not given (the robot's default look)."""
    if text is None:
        return None
    if text not in LOOKS:
        raise CliError(f"--look: expected one of {', '.join(LOOKS)}, got '{clip(text)}'")
    available = looks_of(robot)
    if text not in available:
        raise CliError(f"--look: robot '{robot.name}' has no visual shapes, so its looks are "
                       f"{', '.join(available)}; got '{text}'")
    return text


def parse_joint_number(option: str, text: str, n_dofs: int) -> int:
    """A joint number 1..``n_dofs`` from ``text``, else CliError naming ``option``."""
    if not re.fullmatch(r"\d+", text.strip()) or not 1 <= int(text) <= n_dofs:
        raise CliError(f"{option}: expected a joint number 1..{n_dofs}, got '{text}'")
    return int(text)


def pick_arguments(args: argparse.Namespace, robot: RobotParams, world: World | None = None
                   ) -> tuple[TaskPlan | None, np.ndarray | None, str | None]:
    """--demo pick (with --task and --motion): the plan among the task's and ``world``'s
    (--world) obstacles (made here, so an impossible task is one line before anything
    opens or moves) and, with --motion, the plan as the simulated controller ran it, its
    efforts and its one-line tracking report."""
    if args.demo != "pick":
        return None, None, None
    from robot_sim.viewer.pick_demo import plan_for  # the planner: numba

    try:
        plan = plan_for(robot, args.task, world)
    except ValueError as exc:  # TaskDefinitionError, TaskError
        raise CliError(str(exc)) from None
    if args.motion is None:
        return plan, None, None
    from robot_sim.sim.pick_run import simulate_pick

    try:
        run = simulate_pick(plan, args.motion)
    except ValueError as exc:  # e.g. dynamics refusing the robot's data
        raise CliError(f"--motion {args.motion}: {exc}") from None
    simulated = dataclasses.replace(plan, trajectory=run.motion, placed_pose=run.placed_pose)
    return simulated, run.effort, run.summary()
