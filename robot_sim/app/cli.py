"""The command line of ``robot-sim``: parsing and validating every argument before any
window or GL context exists, and the offscreen ``--screenshot`` (which never imports Qt).

Bad input raises :class:`CliError`; ``simulator.main`` reports it as one
``robot-sim: error: ...`` line on stderr with exit status 2.
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import os
import re
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from robot_sim.app import web_cmd
from robot_sim.io import files as fileio
from robot_sim.viewer import settings as vs
from robot_sim import graphics as go
from robot_sim.app.robot_cmds import dh_table_text, export
from robot_sim.kinematics import available_memory, max_workspace_samples, sampling_bounds
from robot_sim.model.messages import clip
from robot_sim.model.params import CONVENTIONS, JTYPE_PRISMATIC, RobotDefinitionError, RobotParams
from robot_sim.io.meshes import MeshSkippedWarning
from robot_sim.io.robot_file import load_robot
from robot_sim.io.world_file import WorldDefinitionError, load_world
from robot_sim.model.world import World
from robot_sim.viewer import recording
from robot_sim.viewer.pick_demo import plan_for
from robot_sim.control.controllers import PHYSICAL_MODES
from robot_sim.control.pick_run import simulate_pick
from robot_sim.planning.pick_task import TaskPlan
from robot_sim.viewer.builder import PickShow, SessionSpec, build_session
from robot_sim.viewer.session import ViewerSession, compute_workspace, display_range, display_scale

if TYPE_CHECKING:
    from robot_sim.qt.window import WindowOptions

PROG = "robot-sim"
DEFAULT_ROBOT = "anthropomorphic"
DEMOS = ("circle", "pick")
#: ``--motion`` choices: the physical motion modes of robot_sim.control.controllers.
MOTIONS = PHYSICAL_MODES
#: Command-line limits and defaults.
WINDOW_SIZE_LIMITS = (16, 8192)      # px, accepted range of each --size value
RECORD_DEFAULT_FPS = 25.0
RECORD_DEFAULT_DURATION_S = 5.0           # without the pick demo (whose length is the default)
RECORD_MAX_FPS = 1000.0


class CliError(Exception):
    """Bad command line input: reported as one line on stderr with exit status 2."""


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        raise CliError(message)


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
    record: Path | None = None  # --record DIR
    duration: float = RECORD_DEFAULT_DURATION_S  # --duration [s]
    fps: float = RECORD_DEFAULT_FPS  # --fps
    annotate: int | None = None  # joint number whose DH parameters are drawn
    motion: str | None = None  # --motion: physical motion mode
    simulate: float = 0.0  # --duration with --motion and no --record: seconds simulated first [s]
    gains: dict[str, Any] = field(default_factory=dict)  # --bandwidth, --damping, --kp, --kd
    theme: str = go.DEFAULT_THEME  # --theme
    look: str | None = None  # --look (None: the robot's default look)
    command: str = PROG  # the command line as given: pictures record it (picture_text)
    world: World | None = None  # --world: obstacles (None: the floor only)
    collision: bool = False  # --collision: the collision display shown


def picture_text(config: Config) -> dict[str, str]:
    """What a picture says about itself (PNG text chunks): the program and the command
    line that rendered it, as given (relative paths stay relative)."""
    return {"Software": PROG, "Source": config.command}


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of ``robot-sim`` (errors raise CliError instead of exiting)."""
    w, h = vs.WINDOW_DEFAULT_SIZE
    parser = _Parser(prog=PROG, description="DH robot manipulator simulator with an OpenGL viewer.")
    parser.add_argument("--robot", default=DEFAULT_ROBOT, metavar="NAME|FILE.toml|FILE.urdf",
                        help=f"shipped robot name, robot file or URDF file (default: {DEFAULT_ROBOT})")
    parser.add_argument("--tip", metavar="LINK", help="URDF only: the link that ends the chain (when the tree branches)")
    parser.add_argument("--skip-missing-meshes", action="store_true",
                        help="load the robot without the mesh files that cannot be found or read "
                             "(one warning per file) instead of refusing it")
    parser.add_argument("--convention", choices=CONVENTIONS,
                        help="DH convention to use (default: the robot file's own; standard for URDF)")
    parser.add_argument("--print-dh", action="store_true", help="print the DH table in both conventions and exit")
    parser.add_argument("--export-urdf", metavar="FILE.urdf", help="write the robot as URDF and exit")
    parser.add_argument("--export-toml", metavar="FILE.toml", help="write the robot as a robot file and exit")
    parser.add_argument("--q", metavar="v1,v2,...",
                        help="start joint values: degrees for revolute, metres for prismatic joints")
    parser.add_argument("--size", default=f"{w}x{h}", metavar="WxH", help=f"size of --screenshot and --record pictures in pixels (default: {w}x{h}); "
                             "the window opens at 1280x800 or the screen's size")
    parser.add_argument("--screenshot", metavar="FILE.png",
                        help="render one frame offscreen (OSMesa) to FILE.png and exit; needs no display")
    parser.add_argument("--frames", metavar="all|none|0,2,E",
                        help="show exactly these frames (0 = base frame, E = endeffector); default: the base frame")
    parser.add_argument("--wireframe", action="store_true", help="draw the robot as wireframe")
    parser.add_argument("--theme", metavar="|".join(go.THEMES),
                        help="colours of the world: dark (the default, for the screen) or light (for papers)")
    parser.add_argument("--look", metavar="|".join(go.LOOKS),
                        help="how the robot is drawn: its DH segments, solid capsules, its meshes, or the meshes "
                             "translucent over the DH segments (default: its meshes if it has any, else dh)")
    parser.add_argument("--list-robots", action="store_true",
                        help="list the shipped robots (name, DOF, joints, convention, description) and exit")
    parser.add_argument("--workspace", type=_positive_int, default=0, metavar="N",
                        help="compute and show an N-point workspace cloud")
    parser.add_argument("--demo", choices=DEMOS,
                        help="start a demo: circle = endeffector circle by differential IK, "
                             "pick = pick-and-place task (play, pause, scrub; plots)")
    parser.add_argument("--task", metavar="FILE.toml",
                        help="with --demo pick: the task file (default: a task fitted to the robot)")
    parser.add_argument("--time", metavar="T",
                        help="with --demo pick: show the task at T seconds (past the end: the final scene)")
    parser.add_argument("--record", metavar="DIR",
                        help=f"render the scene offscreen to DIR/{vs.RECORD_FRAME_FORMAT.format(index=0)}, ... and exit")
    parser.add_argument("--duration", metavar="T",
                        help="with --record: seconds to record (default: the rest of the pick task, "
                             f"else {RECORD_DEFAULT_DURATION_S:g}); with --motion and no --record: "
                             "seconds to simulate before the screenshot or the window")
    parser.add_argument("--fps", metavar="F", help=f"with --record: frames per second (default: {RECORD_DEFAULT_FPS:g})")
    parser.add_argument("--annotate", metavar="J",
                        help="draw joint J's DH parameters (d, θ, a, α) between frames J-1 and J, J = 1..n")
    parser.add_argument("--world", metavar="FILE.toml",
                        help="obstacles the arm collides with and, simulated, rests on (a world file; "
                             "default: the floor only)")
    parser.add_argument("--collision", action="store_true",
                        help="show the collision display (key C): collision shapes, contacts in red, the closest pair")
    parser.add_argument("--motion", choices=MOTIONS,
                        help="simulate the arm: passive (falls), pd, pdg (PD + gravity), ct (computed torque), "
                             "osc (operational space), impedance")
    parser.add_argument("--bandwidth", metavar="HZ", help="controller bandwidth (closed-loop natural frequency) in Hz")
    parser.add_argument("--damping", metavar="ZETA", help="controller damping ratio")
    parser.add_argument("--kp", metavar="k1,k2,...", help="PD stiffness per joint (N·m/rad or N/m)")
    parser.add_argument("--kd", metavar="k1,k2,...", help="PD damping per joint (N·m·s/rad or N·s/m)")
    web_cmd.add_arguments(parser)
    return parser


def gain_arguments(args: argparse.Namespace, robot: RobotParams) -> dict[str, Any]:
    """--bandwidth, --damping, --kp, --kd as control.control_gains keywords."""
    gains: dict[str, Any] = {}
    for option in ("bandwidth", "damping"):
        if getattr(args, option) is not None:
            gains[option] = _number(f"--{option}", getattr(args, option), "a positive number", True)
    for option in ("kp", "kd"):
        if getattr(args, option) is not None:
            gains[option] = parse_gains(getattr(args, option), robot, f"--{option}")
    return gains


def parse_gains(text: str, robot: RobotParams, option: str) -> np.ndarray:
    """Parse ``--kp``/``--kd``: one finite gain >= 0 per joint, comma separated."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != robot.n_dofs:
        raise CliError(f"{option}: robot '{robot.name}' has {robot.n_dofs} joints, got {len(parts)} gains")
    gains = []
    for i, part in enumerate(parts):
        try:
            value = float(part)
        except ValueError:
            value = math.nan
        if not (math.isfinite(value) and value >= 0):
            raise CliError(f"{option}: gain {i + 1} '{part}' is not a finite number >= 0")
        gains.append(value)
    return np.array(gains)


def _positive_int(text: str) -> int:
    # at most 4000 digits: int() refuses longer strings, and no memory holds that many points
    if not re.fullmatch(r"\d{1,4000}", text.strip()) or int(text) <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got '{clip(text)}'")
    return int(text)


def parse_q(text: str, robot: RobotParams) -> np.ndarray:
    """Parse ``--q`` (degrees for revolute, metres for prismatic) into SI joint values (n,)."""
    parts = [p.strip() for p in text.split(",")]
    if len(parts) != robot.n_dofs:
        raise CliError(f"--q: robot '{robot.name}' has {robot.n_dofs} joints, got {len(parts)} values")
    values = []
    for i, part in enumerate(parts):
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


def parse_size(text: str) -> tuple[int, int]:
    """Parse ``--size WxH`` into (width, height) pixels within WINDOW_SIZE_LIMITS."""
    lo, hi = WINDOW_SIZE_LIMITS
    match = re.fullmatch(r"(\d+)x(\d+)", text.strip().lower())
    if match is None or not all(lo <= int(v) <= hi for v in match.groups()):
        raise CliError(f"--size: expected WxH with each of W and H in {lo}..{hi} pixels (e.g. 800x600), got '{text}'")
    return int(match.group(1)), int(match.group(2))


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


def check_writable(path: Path) -> Path:
    """Absolute ``path`` if a PNG can be written there (fileio.check_writable), else
    CliError naming the reason."""
    path = path.expanduser().absolute()
    try:
        fileio.check_writable(path)
    except fileio.FileWriteError as exc:
        raise CliError(f"--screenshot: {exc}") from None
    if path.suffix.lower() != ".png":
        raise CliError(f"--screenshot: '{clip(path.name)}' must end in .png (screenshots are PNG files)")
    return path


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


def check_display() -> None:
    """CliError unless a window can be opened: X11 or Wayland display, or Qt's offscreen platform."""
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return
    if os.environ.get("QT_QPA_PLATFORM") == "offscreen":
        return
    raise CliError("no display (DISPLAY and WAYLAND_DISPLAY are not set): "
                   "use --screenshot FILE.png to render offscreen, or run under xvfb-run")


def parse_theme(text: str | None) -> str:
    """``--theme``: one of ``graphics.THEMES`` (the default theme when not given)."""
    if text is None:
        return go.DEFAULT_THEME
    if text not in go.THEMES:
        raise CliError(f"--theme: expected one of {', '.join(go.THEMES)}, got '{clip(text)}'")
    return text


def parse_look(text: str | None, robot: RobotParams) -> str | None:
    """``--look``: one of ``graphics.LOOKS`` that ``robot`` can be drawn in (``mesh`` and
    ``both`` need visual shapes); None when not given (the robot's default look)."""
    if text is None:
        return None
    if text not in go.LOOKS:
        raise CliError(f"--look: expected one of {', '.join(go.LOOKS)}, got '{clip(text)}'")
    available = go.looks_of(robot)
    if text not in available:
        raise CliError(f"--look: robot '{robot.name}' has no visual shapes, so its looks are "
                       f"{', '.join(available)}; got '{text}'")
    return text


def parse_joint_number(option: str, text: str, n_dofs: int) -> int:
    """A joint number 1..``n_dofs`` from ``text``, else CliError naming ``option``."""
    if not re.fullmatch(r"\d+", text.strip()) or not 1 <= int(text) <= n_dofs:
        raise CliError(f"{option}: expected a joint number 1..{n_dofs}, got '{text}'")
    return int(text)


def config_from_args(args: argparse.Namespace) -> Config:
    """Validate parsed arguments: load the robot, parse q, size, frames and the screenshot path."""
    if args.tip is not None and not args.robot.lower().endswith(".urdf"):
        raise CliError(f"--tip: applies to a URDF robot (--robot FILE.urdf), not to '{args.robot}'")
    theme = parse_theme(args.theme)
    try:
        with warnings.catch_warnings(record=True) as skipped:
            warnings.simplefilter("always", MeshSkippedWarning)
            robot = load_robot(args.robot, tip=args.tip, convention=args.convention,
                               skip_missing_meshes=args.skip_missing_meshes)
    except RobotDefinitionError as exc:
        raise CliError(str(exc)) from None
    for warning in skipped:
        if issubclass(warning.category, MeshSkippedWarning):
            print(f"{PROG}: warning: {' '.join(str(warning.message).split())}", file=sys.stderr)
        else:
            warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno)
    if args.workspace:
        check_workspace(args.workspace, robot)
    pick_plan, time, pick_effort, pick_report = pick_arguments(args, robot)
    record, duration, fps = record_arguments(args, pick_plan, time)
    gains = gain_arguments(args, robot)
    simulate = duration if args.motion is not None and record is None and args.duration is not None else 0.0
    try:
        world = None if args.world is None else load_world(args.world)
    except WorldDefinitionError as exc:
        raise CliError(f"--world: {exc}") from None
    return Config(
        robot_arg=args.robot,
        robot=robot,
        q=None if args.q is None else parse_q(args.q, robot),
        size=parse_size(args.size),
        screenshot=None if args.screenshot is None else check_writable(Path(args.screenshot)),
        frames=parse_frames(args.frames, robot.n_dofs + 1),
        wireframe=args.wireframe,
        workspace=args.workspace,
        demo=args.demo,
        pick_plan=pick_plan,
        pick_effort=pick_effort,
        pick_report=pick_report,
        time=time,
        record=record,
        duration=duration,
        fps=fps,
        annotate=None if args.annotate is None else parse_joint_number("--annotate", args.annotate, robot.n_dofs),
        motion=args.motion,
        simulate=simulate,
        gains=gains,
        theme=theme,
        look=parse_look(args.look, robot),
        world=world,
        collision=args.collision,
    )


def _number(option: str, text: str, what: str, positive: bool) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < 0.0 or (positive and value == 0.0):
        raise CliError(f"{option}: expected {what}, got '{text}'")
    return value


def pick_arguments(
    args: argparse.Namespace, robot: RobotParams
) -> tuple[TaskPlan | None, float, np.ndarray | None, str | None]:
    """--task, --time and --motion of the pick demo: the plan (made here, so an impossible
    task is one line before anything opens or moves), the start time [s] and, with
    --motion, the plan as the simulated controller ran it, its efforts and its one-line
    tracking report."""
    for option in ("task", "time"):
        if getattr(args, option) is not None and args.demo != "pick":
            raise CliError(f"--{option}: needs --demo pick")
    if args.demo != "pick":
        return None, 0.0, None, None
    time = 0.0 if args.time is None else _number("--time", args.time, "a finite time in seconds >= 0", False)
    try:
        plan = plan_for(robot, args.task)
    except ValueError as exc:  # TaskDefinitionError, TaskError
        raise CliError(str(exc)) from None
    if args.motion is None:
        return plan, time, None, None
    try:
        run = simulate_pick(plan, args.motion)
    except ValueError as exc:  # e.g. dynamics refusing the robot's data
        raise CliError(f"--motion {args.motion}: {exc}") from None
    simulated = dataclasses.replace(plan, trajectory=run.motion, placed_pose=run.placed_pose)
    return simulated, time, run.effort, run.summary()


def record_arguments(args: argparse.Namespace, plan: TaskPlan | None, time: float) -> tuple[Path | None, float, float]:
    """--record DIR (created if missing; its parent must exist), --duration and --fps."""
    fps = RECORD_DEFAULT_FPS
    if args.fps is not None:
        fps = _number("--fps", args.fps, f"a positive number of frames per second up to {RECORD_MAX_FPS:g}", True)
        if fps > RECORD_MAX_FPS:
            raise CliError(f"--fps: expected a positive number of frames per second up to {RECORD_MAX_FPS:g}, got '{args.fps}'")
    duration = RECORD_DEFAULT_DURATION_S if plan is None else max(plan.duration - time, 0.0)
    if args.duration is not None:
        duration = _number("--duration", args.duration, "a finite number of seconds >= 0", False)
    if args.record is None:
        if args.fps is not None:
            raise CliError("--fps: needs --record DIR")
        if args.duration is not None and args.motion is None:
            raise CliError(f"--duration: needs --record DIR, or --motion {'|'.join(MOTIONS)} to simulate first")
        return None, duration, fps
    out = Path(args.record).expanduser().absolute()
    try:
        out.mkdir(exist_ok=True)
    except OSError as exc:
        raise CliError(f"--record: cannot write frames to '{out}': {exc.strerror}") from None
    if not out.is_dir() or not os.access(out, os.W_OK):
        raise CliError(f"--record: cannot write frames to '{out}': not a writable directory")
    return out, duration, fps


def robot_actions(args: argparse.Namespace, robot: RobotParams) -> bool:
    """Run ``--print-dh``, ``--export-urdf`` and ``--export-toml`` (in this order) for the
    loaded robot; True if any was asked for (the program then exits without a window)."""
    if args.print_dh:
        print(dh_table_text(robot))
    for option, kind in (("--export-urdf", "urdf"), ("--export-toml", "toml")):
        path = getattr(args, option[2:].replace("-", "_"))
        if path is None:
            continue
        try:
            print(f"wrote {export(robot, path, kind)}")
        except (OSError, ValueError) as exc:  # FileWriteError names the path and reason
            raise CliError(f"{option}: {exc}") from None
    return bool(args.print_dh or args.export_urdf or args.export_toml)


def session_from_config(config: Config) -> ViewerSession:
    """A ViewerSession with the command line's q, motion (simulated for --duration),
    frames, wireframe and annotated joint applied, framed for all of it."""
    pick = None if config.pick_plan is None else PickShow(
        config.pick_plan, config.time, config.pick_effort,
        config.motion if config.pick_effort is not None else "kinematic")
    spec = SessionSpec(config.robot, size=config.size, q=config.q, theme=config.theme, look=config.look,
                       world=config.world, gains=config.gains, motion=config.motion, simulate=config.simulate,
                       frames=config.frames, wireframe=config.wireframe, collision=config.collision,
                       annotate=config.annotate, pick=pick, demo="circle" if config.demo == "circle" else None)
    try:
        return build_session(spec)
    except ValueError as exc:  # e.g. dynamics refusing the robot's data, a stop in the first seconds
        raise CliError(f"--motion {config.motion}: {exc}") from None


def window_options(config: Config) -> "WindowOptions":
    """How the window opens for ``config`` (imports Qt: call only when a window opens)."""
    from robot_sim.qt.window import WindowOptions

    return WindowOptions(robot_arg=config.robot_arg, workspace=config.workspace,
                         message=config.pick_report)


def write_recording(config: Config) -> tuple[list[Path], Path | None]:
    """``--record``: the session rendered offscreen to a numbered PNG sequence, and an MP4
    when the optional ``video`` extra is installed (no Qt); returns both paths."""
    session = session_from_config(config)
    try:
        return recording.record(session, config.record, config.duration, config.fps, config.size,
                                picture_text(config))
    except RuntimeError as exc:
        raise CliError(f"offscreen rendering failed: {exc}") from None
    except OSError as exc:
        raise CliError(f"--record: cannot write frames to '{config.record}': {exc.strerror or exc}") from None


def write_screenshot(config: Config) -> None:
    """Render one frame offscreen through OSMesa and save it as PNG; never imports Qt."""
    session = session_from_config(config)
    if config.workspace:
        session.workspace = compute_workspace(config.robot, config.workspace)
        session.options.show_workspace = True
        session.fit_camera()
    try:
        go.require_osmesa_platform()  # before anything imports OpenGL
        with go.OffscreenRenderer(*config.size) as renderer:
            image = renderer.render(session.camera, session.scene(), session.options)
    except RuntimeError as exc:
        raise CliError(f"offscreen rendering failed: {exc}") from None
    try:
        go.save_png(config.screenshot, image, picture_text(config))
    except fileio.FileWriteError as exc:
        raise CliError(f"--screenshot: {exc}") from None


def attach_negative_values(argv: Sequence[str]) -> list[str]:
    """Turn ``--q -30,45`` into ``--q=-30,45``: argparse takes a value starting with "-"
    and a comma for an option name."""
    out: list[str] = []
    for token in argv:
        if out and out[-1] == "--q" and re.match(r"-[\d.]", token):
            out[-1] = f"--q={token}"
        else:
            out.append(token)
    return out

