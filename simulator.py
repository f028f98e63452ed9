"""robot-sim: command line, Qt main window and GL widget of the DH manipulator simulator.

Layers (data flows one way, see DESIGN.md):

* the command line (:func:`main`) validates everything before any window or GL context
  exists and reports bad input as one ``robot-sim: error: ...`` line with exit status 2;
* :class:`Simulation` is the Qt-free state of a viewer: robot, current and desired joint
  state, kinematics, camera, graphics options, IK target, circle demo and workspace cloud.
  ``--screenshot`` renders it offscreen through OSMesa without importing Qt at all;
* the Qt host (``MainWindow`` and its ``GLView``, built on first use by
  :func:`qt_classes`) turns keys, mouse and sliders into calls on the simulation and
  paints it with the one render path ``graphics_objects.render_scene``.

Units: joint values are radians (revolute) and metres (prismatic) inside; the command line
``--q`` and the sliders use degrees for revolute joints and metres for prismatic ones.
Positions are in metres in the world frame.
"""
from __future__ import annotations

import argparse
import functools
import math
import os
import re
import sys
import threading
import time
from collections import deque
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Sequence

# The renderer (llvmpipe) needs both cores; OpenBLAS worker threads spinning after the
# small matrix products of each frame only compete with it.  Set before NumPy loads.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402

import graphics_defs as gd
import graphics_objects as go
from kinematics import (
    IKResult,
    Kinematics,
    diff_ik_velocity,
    ik_position_only_required,
    solve_ik,
    workspace_points,
)
from robot_defs import JTYPE_PRISMATIC, RobotDefinitionError, RobotParams, available_robots, load_robot
from robot_state import RobotState
from transforms import HomogeneousTransform, rpy_from_rot

PROG = "robot-sim"
DEFAULT_ROBOT = "anthropomorphic"
DEMOS = ("circle",)


# --------------------------------------------------------------------------------------
# units shared by the command line and the sliders
# --------------------------------------------------------------------------------------
def display_scale(robot: RobotParams) -> np.ndarray:
    """Per-joint factor (n,) from SI joint values (rad, m) to display units (deg, m)."""
    return np.where(robot.jtype == JTYPE_PRISMATIC, 1.0, 180.0 / math.pi)


def display_range(robot: RobotParams) -> tuple[np.ndarray, np.ndarray]:
    """Slider range (lo, hi), each (n,), in display units (deg, m).

    Joint limits where finite; otherwise ±UNLIMITED_REVOLUTE_RANGE_DEG for revolute and
    ±UNLIMITED_PRISMATIC_RANGE_M for prismatic joints.
    """
    prismatic = robot.jtype == JTYPE_PRISMATIC
    default = np.where(prismatic, gd.UNLIMITED_PRISMATIC_RANGE_M, gd.UNLIMITED_REVOLUTE_RANGE_DEG)
    scale = display_scale(robot)
    lo = np.where(np.isfinite(robot.q_min), robot.q_min * scale, -default)
    hi = np.where(np.isfinite(robot.q_max), robot.q_max * scale, default)
    return lo, hi


def wrap_display(robot: RobotParams, q: np.ndarray) -> np.ndarray:
    """Joint values (n,) in display units; unlimited revolute joints wrapped to [-180, 180)."""
    values = np.asarray(q, dtype=float) * display_scale(robot)
    wrap = (robot.jtype != JTYPE_PRISMATIC) & ~np.isfinite(robot.q_min) & ~np.isfinite(robot.q_max)
    return np.where(wrap, (values + 180.0) % 360.0 - 180.0, values)


# --------------------------------------------------------------------------------------
# the Qt-free simulation shown by the window and by --screenshot
# --------------------------------------------------------------------------------------
@dataclass
class DemoCircle:
    """Endeffector circle in the horizontal world plane through its start position (m, s)."""

    center: np.ndarray
    radius: float = gd.DEMO_CIRCLE_RADIUS_M
    period: float = gd.DEMO_CIRCLE_PERIOD_S
    time: float = 0.0

    def point_and_velocity(self) -> tuple[np.ndarray, np.ndarray]:
        """Desired world position (3,) in m and linear velocity (3,) in m/s at ``time``."""
        omega = 2.0 * math.pi / self.period
        c, s = math.cos(omega * self.time), math.sin(omega * self.time)
        point = self.center + self.radius * np.array([c, s, 0.0])
        velocity = self.radius * omega * np.array([-s, c, 0.0])
        return point, velocity


@dataclass
class Simulation:
    """What a viewer shows, without Qt: one robot's state, kinematics, camera and options.

    ``state.joint_state`` is drawn as the robot, ``state.joint_state_des`` as the ghost.
    The IK target ``target_tf`` is a world pose; moving it solves IK from the desired q and
    the current q then follows with :meth:`step_animation`.
    """

    robot: RobotParams
    aspect: float = 1.0  # viewport width / height, for framing the robot
    state: RobotState = field(init=False)
    kin: Kinematics = field(init=False)
    ghost: Kinematics = field(init=False)
    camera: Any = field(init=False)
    options: Any = field(init=False)
    target_tf: HomogeneousTransform | None = None
    ik_result: IKResult | None = None
    workspace: Any = None
    demo: DemoCircle | None = None

    def __post_init__(self) -> None:
        self.state = RobotState(self.robot)
        self.kin = Kinematics(self.robot)
        self.ghost = Kinematics(self.robot)
        self.options = go.GraphicsOptions(self.n_frames)
        self.camera = go.Camera()
        self.update_kinematics()
        self.fit_camera()

    @property
    def n_frames(self) -> int:
        """Number of joint frames that can be shown: frame 0 (base) to frame n."""
        return self.robot.n_dofs + 1

    @property
    def target_reachable(self) -> bool:
        """False when the last IK solve for the target failed."""
        return self.ik_result is None or self.ik_result.success

    def update_kinematics(self) -> None:
        """Recompute the world frames of the current (robot) and desired (ghost) state."""
        self.kin.update(self.state.joint_state)
        self.ghost.update(self.state.joint_state_des)

    def fit_camera(self) -> None:
        """Reset the camera and frame the robot's joint origins, its foot on the ground and
        the workspace cloud if there is one (world, m)."""
        origins = np.array([h.t() for h in self.kin.h_tf] + [self.kin.endeff_tf.t()])
        foot = origins[0] * np.array([1.0, 1.0, 0.0])
        cloud = np.zeros((0, 3)) if self.workspace is None else self.workspace.points
        self.camera.reset()
        self.camera.fit(np.vstack([origins, foot, cloud]), self.aspect)

    # ---- joints ----
    def set_q(self, q: np.ndarray) -> None:
        """Set current and desired q (SI) at rest, e.g. from sliders; stops any motion.

        A shown IK target snaps to the new endeffector pose.
        """
        self.demo = None
        self.state.set_q(q)
        self.state.set_q_des(q)
        self.state.set_qd(np.zeros(self.robot.n_dofs))
        self.update_kinematics()
        if self.target_tf is not None:
            self.target_tf = HomogeneousTransform(self.kin.endeff_tf.mat.copy())
            self.ik_result = None

    def set_joint(self, index: int, value: float) -> None:
        """Set joint ``index`` to ``value`` (rad or m) like :meth:`set_q`."""
        q = self.state.q()
        q[index] = value
        self.set_q(q)

    def moving(self) -> bool:
        """True while the current q has not reached the desired q, or the demo runs."""
        if self.demo is not None:
            return True
        return bool(np.any(np.abs(self.state.q_des() - self.state.q()) > gd.ANIM_ARRIVED_TOL))

    def step_animation(self, dt: float) -> None:
        """Move the current q toward the desired q at bounded joint speed for ``dt`` s."""
        q, q_des = self.state.q(), self.state.q_des()
        speed = np.where(self.robot.jtype == JTYPE_PRISMATIC, gd.ANIM_SPEED_PRISMATIC, gd.ANIM_SPEED_REVOLUTE)
        step = np.clip(q_des - q, -speed * dt, speed * dt)
        arrived = np.all(np.abs(q_des - q) <= np.maximum(speed * dt, gd.ANIM_ARRIVED_TOL))
        self.state.set_q(q_des if arrived else q + step)
        self.state.set_qd(np.zeros_like(q) if arrived else step / dt)
        self.update_kinematics()

    # ---- IK target ----
    def toggle_target(self) -> bool:
        """Show or hide the IK target and the ghost (the desired state); a new target starts
        at the endeffector.  Returns whether it is shown."""
        shown = self.target_tf is None
        self.target_tf = HomogeneousTransform(self.kin.endeff_tf.mat.copy()) if shown else None
        self.ik_result = None
        return shown

    def move_target(self, translation: np.ndarray | None = None, rpy: np.ndarray | None = None) -> bool:
        """Translate the target by ``translation`` (3,) m and rotate it about world axes
        through its origin by ``rpy`` (3,) rad; then re-solve IK.  Shows a hidden target.

        Returns whether the target is reachable; if not, the ghost stays where it was.
        """
        if self.target_tf is None:
            self.toggle_target()
        mat = self.target_tf.mat.copy()
        if translation is not None:
            mat[:3, 3] += translation
        if rpy is not None:
            mat[:3, :3] = HomogeneousTransform.from_xyz_rpy(np.zeros(3), rpy).R() @ mat[:3, :3]
        self.target_tf = HomogeneousTransform(mat)
        self.demo = None
        self.ik_result = solve_ik(
            self.robot,
            self.target_tf,
            q0=self.state.q_des(),
            position_only=ik_position_only_required(self.robot),
        )
        if self.ik_result.success:
            self.state.set_q_des(self.ik_result.q)
            self.update_kinematics()
        return self.ik_result.success

    def move_target_in_view(self, dx_px: float, dy_px: float, height_px: int) -> bool:
        """Move the target by a mouse drag of (dx, dy) pixels (x right, y down) in the view plane."""
        right, up = self.camera.view_plane_axes()
        scale = self.camera.world_per_pixel(height_px)
        return self.move_target(translation=(dx_px * np.asarray(right) - dy_px * np.asarray(up)) * scale)

    # ---- circle demo (differential IK) ----
    def toggle_demo(self) -> bool:
        """Start the circle demo at the current endeffector position, or stop it."""
        if self.demo is not None:
            self.demo = None
            self.state.set_qd(np.zeros(self.robot.n_dofs))
            self.update_kinematics()
            return False
        start = self.kin.endeff_tf.t()
        self.demo = DemoCircle(center=start - np.array([gd.DEMO_CIRCLE_RADIUS_M, 0.0, 0.0]))
        return True

    def step_demo(self, dt: float) -> None:
        """Advance the circle demo by ``dt`` s: qd from diff_ik_velocity with position feedback."""
        self.demo.time += dt
        point, velocity = self.demo.point_and_velocity()
        command = velocity + gd.DEMO_FEEDBACK_GAIN * (point - self.kin.endeff_tf.t())
        q = self.state.q()
        qd = diff_ik_velocity(self.robot, q, command)
        q_new = np.clip(q + qd * dt, self.robot.q_min, self.robot.q_max)
        self.state.set_q(q_new)
        self.state.set_q_des(q_new)
        self.state.set_qd((q_new - q) / dt)
        self.update_kinematics()

    def step(self, dt: float) -> None:
        """Advance whatever moves (demo or animation toward the ghost) by ``dt`` s."""
        if self.demo is not None:
            self.step_demo(dt)
        else:
            self.step_animation(dt)

    # ---- drawing ----
    def velocity_vectors(self) -> list[tuple[np.ndarray, np.ndarray, tuple[float, ...]]]:
        """Endeffector linear (m/s) and angular (rad/s) velocity arrows at its origin (world)."""
        origin = self.kin.endeff_tf.t()
        twist = np.asarray(self.kin.endeff_twist)
        return [
            (origin, twist[:3] * gd.VECTOR_SCALE_LINEAR, gd.LINEAR_VELOCITY_COLOR),
            (origin, twist[3:] * gd.VECTOR_SCALE_ANGULAR, gd.ANGULAR_VELOCITY_COLOR),
        ]

    def scene(self) -> Any:
        """The graphics_objects.Scene of the current state."""
        return go.Scene(
            self.kin,
            ghost=self.ghost if self.target_tf is not None else None,
            target_tf=self.target_tf,
            target_reachable=self.target_reachable,
            vectors=self.velocity_vectors() if self.options.show_vectors else [],
            workspace=self.workspace,
        )

    def status_text(self, fps_text: str) -> str:
        """Status bar text: robot name, endeffector position (m) and roll-pitch-yaw (deg)."""
        x, y, z = self.kin.endeff_tf.t()
        roll, pitch, yaw = np.degrees(rpy_from_rot(self.kin.endeff_tf.R()))
        text = gd.STATUS_FORMAT.format(
            robot=self.robot.name, x=x, y=y, z=z, roll=roll, pitch=pitch, yaw=yaw, fps=fps_text
        )
        if self.target_tf is not None and not self.target_reachable:
            text += gd.STATUS_TARGET_UNREACHABLE.format(
                pos_err=self.ik_result.pos_err, rot_err_deg=math.degrees(self.ik_result.rot_err)
            )
        return text


def compute_workspace(robot: RobotParams, n_points: int) -> Any:
    """Workspace cloud of ``n_points`` endeffector positions (m, world) coloured by manipulability."""
    points, manipulability = workspace_points(robot, n_points, seed=gd.WORKSPACE_SEED)
    return go.WorkspaceCloud(points, manipulability)


# --------------------------------------------------------------------------------------
# command line
# --------------------------------------------------------------------------------------
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
    frames: list[int]
    wireframe: bool
    workspace: int
    demo: str | None


def build_parser() -> argparse.ArgumentParser:
    """The argparse parser of ``robot-sim`` (errors raise CliError instead of exiting)."""
    w, h = gd.WINDOW_DEFAULT_SIZE
    parser = _Parser(prog=PROG, description="DH robot manipulator simulator with an OpenGL viewer.")
    parser.add_argument("--robot", default=DEFAULT_ROBOT, metavar="NAME|FILE.toml",
                        help=f"shipped robot name or robot file (default: {DEFAULT_ROBOT})")
    parser.add_argument("--q", metavar="v1,v2,...",
                        help="start joint values: degrees for revolute, metres for prismatic joints")
    parser.add_argument("--size", default=f"{w}x{h}", metavar="WxH", help=f"picture size in pixels (default: {w}x{h})")
    parser.add_argument("--screenshot", metavar="FILE.png",
                        help="render one frame offscreen (OSMesa) to FILE.png and exit; needs no display")
    parser.add_argument("--frames", default="", metavar="all|1,3", help="joint frames to show (0 = base frame)")
    parser.add_argument("--wireframe", action="store_true", help="draw the robot as wireframe")
    parser.add_argument("--list-robots", action="store_true", help="list the shipped robots and exit")
    parser.add_argument("--workspace", type=_positive_int, default=0, metavar="N",
                        help="compute and show an N-point workspace cloud")
    parser.add_argument("--demo", choices=DEMOS, help="start a demo: circle = endeffector circle by differential IK")
    return parser


def _positive_int(text: str) -> int:
    if not re.fullmatch(r"\d+", text.strip()) or int(text) <= 0:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got '{text}'")
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
    lo, hi = gd.WINDOW_SIZE_LIMITS
    match = re.fullmatch(r"(\d+)x(\d+)", text.strip().lower())
    if match is None or not all(lo <= int(v) <= hi for v in match.groups()):
        raise CliError(f"--size: expected WxH with each of W and H in {lo}..{hi} pixels (e.g. 800x600), got '{text}'")
    return int(match.group(1)), int(match.group(2))


def parse_frames(text: str, n_frames: int) -> list[int]:
    """Parse ``--frames all|i,j,...`` into frame indices in 0..n_frames-1."""
    if text.strip() == "":
        return []
    if text.strip().lower() == "all":
        return list(range(n_frames))
    frames = []
    for part in text.split(","):
        part = part.strip()
        if not re.fullmatch(r"\d+", part) or int(part) >= n_frames:
            raise CliError(f"--frames: expected 'all' or frame numbers 0..{n_frames - 1} separated by commas, got '{part}'")
        frames.append(int(part))
    return frames


def check_writable(path: Path) -> Path:
    """Absolute ``path`` if a file can be written there, else CliError naming the reason."""
    path = path.expanduser().absolute()
    if path.is_dir():
        raise CliError(f"--screenshot: cannot write '{path}': it is a directory")
    if not path.parent.is_dir():
        raise CliError(f"--screenshot: cannot write '{path}': directory '{path.parent}' does not exist")
    if not os.access(path.parent, os.W_OK) or (path.exists() and not os.access(path, os.W_OK)):
        raise CliError(f"--screenshot: cannot write '{path}': permission denied")
    return path


def check_display() -> None:
    """CliError unless a window can be opened: X11 or Wayland display, or Qt's offscreen platform."""
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return
    if os.environ.get("QT_QPA_PLATFORM") == "offscreen":
        return
    raise CliError("no display (DISPLAY and WAYLAND_DISPLAY are not set): "
                   "use --screenshot FILE.png to render offscreen, or run under xvfb-run")


def config_from_args(args: argparse.Namespace) -> Config:
    """Validate parsed arguments: load the robot, parse q, size, frames and the screenshot path."""
    try:
        robot = load_robot(args.robot)
    except RobotDefinitionError as exc:
        raise CliError(str(exc)) from None
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
    )


def simulation_from_config(config: Config) -> Simulation:
    """A Simulation with the command line's q, frames and wireframe applied."""
    sim = Simulation(config.robot, aspect=config.size[0] / config.size[1])
    if config.q is not None:
        sim.set_q(config.q)
        sim.fit_camera()
    for i in config.frames:
        sim.options.toggle_frame(i)
    if config.wireframe:
        sim.options.toggle_wireframe()
    return sim


def write_screenshot(config: Config) -> None:
    """Render one frame offscreen through OSMesa and save it as PNG; never imports Qt."""
    sim = simulation_from_config(config)
    if config.workspace:
        sim.workspace = compute_workspace(config.robot, config.workspace)
        sim.options.show_workspace = True
        sim.fit_camera()
    try:
        go.require_osmesa_platform()  # before anything imports OpenGL
        with go.OffscreenRenderer(*config.size) as renderer:
            image = renderer.render(sim.camera, sim.scene(), sim.options)
    except RuntimeError as exc:
        raise CliError(f"offscreen rendering failed: {exc}") from None
    try:
        go.save_png(config.screenshot, image)
    except OSError as exc:
        raise CliError(f"--screenshot: cannot write '{config.screenshot}': {exc.strerror or exc}") from None


def _attach_negative_values(argv: Sequence[str]) -> list[str]:
    """Turn ``--q -30,45`` into ``--q=-30,45``: argparse takes a value starting with "-"
    and a comma for an option name."""
    out: list[str] = []
    for token in argv:
        if out and out[-1] == "--q" and re.match(r"-[\d.]", token):
            out[-1] = f"--q={token}"
        else:
            out.append(token)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``robot-sim``; returns the exit status (2 for bad input)."""
    try:
        args = build_parser().parse_args(_attach_negative_values(sys.argv[1:] if argv is None else argv))
        if args.list_robots:
            print("\n".join(available_robots()))
            return 0
        config = config_from_args(args)
        if config.screenshot is not None:
            write_screenshot(config)
            print(f"wrote {config.screenshot}")
            return 0
        check_display()
    except CliError as exc:
        message = " ".join(str(exc).split())
        print(f"{PROG}: error: {message}", file=sys.stderr)
        return 2
    return run_window(config)


# --------------------------------------------------------------------------------------
# the Qt window (classes built on first use so that --screenshot never imports Qt)
# --------------------------------------------------------------------------------------
def help_lines() -> list[str]:
    """Help overlay text generated from KEY_BINDINGS then MOUSE_BINDINGS.

    Consecutive bindings with the same description share a line ("W / S", "1 .. 9").
    """
    groups: list[tuple[list[str], str]] = []
    for key, mods, _action, text in gd.KEY_BINDINGS:
        name = f"{mods}+{key}" if mods else key
        if groups and groups[-1][1] == text:
            groups[-1][0].append(name)
        else:
            groups.append(([name], text))
    rows = [(" / ".join(names) if len(names) <= 2 else f"{names[0]} .. {names[-1]}", text) for names, text in groups]
    rows += list(gd.MOUSE_BINDINGS)
    width = max(len(name) for name, _ in rows)
    return [f"{name:<{width}}  {text}" for name, text in rows]


def run_window(config: Config) -> int:
    """Open the main window and run the Qt event loop; returns its exit status."""
    from PyQt5.QtWidgets import QApplication

    app = QApplication.instance() or QApplication(sys.argv[:1])
    window = qt_classes().MainWindow(config)
    window.show()
    window.view.setFocus()
    return app.exec_()


def __getattr__(name: str) -> Any:
    """``simulator.MainWindow`` and ``simulator.GLView`` build the Qt classes on first use."""
    if name in ("MainWindow", "GLView"):
        return getattr(qt_classes(), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@functools.cache
def qt_classes() -> Any:
    """Import Qt and define the window classes; returns a namespace with MainWindow, GLView."""
    from PyQt5 import QtCore, QtGui, QtWidgets
    from PyQt5.QtCore import Qt

    modifier_flags = {"Shift": Qt.ShiftModifier, "Ctrl": Qt.ControlModifier, "Alt": Qt.AltModifier}
    modifier_mask = functools.reduce(lambda a, b: a | b, modifier_flags.values())

    def key_of(key: str, mods: str) -> tuple[int, int]:
        """(Qt key code, modifier bits) of a KEY_BINDINGS row."""
        bits = functools.reduce(lambda a, b: a | b, (modifier_flags[m] for m in mods.split("+") if m), Qt.NoModifier)
        return int(getattr(Qt, f"Key_{key}")), int(bits)

    class HelpOverlay(QtWidgets.QWidget):
        """Key and mouse bindings drawn with QPainter over the GL picture: a transparent
        child of the GL view, so its painting shares no GL state with render_scene."""

        def __init__(self, parent: QtWidgets.QWidget) -> None:
            super().__init__(parent)
            self.setAttribute(Qt.WA_TransparentForMouseEvents)
            self.setFocusPolicy(Qt.NoFocus)
            self.hide()

        def paintEvent(self, event: QtGui.QPaintEvent) -> None:
            painter = QtGui.QPainter(self)
            font = QtGui.QFont(gd.HELP_FONT_FAMILY, gd.HELP_FONT_PT)
            font.setStyleHint(QtGui.QFont.TypeWriter)
            painter.setFont(font)
            metrics = QtGui.QFontMetrics(font)
            lines = help_lines()
            margin, line_h = gd.HELP_MARGIN_PX, metrics.lineSpacing()
            rows = max(1, (self.height() - 4 * margin) // line_h)
            columns = [lines[i:i + rows] for i in range(0, len(lines), rows)]
            col_w = max(metrics.horizontalAdvance(line) for line in lines) + 2 * margin
            box = QtCore.QRect(margin, margin, col_w * len(columns) + margin, line_h * min(rows, len(lines)) + 2 * margin)
            painter.fillRect(box, QtGui.QColor(*gd.HELP_BACKGROUND_RGBA))
            painter.setPen(QtGui.QColor(*gd.HELP_TEXT_RGB))
            for c, column in enumerate(columns):
                for r, line in enumerate(column):
                    painter.drawText(2 * margin + c * col_w, 2 * margin + r * line_h + metrics.ascent(), line)
            painter.end()

    class GLView(QtWidgets.QOpenGLWidget):
        """GL widget: paints the simulation with render_scene, turns the mouse into camera
        and target moves, carries the help overlay and measures the frame rate over actual
        paints."""

        def __init__(self, window: "MainWindow") -> None:
            super().__init__(window)
            # Qt's default surface has no depth buffer: without one every part would
            # paint over the others in drawing order
            surface = QtGui.QSurfaceFormat()
            surface.setDepthBufferSize(gd.DEPTH_BUFFER_BITS)
            self.setFormat(surface)
            self.window_ = window
            self.help = HelpOverlay(self)
            self.paint_times: deque[float] = deque()
            self.drag_pos: QtCore.QPoint | None = None
            self.framed = False
            self.setFocusPolicy(Qt.StrongFocus)
            self.setMinimumSize(160, 120)

        def pixel_size(self) -> tuple[int, int]:
            """Framebuffer size (width, height) in device pixels."""
            ratio = self.devicePixelRatioF()
            return max(1, round(self.width() * ratio)), max(1, round(self.height() * ratio))

        def fps_text(self) -> str:
            """Frame rate over the paints of the last FPS_WINDOW_S seconds ("idle" if < 2)."""
            now = time.monotonic()
            while self.paint_times and now - self.paint_times[0] > gd.FPS_WINDOW_S:
                self.paint_times.popleft()
            span = self.paint_times[-1] - self.paint_times[0] if len(self.paint_times) >= 2 else 0.0
            if span <= 0.0:
                return gd.STATUS_FPS_IDLE
            return gd.STATUS_FPS_FORMAT.format(fps=(len(self.paint_times) - 1) / span)

        def paintGL(self) -> None:
            sim = self.window_.sim
            width, height = self.pixel_size()
            try:
                go.render_scene(sim.camera, sim.scene(), sim.options, width, height)
            except RuntimeError as exc:  # an exception escaping paintGL aborts PyQt
                self.window_.statusBar().showMessage(f"cannot draw: {exc}")
                return
            self.paint_times.append(time.monotonic())
            self.window_.refresh_status()

        def resizeGL(self, width: int, height: int) -> None:
            # frame the robot for the widget's real shape once it is known (the dock
            # takes part of the window); later resizes leave the user's camera alone
            sim = self.window_.sim
            sim.aspect = width / max(height, 1)
            if not self.framed:
                sim.fit_camera()
                self.framed = True

        def resizeEvent(self, event: QtGui.QResizeEvent) -> None:
            super().resizeEvent(event)
            self.help.resize(self.size())

        def mousePressEvent(self, event: QtGui.QMouseEvent) -> None:
            self.drag_pos = event.pos()
            self.setFocus()

        def mouseReleaseEvent(self, event: QtGui.QMouseEvent) -> None:
            self.drag_pos = None

        def mouseMoveEvent(self, event: QtGui.QMouseEvent) -> None:
            if self.drag_pos is None:
                return
            delta = event.pos() - self.drag_pos
            self.drag_pos = event.pos()
            self.window_.drag(delta.x(), delta.y(), event.buttons(), event.modifiers())

        def wheelEvent(self, event: QtGui.QWheelEvent) -> None:
            notches = event.angleDelta().y() / 120.0  # > 0: wheel turned away, zoom in
            self.window_.zoom(gd.WHEEL_ZOOM_FACTOR ** -notches)

    class MainWindow(QtWidgets.QMainWindow):
        """Main window: GL view in the middle, a dock with the robot chooser, one slider per
        joint and the frame list, a status bar.  Keys are dispatched through KEY_BINDINGS."""

        workspace_ready = QtCore.pyqtSignal(int, object)

        def __init__(self, config: Config) -> None:
            super().__init__()
            self.config = config
            self.sim = simulation_from_config(config)
            self.sliders: list[tuple[QtWidgets.QSlider, QtWidgets.QLabel]] = []
            self.workspace_token = 0
            self.workspace_busy = False
            self.last_tick = 0.0
            self.setWindowTitle(PROG)
            self.view = GLView(self)
            self.setCentralWidget(self.view)
            self.timer = QtCore.QTimer(self)
            self.timer.setInterval(gd.ANIM_INTERVAL_MS)
            self.timer.timeout.connect(self.tick)
            self.workspace_ready.connect(self.on_workspace_ready)
            self.status = QtWidgets.QLabel()
            self.statusBar().addPermanentWidget(self.status, 1)
            self.build_dock()
            self.actions_by_name = self.build_actions()
            self.key_table = {key_of(key, mods): action for key, mods, action, _ in gd.KEY_BINDINGS}
            self.resize(*config.size)
            self.robot_changed()
            if config.workspace:
                self.start_workspace(config.workspace)
            if config.demo == "circle":
                self.sim.toggle_demo()
                self.start_motion()

        # ---- dock ----
        def build_dock(self) -> None:
            dock = QtWidgets.QDockWidget("Robot", self)
            dock.setFeatures(QtWidgets.QDockWidget.NoDockWidgetFeatures)
            panel = QtWidgets.QWidget()
            layout = QtWidgets.QVBoxLayout(panel)
            self.robot_combo = QtWidgets.QComboBox()
            names = available_robots()
            self.robot_combo.addItems(names)
            if self.config.robot_arg not in names:
                self.robot_combo.insertItem(0, self.config.robot_arg)
            self.robot_combo.setCurrentText(self.config.robot_arg)
            self.robot_combo.currentTextChanged.connect(self.choose_robot)
            layout.addWidget(self.robot_combo)
            self.joints_box = QtWidgets.QWidget()
            self.joints_layout = QtWidgets.QVBoxLayout(self.joints_box)
            self.joints_layout.setSpacing(2)
            self.joints_layout.addStretch(1)
            scroll = QtWidgets.QScrollArea()
            scroll.setWidgetResizable(True)
            scroll.setWidget(self.joints_box)
            layout.addWidget(scroll, 3)
            layout.addWidget(QtWidgets.QLabel("Frames"))
            self.frames_list = QtWidgets.QListWidget()
            self.frames_list.itemChanged.connect(self.frame_item_changed)
            layout.addWidget(self.frames_list, 2)
            for widget in (self.robot_combo, scroll, self.frames_list):
                widget.setFocusPolicy(Qt.NoFocus)  # keys stay with the GL view
            dock.setWidget(panel)
            dock.setMinimumWidth(gd.DOCK_MIN_WIDTH)
            self.addDockWidget(Qt.RightDockWidgetArea, dock)

        def robot_changed(self) -> None:
            """Rebuild the sliders and the frame list for ``self.sim.robot``."""
            for slider, label in self.sliders:
                slider.deleteLater()
                label.deleteLater()
            self.sliders = []
            robot = self.sim.robot
            lo, hi = display_range(robot)
            for i in range(robot.n_dofs):
                label = QtWidgets.QLabel()
                slider = QtWidgets.QSlider(Qt.Horizontal)
                slider.setFocusPolicy(Qt.NoFocus)
                ticks = self.ticks_per_unit(i)
                slider.setRange(math.floor(lo[i] * ticks), math.ceil(hi[i] * ticks))
                slider.valueChanged.connect(functools.partial(self.slider_moved, i))
                self.joints_layout.insertWidget(2 * i, label)
                self.joints_layout.insertWidget(2 * i + 1, slider)
                self.sliders.append((slider, label))
            self.frames_list.blockSignals(True)
            self.frames_list.clear()
            names = [f"frame {i}" + (" (base)" if i == 0 else "") for i in range(self.sim.n_frames)]
            for name in names + ["endeffector"]:
                item = QtWidgets.QListWidgetItem(name)
                item.setFlags(Qt.ItemIsUserCheckable | Qt.ItemIsEnabled)
                self.frames_list.addItem(item)
            self.frames_list.blockSignals(False)
            self.sync_widgets()

        def ticks_per_unit(self, joint: int) -> int:
            prismatic = self.sim.robot.jtype[joint] == JTYPE_PRISMATIC
            return gd.SLIDER_TICKS_PER_M if prismatic else gd.SLIDER_TICKS_PER_DEG

        def sync_widgets(self) -> None:
            """Show the simulation's q on the sliders and its frame options in the list."""
            values = wrap_display(self.sim.robot, self.sim.state.q())
            for i, (slider, label) in enumerate(self.sliders):
                prismatic = self.sim.robot.jtype[i] == JTYPE_PRISMATIC
                fmt = gd.SLIDER_LABEL_FORMAT_PRISMATIC if prismatic else gd.SLIDER_LABEL_FORMAT_REVOLUTE
                label.setText(fmt.format(name=f"joint {i + 1}", value=round(values[i], 3) + 0.0))
                slider.blockSignals(True)
                slider.setValue(round(values[i] * self.ticks_per_unit(i)))
                slider.blockSignals(False)
            self.frames_list.blockSignals(True)
            options = self.sim.options
            for i, shown in enumerate(options.show_frames + [options.show_endeff_frame]):
                self.frames_list.item(i).setCheckState(Qt.Checked if shown else Qt.Unchecked)
            self.frames_list.blockSignals(False)
            self.view.update()

        def refresh_status(self) -> None:
            self.status.setText(self.sim.status_text(self.view.fps_text()))

        def message(self, text: str) -> None:
            self.statusBar().showMessage(text, gd.STATUS_MESSAGE_MS)

        # ---- widget callbacks ----
        def choose_robot(self, name: str) -> None:
            """Switch to robot ``name`` (shipped name or file) without restarting."""
            try:
                robot = load_robot(name)
            except RobotDefinitionError as exc:
                self.message(str(exc))
                return
            previous = self.sim.options
            self.timer.stop()
            self.sim = Simulation(robot, aspect=self.view.width() / max(self.view.height(), 1))
            for flag in ("wireframe", "alpha", "show_vectors"):
                setattr(self.sim.options, flag, getattr(previous, flag))
            self.workspace_token += 1
            self.workspace_busy = False
            self.robot_changed()
            self.view.setFocus()

        def slider_moved(self, joint: int, ticks: int) -> None:
            self.timer.stop()
            scale = display_scale(self.sim.robot)[joint]
            self.sim.set_joint(joint, ticks / self.ticks_per_unit(joint) / scale)
            self.sync_widgets()

        def frame_item_changed(self, item: QtWidgets.QListWidgetItem) -> None:
            """A frame list checkbox: rows 0..n are DH frames, the last the endeffector frame."""
            row, shown = self.frames_list.row(item), item.checkState() == Qt.Checked
            if row < self.sim.n_frames:
                self.sim.options.show_frames[row] = shown
            else:
                self.sim.options.show_endeff_frame = shown
            self.view.update()

        # ---- keys ----
        def keyPressEvent(self, event: QtGui.QKeyEvent) -> None:
            action = self.key_table.get((int(event.key()), int(event.modifiers() & modifier_mask)))
            if action is None:
                super().keyPressEvent(event)
                return
            self.actions_by_name[action]()
            self.sync_widgets()

        def build_actions(self) -> dict[str, Callable[[], Any]]:
            """Action name (KEY_BINDINGS column 3) -> handler; every table action must have one."""
            opts = lambda: self.sim.options  # noqa: E731 - options are replaced with the robot
            cam = lambda: self.sim.camera  # noqa: E731
            actions: dict[str, Callable[[], Any]] = {
                "toggle_help": self.toggle_help,
                "quit": self.close,
                "toggle_wireframe": lambda: opts().toggle_wireframe(),
                "toggle_alpha": lambda: opts().toggle_alpha(),
                "toggle_all_frames": lambda: opts().toggle_all_frames(),
                "zoom_in": lambda: self.zoom(1.0 / gd.KEY_ZOOM_FACTOR),
                "zoom_out": lambda: self.zoom(gd.KEY_ZOOM_FACTOR),
                "orbit_left": lambda: cam().orbit(-gd.KEY_ORBIT_STEP_DEG, 0.0),
                "orbit_right": lambda: cam().orbit(gd.KEY_ORBIT_STEP_DEG, 0.0),
                "orbit_up": lambda: cam().orbit(0.0, gd.KEY_ORBIT_STEP_DEG),
                "orbit_down": lambda: cam().orbit(0.0, -gd.KEY_ORBIT_STEP_DEG),
                "reset_view": lambda: self.sim.fit_camera(),
                "save_screenshot": self.save_screenshot,
                "toggle_workspace": self.toggle_workspace,
                "toggle_vectors": lambda: setattr(opts(), "show_vectors", not opts().show_vectors),
                "toggle_demo": self.toggle_demo,
                "toggle_target": lambda: self.sim.toggle_target(),
            }
            for i in range(1, 10):
                actions[f"toggle_frame_{i}"] = functools.partial(self.toggle_frame, i)
            step_rad = math.radians(gd.TARGET_STEP_DEG)
            for axis, name in enumerate("xyz"):
                for sign, suffix in ((1.0, "plus"), (-1.0, "minus")):
                    unit = sign * np.eye(3)[axis]
                    actions[f"target_{name}_{suffix}"] = functools.partial(self.move_target, translation=unit * gd.TARGET_STEP_M)
                    actions[f"target_r{name}_{suffix}"] = functools.partial(self.move_target, rpy=unit * step_rad)
            missing = {action for _, _, action, _ in gd.KEY_BINDINGS} - actions.keys()
            if missing:
                raise RuntimeError(f"KEY_BINDINGS actions without a handler: {sorted(missing)}")
            return actions

        def toggle_help(self) -> None:
            self.view.help.setVisible(not self.view.help.isVisible())

        def toggle_frame(self, index: int) -> None:
            if not self.sim.options.toggle_frame(index):
                self.message(f"{self.sim.robot.name} has no frame {index} (frames 0..{self.sim.n_frames - 1})")

        def zoom(self, factor: float) -> None:
            """Multiply the camera distance by ``factor`` (< 1 zooms in)."""
            self.sim.camera.zoom(factor)
            self.view.update()

        def drag(self, dx: int, dy: int, buttons: Qt.MouseButtons, modifiers: Qt.KeyboardModifiers) -> None:
            """Mouse drag of (dx, dy) pixels: left orbits, Ctrl+left moves the IK target,
            right or middle pans."""
            if buttons & Qt.LeftButton and modifiers & Qt.ControlModifier:
                self.move_target_by(lambda: self.sim.move_target_in_view(dx, dy, self.view.pixel_size()[1]))
            elif buttons & Qt.LeftButton:
                self.sim.camera.orbit(-dx * gd.MOUSE_ORBIT_DEG_PER_PX, dy * gd.MOUSE_ORBIT_DEG_PER_PX)
            elif buttons & (Qt.RightButton | Qt.MiddleButton):
                self.sim.camera.pan(dx, dy, self.view.pixel_size()[1])
            self.view.update()

        # ---- IK target, animation, demo ----
        def move_target(self, **move: np.ndarray) -> None:
            self.move_target_by(lambda: self.sim.move_target(**move))

        def move_target_by(self, move: Callable[[], bool]) -> None:
            if not move():
                self.message("IK target unreachable: the ghost stays at the last reachable pose")
            self.start_motion()

        def toggle_demo(self) -> None:
            self.message("circle demo " + ("started" if self.sim.toggle_demo() else "stopped"))
            self.start_motion()

        def start_motion(self) -> None:
            """Run the timer while something moves; it stops itself when all has arrived."""
            if self.sim.moving() and not self.timer.isActive():
                self.last_tick = time.monotonic()
                self.timer.start()

        def tick(self) -> None:
            now = time.monotonic()
            dt = min(max(now - self.last_tick, 1e-3), 4 * gd.ANIM_INTERVAL_MS / 1000.0)
            self.last_tick = now
            self.sim.step(dt)
            if not self.sim.moving():
                self.timer.stop()
                # once the last paints are older than the fps window the status says idle
                QtCore.QTimer.singleShot(round(gd.FPS_WINDOW_S * 1000) + 50, self.refresh_status)
            self.sync_widgets()

        # ---- screenshot and workspace ----
        def save_screenshot(self) -> None:
            stamp = time.strftime("%Y%m%d-%H%M%S") + f"-{int(time.time() * 1000) % 1000:03d}"
            stem = Path(self.robot_combo.currentText()).stem
            path = Path.cwd() / gd.SCREENSHOT_NAME_FORMAT.format(robot=stem, stamp=stamp)
            if self.view.grab().save(str(path)):  # the GL picture with the help overlay if shown
                self.message(f"screenshot saved to {path}")
            else:
                self.message(f"could not save screenshot to {path}")

        def toggle_workspace(self) -> None:
            if self.sim.workspace is None and not self.workspace_busy:
                self.start_workspace(self.config.workspace or gd.WORKSPACE_DEFAULT_POINTS)
            else:
                self.sim.options.show_workspace = not self.sim.options.show_workspace

        def start_workspace(self, n_points: int) -> None:
            """Compute the workspace cloud in a background thread (numpy releases the GIL)."""
            self.workspace_busy = True
            self.sim.options.show_workspace = True
            token, robot = self.workspace_token, self.sim.robot
            self.message(f"computing workspace ({n_points} points) ...")

            def work() -> None:
                self.workspace_ready.emit(token, compute_workspace(robot, n_points))

            threading.Thread(target=work, name="workspace", daemon=True).start()

        def on_workspace_ready(self, token: int, cloud: Any) -> None:
            if token != self.workspace_token:
                return  # computed for a robot that is no longer shown
            self.workspace_busy = False
            self.sim.workspace = cloud
            self.message(f"workspace: {len(cloud.points)} points")
            self.view.update()

    return argparse.Namespace(GLView=GLView, MainWindow=MainWindow)


if __name__ == "__main__":
    sys.exit(main())
