"""``robot-sim``'s entry point (thin, as MuJoCo's viewer): parse and validate the command line
(:mod:`robot_sim.app.cli`), run the offscreen actions, or open the window on a viewer session.

Bad input is reported as one ``robot-sim: error: ...`` line with exit status 2;
``--screenshot`` renders offscreen through OSMesa without importing Qt at all.
"""
from __future__ import annotations

import os
import shlex
import sys
from typing import Sequence

# The renderer (llvmpipe) needs both cores; OpenBLAS worker threads spinning after the
# small matrix products of each frame only compete with it.  Set before NumPy loads.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from robot_sim.app import web_cmd
from robot_sim.app.cli import (
    PROG,
    CliError,
    Config,
    attach_negative_values,
    build_parser,
    check_display,
    config_from_args,
    robot_actions,
    session_from_config,
    window_options,
    write_recording,
    write_screenshot,
)
from robot_sim.app.robot_cmds import robots_table  # noqa: E402

__all__ = ["Config", "build_parser", "config_from_args", "launch", "main"]


def launch(config: Config) -> int:
    """Open the viewer window for a validated ``config`` and run Qt's event loop until it
    closes; returns the loop's exit status.  Imports Qt (and only here)."""
    from robot_sim.qt import window

    return window.run_window(session_from_config(config), window_options(config))


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``robot-sim``; returns the exit status (2 for bad input)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["sweep"]:  # robot-sim sweep ...: its own parser (robot_sim.app.sweep_cmd)
        from robot_sim.app import sweep_cmd

        return sweep_cmd.main(argv[1:])
    try:
        args = build_parser().parse_args(attach_negative_values(argv))
        if args.list_robots:
            print(robots_table())
            return 0
        config = config_from_args(args)
        config.command = shlex.join([PROG, *argv])
        if robot_actions(args, config.robot) and config.screenshot is None:
            return 0
        if config.pick_report is not None:
            print(config.pick_report)
        if config.record is not None:
            frames, video = write_recording(config)
            print(f"wrote {len(frames)} frames to {config.record}" + (f" and {video}" if video else ""))
            return 0
        if web_cmd.wanted(args):
            return web_cmd.run(args, config, session_from_config, CliError)
        if config.screenshot is not None:
            write_screenshot(config)
            print(f"wrote {config.screenshot}")
            return 0
        check_display()
    except CliError as exc:
        message = " ".join(str(exc).split())
        print(f"{PROG}: error: {message}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # The reader of a table went away (`--print-dh | head`): stop quietly, and point
        # stdout at /dev/null so the interpreter's final flush cannot raise again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    return launch(config)

