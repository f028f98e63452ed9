"""The command line of ``robot-sim``, step 3 of 3: output.  The robot actions (--print-dh,
--export-urdf, --export-toml), the offscreen --screenshot and --record (OSMesa; never Qt),
and the window (Qt is imported only here, and only when it opens).
"""
from __future__ import annotations

import argparse
import os
from pathlib import Path
from typing import TYPE_CHECKING

from robot_sim import graphics as go
from robot_sim.app.cli import PROG, CliError
from robot_sim.app.prepare import Config, session_from_config
from robot_sim.app.robot_cmds import dh_table_text, export
from robot_sim.io import files as fileio
from robot_sim.model.params import RobotParams
from robot_sim.viewer import recording
from robot_sim.viewer.workspace_job import compute_workspace

if TYPE_CHECKING:
    from robot_sim.qt.window import WindowOptions


def picture_text(config: Config) -> dict[str, str]:
    """What a picture says about itself (PNG text chunks): the program and the command
    line that rendered it, as given (relative paths stay relative)."""
    return {"Software": PROG, "Source": config.command}


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


def check_display() -> None:
    """CliError unless a window can be opened: X11 or Wayland display, or Qt's offscreen platform."""
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return
    if os.environ.get("QT_QPA_PLATFORM") == "offscreen":
        return
    raise CliError("no display (DISPLAY and WAYLAND_DISPLAY are not set): "
                   "use --screenshot FILE.png to render offscreen, or run under xvfb-run")


def window_options(config: Config) -> WindowOptions:
    """How the window opens for ``config`` (imports Qt: call only when a window opens)."""
    from robot_sim.qt.window import WindowOptions

    return WindowOptions(robot_arg=config.robot_arg, workspace=config.workspace, message=config.pick_report)


def launch(config: Config) -> int:
    """Open the viewer window for a prepared ``config`` and run Qt's event loop until it
    closes; returns the loop's exit status.  Imports Qt (and only here)."""
    from robot_sim.qt import window

    return window.run_window(session_from_config(config), window_options(config))


def write_recording(config: Config) -> tuple[list[Path], Path | None]:
    """``--record``: the session rendered offscreen to a numbered PNG sequence in the
    folder (written beside it and moved into place when complete, its parent checked by
    the parse step), and an MP4 when the optional ``video`` extra is installed (no Qt);
    returns both paths."""
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
