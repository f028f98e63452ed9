"""The command line of ``robot-sim``, step 1 of 3: parse.  The parser, and every check that
needs no robot: option combinations, sizes, times, rates, theme, output paths (nothing is
loaded, planned or created here).  Step 2 (robot_sim.app.prepare) loads the robot and
builds what is shown; step 3 (robot_sim.app.output) writes pictures or opens the window.

Bad input raises :class:`CliError`; ``robot_sim.app.main.main`` reports it as one
``robot-sim: error: ...`` line on stderr with exit status 2.  This module imports no
robot loader, no planner, no numba, no OpenGL and no Qt.
"""
from __future__ import annotations

import argparse
import math
import re
from pathlib import Path
from typing import Sequence

from robot_sim.app import web_cmd
from robot_sim.control.controllers import PHYSICAL_MODES
from robot_sim.graphics.looks import LOOKS
from robot_sim.graphics.themes import DEFAULT_THEME, THEMES
from robot_sim.io import files as fileio
from robot_sim.model.messages import clip, clip_middle
from robot_sim.io.robot_kind import robot_kind
from robot_sim.io.staged_folder import check_output_folder
from robot_sim.model.params import CONVENTIONS
from robot_sim.viewer import settings as vs
from robot_sim.viewer.builder import DEMOS

PROG = "robot-sim"
DEFAULT_ROBOT = "anthropomorphic"
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


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of ``robot-sim`` (errors raise CliError instead of exiting)."""
    w, h = vs.WINDOW_DEFAULT_SIZE
    parser = _Parser(prog=PROG, description="DH robot manipulator simulator with an OpenGL viewer.")
    parser.add_argument("--robot", default=DEFAULT_ROBOT, metavar="NAME|FILE.toml|FILE.urdf|FILE.urdf.xacro",
                        help=f"shipped robot name, robot file, URDF file (any XML with a <robot> root) or "
                             f"xacro file (needs pip install xacro) (default: {DEFAULT_ROBOT})")
    parser.add_argument("--xacro-arg", action="append", default=[], metavar="NAME:=VALUE",
                        help="xacro robots only: an argument of the xacro file (repeatable)")
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
    parser.add_argument("--theme", metavar="|".join(THEMES),
                        help="colours of the world: dark (the default, for the screen) or light (for papers)")
    parser.add_argument("--look", metavar="|".join(LOOKS),
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
    parser.add_argument("--trail", action="store_true",
                        help="draw the endeffector's path (key Shift+F): in the window, in --record pictures, and in "
                             "a --screenshot of what --motion simulated for --duration")
    parser.add_argument("--ik-branches", action="store_true",
                        help="draw every analytic IK branch of the start pose (--q) at once, translucent and "
                             "labelled with its posture (key Shift+B)")
    web_cmd.add_arguments(parser)
    return parser


def parse_args(argv: Sequence[str]) -> argparse.Namespace:
    """Parse ``argv`` and check what needs no robot; the namespace then holds ``size``
    (width, height) px, ``theme``, ``time`` [s], ``fps``, ``duration`` [s] or None,
    ``screenshot`` and ``record`` as absolute paths or None.  CliError for bad input."""
    args = build_parser().parse_args(attach_negative_values(argv))
    if args.tip is not None and robot_kind(Path(args.robot)) == "toml":
        raise CliError(f"--tip: applies to a URDF robot (--robot FILE.urdf), not to '{clip(args.robot)}'")
    args.theme = parse_theme(args.theme)
    for option in ("task", "time"):
        if getattr(args, option) is not None and args.demo != "pick":
            raise CliError(f"--{option}: needs --demo pick")
    args.time = 0.0 if args.time is None else parse_number("--time", args.time, "a finite time in seconds >= 0", False)
    fps_text = args.fps
    args.fps = RECORD_DEFAULT_FPS
    if fps_text is not None:
        args.fps = parse_number("--fps", fps_text, f"a positive number of frames per second up to {RECORD_MAX_FPS:g}", True)
        if args.fps > RECORD_MAX_FPS:
            raise CliError(f"--fps: expected a positive number of frames per second up to {RECORD_MAX_FPS:g}, got '{fps_text}'")
    duration_text = args.duration
    if duration_text is not None:
        args.duration = parse_number("--duration", duration_text, "a finite number of seconds >= 0", False)
    args.size = parse_size(args.size)  # before --record's folder is checked
    if args.record is None:
        if fps_text is not None:
            raise CliError("--fps: needs --record DIR")
        if duration_text is not None and args.motion is None:
            raise CliError(f"--duration: needs --record DIR, or --motion {'|'.join(MOTIONS)} to simulate first")
    else:
        if args.duration is not None and not args.duration * args.fps < vs.RECORD_MAX_FRAMES:
            raise CliError(f"--duration × --fps: {args.duration:g} s at {args.fps:g} frames per second is "
                           f"{args.duration * args.fps:.3g} frames; at most {vs.RECORD_MAX_FRAMES} are accepted")
        args.record = check_record_dir(Path(args.record))
    args.screenshot = None if args.screenshot is None else check_writable(Path(args.screenshot))
    return args


def _positive_int(text: str) -> int:
    # at most 4000 digits: int() refuses longer strings, and no memory holds that many points
    if not re.fullmatch(r"\d{1,4000}", text.strip()) or int(text) <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got '{clip(text)}'")
    return int(text)


def parse_number(option: str, text: str, what: str, positive: bool) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < 0.0 or (positive and value == 0.0):
        raise CliError(f"{option}: expected {what}, got '{text}'")
    return value


def parse_size(text: str) -> tuple[int, int]:
    """Parse ``--size WxH`` into (width, height) pixels within WINDOW_SIZE_LIMITS."""
    lo, hi = WINDOW_SIZE_LIMITS
    match = re.fullmatch(r"(\d+)x(\d+)", text.strip().lower())
    if match is None or not all(lo <= int(v) <= hi for v in match.groups()):
        raise CliError(f"--size: expected WxH with each of W and H in {lo}..{hi} pixels (e.g. 800x600), got '{text}'")
    return int(match.group(1)), int(match.group(2))


def parse_theme(text: str | None) -> str:
    """``--theme``: one of ``graphics.THEMES`` (the default theme when not given)."""
    if text is None:
        return DEFAULT_THEME
    if text not in THEMES:
        raise CliError(f"--theme: expected one of {', '.join(THEMES)}, got '{clip(text)}'")
    return text


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


def check_record_dir(path: Path) -> Path:
    """Absolute ``path`` if frames can be written there: a writable directory, or a new
    one whose parent is (the recording creates it when complete).  CliError otherwise;
    nothing is created."""
    out = path.expanduser().absolute()
    reason = check_output_folder(out)
    if reason is not None:
        raise CliError(f"--record: cannot write frames to '{clip_middle(str(out))}': {reason}")
    return out


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
