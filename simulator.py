"""robot-sim: the entry point of the DH manipulator simulator (thin, as MuJoCo's viewer).

Layers (data flows one way, see DESIGN.md):

* ``_cli``: the command line, validated before any window or GL context exists; bad
  input is reported as one ``robot-sim: error: ...`` line with exit status 2, and
  ``--screenshot`` renders offscreen through OSMesa without importing Qt at all;
* ``viewer_state.ViewerSession``: the Qt-free state of a viewer (robot, joint states,
  kinematics, camera, options, IK target, demo, workspace cloud);
* ``window``: the Qt main window and GL widget (PyQt5 imported at its top), imported
  only when a window is opened;
* ``graphics_objects.render_scene``: the one render path of both hosts.
"""
from __future__ import annotations

import os
import sys
from typing import Sequence

# The renderer (llvmpipe) needs both cores; OpenBLAS worker threads spinning after the
# small matrix products of each frame only compete with it.  Set before NumPy loads.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from _cli import (  # noqa: E402
    PROG,
    CliError,
    Config,
    attach_negative_values,
    build_parser,
    check_display,
    config_from_args,
    robot_actions,
    write_recording,
    write_screenshot,
)
from _cli_robot import robots_table  # noqa: E402

__all__ = ["Config", "build_parser", "config_from_args", "launch", "main"]


def launch(config: Config) -> int:
    """Open the viewer window for a validated ``config`` and run Qt's event loop until it
    closes; returns the loop's exit status.  Imports Qt (and only here)."""
    import window

    return window.run_window(config)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``robot-sim``; returns the exit status (2 for bad input)."""
    try:
        args = build_parser().parse_args(attach_negative_values(sys.argv[1:] if argv is None else argv))
        if args.list_robots:
            print(robots_table())
            return 0
        config = config_from_args(args)
        if robot_actions(args, config.robot) and config.screenshot is None:
            return 0
        if config.pick_report is not None:
            print(config.pick_report)
        if config.record is not None:
            frames, video = write_recording(config)
            print(f"wrote {len(frames)} frames to {config.record}" + (f" and {video}" if video else ""))
            return 0
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


if __name__ == "__main__":
    sys.exit(main())
